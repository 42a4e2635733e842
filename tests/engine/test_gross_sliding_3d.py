"""A block on a rigid frictional plane in space, pressed, then pushed sideways until it slides.

Rigid-body statics (Coulomb): the block is held by friction alone, and its pairs carry at most
mu lambda_n each whatever their statuses and slip directions, so no equilibrium exists once the
tangential load T reaches mu N. Pressed by p = 1 on its 1 x 1 top (N = 1), then pushed by
tractions on its left face (along x) and its front face (along y), each face 1 x 0.5 (T = 0.5
tau at the stage's end), it slides at t = 1 + mu N / (0.5 tau), whatever the direction of the
push in the plane and however the pairs slip before (under the pressure they slip outwards,
radially: at mu = 0.2 all but the centre's from the first instant, at zero normal force).
The run stops there with its results (the issue's "a load that friction cannot hold").

The push has no moment about the vertical axis through the contact's centre (each face's
traction acts on its mid-line). A push with one (a slanted traction on the left face alone, or a
twist: a couple of tractions on the four sides) slides the block earlier, turning it, where the
load (F, M) meets the limit surface of planar sliding: some friction forces |f_i| <= mu
lambda_n,i balance the load up to there, none beyond. Checked independently from the arrays at
the stop: an LP with the pairs' Coulomb disks replaced by regular K-gons inscribed in them and
circumscribed about them brackets the factor on the load that the pairs can carry, which must
straddle 1; for the twist, whose normal forces are symmetric about the contact's centre (so it
turns about that centre), the closed form M = sum mu lambda_n,i |r_i - c|.

Checked for the pushes without a moment: the stop and its t against the closed form (to the engine's tie tolerance 1e-9 of the
stage, as the 2D block's), the results kept up to it, Coulomb at every snapshot recomputed from
the arrays, the equilibrium of the last snapshot recomputed from its stresses, and a push below
the capacity that completes.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from physics import EQUILIBRIUM_TOL, contact_force, equilibrium_residual
from scipy.optimize import linprog

from slipstep import build_scene, parse_case, solve

BLOCK = """
[analysis]
dimension = 3
[[stage]]
name = "press"
factors = {{ press = 1.0 }}
[[stage]]
name = "push"
factors = {{ {factors} }}
[output]
snapshots = "events"
[[body]]
name = "block"
[body.mesh]
generator = "box"
width = 1.0
depth = 1.0
height = 0.5
nx = 4
ny = 4
nz = 2
[body.material]
E = 1000.0
nu = 0.3
[[bc]]
name = "press"
body = "block"
face = "top"
pressure = 1.0
[[bc]]
name = "push"
body = "block"
face = "left"
traction = [{tx}, {ty_left}, 0.0]
{front}[[contact]]
kind = "rigid_plane"
body = "block"
face = "bottom"
mu = {mu}
"""

AREA_PUSHED, N = 0.5, 1.0  # a pushed face's area, the pressure's resultant
T_TOL = 1e-9  # the engine's tie tolerance on the stage fraction
SLIP_TURN = 0.1  # the engine's default facet angle (rad)
# Coulomb: a slipping pair's force lies on its facet, up to 1/cos(slip_turn) of the round cone
# (rust/src/contact.rs), plus the engine's contact check's round-off (1e-9 of the load).
FACET = 1.0 / math.cos(SLIP_TURN)
FORCE_TOL = 1e-9


FRONT = """[[bc]]
name = "push_y"
body = "block"
face = "front"
traction = [0.0, {ty}, 0.0]
"""


def run(mu: float, tau: float, angle_deg: float = 0.0):
    """The block pushed by tau at angle_deg to x: along x on its left face, along y on its front."""
    a = math.radians(angle_deg)
    ty = tau * math.sin(a)
    factors = "push = 1.0" + (", push_y = 1.0" if ty else "")
    front = FRONT.format(ty=ty) if ty else ""
    text = BLOCK.format(mu=mu, tx=tau * math.cos(a), ty_left=0.0, front=front, factors=factors)
    scene = build_scene(parse_case(text, "block.toml"))
    return scene, solve(scene)


@pytest.mark.parametrize(
    "mu, tau, angle", [(0.3, 1.0, 0.0), (0.2, 1.0, 0.0), (0.1, 1.0, 0.0), (0.3, 0.8, 30.0)]
)
def test_the_block_slides_where_the_push_reaches_mu_n(mu, tau, angle):
    scene, result = run(mu, tau, angle)
    stop = result["stop"]
    assert stop["kind"] == "support_lost", stop
    expected = 1.0 + mu * N / (AREA_PUSHED * tau)
    assert abs(stop["t"] - expected) <= T_TOL, (stop["t"], expected)
    snaps = result["snapshots"]
    assert snaps and abs(snaps[-1]["t"] - stop["t"]) <= T_TOL
    assert equilibrium_residual(scene.model, snaps[-1]) <= EQUILIBRIUM_TOL
    assert_coulomb(scene.model, result)
    # at the stop the pairs carry the whole push: their friction forces sum to T = mu N
    assert (
        abs(np.linalg.norm(snaps[-1]["lambda_t"].sum(axis=0)) - mu * N)
        <= FORCE_TOL + (FACET - 1) * mu * N
    )


def assert_coulomb(model: dict, result: dict) -> None:
    """No pair outside its facet at any snapshot, and none the last-resort rule froze."""
    assert "frozen" not in set(result["events"]["kind"])
    mu = np.asarray(model["pairs"]["mu"])
    for k, s in enumerate(result["snapshots"]):
        excess = np.linalg.norm(s["lambda_t"], axis=1) - FACET * mu * s["lambda_n"]
        assert excess.max() <= FORCE_TOL, (k, excess.max())


def test_a_push_below_the_capacity_is_held():
    # T = 0.5 x 0.5 = 0.25 < mu N = 0.3
    scene, result = run(0.3, 0.5)
    assert result["stop"]["kind"] == "completed", result["stop"]
    assert_coulomb(scene.model, result)
    assert equilibrium_residual(scene.model, result["snapshots"][-1]) <= EQUILIBRIUM_TOL


# ---------------------------------------------------------------- force and moment: turning

K_GON = 256  # facets of the LP's polygons: they bracket the disk's limit within 1/cos(pi/K) - 1 = 7.5e-5
LIMIT_TOL = 1e-9  # the engine's tie tolerance on the limit, with the arrays' round-off


def slanted(mu: float, tau: float, angle_deg: float):
    """The block pushed by tau at angle_deg to x on its left face alone: a moment about z."""
    a = math.radians(angle_deg)
    text = BLOCK.format(
        mu=mu, tx=tau * math.cos(a), ty_left=tau * math.sin(a), front="", factors="push = 1.0"
    )
    scene = build_scene(parse_case(text, "slanted.toml"))
    # the push's resultant at t = 2 and its moment about z through the origin: it acts on the
    # left face (x = 0) at its mid-line y = 0.5
    force = AREA_PUSHED * tau * np.array([math.cos(a), math.sin(a)])
    return scene, solve(scene), force, -0.5 * force[0]


TWIST = """[[bc]]
name = "t_{face}"
body = "block"
face = "{face}"
traction = [{tx}, {ty}, 0.0]
"""
# a couple on the four sides, each 1 x 0.5 at 0.5 from the centre: M = 4 x 0.5 x 0.5 tau = tau
# (the left face's share is BLOCK's push: -tau along y)
TWIST_FACES = {"right": (0.0, 1.0), "front": (1.0, 0.0), "back": (-1.0, 0.0)}


def twisted(mu: float, tau: float):
    """The block twisted about z by tau: no force, the moment tau at t = 2."""
    front = "".join(
        TWIST.format(face=f, tx=tau * x, ty=tau * y) for f, (x, y) in TWIST_FACES.items()
    )
    factors = ", ".join(f"t_{f} = 1.0" for f in TWIST_FACES)
    text = BLOCK.format(mu=mu, tx=0.0, ty_left=-tau, front=front, factors=factors + ", push = 1.0")
    scene = build_scene(parse_case(text, "twisted.toml"))
    return scene, solve(scene), np.zeros(2), tau


def pair_points(model: dict) -> np.ndarray:
    return np.asarray(model["nodes"], dtype=float)[np.asarray(model["pairs"]["node_a"])][:, :2]


def carried_factor(
    points: np.ndarray, capacity: np.ndarray, force: np.ndarray, moment: float, inscribed: bool
) -> float:
    """The largest k for which friction forces f_i in regular K-gons inscribed in the disks
    |f_i| <= capacity_i (circumscribed about them: inscribed False) balance k (force, moment
    about z through the origin): a lower (upper) bound of the disks' own k."""
    n = len(points)
    d = np.stack(
        [
            np.cos(2 * np.pi * np.arange(K_GON) / K_GON),
            np.sin(2 * np.pi * np.arange(K_GON) / K_GON),
        ],
        1,
    )
    shrink = math.cos(math.pi / K_GON) if inscribed else 1.0
    a_eq = np.zeros((3, 2 * n + 1))
    a_eq[0, 0 : 2 * n : 2] = 1.0
    a_eq[1, 1 : 2 * n : 2] = 1.0
    a_eq[2, 0 : 2 * n : 2], a_eq[2, 1 : 2 * n : 2] = -points[:, 1], points[:, 0]
    a_eq[:, -1] = [force[0], force[1], moment]
    a_ub = np.zeros((n * K_GON, 2 * n + 1))
    for i in range(n):
        a_ub[i * K_GON : (i + 1) * K_GON, 2 * i : 2 * i + 2] = d
    b_ub = shrink * np.repeat(np.maximum(capacity, 0.0), K_GON)
    cost = np.zeros(2 * n + 1)
    cost[-1] = -1.0
    out = linprog(
        cost,
        A_ub=a_ub,
        b_ub=b_ub,
        A_eq=a_eq,
        b_eq=np.zeros(3),
        bounds=[(None, None)] * (2 * n + 1),
        method="highs",
    )
    assert out.status == 0, out.message
    return float(out.x[-1])


