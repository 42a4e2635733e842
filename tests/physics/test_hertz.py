"""The default case against Hertz (frictionless) and the paper's frictional trends (§5.1).

Reference, plane strain: E* = E/(1-nu^2), a = sqrt(4PR/(pi E*)) = 1.4384 mm,
p0 = 2P/(pi a) = 442.6 MPa, and a(f) = a sqrt(f) at load fraction f (P scales with f).
Plane stress (an elastic body on a rigid flat): E* = E, a = 1.5079 mm, p0 = 422.2 MPa.
Equilibrium is recomputed from each snapshot's stresses, load and contact forces
(tests/physics.py), not read from the engine.
"""

import math

import numpy as np
import pytest
from physics import EQUILIBRIUM_TOL, worst_equilibrium
from slipstep.measures.references import hertz_line

from slipstep import prepare, solve
from slipstep.output.summary import summarize

R, E, NU, P = 125.0, 70000.0, 0.3, 1000.0
E_STAR = E / (1 - NU**2)
A_HERTZ = math.sqrt(4 * P * R / (math.pi * E_STAR))
P0_HERTZ = 2 * P / (math.pi * A_HERTZ)


def run(*overrides, events=True):
    """The default case; `events=True` keeps a snapshot after every event.
    Returns (result, summary, scene)."""
    extra = ["output.snapshots=events"] if events else ["output.snapshots=[1.0]"]
    scene = prepare(None, overrides=[*extra, *overrides])
    result = solve(scene)
    return result, summarize(scene, result), scene


@pytest.fixture(scope="module")
def frictionless():
    return run()


@pytest.fixture(scope="module", params=[0.1, 0.35])
def frictional(request):
    return request.param, run(f"contact.mu={request.param}")


def test_reference_values_match_the_issue():
    assert A_HERTZ == pytest.approx(1.4384, abs=1e-4)
    assert P0_HERTZ == pytest.approx(442.6, abs=0.05)


def test_frictionless_a_and_p0_within_one_percent(frictionless):
    # Acceptance: 1 % on the default mesh (h = 0.03 mm at the contact, a/h ~ 48).
    _, s, _ = frictionless
    assert s["contact_half_width"] == pytest.approx(A_HERTZ, rel=0.01)
    assert s["peak_pressure"] == pytest.approx(P0_HERTZ, rel=0.01)


def test_contact_width_converges_at_first_order():
    """a against Hertz on four meshes, h_contact halved each time (a/h = 12 ... 96).

    Theory: the contact edge is located by the nodes: the last closed node and the next open
    one bracket it, and the interpolation between them in load fraction does not remove the
    error of the nodal (lumped) contact forces, which act a node spacing apart.  So |a − a_H|
    is O(h): first order, and never more than a node spacing.  The observed order of a
    least-squares fit of log|a − a_H| against log h must then be about 1; it is asserted > 0.8,
    the 20 % allowing for the pre-asymptotic coarsest mesh (a/h = 12) and for where the edge
    falls between nodes on each mesh.  A zeroth-order error (an edge off by a fixed amount, or
    one that jumps with the node positions) fails.  p0 is not monotone in h (the nodal pressure
    samples the peak with an O(h²) tributary average plus the FE error, of either sign): it is
    held to the 1 % acceptance on every mesh instead."""
    hs = np.array([0.12, 0.06, 0.03, 0.015])
    err_a = []
    for h in hs:
        _, s, _ = run(f"mesh.h_contact={h}", events=False)
        err_a.append(abs(s["contact_half_width"] / A_HERTZ - 1))
        assert abs(s["contact_half_width"] - A_HERTZ) <= h, (h, s["contact_half_width"])
        assert s["peak_pressure"] == pytest.approx(P0_HERTZ, rel=0.01), h
    order = np.polyfit(np.log(hs), np.log(err_a), 1)[0]
    assert order > 0.8, (order, err_a)


def test_every_closure_follows_hertz_growth(frictionless):
    # A node at x closes when the contact edge a*sqrt(f) reaches it: |x_i - a sqrt(f_i)| must be
    # within the local node spacing (the edge lies between the last closed and the next node).
    result, s, scene = frictionless
    x = scene.pair_xy[:, 0]
    order = np.argsort(x)
    spacing = np.empty_like(x)
    xs = x[order]
    spacing[order] = np.maximum(np.diff(xs, prepend=xs[0]), np.diff(xs, append=xs[-1]))
    ev = result["events"]
    closes = [
        (int(e), f)
        for k, e, f in zip(ev["kind"], ev["entity"], ev["load_fraction"])
        if k == "close"
    ]
    assert len(closes) >= 40, "the default mesh closes ~48 nodes"
    for pair, f in closes:
        assert abs(x[pair] - A_HERTZ * math.sqrt(f)) <= spacing[pair], (pair, x[pair], f)


def test_normal_force_equals_applied_load_at_every_event(frictionless):
    # Quarter model: the flat carries P/2 at full load (1e-9: round-off, the equilibrium
    # contract); every event state is in equilibrium, recomputed from its stresses.
    result, _, scene = frictionless
    for snap in result["snapshots"]:
        assert np.sum(snap["lambda_n"]) == pytest.approx(
            snap["load_fraction"] * P / 2, rel=1e-9, abs=1e-9 * P
        )
    worst, k, f = worst_equilibrium(scene.model, result["snapshots"])
    assert worst <= EQUILIBRIUM_TOL, (k, f, worst)


