"""Hertz contact of an elastic sphere on a rigid flat (cases/hertz_sphere.toml, axisymmetric)
against the closed forms (Johnson, Contact Mechanics §3.4 and §4.2; tests/physics.py):

    a = (3 P R / (4 E*))^(1/3),  p0 = 3 P / (2 pi a^2),  p(r) = p0 sqrt(1 - r^2/a^2),
    delta = a^2 / R  (the approach of distant points),  E* = E/(1 - nu^2).

R = 50 mm, P = 30 N, E = 70 GPa, nu = 0.3: a = 0.2445 mm (a/R = 0.0049), p0 = 239.5 MPa,
delta = 1.196 um.  a/R is kept small because Hertz's theory is the a/R -> 0 limit: the
finite sphere shifts the subsurface stresses by O(a/R) (measured on the axis at a/h = 20 and 40:
the von Mises stress -1.4, -0.7, -0.3, -0.1 % of Huber's at a/R = 0.04, 0.02, 0.01, 0.005),
which the first-yield check below could not resolve otherwise.

Where the approach is measured: Hertz's delta is the displacement of points far from the
contact compared with a, in a half-space.  The sphere's loaded cut is not such a point (its
displacement adds the compression of the whole sphere), so the approach is measured on the
axis, where the half-space field is known in closed form: the shortening of the axis from the
contact point down to a depth z (from the run's axis nodes) plus the half-space's shortening
below z (``references.sphere_axis_compression``, Huber's axial strain integrated from z to
infinity) must be delta, for any a << z << R.  It is checked at z = 2a, 5a and 10a.

Mesh: the case's (h = 0.012 mm in the contact zone, a/h = 20).  Tolerances follow from h/a:
the contact edge lies between two nodes (a to half a node spacing, h/(2a) = 2.5 %; p0 ~ P/a^2,
so p0 likewise); the pressure profile is sampled at nodes (rms within h/(2a), every node within
h/a); delta is a displacement, second order: (h/a)^2 = 0.25 %.  The refinement series (the
whole mesh scaled by 4, 2, 1, 1/2: h, growth and h_max together) gives the orders.
"""

from __future__ import annotations


import numpy as np
import pytest
from conftest import CASES, needs_gmsh
from scipy.optimize import minimize_scalar
import physics
from slipstep.measures import references

from slipstep import prepare, solve
from slipstep.case import load_case
from slipstep.measures.contact_edges import contact_profile

CASE = CASES / "hertz_sphere.toml"
_data = load_case(CASE).data
_body = _data["body"][0]
R, H = _body["mesh"]["R"], _body["mesh"]["h_contact"]
E, NU = _body["material"]["E"], _body["material"]["nu"]
P = _data["load"]["P"]
A, P0, DELTA = references.hertz_sphere(P, R, E, NU)
DEPTHS = (2.0, 5.0, 10.0)  # z/a where the approach is measured


def measured_approach(scene, snap, depth: float) -> float:
    """Shortening of the axis from the contact point to z = depth a (linear between the axis
    nodes) plus Huber's half-space shortening below it."""
    u = np.asarray(snap["u"], dtype=float).reshape(-1, 2)
    axis = np.flatnonzero(scene.nodes[:, 0] == 0.0)
    axis = axis[np.argsort(scene.nodes[axis, 1])]
    z, uz = scene.nodes[axis, 1], u[axis, 1]
    assert z[0] == 0.0 and z[-1] > depth * A
    shortening = uz[0] - np.interp(depth * A, z, uz)
    return shortening + references.sphere_axis_compression(depth, NU) * P0 * A / E


def errors(scene, result) -> dict:
    """Relative errors of a, p0, the pressure profile (rms and largest over nodes with
    r < 0.9 a, against p0) and the approach at DEPTHS, at full load."""
    snap = result["snapshots"][-1]
    prof = contact_profile(scene, snap)
    closed = prof["status"] > 0
    r_edge, r_open = prof["x"][closed].max(), prof["x"][~closed].min()
    # the contact radius: between the outermost closed node and the first open one, where the
    # engine's last trial would close it (linear in the load), as the summary measures it
    k_edge = prof["pair"][np.argmax(np.where(closed, prof["x"], -1))]
    k_open = prof["pair"][np.argmin(np.where(~closed, prof["x"], np.inf))]
    f_edge, f_open = result["closure_fraction"][k_edge], result["predicted_closure"][k_open]
    a_fe = r_edge + (r_open - r_edge) * min(max((1 - f_edge) / (f_open - f_edge), 0), 1)
    r, p = (prof[key][prof["x"] < 0.9 * A] for key in ("x", "pressure"))
    dev = (p - P0 * np.sqrt(1 - (r / A) ** 2)) / P0
    return {
        "a": a_fe / A - 1,
        "p0": prof["pressure"].max() / P0 - 1,
        "rms": float(np.sqrt(np.mean(dev**2))),
        "max": float(np.abs(dev).max()),
        "delta": [measured_approach(scene, snap, d) / DELTA - 1 for d in DEPTHS],
    }


@pytest.fixture(scope="module")
def sphere():
    scene = prepare(CASE)
    return scene, solve(scene)


