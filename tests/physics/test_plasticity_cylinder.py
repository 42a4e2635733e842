"""Thick-walled cylinder under internal pressure (cases/thick_cylinder.toml) against the closed
forms: plane strain, von Mises, elastic-perfectly plastic (H' = 0), a bulk-only scene (no
contact: every event is a yield event).

a = 10, b = 20 mm, E = 200000 MPa, nu = 0.3, Sy = 250 MPa, k = Sy/sqrt(3), p = 175 MPa.

Elastic state (Lame, exact for the compressible material), per unit thickness:
    sigma_r = A - B/r^2, sigma_theta = A + B/r^2, sigma_z = 2 nu A,
    A = p a^2/(b^2 - a^2), B = p a^2 b^2/(b^2 - a^2)
    => sigma_e(r)^2 = 3 B^2/r^4 + (1 - 2 nu)^2 A^2, largest at the bore:
    first yield when sigma_e(a) = Sy, p_e = 108.07 MPa (Hill's incompressible k(1 - a^2/b^2)
    = 108.25 MPa).
Elastic-plastic (Hill, The Mathematical Theory of Plasticity, ch. V): the plastic zone
a <= r <= c with sigma_theta - sigma_r = 2k, and
    p = k [2 ln(c/a) + 1 - c^2/b^2].
Hill's solution takes sigma_z = (sigma_r + sigma_theta)/2 in the plastic zone (incompressible);
with nu = 0.3 sigma_z differs, so von Mises gives sigma_theta - sigma_r slightly below 2k (by
< 1 %, checked below) and the zone reaches slightly further than Hill's c: 14.491 mm instead of
14.423 at p = 175 MPa, from the converged 1D radial model (slipstep.fenicsx.radial, checked
here against Lame and, as nu -> 1/2, against Hill), the reference for the plastic radius.

Mesh (the shipped case): gmsh, h = 0.25 mm at the bore growing linearly to 0.8 mm at r = b,
2507 elements, 2656 dofs; ~1600 yield events (one per plastic element), each an increment
with its own factorization: ~4-5 s.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import CASES, needs_gmsh
from slipstep.measures import references
from physics import EQUILIBRIUM_TOL, worst_equilibrium

from slipstep import prepare, solve
from slipstep.case import load_case
from slipstep.fenicsx import radial

CASE = CASES / "thick_cylinder.toml"
_data = load_case(CASE).data
_mesh, _mat = _data["body"][0]["mesh"], _data["body"][0]["material"]
A_IN, B_OUT, H_BORE, H_OUTER = _mesh["a"], _mesh["b"], _mesh["h"], _mesh["h_outer"]
E, NU, SY = _mat["E"], _mat["nu"], _mat["Sy"]
P = next(bc["pressure"] for bc in _data["bc"] if bc["edge"] == "inner")
K = SY / math.sqrt(3.0)


# --------------------------------------------------------------------------- closed forms
def lame_von_mises(r, p=1.0):
    """Von Mises stress of the elastic (Lame) state at radius r under pressure p."""
    A = p * A_IN**2 / (B_OUT**2 - A_IN**2)
    B = p * A_IN**2 * B_OUT**2 / (B_OUT**2 - A_IN**2)
    return np.sqrt(3.0 * B**2 / np.asarray(r) ** 4 + (1.0 - 2.0 * NU) ** 2 * A**2)


P_ELASTIC = SY / lame_von_mises(A_IN)  # exact elastic limit, 108.07 MPa
P_ELASTIC_HILL = K * (1.0 - A_IN**2 / B_OUT**2)  # Hill's (incompressible) value
P_LIMIT = 2.0 * K * math.log(B_OUT / A_IN)  # fully plastic


def hill_pressure(c):
    """Hill: internal pressure at which the plastic zone reaches radius c."""
    return references.thick_cylinder_pressure(c, A_IN, B_OUT, K)


def hill_radius(p):
    return references.thick_cylinder_radius(p, A_IN, B_OUT, K)


def element_size(r):
    """The mesh size the case asks for at radius r (linear grading)."""
    return H_BORE + (H_OUTER - H_BORE) * (r - A_IN) / (B_OUT - A_IN)


# --------------------------------------------------------------------------- FE measures
def centroid_radius(scene):
    return np.linalg.norm(scene.nodes[scene.triangles].mean(axis=1), axis=1)


def areas(scene):
    p = scene.nodes[scene.triangles]
    d1, d2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    return 0.5 * (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])


def area_radius(scene, plastic):
    """c such that the quarter ring a..c has the area of the plastic elements."""
    return math.sqrt(A_IN**2 + 4.0 * areas(scene)[plastic].sum() / math.pi)


def separating_radius(r, plastic):
    """The radius that best splits plastic (inside) from elastic (outside) elements by their
    centroid radius r: fewest misclassified elements; returns (c, number misclassified)."""
    order = np.argsort(r)
    r, plastic = r[order], plastic[order]
    elastic_inside = np.concatenate([[0], np.cumsum(~plastic)])
    plastic_outside = np.concatenate([np.cumsum(plastic[::-1])[::-1], [0]])
    miss = elastic_inside + plastic_outside
    i = int(np.argmin(miss))
    lo = r[i - 1] if i > 0 else A_IN
    hi = r[i] if i < len(r) else B_OUT
    return 0.5 * (lo + hi), int(miss[i])


def first_yield(result):
    ev = result["events"]
    k = list(ev["kind"]).index("yield")
    return float(ev["load_fraction"][k]), int(ev["entity"][k])


def sampling_tolerance(scene, element):
    """How much the elastic-limit pressure seen by a CST element differs from p_e because its
    constant stress samples the 1/r^2 field inside the element, not at r = a: the Lame
    pressure to yield at the centroid radius r_c over p_e, minus 1 (= sigma_e(a)/sigma_e(r_c)
    - 1 ~ 2 (r_c - a)/a)."""
    r_c = centroid_radius(scene)[element]
    return float(lame_von_mises(A_IN) / lame_von_mises(r_c) - 1.0), float(r_c)


@pytest.fixture(scope="module")
def cylinder():
    scene = prepare(CASE)
    return scene, solve(scene)


# --------------------------------------------------------------------------- tests
def test_closed_form_values():
    assert P_ELASTIC == pytest.approx(108.07, abs=0.01)
    assert P_ELASTIC_HILL == pytest.approx(108.25, abs=0.01)
    assert abs(P_ELASTIC_HILL / P_ELASTIC - 1) < 0.002  # Hill's approximation at nu = 0.3
    assert P_ELASTIC < P < P_LIMIT == pytest.approx(200.09, abs=0.01)
    assert hill_pressure(A_IN) == pytest.approx(P_ELASTIC_HILL, rel=1e-12)
    assert hill_radius(P) == pytest.approx(14.42, abs=0.01)


@needs_gmsh
def test_run_completes_in_equilibrium_with_yield_events_only(cylinder):
    scene, result = cylinder
    assert len(scene.model["pairs"]["node_a"]) == 0  # bulk-only
    assert result["steps"]["load_fraction"][-1] == 1.0 and result["stop_reason"] is None
    # every snapshot in equilibrium, recomputed from its stresses and load (tests/physics.py)
    worst, k, f = worst_equilibrium(scene.model, result["snapshots"])
    assert worst <= EQUILIBRIUM_TOL, (k, f, worst)
    # monotonic loading, Hill's zone only grows: no plastic unloading, no anti-cycling
    assert set(result["events"]["kind"]) == {"yield"}
    assert np.all(np.diff(result["steps"]["n_plastic"]) >= 0)
    # Perfectly plastic and proportional: the stresses stay on the yield surface, up to what
    # an equilibrium correction moves them along a tangent K has not renewed yet (grouped
    # increments, the default): at most max_stress_step² = 0.05² (the drift that makes the
    # engine settle on the surfaces); event by event it is ~1e-5.
    assert result["max_drift"] <= 0.05**2


@needs_gmsh
def test_elastic_limit_on_the_case_mesh(cylinder):
    """First yield at the bore at p_e, within the centroid-sampling tolerance (about 1 % for
    h = 0.25 mm at a = 10 mm)."""
    scene, result = cylinder
    f, element = first_yield(result)
    tol, r_c = sampling_tolerance(scene, element)
    r_nodes = np.linalg.norm(scene.nodes[scene.triangles[element]], axis=1)
    assert r_nodes.min() == pytest.approx(A_IN)  # an element on the bore
    assert r_c - A_IN <= H_BORE / 2
    assert tol <= 0.02
    assert abs(f * P / P_ELASTIC - 1.0) <= tol


@needs_gmsh
def test_elastic_limit_on_a_fine_mesh():
    """h = 0.0625 mm at the bore, stopped at the first yield event (0.3 s): within 0.5 %."""
    scene = prepare(
        CASE, ["mesh.h=0.0625", "solver.stop_at_first_yield=true", "output.snapshots=[1.0]"]
    )
    result = solve(scene)
    f, element = first_yield(result)
    assert len(result["events"]["step"]) == 1 and result["steps"]["load_fraction"][-1] == f
    tol, _ = sampling_tolerance(scene, element)
    assert tol <= 0.005
    assert abs(f * P / P_ELASTIC - 1.0) <= tol


@needs_gmsh
def test_plastic_radius_follows_the_exact_answer(cylinder):
    """At every snapshot above the elastic limit the plastic zone is a ring a..c, with c the
    exact von Mises answer at nu = 0.3 (the converged 1D radial model, slipstep.fenicsx.radial;
    Hill's closed form, exact at nu = 1/2 only, is 0.46 % short of it at p = 175 MPa).
    Tolerance: a quarter of the local element size (the front is resolved to an element; both
    measures average it over the whole quarter)."""
    scene, result = cylinder
    r = centroid_radius(scene)
    snaps = [s for s in result["snapshots"] if float(s["load_fraction"]) * P >= P_ELASTIC * 1.02]
    exact = radial.solve(A_IN, B_OUT, E, NU, SY, [float(s["load_fraction"]) * P for s in snaps])
    for snap, c in zip(snaps, exact.c):
        plastic = np.asarray(snap["plastic"]).astype(bool)
        assert np.array_equal(plastic, np.asarray(snap["plastic_strain"]) > 0)
        tol = element_size(c) / 4
        c_sep, miss = separating_radius(r, plastic)
        assert abs(area_radius(scene, plastic) - c) <= tol, (snap["load_fraction"], c)
        assert abs(c_sep - c) <= tol, (snap["load_fraction"], c)
        assert miss <= 0.02 * plastic.sum()  # a ring, up to a ragged front
    assert len(snaps) >= 7


def test_radial_reference_against_lame_and_hill():
    """The 1D reference itself: elastic u(b) is Lame's to 1e-6 (linear elements, graded; the
    discretization error is O(h^2) ~ 1e-7 here); as nu -> 1/2 its c tends to Hill's closed form,
    which is exact there: the difference goes as (1/2 - nu)^2 (measured 4.6e-3 relative at
    0.3, 2.9e-4 at 0.45, so ~1e-5 at 0.49, where the linear elements' volumetric locking adds
    ~3e-5: tolerance 1e-4); and it is converged: 4x the elements and steps move c by < 1e-5
    relative at nu = 0.3."""
    p_el = 0.9 * P_ELASTIC
    elastic = radial.solve(A_IN, B_OUT, E, NU, SY, [p_el])
    assert elastic.c[0] == A_IN
    lame_ub = (1 + NU) / E * p_el * A_IN**2 / (B_OUT**2 - A_IN**2) * ((1 - 2 * NU) * B_OUT + B_OUT)
    assert elastic.u_outer[0] == pytest.approx(lame_ub, rel=1e-6)
    near_incompressible = radial.solve(A_IN, B_OUT, E, 0.49, SY, [P])
    assert near_incompressible.c[0] == pytest.approx(hill_radius(P), rel=1e-4)
    at_nu = radial.solve(A_IN, B_OUT, E, NU, SY, [P])
    fine = radial.solve(
        A_IN, B_OUT, E, NU, SY, [P], n_elements=4 * radial.N_ELEMENTS, n_steps=4 * radial.N_STEPS
    )
    assert at_nu.c[0] == pytest.approx(fine.c[0], rel=1e-5)
    assert 0.003 < at_nu.c[0] / hill_radius(P) - 1 < 0.006


@needs_gmsh
def test_hill_yield_condition_in_the_plastic_zone(cylinder):
    """sigma_theta - sigma_r = 2k is Hill's (incompressible) form of the yield condition; with
    nu = 0.3 it holds to 1 %: the size of Hill's approximation."""
    scene, result = cylinder
    snap = result["snapshots"][-1]
    plastic = np.asarray(snap["plastic"]).astype(bool)
    centre = scene.nodes[scene.triangles].mean(axis=1)
    c, s = (centre / np.linalg.norm(centre, axis=1, keepdims=True)).T
    sx, sy, _, txy = np.asarray(snap["stress"]).T
    diff = (sy - sx) * (c**2 - s**2) - 4.0 * txy * c * s  # sigma_theta - sigma_r
    ratio = diff[plastic] / (2.0 * K)
    assert ratio.max() <= 1.0 + 1e-6 and ratio.min() >= 0.99


def test_run_beyond_the_limit_load_stops_at_hills_limit():
    # Hill: the fully plastic cylinder collapses at p_L = 2k ln(b/a) = 200.1 MPa (k = Sy/sqrt(3)).
    # Asked for 1.1 p_L, the engine must not report success on a singular tangent: it stops with
    # a limit-load reason once the current stiffness falls to 1e-3 of the initial one, at a
    # pressure within 2 % of p_L (CST on this mesh overshoots slightly: locking, see issue 7).
    from slipstep import prepare, solve

    p_limit = 2 * 250.0 / math.sqrt(3) * math.log(2.0)
    scene = prepare(CASE, overrides=[f"bc.bore.pressure={1.1 * p_limit}", "output.snapshots=[1.0]"])
    result = solve(scene)
    assert result["stop_reason"] and result["stop_reason"].startswith("limit load reached")
    p_stop = result["steps"]["load_fraction"][-1] * 1.1 * p_limit
    assert p_stop == pytest.approx(p_limit, rel=0.02)
    # the state it stops in is in equilibrium (recomputed; 1e-9: the equilibrium contract)
    worst, k, f = worst_equilibrium(scene.model, result["snapshots"])
    assert worst <= EQUILIBRIUM_TOL, (k, f, worst)
