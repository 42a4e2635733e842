"""The 3D GetFEM peer of `make bench` (bench/getfem_hertz_3d.py) solves slipstep's own 3D Hertz
scene (cases/hertz_sphere_3d.toml) on the same mesh, read from the .msh slipstep's scene is
written to.  GetFEM (Debian python3-getfem) is installed by `make test` (ci/apt-packages.txt):
on a machine without it this skips, and the skip fails the run (tests/conftest.py, ENFORCED).

Frictionless and elastic, the two codes solve the *same* discrete problem: linear tetrahedra
(exact stiffness), the same symmetry rows, the same consistent load on the cut (A/3 per corner,
the same q), nodal contact of the same candidates with the flat z = 0.  It has one solution, so
GetFEM's Newton (Alart–Curnier, one load step) and slipstep's events must give the same nodal
contact forces.  Tolerance 1e-6 of the largest: GetFEM stops at a relative residual of 1e-8
and, once its active set is right, its last update solves the linear system to round-off; 1e-6
leaves a factor 100 for the conditioning and is far below any modelling difference.

Mesh: h_contact = 0.05 mm (6.9k DOFs, 30 nodes in contact; GetFEM takes ~3 s).
"""

from __future__ import annotations

import sys

import numpy as np
import pytest
from conftest import ROOT, needs_gmsh

import slipstep

pytest.importorskip("getfem")
sys.path.insert(0, str(ROOT / "bench"))
import getfem_hertz_3d  # noqa: E402

H = 0.05


@needs_gmsh
def test_frictionless_contact_forces_are_those_of_slipstep(tmp_path):
    result = slipstep.run(
        getfem_hertz_3d.CASE,
        overrides=[f"mesh.h_contact={H}", "output.snapshots=[1.0]"],
        progress=False,
    )
    spec = getfem_hertz_3d.scene_spec(H, "tuned", tmp_path / "scene.msh")
    # the same candidates, in the same order: slipstep's pairs
    assert np.array_equal(np.asarray(spec["candidates"]), result.scene.pair_xy)
    peer = getfem_hertz_3d.one(spec)
    assert peer["status"] == "ok"
    mine = np.asarray(result.raw["snapshots"][-1]["lambda_n"])
    theirs = np.asarray(peer["force"])
    assert (mine > 0).sum() >= 20  # a contact of many nodes, not a trivial one
    assert np.abs(theirs - mine).max() <= 1e-6 * mine.max()
