"""Shared fixtures for the Python-side tests.

``synthetic_hertz_result`` builds a result dict with the exact layout of docs/engine_api.md
from the closed-form frictionless Hertz solution (pairs close at f = (x/a)^2, pressure
p0 sqrt(f) sqrt(1 - x^2/(a^2 f))).  It is NOT a solver: it only lets the output code be tested
without the compiled engine, against numbers known in advance.
"""

from __future__ import annotations

import contextlib
import importlib
import math
import os
import re
import shutil
import signal
import sys
import tomllib
from functools import cache
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT / "py") not in sys.path:  # run from a checkout without installing
    sys.path.insert(0, str(ROOT / "py"))

CASES = ROOT / "cases"


def shipped_cases(dimension: int) -> list[Path]:
    """The shipped cases of one dimension (2: planar and axisymmetric; 3: in space)."""
    return [
        p
        for p in sorted(CASES.glob("*.toml"))
        if tomllib.loads(p.read_text()).get("analysis", {}).get("dimension", 2) == dimension
    ]


#: A small case every concept's tests vary: a 2 x 1 block (4 x 2 cells), bottom fixed, a rigid
#: line above its top (mu = 0.3).
MINIMAL = """
[case]
name = "mini"

[[body]]
name = "b"
[body.mesh]
generator = "block"
width = 2.0
height = 1.0
nx = 4
ny = 2
[body.material]
E = 1000.0
nu = 0.25

[[bc]]
body = "b"
edge = "bottom"
fix = ["x", "y"]

[[contact]]
kind = "rigid_line"
body = "b"
edge = "top"
point = [0.0, 2.0]
normal = [0.0, -1.0]
mu = 0.3
"""


