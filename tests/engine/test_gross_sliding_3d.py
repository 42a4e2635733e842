"""A block on a rigid frictional plane in space, pressed, then pushed sideways until it slides.

Rigid-body statics (Coulomb): the block is held by friction alone, and its pairs carry at most
mu lambda_n each whatever their slip directions, so no equilibrium exists once the tangential
load T reaches mu N; below that the block is held. Pressed by p = 1 on its 1 x 1 top (N = 1),
then pushed by a traction tau on its left face (1 x 0.5: T = 0.5 tau at the stage's end), it
slides at t = 1 + mu N / (0.5 tau), whatever the direction of the push in the plane and however
the pairs slip before (under the pressure they slip outwards, radially, from the first instant:
a block held by pairs that all slip in different directions is not sliding).  The run stops
there with its results (the issue's "a load that friction cannot hold").

Checked: the stop and its t against the closed form (to the engine's tie tolerance 1e-9 of the
stage, as the 2D block's), the results kept up to it, the equilibrium of the last snapshot
recomputed from its stresses, and a push below the capacity that completes.
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
factors = {{ push = 1.0 }}
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
traction = [{tx}, {ty}, 0.0]
[[contact]]
kind = "rigid_plane"
body = "block"
face = "bottom"
mu = {mu}
"""

AREA_LEFT, N = 0.5, 1.0   # the pushed face's area, the pressure's resultant
T_TOL = 1e-9              # the engine's tie tolerance on the stage fraction


def run(mu: float, tau: float, angle_deg: float = 0.0):
    a = math.radians(angle_deg)
    text = BLOCK.format(mu=mu, tx=tau * math.cos(a), ty=tau * math.sin(a))
    scene = build_scene(parse_case(text, "block.toml"))
    return scene, solve(scene)


@pytest.mark.parametrize("mu, tau, angle", [(0.3, 1.0, 0.0), (0.2, 1.0, 0.0), (0.3, 0.8, 30.0)])
def test_the_block_slides_where_the_push_reaches_mu_n(mu, tau, angle):
    scene, result = run(mu, tau, angle)
    stop = result["stop"]
    assert stop["kind"] == "support_lost", stop
    expected = 1.0 + mu * N / (AREA_LEFT * tau)
    assert abs(stop["t"] - expected) <= T_TOL, (stop["t"], expected)
    snaps = result["snapshots"]
    assert snaps and abs(snaps[-1]["t"] - stop["t"]) <= T_TOL
    assert equilibrium_residual(scene.model, snaps[-1]) <= EQUILIBRIUM_TOL


def test_a_push_below_the_capacity_is_held():
    # T = 0.5 x 0.5 = 0.25 < mu N = 0.3
    scene, result = run(0.3, 0.5)
    assert result["stop"]["kind"] == "completed", result["stop"]
    assert equilibrium_residual(scene.model, result["snapshots"][-1]) <= EQUILIBRIUM_TOL
