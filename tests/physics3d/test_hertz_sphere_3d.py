"""Hertz's sphere in 3D (cases/hertz_sphere_3d.toml: the eighth of an elastic sphere on a rigid
flat, frictionless) through ``slipstep.run``, against the closed forms (Johnson, Contact
Mechanics §3.4, §4.2) and against slipstep's axisymmetric run of the same scene
(cases/hertz_sphere.toml) on a matching mesh:

    a = (3 P R / (4 E*))^(1/3) = 0.24455 mm,  p0 = 3 P / (2 pi a^2) = 239.51 MPa,
    p(r) = p0 sqrt(1 - r^2/a^2),  delta = a^2 / R,  E* = E / (1 - nu^2).

CI mesh: h_contact = H = 0.02 mm near the contact point (a/h = 12.2, the case's own; the
bench's 0.0125 is finer), the fine zone of radius 0.4 mm = 1.6 a.  Tolerances, from h/a alone:
- the contact radius is the equivalent radius of the closed nodes' tributary areas: the true
  edge lies between the outermost closed node and the first open one, so the area's radius is
  within one node spacing h of a (the case file's bound);
- p0 = 3P/(2 pi a^2): an error of h/2 in the contact radius is h/a in p0; the peak nodal
  pressure is held to that (8 % here), the pressure profile inside 0.8 a to h/(2a) rms;
- the approach delta, the one number here that goes with E at a given load (delta ~ E*^(-2/3):
  E off by 5 % moves it by 3.2 %, where a moves by 1.6 % and p0 by 3.3 %, both inside their
  node-spacing bounds): measured as in tests/physics/test_axisymmetric_hertz.py, the shortening
  of the axis from the contact point to the depth d a (interpolated in the tetrahedra) plus
  Huber's half-space shortening below it, at d = 1 and 1.5 (inside the fine zone).  A
  displacement of linear elements converges at second order: within (h/a)^2 = 0.67 % of
  delta.  The test runs the scene with E x 1.05 and E x 0.95 too (the same mesh) and requires
  the check to reject both (measured -1.5 % and +1.3 % at 1.5 a, the nominal run -0.16 %);
- the total normal force and the equilibrium of the stresses with the load and the contact
  forces are exact whatever the mesh: to the engine's equilibrium tolerance (1e-9).
Against the axisymmetric run on a mesh of the same h_contact: each contact radius within its
own bound of a gives |a_3D - a_axi| <= h, likewise p0 within h/a.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import CASES, needs_gmsh
from physics import EQUILIBRIUM_TOL, equilibrium_residual
from space3d import hertz_approach_errors

import slipstep
from slipstep.measures.contact_edges import contact_profile

CASE = CASES / "hertz_sphere_3d.toml"
AXI = CASES / "hertz_sphere.toml"
H = 0.02
P, R, E, NU = 30.0, 50.0, 70000.0, 0.3
E_STAR = E / (1 - NU**2)
A = (3 * P * R / (4 * E_STAR)) ** (1 / 3)
P0 = 3 * P / (2 * math.pi * A**2)
OUT = ["output.snapshots=[1.0]"]
DEPTHS = (1.0, 1.5)  # z/a where the approach is measured: inside the fine zone (1.6 a)
MUTANTS = (1.05, 0.95)  # E x these: runs the approach check must reject


@pytest.fixture(scope="module")
def run3d():
    pytest.importorskip("gmsh")
    return slipstep.run(CASE, overrides=[f"mesh.h_contact={H}", *OUT], progress=False)


@pytest.fixture(scope="module")
def mutants():
    pytest.importorskip("gmsh")
    return {
        k: slipstep.run(
            CASE, overrides=[f"mesh.h_contact={H}", f"material.E={E * k}", *OUT], progress=False
        )
        for k in MUTANTS
    }


def approach_errors(result) -> list[float]:
    """The approach's relative errors at DEPTHS against Hertz for the nominal E (P = 30 N)."""
    snap = result.raw["snapshots"][-1]
    return hertz_approach_errors(
        result.scene.nodes,
        result.scene.tetrahedra,
        snap["u"],
        P,
        R,
        E,
        NU,
        origin=[0.0, 0.0, 0.0],
        inward=[0.0, 0.0, 1.0],
        depths=DEPTHS,
    )


def approach_within_bound(result) -> bool:
    return all(abs(e) <= (H / A) ** 2 for e in approach_errors(result))


@pytest.fixture(scope="module")
def run_axi():
    return slipstep.run(AXI, overrides=[f"mesh.h_contact={H}", *OUT], progress=False)


@needs_gmsh
def test_the_contact_carries_the_load_and_the_stresses_balance(run3d):
    assert run3d.completed
    snap = run3d.raw["snapshots"][-1]
    assert snap["load_fraction"] == 1.0
    # the eighth carries P/4: its lambda_n sum, from the arrays, and the summary's full one
    assert math.isclose(4 * np.sum(snap["lambda_n"]), P, rel_tol=EQUILIBRIUM_TOL)
    assert math.isclose(run3d.summary["total_normal_force"], P, rel_tol=EQUILIBRIUM_TOL)
    assert equilibrium_residual(run3d.scene.model, snap) <= EQUILIBRIUM_TOL


@needs_gmsh
def test_contact_radius_and_peak_pressure_against_hertz(run3d):
    s = run3d.summary
    assert abs(s["contact_radius"] - A) <= H, (s["contact_radius"], A)
    assert abs(s["peak_pressure"] / P0 - 1) <= H / A, (s["peak_pressure"], P0)


@needs_gmsh
def test_approach_against_hertz(run3d):
    assert approach_within_bound(run3d), approach_errors(run3d)


@needs_gmsh
def test_the_approach_check_rejects_e_off_by_five_percent(mutants):
    for k, result in mutants.items():
        assert result.completed
        assert not approach_within_bound(result), (k, approach_errors(result))


@needs_gmsh
def test_pressure_profile_against_hertz(run3d):
    prof = run3d.profile()
    r = np.hypot(prof["x"], prof["y"])
    inside = r < 0.8 * A
    assert inside.sum() >= 10  # nodes enough for an rms
    dev = (prof["pressure"][inside] - P0 * np.sqrt(1 - (r[inside] / A) ** 2)) / P0
    assert math.sqrt(np.mean(dev**2)) <= H / (2 * A)
    # outside the contact (beyond a + h) every candidate is open
    assert (prof["status"][r > A + H] == 0).all()


@needs_gmsh
def test_the_same_scene_as_its_axisymmetric_run(run3d, run_axi):
    axi = run_axi.summary
    assert math.isclose(axi["total_normal_force"], P, rel_tol=EQUILIBRIUM_TOL)
    assert abs(run3d.summary["contact_radius"] - axi["contact_half_width"]) <= H
    assert abs(run3d.summary["peak_pressure"] / axi["peak_pressure"] - 1) <= H / A
    # the axisymmetric profile, interpolated at the 3D nodes' radii, within 0.8 a
    a_prof = contact_profile(run_axi.scene, run_axi.raw["snapshots"][-1])
    prof = run3d.profile()
    r = np.hypot(prof["x"], prof["y"])
    inside = r < 0.8 * A
    ref = np.interp(r[inside], a_prof["x"], a_prof["pressure"])
    assert math.sqrt(np.mean(((prof["pressure"][inside] - ref) / P0) ** 2)) <= H / A