def assert_stops_at_the_limit(scene, result, force_end, moment_end, mu):
    """The run stops turning, its results kept to the stop, where the load reaches the limit
    of the pairs at the stop (the LP bracket), in equilibrium, every pair within its facet."""
    stop = result["stop"]
    assert stop["kind"] == "support_lost" and "turning about" in stop["message"], stop
    snaps = result["snapshots"]
    assert snaps and abs(snaps[-1]["t"] - stop["t"]) <= T_TOL
    last, s = snaps[-1], stop["t"] - 1.0
    force, moment = s * force_end, s * moment_end
    points, capacity = pair_points(scene.model), mu * np.asarray(last["lambda_n"])
    low = carried_factor(points, capacity, force, moment, inscribed=True)
    high = carried_factor(points, capacity, force, moment, inscribed=False)
    assert low <= 1.0 + LIMIT_TOL and high >= 1.0 - LIMIT_TOL, (low, high)
    # the body's balance from the arrays: the pairs' forces carry the push (force and moment)
    f = contact_force(
        len(scene.model["nodes"]), scene.model["pairs"], last["lambda_n"], last["lambda_t"]
    ).reshape(-1, 3)
    nodes = np.asarray(scene.model["nodes"], dtype=float)
    friction = f[:, :2].sum(axis=0)
    turning = float((nodes[:, 0] * f[:, 1] - nodes[:, 1] * f[:, 0]).sum())
    assert np.abs(friction + force).max() <= FORCE_TOL and abs(turning + moment) <= FORCE_TOL, (
        friction,
        turning,
    )
    assert equilibrium_residual(scene.model, last) <= EQUILIBRIUM_TOL
    assert_coulomb(scene.model, result)


