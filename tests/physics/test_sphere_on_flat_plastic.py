"""An elastic-perfectly plastic sphere pressed by a rigid flat far past first yield
(cases/sphere_on_flat_plastic.toml: axisymmetric, frictionless, the flat moved up to the
interference omega = 50 omega_c), against the published finite-element fits of

* L. Kogut, I. Etsion, "Elastic-plastic contact analysis of a sphere and a rigid flat",
  J. Appl. Mech. 69 (2002) 657-662, DOI 10.1115/1.1490373 (KE), and
* R. L. Jackson, I. Green, "A finite element study of elasto-plastic hemispherical contact
  against a rigid flat", J. Tribol. 127 (2005) 343-354, DOI 10.1115/1.1866166 (JG),

whose formulas are in ``slipstep.measures.references`` (the first test pins them to values worked out
by hand).  Both papers model what the case models: a deformable sphere (a hemisphere, its base
held) pressed by a rigid flat, frictionless, von Mises; JG's abstract states
elastic-perfectly plastic; the case takes H' = 0.  Both normalise by the first-yield
interference omega_c, force P_c and area A_c (their C(nu) and K(nu) give omega_c within 0.08 %
of each other at nu = 0.3).  Both fits were made from carbon-steel properties (E ~ 200 GPa,
several yield strengths; Quicksall, Jackson & Green, "Elasto-plastic hemispherical contact
models for various mechanical properties", WTC 2005, abstract), and below E/Y ~ 300 the contact
behaves differently (Sahoo & Chatterjee, Engineering 2 (2010) 205-211, abstract): the material
here, E = 200 GPa, nu = 0.3, Y = 400 MPa (E/Y = 500), is such a steel.  Sources: the papers'
openings in the stored public record, and two independent public implementations of each
model, for the constants; the accuracy each paper states for its own fits could not be read
there (only the openings are stored), so the tolerances below are built from what can be
computed here, and say so.

Measured (group_tol = 0.01; meshes 2h / h (the case) / h/2, 746 / 2669 / 10,336 nodes), over
1 <= omega/omega_c <= 50: P - KE -4.6..+0.9 / -4.0..+0.8 / -4.1..+1.4 %, P - JG -6.3..+0.3 /
-4.8..+0.3 / -3.9..+0.2 %; A - KE +4.0..+10.5 / +2.3..+10.9 / +0.3..+8.5 % (the largest just
above omega_c, where KE's area starts 7 % below Hertz), A - JG +7.4..+10.5 / +3.6..+7.7 /
+1.7..+6.3 %: the force sits between the two fits, the area converges onto them from above
(`slipstep reproduce` draws it).

Measures, from the result arrays (not the engine's summaries):

* omega at the moment each contact node closes (the engine's ``closure_fraction`` x the motion)
  and the contact radius then, a = the node's radius, A = pi a^2;
* P = the flat's total force on the sphere (ring totals) at the end of that increment (a closure
  ends an increment), checked against the base reaction recomputed from the snapshots.

Mesh: graded so that the element size at the contact edge stays near a/15 for every omega
from omega_c to 50 omega_c (the case file says how); its refinement, twice as coarse, is run
too.  Event grouping: ``solver.group_tol = 0.01`` (the case's; the exact procedure takes ~100 s
instead of ~8 s and moved P by < 0.5 % when measured).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from conftest import CASES, needs_gmsh
from physics import EQUILIBRIUM_TOL, worst_equilibrium
from slipstep import prepare, solve
from slipstep.case import load_case
from slipstep.measures.references import (
    jackson_green,
    jackson_green_critical,
    kogut_etsion,
    kogut_etsion_critical,
)

CASE = CASES / "sphere_on_flat_plastic.toml"
_data = load_case(CASE).data
_mesh, _mat = _data["body"][0]["mesh"], _data["body"][0]["material"]
R, E, NU, Y = _mesh["R"], _mat["E"], _mat["nu"], _mat["Sy"]
E_STAR = E / (1 - NU**2)
OMEGA_MAX = _data["contact"][0]["motion"][1]
KE = kogut_etsion_critical(R, E_STAR, Y, NU)
JG = jackson_green_critical(R, E_STAR, Y, NU)
COARSE = [f"mesh.h_contact={2 * _mesh['h_contact']}", f"mesh.growth={2 * _mesh['growth']}"]

#: The range compared: from first yield to the end of the run (KE's fits hold to 110).
W_RANGE = (1.0, OMEGA_MAX / KE.interference)


def closures(scene, result):
    """(omega, a, P, h) at every closure, in order: the flat's displacement when the node
    closed, the node's radius, the total contact force at the end of that increment, and the
    element size at the contact edge there (the longer arc segment at the node)."""
    steps = result["steps"]
    f = np.asarray(result["closure_fraction"], dtype=float)
    r = scene.pair_xy[:, 0]
    closed = np.isfinite(f) & (f > 0)
    order = np.argsort(f[closed])
    fc, rc = f[closed][order], r[closed][order]
    P = np.interp(fc, np.asarray(steps["load_fraction"]), np.asarray(steps["normal_force"]))
    arc = scene.global_edge("sphere", "arc")
    length = np.linalg.norm(scene.nodes[arc[:, 1]] - scene.nodes[arc[:, 0]], axis=1)
    h = np.zeros(len(scene.nodes))
    np.maximum.at(h, arc[:, 0], length)
    np.maximum.at(h, arc[:, 1], length)
    hc = h[scene.model["pairs"]["node_a"]][closed][order]
    return fc * OMEGA_MAX, rc, P, hc


def compared(curve, crit, w_lo=W_RANGE[0]):
    """Closures with w_lo <= omega/omega_c: (w, P/P_c, A/A_c, h/a)."""
    omega, a, P, h = curve
    w = omega / crit.interference
    keep = w >= w_lo
    return (w[keep], P[keep] / crit.force, math.pi * a[keep] ** 2 / crit.area, h[keep] / a[keep])


@pytest.fixture(scope="module")
def runs():
    out = {}
    for name, over in (("case", []), ("coarse", COARSE)):
        scene = prepare(CASE, over)
        result = solve(scene)
        out[name] = (scene, result, closures(scene, result))
    return out


def test_fit_formulas_at_hand_worked_values():
    """The fits at values worked out by hand from the papers' constants (nu = 0.3):
    K = 0.454 + 0.41 nu = 0.577, KH = 2.8 K Y = 1.6156 Y; C = 1.295 e^(0.2208) = 1.61496;
    B = 0.14 exp(23 Y/E*) = 0.14 e^(0.041860) = 0.14598."""
    assert KE.interference == pytest.approx(
        (math.pi * 1.6156 * Y / (2 * E_STAR)) ** 2 * R, rel=1e-12
    )
    assert JG.interference == pytest.approx(
        (math.pi * 1.614961 * Y / (2 * E_STAR)) ** 2 * R, rel=1e-6
    )
    for crit in (KE, JG):  # P_c and A_c are Hertz's values at omega_c
        assert crit.force == pytest.approx(
            4 / 3 * E_STAR * math.sqrt(R) * crit.interference**1.5, rel=1e-12
        )
        assert crit.area == pytest.approx(math.pi * R * crit.interference, rel=1e-12)
    P, A = kogut_etsion([0.5, 2.0, 20.0])
    assert P == pytest.approx([0.5**1.5, 1.03 * 2**1.425, 1.40 * 20**1.263], rel=1e-12)
    assert A == pytest.approx([0.5, 0.93 * 2**1.136, 0.94 * 20**1.146], rel=1e-12)
    P, A = jackson_green([1.0, 20.0], R, E_STAR, Y, NU)
    B = 0.14 * math.exp(23 * Y / E_STAR)
    assert B == pytest.approx(0.14598, abs=1e-5)
    assert A == pytest.approx([1.0, 20 * (20 / 1.9) ** B], rel=1e-12)
    a = math.sqrt(A[1] * JG.area / math.pi)  # 0.246 mm: H_G = 2.84 Y to 4e-6
    h_g = 2.84 * (1 - math.exp(-0.82 * (a / R) ** -0.7))
    assert P[1] == pytest.approx(
        math.exp(-(20 ** (5 / 12)) / 4) * 20**1.5
        + 4 * h_g / 1.614961 * (1 - math.exp(-(20 ** (5 / 9)) / 25)) * 20,
        rel=1e-6,
    )


def fit_spread(w):
    """Largest relative difference between the two fits, (P, A), over the given w (each
    fit normalised by its own critical values, compared in absolute terms)."""
    Pk, Ak = kogut_etsion(w)
    Pj, Aj = jackson_green(w * KE.interference / JG.interference, R, E_STAR, Y, NU)
    return (
        float(np.abs(Pk * KE.force / (Pj * JG.force) - 1).max()),
        float(np.abs(Ak * KE.area / (Aj * JG.area) - 1).max()),
    )


#: The two fits, fitted to two independent finite-element studies of the same problem, differ
#: from each other over 1 <= omega/omega_c <= 50 by up to 4.6 % in P and 7.0 % in A (asserted
#: below from the formulas: KE's area starts 7 % below Hertz at omega_c, JG's follows Hertz to
#: 1.9 omega_c): neither can be taken as exact to better than that.
SPREAD_P, SPREAD_A = 0.05, 0.075
#: Our own discretization of the force (see test_refinement).  The force at the closures moves
#: by 3.0 % at most from the coarse mesh to this one; with first-order convergence the
#: difference of the two is this mesh's own error, so MESH_P bounds it.
MESH_P = 0.035


def area_bounds(h_over_a):
    """The band A/A_fit must reach at a closure, from the mesh and the fits' accuracy.  The
    contact radius read at the closing node is the discrete contact edge, which lies within one
    element h of the continuum's (h the element size at the contact edge there; the mesh is
    graded so that h ~ a/15): the true area lies in [pi (a - h)^2, pi (a + h)^2], the fit's
    within SPREAD_A of the true one (the fits' spread: neither is exact to better; the papers'
    own stated accuracy is not in the stored record).  The two intervals must overlap:
    (1 - SPREAD_A)/(1 + h/a)^2 <= A/A_fit <= (1 + SPREAD_A)/(1 - h/a)^2."""
    return (1 - SPREAD_A) / (1 + h_over_a) ** 2, (1 + SPREAD_A) / (1 - h_over_a) ** 2


def test_the_fits_differ_by_their_spread():
    w = np.linspace(*W_RANGE, 400)
    spread_p, spread_a = fit_spread(w)
    assert spread_p <= SPREAD_P and spread_a <= SPREAD_A, (spread_p, spread_a)


@needs_gmsh
def test_run_completes_in_equilibrium_without_separation(runs):
    scene, result, _ = runs["case"]
    assert result["stop"]["kind"] == "completed"
    assert "separate" not in set(result["events"]["kind"])
    worst, k, f = worst_equilibrium(scene.model, result["snapshots"])
    assert worst <= EQUILIBRIUM_TOL, (k, f, worst)
    # the flat's force is what the base carries (recomputed from the snapshot's reactions)
    base = 2 * np.unique(scene.meshes["sphere"].edges["top"]) + 1
    for snap in result["snapshots"]:
        base_force = np.asarray(snap["reaction"]).reshape(-1)[base].sum()
        assert np.sum(snap["lambda_n"]) == pytest.approx(-base_force, rel=1e-9)


@needs_gmsh
def test_elastic_range_is_hertz(runs):
    """Before first yield P = (4/3) E* R^(1/2) omega^(3/2) (Hertz, the flat's approach),
    within 1 %: the base of the hemisphere adds a compliance O(a/R) < 0.5 %, and the P1
    field at a/h >= 5 (closures from r = 5 h on) is within 0.5 % (part A).  Measured:
    -0.5 % to +0.2 %."""
    scene, result, (omega, a, P, _) = runs["case"]
    h = load_case(CASE).data["body"][0]["mesh"]["h_contact"]
    keep = (omega < 0.95 * KE.interference) & (a >= 5 * h)
    assert keep.sum() >= 6
    hertz = 4 / 3 * E_STAR * math.sqrt(R) * omega[keep] ** 1.5
    assert np.abs(P[keep] / hertz - 1).max() <= 0.01


@needs_gmsh
def test_first_yield_at_the_critical_interference(runs):
    """The first yield event at omega_c within 3 %: omega ~ p0^2, and the first yielding
    element's centroid samples the von Mises field of Huber's axis within 1.5 % in p0 (part A,
    the Hertz sphere, 0.18 % at a/h = 20; here a_c/h = 11.5); measured -1.6 %."""
    scene, result, _ = runs["case"]
    k = list(result["events"]["kind"]).index("yield")
    omega = result["events"]["load_fraction"][k] * OMEGA_MAX
    for crit in (KE, JG):
        assert omega / crit.interference == pytest.approx(1.0, abs=0.03)


@needs_gmsh
@pytest.mark.parametrize("fit", ["KE", "JG"])
def test_force_and_area_against_the_fits(runs, fit):
    """From first yield to 50 omega_c, at every closure: P within SPREAD_P + MESH_P of the
    fit, A within ``area_bounds`` of it (one element at the contact edge, and SPREAD_A; on this
    mesh h/a = 0.064 .. 0.084 at these closures: a band from -18 % .. +23 % to -21 % .. +28 %;
    an area read one element too far out would be +13 % .. +17 % off).  Measured on this mesh: P -4.0 % .. +1.2 % (KE),
    -4.8 % .. +0.3 % (JG); A +2.3 % .. +10.9 % (KE: its fit starts 7 % below Hertz at
    omega_c), +3.6 % .. +7.7 % (JG)."""
    scene, result, curve = runs["case"]
    crit, formula = (
        (KE, lambda w: kogut_etsion(w))
        if fit == "KE"
        else (JG, lambda w: jackson_green(w, R, E_STAR, Y, NU))
    )
    w, P, A, h_over_a = compared(curve, crit)
    assert len(w) >= 25 and w[-1] >= 40
    P_fit, A_fit = formula(w)
    assert np.abs(P / P_fit - 1).max() <= SPREAD_P + MESH_P, np.c_[w, P / P_fit]
    lo, hi = area_bounds(h_over_a)
    ratio = A / A_fit
    assert ((ratio >= lo) & (ratio <= hi)).all(), np.c_[w, ratio, lo, hi]


@needs_gmsh
def test_refinement(runs):
    """The coarse mesh (every size doubled) against the case's.  Forces compared at the coarse
    mesh's closures (where its discrete contact edge sits on a node; between closures a mesh's
    force lags its edge by a saw-tooth of a few per cent, smaller on the finer mesh): within
    MESH_P (measured 3.0 %).  The contact area comes closer to both fits on the finer mesh
    (first-order convergence of the radius read at the closing node)."""
    fine, coarse = runs["case"][2], runs["coarse"][2]
    result = runs["case"][1]
    omega, _, P_coarse, _ = coarse
    keep = omega >= KE.interference
    P = np.interp(
        omega[keep] / OMEGA_MAX, result["steps"]["load_fraction"], result["steps"]["normal_force"]
    )
    assert np.abs(P_coarse[keep] / P - 1).max() <= MESH_P
    for crit, formula in ((KE, kogut_etsion), (JG, lambda w: jackson_green(w, R, E_STAR, Y, NU))):
        err = []
        for curve in (coarse, fine):
            w, _, A, _ = compared(curve, crit, w_lo=2.0)
            err.append(float(np.mean(np.abs(A / formula(w)[1] - 1))))
        assert err[1] < err[0], err
