"""A wheel that runs anywhere (issue 17, point 5): the wheel is built from this checkout
(`maturin build --release`, reusing target/, so it only packs and re-links), installed into
fresh venvs, and `slipstep run`, `reproduce --quick`, `study stability --quick`, `sweep` and
the Python API run from a folder outside the repository, with nothing of the checkout on the
path.

Two venvs, the two ways README "pip" describes:
- plain (`python3 -m venv`): pip pulls every dependency from PyPI, numpy unpinned (today a
  numpy 2): the four commands and the API run there;
- beside Debian's dolfinx (`--system-site-packages`, extra `debian-dolfinx`): pip must keep
  Debian's numpy 1.24.2, so dolfinx still imports.

Needs PyPI (as `make` does for .venv); pip's cache makes a second run quick.
"""

from __future__ import annotations

import csv
import json
import os
import shutil
import subprocess
import sys
import textwrap
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
    assert not missing, (f"not shipped in the wheel: {missing}; link each: cd {DATA / kind} "
                         f"&& ln -s ../../../../{kind}/NAME.toml")
    assert links == files
    for name in links:
        link = DATA / kind / name
        assert link.is_symlink(), f"{link} must be a link, not a second copy"
        assert link.resolve() == (ROOT / kind / name).resolve(), link


# --------------------------------------------------------------------------- the wheel
def _env(**extra) -> dict:
    """The environment of a user outside the checkout: no PYTHONPATH, no pip constraint (a
    user has no ci/constraints.txt), cargo on PATH for maturin."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "PIP_CONSTRAINT", "VIRTUAL_ENV")}
    env["PATH"] = os.pathsep.join([str(Path.home() / ".cargo" / "bin"), env.get("PATH", "")])
    env["MPLBACKEND"] = "Agg"
    env.update(extra)
    return env


def _run(args, cwd, timeout=600, **env) -> subprocess.CompletedProcess:
    proc = subprocess.run([str(a) for a in args], cwd=cwd, env=_env(**env), capture_output=True,
                          text=True, timeout=timeout)
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
def plain_venv(wheel, tmp_path_factory) -> Path:
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


def test_run_from_anywhere(plain_venv, outside):
    """`slipstep run` (the built-in case) and a shipped case by name, from a plain venv."""
    bin_ = plain_venv / "bin"
    _run([bin_ / "slipstep", "run", "--quiet", "--set", "mesh.h_contact=0.1", "--out", "hertz"],
         cwd=outside)
    s = json.loads((outside / "hertz" / "summary.json").read_text())
    # Hertz a: within one node spacing h of the closed form (tests/test_hertz.py)
    assert abs(s["contact_half_width"] - s["hertz"]["a_hertz"]) <= 0.1
    assert {"contact_interface.png", "results.xdmf", "events.csv"} <= {
        p.name for p in (outside / "hertz").iterdir()}
    listed = _run([bin_ / "slipstep", "list"], cwd=outside).stdout
    assert "hertz_load_unload" in listed and "fig10_onset_of_yield" in listed
    _run([bin_ / "slipstep", "run", "two_blocks", "--quiet", "--out", "tb"], cwd=outside)
    assert json.loads((outside / "tb" / "summary.json").read_text())["case"] == "two_blocks"


def test_reproduce_quick_from_anywhere(plain_venv, outside):
    """The paper reproduction from the shipped cases and study; its required checks (the
    paper's qualitative claims, tests/test_reproduce.py) hold there too."""
    _run([plain_venv / "bin" / "slipstep", "reproduce", "--quick", "--out", "rq"], cwd=outside,
         timeout=1200)
    numbers = json.loads((outside / "rq" / "reproduce.json").read_text())
    failed = [k for k, c in numbers["checks"].items() if c["required"] and not c["pass"]]
    assert not failed, failed
    assert (outside / "rq" / "report.md").exists() and (outside / "rq" / "table1.png").exists()


def test_study_stability_quick_from_anywhere(plain_venv, outside):
    _run([plain_venv / "bin" / "slipstep", "study", "stability", "--quick", "--out", "st"],
         cwd=outside, timeout=1200)
    with open(outside / "st" / "stability.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert rows and all(r["status"] != "error" for r in rows), rows
    assert (outside / "st" / "report.md").exists()


def test_sweep_a_shipped_study_from_anywhere(plain_venv, outside):
    """Fig. 10's study by name: 11 friction coefficients, each to its first yield; the onset
    load at mu = 0.5 below the frictionless one (the paper's claim)."""
    _run([plain_venv / "bin" / "slipstep", "sweep", "fig10_onset_of_yield", "--quiet", "--set",
          "mesh.h_contact=0.2", "--out", "sw", "--workers", "2"], cwd=outside)
    with open(outside / "sw" / "summaries.csv") as fh:
        rows = {float(r["contact.mu"]): r for r in csv.DictReader(fh)}
    assert len(rows) == 11
    assert float(rows[0.5]["first_yield_load_fraction"]) < float(rows[0.0]["first_yield_load_fraction"])


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
    got = json.loads(_run([plain_venv / "bin" / "python", "-c", API_SCRIPT],
                          cwd=outside).stdout.strip().splitlines()[-1])
    assert got["file"].startswith(str(plain_venv)), got["file"]  # the wheel, not the checkout
    assert got["completed"] and got["times"] == [0.5, 1.0] and got["n_u"] == got["n_points"]
    assert "body" in got["cell_data"] and got["events"] > 0


def test_beside_debian_dolfinx_numpy_stays(wheel, tmp_path_factory):
    """A venv that sees Debian's dolfinx: the extra debian-dolfinx keeps numpy 1.24.2 (a
    newer one in the venv would shadow it and break petsc4py), and dolfinx still imports."""
    probe = subprocess.run([SYSTEM_PYTHON, "-c", "import dolfinx"], capture_output=True)
    if probe.returncode:
        pytest.skip("Debian's python3-dolfinx is not installed")
    venv = tmp_path_factory.mktemp("venv") / "system"
    _run([SYSTEM_PYTHON, "-m", "venv", "--system-site-packages", venv], cwd=venv.parent)
    _run([venv / "bin" / "pip", "install", "-q", f"{wheel}[debian-dolfinx]"], cwd=venv.parent,
         timeout=1200)
    code = ("import numpy, dolfinx, slipstep; "
            "print(numpy.__version__, slipstep.__file__)")
    out = _run([venv / "bin" / "python", "-c", code], cwd=venv.parent).stdout.split()
    assert out[0] == "1.24.2" and out[1].startswith(str(venv))
