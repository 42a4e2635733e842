"""Thick-walled sphere under internal pressure (cases/thick_sphere.toml) against the closed forms:
axisymmetric, von Mises, elastic-perfectly plastic (H' = 0), a bulk-only scene (every event is
a yield event).  a = 10, b = 20 mm, E = 200 GPa, nu = 0.3, Y = 250 MPa, p = 280 MPa.

In the (r, z) plane the sphere's quarter section is a quarter annulus; rho = |(r, z)| is the
spherical radius.  The state is spherically symmetric: sigma_R radial, sigma_t = sigma_theta
(the hoop stress, out of the plane, from the ring's hoop strain) = sigma_phi (meridional, in the
plane).  Closed forms (tests/physics.py; Hill, The Mathematical Theory of Plasticity, ch. V):

    elastic (Lame): sigma_R = -p (b^3/rho^3 - 1)/(b^3/a^3 - 1),
                    sigma_t = p (b^3/(2 rho^3) + 1)/(b^3/a^3 - 1)
    first yield at the bore: p_e = (2Y/3)(1 - a^3/b^3) = 145.83 MPa
    plastic zone a..c:  p = 2Y ln(c/a) + (2Y/3)(1 - c^3/b^3)   (c = 14.10 mm at p = 280)
    limit: 2Y ln(b/a) = 346.57 MPa.

With sigma_theta = sigma_phi, von Mises and Tresca are one condition, |sigma_t - sigma_R| = Y, so
Hill's solution is exact for von Mises (no incompressibility approximation, unlike the
cylinder's).

Mesh (the case): gmsh, h = 0.25 mm at the bore growing linearly to 0.8 mm at rho = b, 2507
elements, 2656 dofs; ~1500 yield events, ~5 s.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import CASES, needs_gmsh
import physics
from slipstep.measures import references
from physics import EQUILIBRIUM_TOL, worst_equilibrium

from slipstep import prepare, solve
from slipstep.case import load_case

CASE = CASES / "thick_sphere.toml"
_data = load_case(CASE).data
_mesh, _mat = _data["body"][0]["mesh"], _data["body"][0]["material"]
A_IN, B_OUT, H_BORE, H_OUTER = _mesh["a"], _mesh["b"], _mesh["h"], _mesh["h_outer"]
E, NU, Y = _mat["E"], _mat["nu"], _mat["Sy"]
P = next(bc["pressure"] for bc in _data["bc"] if bc["edge"] == "inner")
P_ELASTIC = references.thick_sphere_pressure(A_IN, A_IN, B_OUT, Y)
P_LIMIT = references.thick_sphere_pressure(B_OUT, A_IN, B_OUT, Y)


def element_size(rho):
    """The mesh size the case asks for at radius rho (linear grading)."""
    return H_BORE + (H_OUTER - H_BORE) * (rho - A_IN) / (B_OUT - A_IN)


def spherical(scene, stress):
    """Per element: centroid radius rho and (sigma_R, sigma_theta, sigma_phi) from the
    (sigma_r, sigma_z, sigma_theta, tau_rz) columns, rotated to the centroid's direction."""
    centre = scene.nodes[scene.triangles].mean(axis=1)
    rho = np.linalg.norm(centre, axis=1)
    c, s = (centre / rho[:, None]).T  # c = r/rho, s = z/rho
    sr, sz, st, trz = np.asarray(stress, dtype=float).T
    radial = sr * c**2 + sz * s**2 + 2 * trz * c * s
    meridional = sr * s**2 + sz * c**2 - 2 * trz * c * s
    return rho, radial, st, meridional


def volumes(scene):
    """Ring volumes 2 pi r_bar A of the elements."""
    p = scene.nodes[scene.triangles]
    d1, d2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    return 2 * math.pi * p[:, :, 0].mean(axis=1) * 0.5 * (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])


@pytest.fixture(scope="module")
def sphere():
    scene = prepare(CASE)
    return scene, solve(scene)


