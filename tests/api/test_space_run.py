"""A 3D scene meets an engine without dimension = 3 support: ``slipstep check`` validates and
meshes it, ``slipstep run`` and ``slipstep.run`` stop with one clear line (EngineMissing) and
write nothing.  Skipped once the engine solves 3D (then the closed-form tests of the shipped 3D
cases take over)."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest
from conftest import ROOT
from space3d import BOX

import slipstep
from slipstep.errors import EngineMissing
from slipstep.runner import engine_solves_3d

pytestmark = pytest.mark.skipif(engine_solves_3d(), reason="the engine solves 3D scenes")


def cli(*args, cwd):
    env = {**os.environ, "PYTHONPATH": str(ROOT / "py"), "MPLBACKEND": "Agg"}
    return subprocess.run([sys.executable, "-m", "slipstep", *map(str, args)], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=120)


def test_a_3d_case_is_checked_and_its_run_is_one_clear_line(tmp_path):
    case = tmp_path / "box3.toml"
    case.write_text(BOX + '[[bc]]\nbody = "b"\nface = "top"\npressure = 1.0\n')
    check = cli("check", case, cwd=tmp_path)
    assert check.returncode == 0, check.stderr
    # 5 x 3 x 3 grid nodes, 6 tetrahedra per cell, 3 dofs per node, the bottom's 15 x 3 fixed
    assert check.stdout.strip() == ("box3: 45 nodes, 96 elements, 135 dofs, 0 contact pairs, "
                                    "45 fixed dofs")
    run = cli("run", case, "--out", tmp_path / "out", cwd=tmp_path)
    assert run.returncode == 2
    assert run.stderr.strip().splitlines() == [
        f"slipstep: error: {case}: 3D scenes need an engine with dimension = 3 support, and "
        f"this slipstep._engine solves 2D models only: the case is valid and meshed (slipstep "
        f"check), its run waits for the 3D engine"]
    assert not (tmp_path / "out").exists()


def test_slipstep_run_raises_engine_missing_for_a_3d_case():
    with pytest.raises(EngineMissing, match="3D scenes need an engine with dimension = 3"):
        slipstep.run(slipstep.Case.from_toml(BOX + '[[bc]]\nbody = "b"\nface = "top"\n'
                                             'pressure = 1.0\n'), progress=False)
