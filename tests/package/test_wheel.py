"""A wheel that runs anywhere: the wheel is built from this checkout (`maturin build
--release`, reusing target/, so it only packs and re-links), installed into fresh venvs, and
`slipstep run`, `reproduce --quick`, `study stability --quick`, `sweep`, `keys`, `new` and the
Python API run from a folder outside the repository, with nothing of the checkout on the path.

Two venvs, the two ways README "pip" describes:
- plain (`python3 -m venv`): pip pulls every dependency from PyPI, numpy unpinned (today a
  numpy 2): the commands and the API run there;
- beside Debian's dolfinx (`--system-site-packages`, Debian's h5py registered for pip by
  ci/debian-h5py.sh, extra `debian-dolfinx`): pip keeps Debian's numpy 1.24.2 and h5py (the
  HDF5 dolfinx uses), dolfinx imports in either order with h5py, and `slipstep crosscheck`
  runs.

Needs PyPI (as `make` does for .venv): without it the venv tests are skipped, saying so; pip's
cache makes a second run quick.
"""

from __future__ import annotations

import csv
import json
import math
import os
import re
import shutil
import subprocess
import sys
import textwrap
import tomllib
import zipfile
from pathlib import Path

import pytest

from conftest import ROOT

DATA = ROOT / "py" / "slipstep" / "data"
SYSTEM_PYTHON = "/usr/bin/python3"  # Debian's: the one python3-dolfinx belongs to


# --------------------------------------------------------------------------- package data
@pytest.mark.parametrize("kind", ["cases", "studies"])
def test_every_case_and_study_is_shipped(kind):
    """py/slipstep/data/<kind>/x.toml is a link to <kind>/x.toml for every file there (one copy
    in git, the wheel gets the file): a new case without its link fails here."""
    files = sorted(p.name for p in (ROOT / kind).glob("*.toml"))
    links = sorted(p.name for p in (DATA / kind).glob("*.toml"))
    missing = sorted(set(files) - set(links))
    assert not missing, (
        f"not shipped in the wheel: {missing}; link each: cd {DATA / kind} "
        f"&& ln -s ../../../../{kind}/NAME.toml"
    )
    assert links == files
    for name in links:
        link = DATA / kind / name
        assert link.is_symlink(), f"{link} must be a link, not a second copy"
        assert link.resolve() == (ROOT / kind / name).resolve(), link


# --------------------------------------------------------------------------- the wheel
def _env(**extra) -> dict:
    """The environment of a user outside the checkout: no PYTHONPATH, no pip constraint (a
    user has no ci/constraints.txt), cargo on PATH for maturin."""
    env = {
        k: v
        for k, v in os.environ.items()
        if k not in ("PYTHONPATH", "PIP_CONSTRAINT", "VIRTUAL_ENV")
    }
    env["PATH"] = os.pathsep.join([str(Path.home() / ".cargo" / "bin"), env.get("PATH", "")])
    env["MPLBACKEND"] = "Agg"
    env.update(extra)
    return env


@pytest.fixture(scope="module")
def pypi(tmp_path_factory) -> None:
    """Skip (with pip's reason) when pip cannot reach its package index: the venvs need it."""
    probe = subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "download",
            "--no-deps",
            "--no-cache-dir",
            "--timeout",
            "15",
            "--retries",
            "1",
            "-d",
            tmp_path_factory.mktemp("probe"),
            "tqdm",
        ],
        env=_env(),
        capture_output=True,
        text=True,
        timeout=120,
    )
    if probe.returncode:
        why = (probe.stderr.strip().splitlines() or ["no answer"])[-1]
        pytest.skip(
            f"pip's package index (PyPI) is unreachable, the wheel's venvs cannot be "
            f"made: {why}"
        )