def test_closed_form_values():
    assert P_ELASTIC == pytest.approx(145.83, abs=0.01)
    assert P_LIMIT == pytest.approx(346.57, abs=0.01)
    assert P_ELASTIC < P < P_LIMIT
    assert references.thick_sphere_radius(P, A_IN, B_OUT, Y) == pytest.approx(14.10, abs=0.01)
    # Lame's von Mises stress |sigma_t - sigma_R| reaches Y at the bore exactly at p_e
    sr, st = references.thick_sphere_lame(A_IN, P_ELASTIC, A_IN, B_OUT)
    assert st - sr == pytest.approx(Y, rel=1e-12)


@needs_gmsh
def test_elastic_lame_field_converges():
    """Elastic (Y raised out of reach) at p = 140 MPa, meshes h = 0.5, 0.25, 0.125 at the bore:
    the element stresses against Lame's at their centroids converge at first order (the CST
    samples a 1/rho^3 field: rms error ~ h/a, fitted order >= 0.8), the hoop stress sigma_theta
    (from the ring's hoop strain) as fast as the in-plane meridional sigma_phi, and the radial
    node displacements at second order (fitted >= 1.7).  Every run in equilibrium (recomputed,
    ring forces)."""
    rows = []
    for k in (2.0, 1.0, 0.5):
        scene = prepare(
            CASE,
            [
                "material.Sy=1e9",
                "output.snapshots=[0.5]",
                f"mesh.h={H_BORE * k}",
                f"mesh.h_outer={H_OUTER * k}",
            ],
        )
        snap = solve(scene)["snapshots"][0]
        assert physics.equilibrium_residual(scene.model, snap) < EQUILIBRIUM_TOL
        p = P * snap["load_fraction"]
        rho, radial, hoop, meridional = spherical(scene, snap["stress"])
        sr, st = references.thick_sphere_lame(rho, p, A_IN, B_OUT)
        rms = [
            float(np.sqrt(np.mean(((fe - ref) / p) ** 2)))
            for fe, ref in ((radial, sr), (hoop, st), (meridional, st))
        ]
        u = np.asarray(snap["u"]).reshape(-1, 2)
        rn = np.linalg.norm(scene.nodes, axis=1)
        ur = np.einsum("ij,ij->i", u, scene.nodes) / rn
        exact = references.thick_sphere_displacement(rn, p, A_IN, B_OUT, E, NU)
        rows.append(rms + [float(np.abs(ur / exact - 1).max())])
    rows = np.array(rows)
    h = H_BORE * np.array([2.0, 1.0, 0.5])
    order = [np.polyfit(np.log(h), np.log(rows[:, j]), 1)[0] for j in range(4)]
    assert min(order[:3]) >= 0.8 and order[3] >= 1.7, (order, rows)
    assert rows[1, 1] <= rows[1, 2]  # hoop no worse than meridional on the case mesh
    assert rows[1, :3].max() <= H_BORE / A_IN  # ~ h/a at the bore: 1.8 % measured


@needs_gmsh
def test_run_completes_in_equilibrium_with_yield_events_only(sphere):
    scene, result = sphere
    assert len(scene.model["pairs"]["node_a"]) == 0
    assert result["stop"]["kind"] == "completed"
    worst, k, f = worst_equilibrium(scene.model, result["snapshots"])
    assert worst <= EQUILIBRIUM_TOL, (k, f, worst)
    assert set(result["events"]["kind"]) == {"yield"}
    assert np.all(np.diff(result["steps"]["n_plastic"]) >= 0)  # the zone only grows
    # Perfectly plastic and proportional: the stresses stay on the yield surface, up to what
    # an equilibrium correction moves them along a tangent K has not renewed yet (grouped
    # increments, the default): at most max_stress_step² = 0.05² (the drift that makes the
    # engine settle on the surfaces); event by event it is ~1e-5.
    assert result["max_drift"] <= 0.05**2


