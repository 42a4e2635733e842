"""What `make test` installs cannot be skipped (tests/conftest.py: ENFORCED, enforce_skip).

- Each enforced dependency names where `make test` gets it, and that source is really on its
  list: a line of ci/requirements.txt (pip) or ci/apt-packages.txt (apt), or `make build`.
- On this machine every one of them is there (a missing one fails here even if no test names
  it in a skip), unless SLIPSTEP_ALLOW_MISSING lists it (the Makefile unsets that).
- The hook turns a skipped test report and a skipped module (collection) into failures when the
  reason names a missing enforced dependency, in each wording the suite uses (importorskip's,
  the skipif reasons of gmsh, pvpython, mpirun/petsc4py, dolfinx), and leaves other skips and
  xfails alone (PyPI unreachable; more MPI ranks wanted; a dependency that is present).
"""

from __future__ import annotations

import os

import pytest
from conftest import ALLOW_MISSING, ENFORCED, ROOT, available, enforce_skip


def listed(path) -> set[str]:
    """The package names of a requirements or apt list (comments, blank lines, version pins
    and markers dropped)."""
    names = set()
    for line in (ROOT / path).read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            names.add(line.split(";")[0].split("<")[0].split(">")[0].split("=")[0].strip())
    return names


def test_every_enforced_dependency_comes_from_a_list_make_test_installs():
    lists = {
        "pip": listed("ci/requirements.txt"),
        "apt": listed("ci/apt-packages.txt"),
        "make": {"build"},
    }
    for name, (kind, (where, package)) in ENFORCED.items():
        assert kind in ("module", "program"), name
        assert package in lists[where], f"{name}: {package} is not in the {where} list"
    # the getfem peers (issue 38: skipped by `make test` while GetFEM was the bench's alone)
    assert {"python3-getfem", "libopenblas0-pthread"} <= lists["apt"]


def test_every_enforced_dependency_is_present():
    allowed = {n.strip() for n in os.environ.get(ALLOW_MISSING, "").split(",") if n.strip()}
    missing = [n for n in ENFORCED if n not in allowed and not available(n)]
    assert not missing, f"missing what `make test` installs: {missing}"


REASONS = {  # the reasons the suite's skips give, by the dependency they name
    "getfem": "could not import 'getfem': No module named 'getfem'",
    "gmsh": "gmsh is not installed",
    "pvpython": "pvpython is not installed (Debian: apt-get install python3-paraview)",
    "petsc4py": "mpirun or petsc4py (Debian: python3-petsc4py) is not installed: the MUMPS "
    "factorization runs through PETSc under mpirun",
    "mpirun": "mpirun is not installed (Debian's openmpi-bin comes with dolfinx)",
    "mpi4py": "could not import 'mpi4py.futures': No module named 'mpi4py'",
    "dolfinx": "Debian's python3-dolfinx is not installed",
    "hypothesis": "could not import 'hypothesis': No module named 'hypothesis'",
}


def report(reason: str, when: str = "setup", **extra) -> pytest.TestReport:
    rep = pytest.TestReport(
        nodeid="t.py::t",
        location=("t.py", 0, "t"),
        keywords={},
        outcome="skipped",
        longrepr=("t.py", 1, f"Skipped: {reason}"),
        when=when,
    )
    for key, value in extra.items():
        setattr(rep, key, value)
    return rep


@pytest.mark.parametrize("name", sorted(REASONS))
def test_a_skip_for_a_missing_enforced_dependency_fails(name, monkeypatch):
    monkeypatch.delenv(ALLOW_MISSING, raising=False)
    rep = report(REASONS[name])
    enforce_skip(rep, is_available=lambda n: n != name)
    assert rep.failed and name in rep.longrepr
    # a module-level skip (pytest.importorskip at import) is a collection report
    col = pytest.CollectReport("t.py", "skipped", ("t.py", 1, f"Skipped: {REASONS[name]}"), [])
    enforce_skip(col, is_available=lambda n: n != name)
    assert col.failed
    # the same dependency present, or allowed missing: the skip stays a skip
    rep = report(REASONS[name])
    enforce_skip(rep, is_available=lambda n: True)
    assert rep.skipped
    monkeypatch.setenv(ALLOW_MISSING, f"other, {name}")
    rep = report(REASONS[name])
    enforce_skip(rep, is_available=lambda n: n != name)
    assert rep.skipped


@pytest.mark.parametrize(
    "reason",
    [
        "pip's package index (PyPI) is unreachable, the wheel's venvs cannot be built",
        "needs 4 MPI ranks, run under mpirun -n 4",  # names mpirun, which is there
    ],
)
def test_other_skips_stay_skips(reason, monkeypatch):
    monkeypatch.delenv(ALLOW_MISSING, raising=False)
    rep = report(reason)
    enforce_skip(rep, is_available=lambda n: n != "getfem")
    assert rep.skipped
    # an expected failure is no skip of a dependency either
    rep = report("could not import 'getfem'", when="call", wasxfail="known")
    enforce_skip(rep, is_available=lambda n: n != "getfem")
    assert rep.skipped
