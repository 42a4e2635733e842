"""The default case against Hertz (frictionless) and the paper's frictional trends (§5.1).

Reference, plane strain: E* = E/(1-nu^2), a = sqrt(4PR/(pi E*)) = 1.4384 mm,
p0 = 2P/(pi a) = 442.6 MPa, and a(f) = a sqrt(f) at load fraction f (P scales with f).
"""

import math

import numpy as np
import pytest

from slipstep import run_case

R, E, NU, P = 125.0, 70000.0, 0.3, 1000.0
E_STAR = E / (1 - NU**2)
A_HERTZ = math.sqrt(4 * P * R / (math.pi * E_STAR))
P0_HERTZ = 2 * P / (math.pi * A_HERTZ)


def run(*overrides, events=True):
    """The default case; `events=True` keeps a snapshot after every event."""
    extra = ["output.snapshots=events"] if events else []
    return run_case(None, overrides=[*extra, *overrides])


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
    _, s = frictionless
    assert s["contact_half_width"] == pytest.approx(A_HERTZ, rel=0.01)
    assert s["peak_pressure"] == pytest.approx(P0_HERTZ, rel=0.01)


def test_refinement_reduces_the_error(frictionless):
    # Three meshes, h_contact halved each time: the errors of a and p0 must both decrease.
    # (a converges ~ linearly in h: its error is set by the node spacing at the contact edge.)
    errors = []
    for h in (0.12, 0.06):
        _, s = run(f"mesh.h_contact={h}", events=False)
        errors.append((abs(s["contact_half_width"] / A_HERTZ - 1), abs(s["peak_pressure"] / P0_HERTZ - 1)))
    s = frictionless[1]
    errors.append((abs(s["contact_half_width"] / A_HERTZ - 1), abs(s["peak_pressure"] / P0_HERTZ - 1)))
    ea, ep = np.array(errors).T
    assert np.all(np.diff(ea) < 0), f"a errors {ea}"
    assert np.all(np.diff(ep) < 0), f"p0 errors {ep}"



def test_every_closure_follows_hertz_growth(frictionless):
    # A node at x closes when the contact edge a*sqrt(f) reaches it: |x_i - a sqrt(f_i)| must be
    # within the local node spacing (the edge lies between the last closed and the next node).
    result, s = frictionless
    from slipstep import prepare
    scene = prepare(None)
    x = scene.pair_xy[:, 0]
    order = np.argsort(x)
    spacing = np.empty_like(x)
    xs = x[order]
    spacing[order] = np.maximum(np.diff(xs, prepend=xs[0]), np.diff(xs, append=xs[-1]))
    ev = result["events"]
    closes = [(int(e), f) for k, e, f in zip(ev["kind"], ev["entity"], ev["load_fraction"]) if k == "close"]
    assert len(closes) >= 40, "the default mesh closes ~48 nodes"
    for pair, f in closes:
        assert abs(x[pair] - A_HERTZ * math.sqrt(f)) <= spacing[pair], (pair, x[pair], f)


def test_normal_force_equals_applied_load_at_every_event(frictionless):
    # Quarter model: the flat carries P/2 at full load; every step ends in equilibrium.
    result, _ = frictionless
    steps = result["steps"]
    applied = np.asarray(steps["load_fraction"]) * P / 2
    np.testing.assert_allclose(steps["normal_force"], applied, rtol=1e-9)
    assert np.max(steps["residual"]) <= 1e-9


def test_frictional_stick_zone_slip_edges_and_coulomb(frictional):
    mu, (result, s) = frictional
    from slipstep import prepare
    x = prepare(None).pair_xy[:, 0]
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
    mu, (result, _) = frictional
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
    mu, (_, s) = frictional
    s0 = frictionless[1]
    assert s0["peak_pressure"] < s["peak_pressure"] < 1.10 * s0["peak_pressure"]
    assert 0.95 * s0["contact_half_width"] < s["contact_half_width"] < s0["contact_half_width"]