@needs_gmsh
def test_first_yield_at_the_elastic_limit(sphere):
    """First yield on the bore at p_e, within how much the element's constant stress, sampled
    at its centroid radius rho_c, lags the bore: Lame's von Mises ~ 1/rho^3, so the element
    yields at p_e (rho_c/a)^3 (~1.6 % for h = 0.25 mm)."""
    scene, result = sphere
    k = list(result["events"]["kind"]).index("yield")
    f, element = float(result["events"]["load_fraction"][k]), int(result["events"]["entity"][k])
    corners = np.linalg.norm(scene.nodes[scene.triangles[element]], axis=1)
    assert corners.min() == pytest.approx(A_IN)  # an element on the bore
    rho_c = np.linalg.norm(scene.nodes[scene.triangles[element]].mean(axis=0))
    tol = (rho_c / A_IN) ** 3 - 1
    assert tol <= 0.03
    assert abs(f * P / P_ELASTIC - 1) <= tol, (f * P, P_ELASTIC, tol)


@needs_gmsh
def test_plastic_radius_follows_hill(sphere):
    """At every snapshot above the elastic limit the plastic zone is a shell a..c with Hill's
    c(p), measured by the plastic elements' ring volume (2 pi/3 (c^3 - a^3) for the upper
    hemisphere) and by the radius that best separates plastic from elastic centroids; within a
    quarter of the local element size (the front is resolved to an element; both measures
    average it over the section)."""
    scene, result = sphere
    rho = np.linalg.norm(scene.nodes[scene.triangles].mean(axis=1), axis=1)
    vol = volumes(scene)
    checked = 0
    for snap in result["snapshots"]:
        p = float(snap["load_fraction"]) * P
        if p < 1.05 * P_ELASTIC:
            continue
        plastic = np.asarray(snap["plastic"]).astype(bool)
        c_hill = references.thick_sphere_radius(p, A_IN, B_OUT, Y)
        c_vol = (A_IN**3 + 1.5 * vol[plastic].sum() / math.pi) ** (1 / 3)
        inside, outside = rho[plastic].max(), rho[~plastic].min()
        assert abs(c_vol - c_hill) <= element_size(c_hill) / 4, (p, c_vol, c_hill)
        assert inside - outside <= 2 * element_size(c_hill)  # a shell, up to a ragged front
        checked += 1
    assert checked >= 7


@needs_gmsh
def test_yield_condition_in_the_plastic_zone(sphere):
    """Plastic elements sit on the yield surface (von Mises, drift <= 1e-4), and their state is
    the spherical one of Hill's solution: sigma_t - sigma_R = Y with the hoop sigma_theta and the
    meridional sigma_phi equal, up to the CST's sampling of the zone (each within 3 % of Y on
    the case mesh, ~ 3h/rho of the stress variation across an element at the bore)."""
    scene, result = sphere
    snap = result["snapshots"][-1]
    plastic = np.asarray(snap["plastic"]).astype(bool)
    _, radial, hoop, meridional = spherical(scene, snap["stress"])
    assert np.abs(physics.von_mises(snap["stress"])[plastic] / Y - 1).max() <= 1e-4
    for tangential in (hoop, meridional):
        assert np.abs((tangential - radial)[plastic] / Y - 1).max() <= 0.03
    assert np.abs((hoop - meridional)[plastic]).max() <= 0.05 * Y


def test_run_beyond_the_limit_load_stops_at_hills_limit():
    """Asked for 1.1 p_L, the engine stops with its limit-load reason (stiffness of the remaining
    load below 1e-3 of the initial one) at a pressure within 2 % of 2Y ln(b/a) (the CST's
    overshoot in isochoric plastic flow, as for the cylinder), in equilibrium, and with no
    stress beyond the yield surface (H = 0: von Mises <= Y, up to the drift bound
    max_stress_step² = 0.05² of the default grouped increments). A grouped window that ran
    past the limit used to be kept with its linear stresses, 1.3 % beyond Y."""
    scene = prepare(CASE, [f"bc.bore.pressure={1.1 * P_LIMIT}", "output.snapshots=[1.0]"])
    result = solve(scene)
    assert result["stop"]["kind"] == "limit_load", result["stop"]
    p_stop = result["steps"]["load_fraction"][-1] * 1.1 * P_LIMIT
    assert p_stop == pytest.approx(P_LIMIT, rel=0.02)
    assert physics.von_mises(result["snapshots"][-1]["stress"]).max() <= Y * (1 + 0.05**2)
    worst, k, f = worst_equilibrium(scene.model, result["snapshots"])
    assert worst <= EQUILIBRIUM_TOL, (k, f, worst)
