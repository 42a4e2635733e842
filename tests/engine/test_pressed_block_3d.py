"""A block pressed on a rigid frictional plane in space, with no tangential load: well posed at
every mu.

test_engine_3d's box (2 x 1 x 1, nu = 0.3 here) under a uniform pressure p on its top, held by
nothing but its frictional bottom pairs. Its Poisson expansion slides every bottom node outwards
(radially from the centre) at a low mu, at zero normal force from the first instant; the centre
node sticks (by symmetry it does not move). Rigid-body statics gives sum lambda_n = p x the top's
area and a zero friction resultant; no tangential load, so nothing slides the block as a whole.

Checked from the arrays: the run completes, equilibrium recomputed at every snapshot, no pair
beyond its facet (mu lambda_n / cos(slip_turn)) at any snapshot, the normal forces' sum, every
bottom pair but the centre's slipping outwards with its friction force inwards; at mu = 0.01 and
0.05 the mesh's symmetry about the centre (the pair at 2c - r carries r's forces mirrored) and
the friction force against the slip within the facet's angle.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from physics import EQUILIBRIUM_TOL, equilibrium_residual, tangent_basis
from test_engine_3d import block_on_a_frictional_plane

from slipstep.runner import engine

P, TOP_AREA = 2.0, 2.0  # block_on_a_frictional_plane's pressure and the box's top
SLIP_TURN = 0.1  # the engine's default facet angle (rad)
FACET = 1.0 / math.cos(SLIP_TURN)
# forces are sums of a few hundred O(1) operations: round-off ~1e-13 of P x area; an error in
# the statics or a mirrored force is of the order of the friction forces (1e-3 and up)
FORCE_TOL = 1e-9


def pressed(mu: float):
    model, _, _ = block_on_a_frictional_plane(0.0, mu)
    model["materials"] = [{"E": 1000.0, "nu": 0.3}]
    model["options"] = {"output": "events"}
    return model, engine().solve(model)


def in_plane(model: dict, snap: dict):
    """Each pair's position (x, y), its in-plane displacement and friction force (x, y)."""
    a = np.asarray(model["pairs"]["node_a"])
    points = np.asarray(model["nodes"], dtype=float)[a][:, :2]
    t1, t2 = tangent_basis(np.asarray(model["pairs"]["normal"], dtype=float))
    lt = np.asarray(snap["lambda_t"])
    friction = (lt[:, :1] * t1 + lt[:, 1:] * t2)[:, :2]
    u = np.asarray(snap["u"]).reshape(-1, 3)[a][:, :2]
    return points, u, friction


@pytest.mark.parametrize("mu", [0.01, 0.05, 0.1])
def test_a_pressed_block_runs_at_any_mu(mu):
    model, result = pressed(mu)
    assert result["stop"]["kind"] == "completed", result["stop"]
    assert "frozen" not in set(result["events"]["kind"])
    for k, snap in enumerate(result["snapshots"]):
        assert equilibrium_residual(model, snap) <= EQUILIBRIUM_TOL, k
        excess = np.linalg.norm(snap["lambda_t"], axis=1) - FACET * mu * np.asarray(
            snap["lambda_n"]
        )
        assert excess.max() <= FORCE_TOL * P, (k, excess.max())
    last = result["snapshots"][-1]
    points, u, friction = in_plane(model, last)
    assert abs(np.sum(last["lambda_n"]) - P * TOP_AREA) <= FORCE_TOL * P * TOP_AREA
    assert np.abs(friction.sum(axis=0)).max() <= FORCE_TOL * P * TOP_AREA
    centre = points.mean(axis=0)
    outward = points - centre
    rim = np.linalg.norm(outward, axis=1) > 0.0
    assert (np.asarray(last["status"])[rim] == 2).all(), last["status"]
    assert ((u * outward).sum(axis=1)[rim] > 0.0).all() and (
        (friction * outward).sum(axis=1)[rim] < 0.0
    ).all()


@pytest.mark.parametrize("mu", [0.01, 0.05])
def test_its_pairs_slip_symmetrically_against_their_friction(mu):
    model, result = pressed(mu)
    last = result["snapshots"][-1]
    points, u, friction = in_plane(model, last)
    centre = points.mean(axis=0)
    mirror = [int(np.argmin(np.linalg.norm(points - (2 * centre - p), axis=1))) for p in points]
    ln = np.asarray(last["lambda_n"])
    assert np.abs(ln - ln[mirror]).max() <= FORCE_TOL * P
    assert np.abs(friction + friction[mirror]).max() <= FORCE_TOL * P
    slipping = np.asarray(last["status"]) == 2
    cos = -(friction * u).sum(axis=1) / (
        np.linalg.norm(friction, axis=1) * np.linalg.norm(u, axis=1)
    )
    assert cos[slipping].min() >= math.cos(SLIP_TURN), cos[slipping].min()