def _run(args, cwd, timeout=600, **env) -> subprocess.CompletedProcess:
    proc = subprocess.run(
        [str(a) for a in args],
        cwd=cwd,
        env=_env(**env),
        capture_output=True,
        text=True,
        timeout=timeout,
    )
    assert proc.returncode == 0, f"{args}: exit {proc.returncode}\n{proc.stderr[-3000:]}"
    return proc


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    maturin = shutil.which("maturin") or str(Path(sys.executable).parent / "maturin")
    out = tmp_path_factory.mktemp("wheel")
    _run([maturin, "build", "--release", "--out", out], cwd=ROOT, timeout=1800)
    (found,) = out.glob("slipstep-*.whl")
    return found


@pytest.fixture(scope="module")
def plain_venv(pypi, wheel, tmp_path_factory) -> Path:
    venv = tmp_path_factory.mktemp("venv") / "plain"
    _run([SYSTEM_PYTHON, "-m", "venv", venv], cwd=venv.parent)
    _run([venv / "bin" / "pip", "install", "-q", wheel], cwd=venv.parent, timeout=1200)
    return venv


@pytest.fixture(scope="module")
def outside(tmp_path_factory) -> Path:
    """A working folder that is not the checkout (nor inside it)."""
    where = tmp_path_factory.mktemp("elsewhere")
    assert ROOT not in where.resolve().parents
    return where


def test_the_wheel_holds_the_cases_and_studies_as_files(wheel):
    with zipfile.ZipFile(wheel) as z:
        for kind in ("cases", "studies"):
            for path in (ROOT / kind).glob("*.toml"):
                assert z.read(f"slipstep/data/{kind}/{path.name}") == path.read_bytes(), path
        metadata = z.read(next(n for n in z.namelist() if n.endswith("METADATA"))).decode()
    for dep in ("numpy", "meshio", "h5py", "matplotlib", "gmsh", "tqdm"):
        assert f"Requires-Dist: {dep}\n" in metadata, dep
    # the extras README names: numpy kept at Debian's beside dolfinx; ipywidgets for a
    # progress widget in notebooks
    for dep, extra in (("numpy==1.24.2", "debian-dolfinx"), ("ipywidgets", "notebook")):
        assert re.search(
            rf"^Requires-Dist: {re.escape(dep)} ?; extra == '{extra}'$", metadata, re.M
        ), (
            dep,
            extra,
        )


def test_the_wheel_and_the_command_say_the_cargo_version(wheel, plain_venv, outside):
    want = tomllib.loads((ROOT / "Cargo.toml").read_text())["workspace"]["package"]["version"]
    assert wheel.name.startswith(f"slipstep-{want}-")
    got = _run([plain_venv / "bin" / "slipstep", "--version"], cwd=outside).stdout
    assert got == f"slipstep {want}\n"


def test_keys_and_new_from_anywhere(plain_venv, outside):
    """The key reference --help points to is in the wheel, and a shipped case copies out."""
    bin_ = plain_venv / "bin"
    keys = _run([bin_ / "slipstep", "keys", "contact"], cwd=outside).stdout
    assert '[contact] kind = "rigid_circle"' in keys and "radius" in keys
    _run([bin_ / "slipstep", "new", "ball", "--from", "hertz_sphere"], cwd=outside)
    checked = _run([bin_ / "slipstep", "check", "ball.toml"], cwd=outside).stdout
    assert checked.startswith("ball: ")


def test_run_from_anywhere(plain_venv, outside):
    """`slipstep run` (the built-in case) and a shipped case by name, from a plain venv."""
    bin_ = plain_venv / "bin"
    _run(
        [bin_ / "slipstep", "run", "--quiet", "--set", "mesh.h_contact=0.1", "--out", "hertz"],
        cwd=outside,
    )
    s = json.loads((outside / "hertz" / "summary.json").read_text())
    # Hertz a: within one node spacing h of the closed form (tests/physics/test_hertz.py)
    assert abs(s["contact_half_width"] - s["hertz"]["a_hertz"]) <= 0.1
    assert {"contact_interface.png", "results.xdmf", "events.csv"} <= {
        p.name for p in (outside / "hertz").iterdir()
    }
    listed = _run([bin_ / "slipstep", "list"], cwd=outside).stdout
    assert "hertz_load_unload" in listed and "fig10_onset_of_yield" in listed
    _run([bin_ / "slipstep", "run", "two_blocks", "--quiet", "--out", "tb"], cwd=outside)
    assert json.loads((outside / "tb" / "summary.json").read_text())["case"] == "two_blocks"


