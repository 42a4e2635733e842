"""The GetFEM peer of `make bench` (bench/getfem_hertz.py) solves slipstep's Hertz scene.

GetFEM (Debian python3-getfem) is installed by `make test` (ci/apt-packages.txt): without it
these tests skip, and the skip fails the run (tests/conftest.py, ENFORCED).
Both codes read the same mesh (slipstep's generator, written by slipstep.mesh.triangle_files.write_msh), so:

* frictionless and elastic, the two solve the *same* discrete problem (CST stiffness, nodal
  contact of the same candidates with the flat, the same nodal load vector), which has one
  solution: GetFEM's Newton (Alart–Curnier) and slipstep's events must give the same nodal
  contact forces.  Tolerance 1e-6 of p0: GetFEM stops at a relative residual of 1e-8
  (MAX_RES) and, once its active set is right, its last update solves the linear system to
  round-off; 1e-6 leaves a factor 100 for the conditioning and is far below any modelling
  difference (the load-stepping differences of the frictional runs are 1e-3).
* with friction (μ = 0.3), the central stick zone depends on the loading path; slipstep's is
  checked against Spence's self-similar solution (tests/physics/test_spence.py).  GetFEM's stick edge,
  with N load steps and the slip measured from the previous step, must match it to one node
  spacing h (the edge lies between two nodes in both codes) plus the distance the contact edge
  moves in one load step (a/(2N) at the end, a ∝ √f).  This pins the sign of the incremental
  slip in the GetFEM model: measured from the start of the run instead (or with the opposite
  sign) the stick zone shrinks to c/a ≈ 0.3 instead of 0.69.
"""

from __future__ import annotations

import sys

import numpy as np
import pytest
from conftest import ROOT, needs_gmsh

from slipstep import prepare, solve
from slipstep.measures.contact_edges import contact_profile
from slipstep.output.summary import summarize

pytest.importorskip("getfem")
sys.path.insert(0, str(ROOT / "bench"))
import getfem_hertz  # noqa: E402

H = 0.1  # h_contact, mm: ~4k DOFs, a/h ≈ 14 nodes in contact


def run_both(tmp_path, overrides, steps):
    """slipstep and GetFEM on the same mesh: (slipstep summary, its profile, GetFEM record)."""
    scene = prepare(
        getfem_hertz.CASE, overrides=[*overrides, f"mesh.h_contact={H}", "output.snapshots=[1.0]"]
    )
    result = solve(scene)
    spec = getfem_hertz.scene_spec(H, steps, overrides, msh=tmp_path / "scene.msh")
    return (
        summarize(scene, result),
        contact_profile(scene, result["snapshots"][-1]),
        getfem_hertz.one(spec),
    )


@needs_gmsh
def test_frictionless_elastic_contact_forces_are_those_of_slipstep(tmp_path):
    summary, profile, peer = run_both(tmp_path, ["contact.mu=0"], steps=1)
    assert peer["status"] == "ok"
    assert np.array_equal(peer["x"], profile["x"])  # the same candidates, in the same order
    p0 = summary["peak_pressure"]
    assert np.abs(np.array(peer["pressure"]) - profile["pressure"]).max() <= 1e-6 * p0
    assert peer["total_normal_force"] == pytest.approx(500.0, rel=1e-6)  # P/2 on the quarter


@needs_gmsh
def test_frictional_stick_zone_is_that_of_slipstep(tmp_path):
    mu, steps = 0.3, 20
    summary, profile, peer = run_both(tmp_path, [f"contact.mu={mu}"], steps)
    assert peer["status"] == "ok"
    x = np.array(peer["x"])
    p, t = np.array(peer["pressure"]), np.array(peer["tangential"])
    stick = (p > 0) & (np.abs(t) < mu * p * (1 - 1e-9))  # inside the friction cone
    slip = (p > 0) & ~stick
    assert stick.any() and slip.any()
    c_peer = 0.5 * (x[stick].max() + x[slip & (x > x[stick].max())].min())  # as slipstep's c
    a = summary["contact_half_width"]
    assert abs(c_peer - summary["stick_half_width"]) <= H + a / (2 * steps)