@pytest.fixture(scope="session", autouse=True)
def mesh_cache_of_the_session(tmp_path_factory):
    """The tests' generated meshes are cached in a folder of their own (slipstep.mesh.cache),
    which the processes they start inherit; the user's cache is left alone."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("SLIPSTEP_CACHE", str(tmp_path_factory.mktemp("mesh_cache")))
        yield


# --------------------------------------------------------------------------- enforced skips
#: What `make test` installs and some tests skip without, in one place: name -> (kind, source).
#: kind "module" (importable in the venv) or "program" (on PATH); source (list, package): the
#: line of ci/requirements.txt (pip) or ci/apt-packages.txt (apt) that brings it, or the
#: package of those lists it comes with.  On a machine where one of them is missing, a skip
#: whose reason names it is a failure (``enforce_skip``), and so is
#: tests/package/test_enforced_dependencies.py: `make test` cannot go green without them.  Skips
#: for anything else stay skips (PyPI unreachable, a test wanting more MPI ranks).
ENFORCED = {
    "gmsh": ("module", ("pip", "gmsh")),
    "hypothesis": ("module", ("pip", "hypothesis")),
    "jupytext": ("module", ("pip", "jupytext")),
    "nbclient": ("module", ("pip", "nbclient")),
    "nbformat": ("module", ("pip", "jupytext")),  # jupytext's dependency
    "jsonschema": ("module", ("pip", "jupytext")),  # nbformat's dependency
    "ipywidgets": ("module", ("pip", "ipywidgets")),
    "matplotlib": ("module", ("pip", "matplotlib")),
    "dolfinx": ("module", ("apt", "python3-dolfinx")),
    "meshio": ("module", ("apt", "python3-meshio")),
    "h5py": ("module", ("apt", "python3-h5py")),
    "scipy": ("module", ("apt", "python3-scipy")),
    "getfem": ("module", ("apt", "python3-getfem")),
    "petsc4py": ("module", ("apt", "python3-petsc4py")),
    "mpi4py": ("module", ("apt", "python3-dolfinx")),
    "slipstep._engine": ("module", ("make", "build")),
    "pvpython": ("program", ("apt", "python3-paraview")),
    "mpirun": ("program", ("apt", "mpi-default-bin")),
}

#: Dependencies a developer knowingly lacks, comma-separated (e.g. "pvpython,getfem"): their
#: skips stay skips.  `make test` unsets it.
ALLOW_MISSING = "SLIPSTEP_ALLOW_MISSING"


@cache
def available(name: str) -> bool:
    """Whether an ENFORCED dependency is there: the module imports (not merely found: a broken
    installation counts as missing), the program is on PATH."""
    kind, _ = ENFORCED[name]
    if kind == "program":
        return shutil.which(name) is not None
    try:
        importlib.import_module(name)
    except Exception:
        return False
    return True


def missing_named(reason: str, is_available=available) -> list[str]:
    """The ENFORCED dependencies that ``reason`` (a skip's text) names and that are missing
    (and not allowed to be, SLIPSTEP_ALLOW_MISSING)."""
    allowed = {n.strip() for n in os.environ.get(ALLOW_MISSING, "").split(",") if n.strip()}
    named = [n for n in ENFORCED if re.search(rf"(?<![\w.]){re.escape(n)}(?!\w)", reason)]
    return [n for n in named if n not in allowed and not is_available(n)]


def enforce_skip(report, is_available=available) -> None:
    """Turn a skipped test or collector report into a failure when its reason names a missing
    dependency that `make test` installs (ENFORCED)."""
    if not report.skipped or hasattr(report, "wasxfail"):
        return
    longrepr = report.longrepr
    reason = longrepr[2] if isinstance(longrepr, tuple) else str(longrepr)
    missing = missing_named(reason, is_available)
    if missing:
        sources = ", ".join(f"{n} ({ENFORCED[n][1][0]}: {ENFORCED[n][1][1]})" for n in missing)
        report.outcome = "failed"
        report.longrepr = (
            f"skipped for want of what `make test` installs: {sources}; install it "
            f"(make setup), or name it in {ALLOW_MISSING} on a machine that "
            f"cannot have it.  The skip's reason: {reason}"
        )


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    enforce_skip(outcome.get_result())


@pytest.hookimpl(hookwrapper=True)
def pytest_make_collect_report(collector):
    outcome = yield
    enforce_skip(outcome.get_result())


def _has_gmsh() -> bool:
    try:
        import gmsh  # noqa: F401
    except ImportError:
        return False
    return True


needs_gmsh = pytest.mark.skipif(not _has_gmsh(), reason="gmsh is not installed")


def write_case(tmp_path: Path, text: str, name: str = "case.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def synthetic_hertz_result(scene, final_fraction: float = 1.0, interrupted: bool = False) -> dict:
    """A frictionless Hertz result in the engine's layout, up to ``final_fraction``."""
    ref = scene.reference
    a, p0 = ref["a_hertz"], ref["p0_hertz"]
    t = scene.model["thickness"]
    x = scene.pair_xy[:, 0]
    gap0 = scene.model["pairs"]["gap"]
    closes_at = (x / a) ** 2  # a(f) = a sqrt(f)
    closes_at[gap0 == 0.0] = 0.0

    order = np.argsort(closes_at)
    events = {"step": [], "load_fraction": [], "kind": [], "entity": []}
    steps = {
        k: []
        for k in (
            "load_fraction",
            "scale",
            "residual",
            "n_closed",
            "n_stick",
            "n_slip",
            "normal_force",
        )
    }
    snapshots = []
    n_nodes, n_el = len(scene.nodes), len(scene.triangles)

    def snapshot(f):
        closed = closes_at <= f
        af, pf = a * math.sqrt(f), p0 * math.sqrt(f)
        p = np.where(closed, pf * np.sqrt(np.clip(1 - (x / af) ** 2, 0, None)), 0.0)
        return {
            "load_fraction": f,
            "u": np.zeros((n_nodes, 2)),
            "stress": np.zeros((n_el, 4)),
            "lambda_n": p * scene.pair_length * t,
            "lambda_t": np.zeros(len(x)),
            "status": np.where(closed, 2, 0).astype(np.int8),
            "gap": np.where(closed, 0.0, gap0 * (1 - f / np.maximum(closes_at, 1e-300))),
            "rtd": np.zeros(len(x)),
        }

    step = 0
    for i in order:
        f = closes_at[i]
        if f == 0.0 or f > final_fraction:
            continue
        step += 1
        events["step"].append(step)
        events["load_fraction"].append(f)
        events["kind"].append("close")
        events["entity"].append(int(i))
        steps["load_fraction"].append(f)
        snapshots.append(snapshot(f))
    step += 1
    steps["load_fraction"].append(final_fraction)
    snapshots.append(snapshot(final_fraction))
    n_steps = len(steps["load_fraction"])
    for k in ("scale", "residual", "normal_force"):
        steps[k] = np.zeros(n_steps)
    for k in ("n_closed", "n_stick", "n_slip"):
        steps[k] = np.zeros(n_steps, dtype=np.int64)
    steps["load_fraction"] = np.asarray(steps["load_fraction"])

    final = snapshots[-1]
    closure = np.where(final["status"] > 0, closes_at, np.nan)
    predicted = np.where(final["status"] > 0, np.nan, closes_at)
    return {
        "events": {
            "step": np.asarray(events["step"], dtype=np.int64),
            "load_fraction": np.asarray(events["load_fraction"]),
            "kind": events["kind"],
            "entity": np.asarray(events["entity"], dtype=np.int64),
        },
        "steps": steps,
        "snapshots": snapshots,
        "closure_fraction": closure,
        "predicted_closure": predicted,
        "max_equilibrium_residual": 1e-12,
        "n_factorizations": 1,
        "n_solves": n_steps,
        "interrupted": interrupted,
        "stop": {
            "kind": "interrupted" if interrupted else "completed",
            "message": None,
            "load_fraction": final_fraction,
        },
        "stop_reason": None,
        "timings": {"assembly": 0.0, "factorization": 0.0, "solves": 0.0, "events": 0.0},
    }


class Hang(Exception):
    """A test block ran past its time limit (see ``time_limit``)."""


@contextlib.contextmanager
def time_limit(seconds: float, what: str = "the run"):
    """Raise ``Hang`` if the block runs longer than ``seconds`` (SIGALRM; the engine checks
    Python signals every 0.1 s and stops with ``interrupted``)."""

    def alarm(signum, frame):
        raise Hang(f"{what} took more than {seconds} s")

    old = signal.signal(signal.SIGALRM, alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
