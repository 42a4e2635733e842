"""Autofrettage (cases/autofrettage.toml): a thick-walled cylinder pressurized beyond first
yield (p = 175 MPa, c = 14.4 mm), released, pressurized again. Plane strain, von Mises,
elastic-perfectly plastic; a = 10, b = 20 mm, E = 200 GPa, nu = 0.3, Sy = 250 MPa,
k = Sy/sqrt(3).

Closed form of the residual state (derived here). Unloading from p is elastic while the bore's
stress change stays inside the yield surface (p < 2 p_e = 216 MPa, checked below), so

    residual = loading solution(p) - Lame solution(p).

Loading (Hill, ch. V, with sigma_theta - sigma_r = 2k in the plastic zone a <= r <= c):
    plastic  sigma_r = -p + 2k ln(r/a),           sigma_theta = sigma_r + 2k
    elastic  sigma_r = -k c^2/b^2 (b^2/r^2 - 1),  sigma_theta =  k c^2/b^2 (b^2/r^2 + 1)
    with p = k [2 ln(c/a) + 1 - c^2/b^2].
Lame (elastic, compressible): sigma_r = A - B/r^2, sigma_theta = A + B/r^2,
    A = p a^2/(b^2 - a^2), B = p a^2 b^2/(b^2 - a^2); u(r) = (1+nu)/E [(1-2nu) A r + B/r].
Bore displacement at load: the elastic zone gives u(c) = (1+nu)/E [(1-2nu) k c^3/b^2 + k c];
in the plastic zone the plastic strains are incompressible and, with sigma_theta - sigma_r =
2k, have no z component, so (ru)' = r (eps_r + eps_theta) = r (1+nu)(1-2nu)/E (sigma_r +
sigma_theta) = (1+nu)(1-2nu)/E (r^2 sigma_r)' and
    a u(a) = c u(c) - (1+nu)(1-2nu)/E [c^2 sigma_r(c) + a^2 p].
Residual bore displacement = u(a) - u_Lame(a).

Von Mises with nu = 0.3 is not exactly Hill's condition: sigma_z = nu (sigma_r + sigma_theta)
is not the mean of the other two until the zone is fully plastic, so sigma_theta - sigma_r
stays below 2k by up to 1 % (tests/physics/test_plasticity_cylinder.py) and the zone reaches slightly
further: that is the model error allowed against the closed form below.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from conftest import CASES, needs_gmsh
from physics import EQUILIBRIUM_TOL, worst_equilibrium
from slipstep.measures.references import thick_cylinder_radius

from slipstep import build_scene, parse_case, prepare, solve

pytestmark = needs_gmsh

CASE = CASES / "autofrettage.toml"
A_IN, B_OUT, E, NU, SY, P = 10.0, 20.0, 200000.0, 0.3, 250.0, 175.0
K = SY / math.sqrt(3.0)
H_BORE = 0.25  # the case's element size at the bore


C = thick_cylinder_radius(P, A_IN, B_OUT, K)
LAME_A = P * A_IN**2 / (B_OUT**2 - A_IN**2)
LAME_B = P * A_IN**2 * B_OUT**2 / (B_OUT**2 - A_IN**2)


def loading_stress(r):
    r = np.asarray(r, dtype=float)
    plastic = r <= C
    s_r = np.where(
        plastic, -P + 2 * K * np.log(r / A_IN), -K * C**2 / B_OUT**2 * (B_OUT**2 / r**2 - 1)
    )
    s_t = np.where(plastic, s_r + 2 * K, K * C**2 / B_OUT**2 * (B_OUT**2 / r**2 + 1))
    return s_r, s_t


def lame_stress(r):
    r = np.asarray(r, dtype=float)
    return LAME_A - LAME_B / r**2, LAME_A + LAME_B / r**2


def residual_stress(r):
    (lr, lt), (er, et) = loading_stress(r), lame_stress(r)
    return lr - er, lt - et


def residual_bore_displacement():
    compress = (1 + NU) * (1 - 2 * NU) / E
    u_c = (1 + NU) / E * ((1 - 2 * NU) * K * C**3 / B_OUT**2 + K * C)
    s_r_c = -K * (1 - C**2 / B_OUT**2)
    u_a = (C * u_c - compress * (C**2 * s_r_c + A_IN**2 * P)) / A_IN
    u_lame = (1 + NU) / E * ((1 - 2 * NU) * LAME_A * A_IN + LAME_B / A_IN)
    return u_a - u_lame


def polar(scene, stress):
    """(r, sigma_r, sigma_theta) at the element centroids."""
    x = scene.nodes[scene.triangles].mean(axis=1)
    r = np.linalg.norm(x, axis=1)
    c, s = x[:, 0] / r, x[:, 1] / r
    st = np.asarray(stress)
    sx, sy, txy = st[:, 0], st[:, 1], st[:, 3]
    return r, sx * c * c + sy * s * s + 2 * txy * c * s, sx * s * s + sy * c * c - 2 * txy * c * s


def bore_displacement(scene, snap):
    ids = np.flatnonzero(np.abs(np.linalg.norm(scene.nodes, axis=1) - A_IN) < 1e-9)
    u = np.asarray(snap["u"])[ids]
    return float(np.mean(np.einsum("ij,ij->i", u, scene.nodes[ids]) / A_IN))


def stage_end(result, k):
    return [s for s in result["snapshots"] if abs(s["t"] - k) < 1e-12][0]


@pytest.fixture(scope="module")
def autofrettage():
    scene = prepare(CASE, ["output.figures=false"])
    return scene, solve(scene)


def test_closed_form_assumptions():
    """Unloading is elastic (p below twice the elastic limit; the Lame bore von Mises stress
    for p is sqrt(3) B/a^2 (1 + small), p_e = 108.07 MPa) and the zone is inside the wall."""
    p_e = SY / math.sqrt(3 * LAME_B**2 / A_IN**4 + (1 - 2 * NU) ** 2 * LAME_A**2) * P
    assert P < 2 * p_e and A_IN < C < B_OUT
    assert abs(C - 14.42) < 0.01


def test_path_runs_in_three_stages_in_equilibrium(autofrettage):
    scene, result = autofrettage
    assert result["stop"]["kind"] == "completed" and result["stage_names"] == [
        "pressurize",
        "release",
        "repressurize",
    ]
    worst, k, t = worst_equilibrium(scene.model, result["snapshots"])
    assert worst <= EQUILIBRIUM_TOL, f"recomputed residual {worst:.2e} at t = {t}"


def test_release_is_elastic_and_repressurizing_adds_no_yield(autofrettage):
    """Every plastic element unloads at the start of the release (no yield in stages 2 and 3:
    elastic shakedown), and the reloaded state equals the loaded one (1e-8 of Sy: the two
    states are each in equilibrium to equilibrium_tol = 1e-9 of the load, and the stresses
    follow from equilibrium with a condition number ~10 on this mesh)."""
    _, result = autofrettage
    ev = result["events"]
    kinds, stage = np.array(ev["kind"]), np.asarray(ev["stage"])
    n_yield = int(((kinds == "yield") & (stage == 0)).sum())
    assert n_yield > 500
    assert not ((kinds == "yield") & (stage > 0)).any()
    assert int(((kinds == "unload") & (stage == 1)).sum()) == n_yield
    loaded, reloaded = stage_end(result, 1.0), stage_end(result, 3.0)
    assert np.abs(np.asarray(reloaded["stress"]) - loaded["stress"]).max() <= 1e-8 * SY


def test_release_equals_minus_the_elastic_solution(autofrettage):
    """The release changes the state by exactly minus the elastic solution for p on the same
    mesh (linear unloading): 1e-8 of Sy, as above."""
    scene, result = autofrettage
    text = re.sub(r"\[\[stage\]\][^\[]*", "", CASE.read_text())
    text = re.sub(r"\nSy = .*\n", "\n", text).replace(
        "snapshots = [0.5, 0.75, 1.0, 1.5, 2.0, 2.5, 3.0]", "snapshots = [1.0]"
    )
    escene = build_scene(
        parse_case(text, "elastic", CASES, ["output.figures=false"]), meshes=scene.meshes
    )
    e_snap = solve(escene)["snapshots"][-1]
    assert not e_snap["plastic"].any()
    change = np.asarray(stage_end(result, 2.0)["stress"]) - stage_end(result, 1.0)["stress"]
    assert np.abs(change + e_snap["stress"]).max() <= 1e-8 * SY


def test_residual_stresses_match_the_closed_form(autofrettage):
    """Residual sigma_r and sigma_theta at every element centroid against loading − Lame.
    Allowed, as a fraction of 2k: the von Mises/Hill model difference (1 %) plus the CST's
    constant stress sampling the field at its centroid: |d sigma_res/dr| h/2 with the steepest
    gradient at the bore, 2k/a + 2B/a^3 = 76 MPa/mm, h = 0.25 mm: 9.4 MPa = 3.3 % of 2k. So the
    largest error <= 4.5 % of 2k, and the rms (over mostly smoother elements) <= 1.5 %."""
    scene, result = autofrettage
    r, s_r, s_t = polar(scene, stage_end(result, 2.0)["stress"])
    ref_r, ref_t = residual_stress(r)
    two_k = 2 * K
    for fe, ref in ((s_r, ref_r), (s_t, ref_t)):
        err = np.abs(fe - ref) / two_k
        assert err.max() <= 0.045, f"max error {err.max():.4f} of 2k at r = {r[np.argmax(err)]:.3f}"
        assert math.sqrt(np.mean(err**2)) <= 0.015
    # the bore is left in compression: the point of autofrettage
    bore = r < A_IN + H_BORE
    assert (s_t[bore] < -0.5 * K).all()


def test_residual_bore_displacement_matches_the_closed_form(autofrettage):
    """Residual bore displacement u(a) − u_Lame(a) = 6.10 µm by the closed form; allowed 2 %:
    the 1 % model difference of the yield condition shifts c and, through u(c) ∝ c, the
    loading displacement by the same order, and the elastic part of the FE solution is within
    0.1 % (P1 on h = 0.25 at the bore)."""
    scene, result = autofrettage
    fe = bore_displacement(scene, stage_end(result, 2.0))
    ref = residual_bore_displacement()
    assert ref > 0 and abs(fe - ref) <= 0.02 * ref, f"{fe:.6e} vs {ref:.6e}"


def test_dolfinx_solves_the_same_path():
    """The dolfinx bulk solver (Newton, radial return) on the identical mesh (coarsened to
    h = 0.5 mm), path 0 → p in N load steps, → 0 and → p again in 2 steps each, against
    slipstep's event path. Its error is the loading steps' (release and reload are elastic in
    both, so they carry it over unchanged): the residual stresses agree within 1 % of Sy from
    N = 10 (measured 1.9 MPa = 0.8 % Sy), and the difference falls with N (measured 0.61 MPa at
    N = 40): slipstep's path is the limit dolfinx converges to."""
    pytest.importorskip("dolfinx")
    from slipstep.fenicsx.bulk import BulkProblem

    scene = prepare(CASE, ["mesh.h=0.5", "mesh.h_outer=1.5", "output.figures=false"])
    result = solve(scene)
    bulk = BulkProblem(scene)
    diffs = []
    for n in (10, 40):
        states = []
        path = [k / n for k in range(1, n + 1)] + [0.5, 0.0, 0.5, 1.0]
        bulk.solve_plastic(fractions=path, callback=states.append)
        released, reloaded = states[n + 1], states[n + 3]
        diff = np.abs(released.stress - np.asarray(stage_end(result, 2.0)["stress"])).max()
        assert diff <= 0.01 * SY, f"N = {n}: residual stresses differ by {diff:.3f} MPa"
        again = np.abs(reloaded.stress - np.asarray(stage_end(result, 3.0)["stress"])).max()
        assert again <= 0.01 * SY
        diffs.append(diff)
    assert diffs[1] < 0.5 * diffs[0], f"no convergence towards slipstep's path: {diffs}"