@pytest.mark.parametrize("mu, tau, angle", [(0.3, 0.8, 30.0), (0.2, 0.8, 60.0)])
def test_a_push_with_a_moment_stops_where_force_and_moment_reach_the_limit(mu, tau, angle):
    scene, result, force, moment = slanted(mu, tau, angle)
    assert_stops_at_the_limit(scene, result, force, moment, mu)
    # before the push alone reaches mu N: the moment matters (1.75 and 2.0 without it)
    assert result["stop"]["t"] < 1.0 + mu * N / np.linalg.norm(force) - 0.05, result["stop"]["t"]


def test_a_twist_turns_the_block_about_its_centre():
    mu, tau = 0.3, 0.5
    scene, result, force, moment = twisted(mu, tau)
    assert_stops_at_the_limit(scene, result, force, moment, mu)
    last = result["snapshots"][-1]
    points, ln = pair_points(scene.model), np.asarray(last["lambda_n"])
    # the normal forces are symmetric about the centre c (the pair at c - r has r's force), so
    # the twist turns the block about c, where the pairs carry M = sum mu lambda_n |r_i - c|
    centre = np.array([0.5, 0.5])
    mirror = [int(np.argmin(np.linalg.norm(points - (2 * centre - p), axis=1))) for p in points]
    assert np.abs(ln - ln[mirror]).max() <= FORCE_TOL
    capacity = mu * float((ln * np.linalg.norm(points - centre, axis=1)).sum())
    assert abs(moment * (result["stop"]["t"] - 1.0) - capacity) <= LIMIT_TOL * capacity, (
        result["stop"]["t"],
        capacity,
    )