def test_reproduce_quick_from_anywhere(plain_venv, outside):
    """The paper reproduction from the shipped cases and study; its required checks (the
    paper's qualitative claims, tests/studies/test_reproduce.py) hold there too."""
    _run(
        [plain_venv / "bin" / "slipstep", "reproduce", "--quick", "--out", "rq"],
        cwd=outside,
        timeout=1200,
    )
    numbers = json.loads((outside / "rq" / "reproduce.json").read_text())
    failed = [k for k, c in numbers["checks"].items() if c["required"] and not c["pass"]]
    assert not failed, failed
    assert (outside / "rq" / "report.md").exists() and (outside / "rq" / "table1.png").exists()


def test_study_stability_quick_from_anywhere(plain_venv, outside):
    _run(
        [plain_venv / "bin" / "slipstep", "study", "stability", "--quick", "--out", "st"],
        cwd=outside,
        timeout=1200,
    )
    with open(outside / "st" / "stability.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert rows and all(r["status"] != "error" for r in rows), rows
    assert (outside / "st" / "report.md").exists()


def test_sweep_a_shipped_study_from_anywhere(plain_venv, outside):
    """Fig. 10's study by name: 11 friction coefficients, each to its first yield; the onset
    load at mu = 0.5 below the frictionless one (the paper's claim)."""
    _run(
        [
            plain_venv / "bin" / "slipstep",
            "sweep",
            "fig10_onset_of_yield",
            "--quiet",
            "--set",
            "mesh.h_contact=0.2",
            "--out",
            "sw",
            "--workers",
            "2",
        ],
        cwd=outside,
    )
    with open(outside / "sw" / "summaries.csv") as fh:
        rows = {float(r["contact.mu"]): r for r in csv.DictReader(fh)}
    assert len(rows) == 11
    assert float(rows[0.5]["first_yield_load_fraction"]) < float(
        rows[0.0]["first_yield_load_fraction"]
    )


API_SCRIPT = textwrap.dedent("""
    import json, sys, slipstep
    r = slipstep.run("two_blocks", progress=False, overrides=["output.snapshots=[0.5, 1.0]"])
    f = r.fields(0.5)
    m = r.to_meshio(1.0)
    print(json.dumps({"file": slipstep.__file__, "completed": r.completed,
                      "times": list(r.times), "n_u": len(f["u"]), "n_points": len(m.points),
                      "cell_data": sorted(m.cell_data), "events": len(r.events),
                      "numpy": __import__("numpy").__version__}))
""")


def test_the_api_from_anywhere(plain_venv, outside):
    got = json.loads(
        _run([plain_venv / "bin" / "python", "-c", API_SCRIPT], cwd=outside)
        .stdout.strip()
        .splitlines()[-1]
    )
    assert got["file"].startswith(str(plain_venv)), got["file"]  # the wheel, not the checkout
    assert got["completed"] and got["times"] == [0.5, 1.0] and got["n_u"] == got["n_points"]
    assert "body" in got["cell_data"] and got["events"] > 0


def _system_venv(wheel, where: Path, register_h5py: bool) -> Path:
    """A --system-site-packages venv (it sees Debian's dolfinx) with the wheel installed with
    the extra debian-dolfinx, Debian's h5py registered for pip first or not."""
    probe = subprocess.run([SYSTEM_PYTHON, "-c", "import dolfinx"], capture_output=True)
    if probe.returncode:
        pytest.skip("Debian's python3-dolfinx is not installed")
    venv = where / "system"
    _run([SYSTEM_PYTHON, "-m", "venv", "--system-site-packages", venv], cwd=where)
    if register_h5py:
        _run([ROOT / "ci" / "debian-h5py.sh", venv], cwd=where)
    _run(
        [venv / "bin" / "pip", "install", "-q", f"{wheel}[debian-dolfinx]"], cwd=where, timeout=1200
    )
    return venv


@pytest.fixture(scope="module")
def debian_venv(pypi, wheel, tmp_path_factory) -> Path:
    """README's route beside Debian's dolfinx: Debian's h5py registered (ci/debian-h5py.sh)."""
    return _system_venv(wheel, tmp_path_factory.mktemp("venv"), register_h5py=True)


@pytest.mark.parametrize("order", ["numpy, h5py, dolfinx", "numpy, dolfinx, h5py"])
def test_beside_debian_dolfinx_numpy_and_h5py_stay_debian(debian_venv, order):
    """numpy stays 1.24.2 (a newer one would shadow it and break petsc4py) and h5py is Debian's
    (its HDF5 is dolfinx's), so dolfinx and h5py import in either order: with PyPI's h5py,
    dolfinx first made `import h5py` fail ("Not a datatype")."""
    code = (
        f"import {order}, slipstep; " "print(numpy.__version__, h5py.__file__, slipstep.__file__)"
    )
    out = _run([debian_venv / "bin" / "python", "-c", code], cwd=debian_venv.parent).stdout
    numpy_version, h5py_file, slipstep_file = out.split()
    assert numpy_version == "1.24.2"
    assert h5py_file.startswith("/usr/lib/python3/dist-packages/"), h5py_file
    assert slipstep_file.startswith(str(debian_venv))


def _hill_plastic_radius(p: float, a: float, b: float, sy: float) -> float:
    """Hill's plastic radius c of a thick cylinder (von Mises, plane strain, perfectly
    plastic): p = k [2 ln(c/a) + 1 - c^2/b^2], k = Sy/sqrt(3), by bisection on [a, b] (the
    right side grows with c there)."""
    k = sy / 3**0.5
    lo, hi = a, b
    for _ in range(100):
        c = 0.5 * (lo + hi)
        lo, hi = (c, hi) if k * (2 * math.log(c / a) + 1 - c * c / (b * b)) < p else (lo, c)
    return 0.5 * (lo + hi)


def test_crosscheck_beside_debian_dolfinx(debian_venv, outside):
    """`slipstep crosscheck thick_cylinder` (README's example) from the wheel: it runs, and
    slipstep's and dolfinx's plastic radii are Hill's within one element at the bore (h = 2 mm
    on this coarse mesh; the radius is read off element centroids)."""
    _run(
        [
            debian_venv / "bin" / "slipstep",
            "crosscheck",
            "thick_cylinder",
            "--set",
            "mesh.h=2.0",
            "--steps",
            "5",
            "--out",
            "tc",
        ],
        cwd=outside,
    )
    report = json.loads((outside / "tc" / "crosscheck.json").read_text())
    c = _hill_plastic_radius(175.0, 10.0, 20.0, 250.0)  # cases/thick_cylinder.toml
    for solver in ("slipstep", "dolfinx"):
        assert abs(report["hill"][solver]["plastic_radius"] - c) <= 2.0, (solver, c)


def test_crosscheck_names_the_fix_beside_pypis_h5py(pypi, wheel, tmp_path):
    """Without ci/debian-h5py.sh pip installs PyPI's h5py (its own HDF5) into the venv;
    `slipstep crosscheck` then says so in one line with the fix, instead of dying in
    `import h5py` after dolfinx with a traceback."""
    venv = _system_venv(wheel, tmp_path, register_h5py=False)
    h5py = _run(
        [venv / "bin" / "python", "-c", "import h5py; print(h5py.__file__)"], cwd=tmp_path
    ).stdout.strip()
    assert h5py.startswith(str(venv)), h5py  # the route this guards
    proc = subprocess.run(
        [venv / "bin" / "slipstep", "crosscheck", "thick_cylinder"],
        cwd=tmp_path,
        env=_env(),
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 2 and len(proc.stderr.strip().splitlines()) == 1, proc.stderr
    assert "brings its own HDF5" in proc.stderr and "pip uninstall h5py" in proc.stderr