def test_frictional_stick_zone_slip_edges_and_coulomb(frictional):
    mu, (result, s, scene) = frictional
    x = scene.pair_xy[:, 0]
    worst, k, f = worst_equilibrium(scene.model, result["snapshots"])
    assert worst <= EQUILIBRIUM_TOL, (k, f, worst)
    for snap in result["snapshots"][1:]:
        ln, lt = np.asarray(snap["lambda_n"]), np.asarray(snap["lambda_t"])
        # Coulomb at every pair and every event (1e-9 relative: the cone is hit exactly).
        assert np.all(np.abs(lt) <= mu * ln * (1 + 1e-9) + 1e-12)
        assert np.all(ln >= -1e-12)
        assert np.all(np.asarray(snap["gap"]) >= -1e-12)
    last = result["snapshots"][-1]
    st = np.asarray(last["status"])
    stick, slip = x[st == 1], x[st == 2]
    assert len(stick) >= 2 and len(slip) >= 2
    assert stick.max() < slip.min(), "the stick zone is central and the slip zones are its edges"
    assert 0 < s["stick_half_width"] < s["contact_half_width"]


def test_rtd_frozen_in_stick_zone_and_opposing_friction_in_slip_zone(frictional):
    # Stick: no relative tangential displacement since the pair last stuck (its RTD is the
    # value it had slipped to before, as in Spence's self-similar solution). Slip: the friction
    # force opposes the relative displacement, lambda_t * RTD < 0.
    mu, (result, _, _) = frictional
    snaps = result["snapshots"]
    last = snaps[-1]
    st, rtd, lt = (np.asarray(last[k]) for k in ("status", "rtd", "lambda_t"))
    statuses = np.array([s["status"] for s in snaps])
    rtds = np.array([s["rtd"] for s in snaps])
    scale = np.max(np.abs(rtd))
    for p in np.flatnonzero(st == 1):
        since = len(snaps) - 1
        while since > 0 and statuses[since - 1, p] == 1:
            since -= 1
        assert np.all(np.abs(rtds[since:, p] - rtd[p]) <= 1e-9 * scale), p
    for p in np.flatnonzero(st == 2):
        if abs(rtd[p]) > 1e-6 * scale:
            assert lt[p] * rtd[p] < 0, (p, lt[p], rtd[p])


def test_friction_raises_central_pressure_and_shrinks_contact_slightly(frictionless, frictional):
    # Paper §5.1 (elastic): with friction the central pressure rises slightly and the contact
    # length shrinks slightly. "Slightly": less than 10 % here.
    mu, (_, s, _) = frictional
    s0 = frictionless[1]
    assert s0["peak_pressure"] < s["peak_pressure"] < 1.10 * s0["peak_pressure"]
    assert 0.95 * s0["contact_half_width"] < s["contact_half_width"] < s0["contact_half_width"]


# --------------------------------------------------------------------------- plane stress
def test_plane_stress_against_plane_stress_hertz():
    """`analysis.plane = "stress"`: an elastic body on a rigid flat has E* = E (plane strain:
    E/(1 − ν²)), so a = 1.5079 mm (+4.8 %) and p0 = 422.2 MPa (−4.6 %).

    Tolerance: the 1 % of the plane-strain acceptance test, for the same reason. The plane
    stress CST problem with (E, ν) is exactly the plane strain one with E' = E(1 + 2ν)/(1 + ν)²,
    ν' = ν/(1 + ν) (same D matrix), whose E'/(1 − ν'²) = E: frictionless Hertz depends on the
    material only through E*, and the mesh resolves this a with a/h = 50 nodes (48 in plane
    strain), so the discretization error is the plane-strain one. The plane-strain formulas
    are 4.6-4.8 % away: the test tells the two apart."""
    result, s, scene = run("analysis.plane=stress", events=False)
    assert scene.model["plane"] == "stress"
    a, p0 = hertz_line(P, R, E, NU, "stress")
    assert a == pytest.approx(1.5079, abs=1e-4) and p0 == pytest.approx(422.2, abs=0.05)
    assert s["contact_half_width"] == pytest.approx(a, rel=0.01)
    assert s["peak_pressure"] == pytest.approx(p0, rel=0.01)
    assert abs(A_HERTZ / a - 1) > 0.02 and abs(P0_HERTZ / p0 - 1) > 0.02
    # plane stress: σz = 0 in every element, to round-off relative to the in-plane stresses
    # (1e-12: a few operations in double precision)
    last = np.asarray(result["snapshots"][-1]["stress"])
    assert np.abs(last[:, 2]).max() <= 1e-12 * np.abs(last[:, :2]).max()
    worst, k, f = worst_equilibrium(scene.model, result["snapshots"])
    assert worst <= EQUILIBRIUM_TOL, (k, f, worst)


def test_plane_strain_out_of_plane_stress(frictionless):
    # Elastic plane strain: εz = 0 gives σz = ν(σx + σy) in every element; round-off relative
    # to the largest in-plane stress (1e-12: a few operations in double precision).
    result, _, _ = frictionless
    s = np.asarray(result["snapshots"][-1]["stress"])
    scale = np.abs(s[:, :2]).max()
    assert np.abs(s[:, 2] - NU * (s[:, 0] + s[:, 1])).max() <= 1e-12 * scale