def test_closed_forms():
    assert (A, P0, DELTA) == pytest.approx((0.24455, 239.51, 1.1961e-3), rel=1e-4)
    # Huber's axial shortening from the surface to infinity is the approach (Hertz's delta is
    # pi a p0/(2 E*)); and it is the integral of his axial strain (quadrature, 1e-9).
    assert references.sphere_axis_compression(0.0, NU) * P0 * A / E == pytest.approx(
        DELTA, rel=1e-12
    )
    from scipy.integrate import quad

    def strain(zeta):
        sr, sz = references.sphere_axis_stresses(zeta, NU)
        return -(sz - 2 * NU * sr)

    for zeta in (0.5, 3.0):
        assert references.sphere_axis_compression(zeta, NU) == pytest.approx(
            quad(strain, zeta, np.inf, epsabs=1e-13)[0], rel=1e-9
        )


@needs_gmsh
def test_sphere_on_the_case_mesh(sphere):
    scene, result = sphere
    assert set(result["events"]["kind"]) == {"close"} and result["stop"]["kind"] == "completed"
    last = result["snapshots"][-1]
    assert np.sum(last["lambda_n"]) == pytest.approx(P, rel=1e-9)  # ring totals: the force P
    assert physics.equilibrium_residual(scene.model, last) < physics.EQUILIBRIUM_TOL
    err = errors(scene, result)
    ratio = H / A
    assert abs(err["a"]) <= ratio / 2, err
    assert abs(err["p0"]) <= ratio / 2, err
    assert err["rms"] <= ratio / 2 and err["max"] <= ratio, err
    assert all(abs(e) <= ratio**2 for e in err["delta"]), err


def fitted_order(h, e) -> float:
    """Least-squares slope of log|e| against log h."""
    return float(np.polyfit(np.log(h), np.log(np.abs(e)), 1)[0])


@needs_gmsh
def test_refinement_series_converges_at_the_expected_orders():
    """The whole mesh scaled by k = 4, 2, 1, 1/2 (0.7 s in all): a converges at first order
    (the edge is resolved to a node spacing), p0 and the profile at least at first order, the
    approach at second order (a displacement of linear elements).  Orders fitted over the
    series, asserted with a margin of 0.3 below the expectation (the finest errors approach the
    O(a/R) difference between the sphere and Hertz's half-space, measured ~1e-4 on delta)."""
    mesh = _body["mesh"]
    ks = np.array([4.0, 2.0, 1.0, 0.5])
    rows = []
    for k in ks:
        scene = prepare(
            CASE,
            [
                f"mesh.h_contact={mesh['h_contact'] * k}",
                f"mesh.growth={mesh['growth'] * k}",
                f"mesh.h_max={mesh['h_max'] * k}",
            ],
        )
        rows.append(errors(scene, solve(scene)))
    h = ks * H
    order = {key: fitted_order(h, [r[key] for r in rows]) for key in ("a", "p0", "rms")}
    order["delta"] = fitted_order(h, [r["delta"][1] for r in rows])  # at z = 5a
    assert order["a"] >= 0.7 and order["p0"] >= 1.0 and order["rms"] >= 1.0, (order, rows)
    assert order["delta"] >= 1.7, (order, rows)
    assert all(abs(r["a"]) < abs(q["a"]) for q, r in zip(rows, rows[1:])), rows


# --------------------------------------------------------------------------- first yield
SY = 130.0  # MPa: first yield at about two thirds of the load


def huber_first_yield(nu: float) -> tuple[float, float]:
    """(m, zeta): the largest von Mises stress on the axis over p0 and its depth z/a.  On the
    axis sigma_r = sigma_theta and tau_rz = 0, so sigma_e = |sigma_z - sigma_r| (Huber)."""
    best = minimize_scalar(
        lambda z: -np.subtract(*references.sphere_axis_stresses(z, nu)),
        bounds=(0.05, 2.0),
        method="bounded",
        options={"xatol": 1e-10},
    )
    return float(-best.fun), float(best.x)


@needs_gmsh
def test_first_yield_load_and_depth_follow_huber():
    """With Sy = 130 MPa the sphere first yields (von Mises) below the surface on the axis when
    p0 (f) = Sy/m (m = 0.620 at nu = 0.3, Huber's maximum of sigma_r - sigma_z at z = 0.481 a),
    i.e. at f = (Sy/(m p0))^3 with p0 ~ f^(1/3).  On the case mesh the first yield event must
    be within 1 % of that load fraction and its element's centroid within half an element
    (h/2 of the contact zone's size h) of Huber's depth 0.481 a(f).  The 1 % on f is 0.33 % on
    the stress: the tolerance is why a/R is small here (see the module doc)."""
    m, zeta = huber_first_yield(NU)
    assert (m, zeta) == pytest.approx((0.6200, 0.4807), abs=2e-4)  # Johnson: 0.62, 0.48
    f_ref = (SY / (m * P0)) ** 3
    scene = prepare(CASE, [f"material.Sy={SY}", "solver.stop_at_first_yield=true"])
    result = solve(scene)
    kinds = list(result["events"]["kind"])
    k = kinds.index("yield")
    f = float(result["events"]["load_fraction"][k])
    element = int(result["events"]["entity"][k])
    corners = scene.nodes[scene.triangles[element]]
    longest = max(np.linalg.norm(corners[i] - corners[i - 1]) for i in range(3))
    assert longest <= 1.5 * H  # it lies in the fine zone, where elements have the size H
    assert abs(f / f_ref - 1) <= 0.01, (f, f_ref)
    depth_ref = zeta * A * f_ref ** (1 / 3)
    assert abs(corners[:, 1].mean() - depth_ref) <= H / 2, (corners[:, 1].mean(), depth_ref)
    assert corners[:, 0].mean() <= H  # at the axis
