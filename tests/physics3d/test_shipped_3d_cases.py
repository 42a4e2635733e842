"""Every shipped 3D case (conftest.shipped_cases(3)) runs, and a closed-form test of this folder
runs it.

1. Each case runs here as shipped but coarsened (every body's h_contact, or a shell's h, times
   COARSER; snapshots at its stage ends), as tests/physics/test_balance.py runs every 2D case:
   it completes, and at every snapshot the stresses balance the loads, supports and contact
   forces (recomputed from the arrays, 1e-9), no pair pulls (lambda_n >= -1e-9 of the largest)
   or penetrates (gap >= -1e-8 of the largest displacement, the round-off of
   test_zeno_chain_3d.py), and the contact forces lie in Coulomb's cone at each pair's mu (the
   facet of slipping pairs up to 1/cos(slip_turn)), to 1e-9 of the largest lambda_n.
2. A case's file name is a string in the code of a test module here (a comment or a docstring
   does not count: the module's syntax tree is read), so a new shipped 3D case without a
   closed-form test fails.
"""

from __future__ import annotations

import ast
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
from conftest import needs_gmsh, shipped_cases
from physics import EQUILIBRIUM_TOL, equilibrium_residual

import slipstep

COARSER = 4.0
CASES_3D = shipped_cases(3)


def coarsened(path: Path) -> list[str]:
    data = tomllib.loads(path.read_text())
    out = []
    for body in data["body"]:
        for key in ("h_contact", "h"):
            if key in body["mesh"]:
                out.append(f"body.{body['name']}.mesh.{key}={body['mesh'][key] * COARSER}")
    ends = [float(k + 1) for k in range(len(data.get("stage", [])) or 1)]
    return [*out, f"output.snapshots={ends}"]


@needs_gmsh
@pytest.mark.parametrize("case", CASES_3D, ids=[p.stem for p in CASES_3D])
def test_every_shipped_3d_case_runs_balanced_and_admissible(case):
    result = slipstep.run(
        case, overrides=coarsened(case), progress=False, figures=False, xdmf=False
    )
    assert result.completed, result.stop
    model = result.scene.model
    turn = result.case.data["solver"]["slip_turn"]
    mu = np.asarray(model["pairs"]["mu"], dtype=float)
    assert result.raw["snapshots"]
    for snap in result.raw["snapshots"]:
        assert equilibrium_residual(model, snap) <= EQUILIBRIUM_TOL, snap["t"]
        if not len(mu):
            continue
        ln = np.asarray(snap["lambda_n"])
        lt = np.linalg.norm(np.asarray(snap["lambda_t"]).reshape(len(ln), -1), axis=1)
        force = 1e-9 * max(ln.max(), 1e-300)
        assert ln.min() >= -force, snap["t"]
        assert np.asarray(snap["gap"]).min() >= -1e-8 * np.abs(snap["u"]).max(), snap["t"]
        capacity = mu * ln / np.where(snap["status"] == 2, math.cos(turn), 1.0)
        assert (lt <= capacity + force).all(), snap["t"]


def code_strings(path: Path) -> set[str]:
    """The string constants of a module's code, its docstrings left out."""
    tree = ast.parse(path.read_text())
    docstrings = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.FunctionDef, ast.ClassDef, ast.AsyncFunctionDef)):
            body = node.body
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
                docstrings.add(id(body[0].value))
    return {
        n.value
        for n in ast.walk(tree)
        if isinstance(n, ast.Constant) and isinstance(n.value, str) and id(n) not in docstrings
    }


def test_every_shipped_3d_case_has_a_closed_form_test_that_runs_it(tmp_path):
    here = Path(__file__)
    strings = set().union(*(code_strings(p) for p in here.parent.glob("test_*.py") if p != here))
    untested = [p.name for p in CASES_3D if p.name not in strings]
    assert not untested, f"3D cases no test in {here.parent} runs: {untested}"
    # a name in a comment or a docstring is not a test that runs the case; in code it is
    probe = tmp_path / "test_probe.py"
    probe.write_text(
        '"""Runs a.toml."""\n# b.toml\ndef test():\n    """c.toml"""\n    run("d.toml")\n'
    )
    assert code_strings(probe) == {"d.toml"}
