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
traction acts on its mid-line): a push with one (a slanted traction on the left face alone)
slides the block earlier, turning it, where the load meets the contact's limit surface of
force and moment, and that is not what this file checks.

Checked: the stop and its t against the closed form (to the engine's tie tolerance 1e-9 of the
stage, as the 2D block's), the results kept up to it, Coulomb at every snapshot recomputed from
the arrays, the equilibrium of the last snapshot recomputed from its stresses, and a push below
the capacity that completes.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from physics import EQUILIBRIUM_TOL, equilibrium_residual

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
traction = [{tx}, 0.0, 0.0]
{front}[[contact]]
kind = "rigid_plane"
body = "block"
face = "bottom"
mu = {mu}
"""

AREA_PUSHED, N = 0.5, 1.0  # a pushed face's area, the pressure's resultant
T_TOL = 1e-9               # the engine's tie tolerance on the stage fraction
SLIP_TURN = 0.1            # the engine's default facet angle (rad)
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
    text = BLOCK.format(mu=mu, tx=tau * math.cos(a), front=front, factors=factors)
    scene = build_scene(parse_case(text, "block.toml"))
    return scene, solve(scene)


@pytest.mark.parametrize("mu, tau, angle", [(0.3, 1.0, 0.0), (0.2, 1.0, 0.0), (0.1, 1.0, 0.0),
                                            (0.3, 0.8, 30.0)])
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
    assert abs(np.linalg.norm(snaps[-1]["lambda_t"].sum(axis=0)) - mu * N) <= FORCE_TOL + (FACET - 1) * mu * N


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
