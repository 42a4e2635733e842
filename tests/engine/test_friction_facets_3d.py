"""Friction in space on small scenes, checked from the result arrays alone.

A slipping 3D pair slips on the facet of the round Coulomb cone at its held direction e (its
force λ_t = μ λ_n e + λ_⊥ e⊥, no slip across e), and the facet turns with the force when
|λ_⊥| reaches tan(slip_turn) μ λ_n (rust/src/contact.rs). What follows from that design, and
is checked here pair by pair at every snapshot (tests/physics.py's friction_in_space, which
gives the reasons):

- Coulomb on the facet: μ λ_n ≤ |λ_t| ≤ μ λ_n / cos(slip_turn) for a slipping pair (between
  turns the force is on the facet, beyond the round cone by at most 1/cos − 1), |λ_t| ≤ μ λ_n
  for a stuck one (the round cone exactly);
- no slipping pair produces work, whichever end's force of a step is taken;
- the force lags the slip by at most 2 slip_turn over a step;
- equilibrium recomputed from the stresses, the loads and the contact forces (tests/physics.py).

The scenes: a block pressed onto a rigid frictional flat by its top, then its top moved along
x and then along y, so that its bottom slides and its slip turns through a right angle; and a
tangential point load at a contact node that carries no normal force (a pair closed at zero
force), which slips at once (before, "an event was missed").
"""

from __future__ import annotations

from collections import Counter

import numpy as np
import pytest
from physics import EQUILIBRIUM_TOL, equilibrium_residual, friction_in_space
from space3d import BOX

from slipstep import _engine
from slipstep.build import build_scene
from slipstep.case import parse_case

SLIP_TURN = 0.1
MU = 0.3

TURNING = """
[analysis]
dimension = 3
[solver]
slip_turn = {slip_turn}
[output]
snapshots = "events"
[[stage]]
name = "press"
factors = {{ press = 1.0 }}
[[stage]]
name = "along_x"
factors = {{ along_x = 1.0 }}
[[stage]]
name = "along_y"
factors = {{ along_y = 1.0 }}
[[body]]
name = "b"
[body.mesh]
generator = "box"
width = 2.0
depth = 1.0
height = 0.5
nx = 4
ny = 2
nz = 1
[body.material]
E = 1000.0
nu = 0.0
[[bc]]
name = "press"
body = "b"
face = "top"
displacement = {{ z = -0.01 }}
[[bc]]
name = "along_x"
body = "b"
face = "top"
displacement = {{ x = 0.02 }}
[[bc]]
name = "along_y"
body = "b"
face = "top"
displacement = {{ y = 0.02 }}
[[contact]]
kind = "rigid_plane"
body = "b"
face = "bottom"
mu = {mu}
"""

# Round-off relative to the scene's scales, as tests/engine/test_rate_problem_3d.py's: forces
# to the larger of the applied forces and the largest contact force (the engine's noise floor
# is 1e-12 of its force scale, its own contact check 1e-9), lengths to the largest
# displacement (the solves' round-off on these small meshes is ~1e-12), a work to a force's
# round-off times a slip and vice versa, an angle between directions longer than those floors
# to 1e-6 rad. An error of the design (a force off its facet, a slip along its force) is of
# the order of the forces and slips themselves.
FORCE_TOL = 1e-9
LENGTH_TOL = 1e-9
ANGLE_TOL = 1e-6


def model_of(text: str) -> dict:
    return build_scene(parse_case(text, "scene.toml")).model


def assert_facets_hold(model: dict, result: dict, slip_turn: float) -> dict:
    """tests/physics.py's friction_in_space to round-off, and no tension; returns its values."""
    snaps = result["snapshots"]
    loads = max([np.abs(model["load"]).sum()] + [np.abs(s["lambda_n"]).max() for s in snaps])
    umax = max(np.abs(s["u"]).max() for s in snaps)
    force, length = FORCE_TOL * loads, LENGTH_TOL * umax
    for k, s in enumerate(snaps):
        assert (s["lambda_n"][s["status"] > 0] >= -force).all(), (k, "tension", s["lambda_n"].min())
    worst = friction_in_space(model, snaps, slip_turn, (length, force))
    assert worst["outside_round"] <= force, worst
    assert worst["inside_facet"] <= force and worst["beyond_facet"] <= force, worst
    assert worst["work"] <= loads * length + force * umax, worst
    assert worst["lag"] <= 2 * slip_turn + ANGLE_TOL, worst
    return worst


def test_a_slip_that_turns_through_a_right_angle_stays_on_its_facets():
    model = model_of(TURNING.format(slip_turn=SLIP_TURN, mu=MU))
    result = _engine.solve(model, False)
    assert result["stop"]["kind"] == "completed", result["stop"]
    kinds = Counter(result["events"]["kind"])
    assert "frozen" not in kinds, kinds
    # the bottom slides (stage along_x) and its slip turns towards y: facets turn
    assert kinds["stick_to_slip"] > 0 and kinds["slip_turn"] > 0, kinds
    seen = assert_facets_hold(model, result, SLIP_TURN)
    assert seen["slipping_steps"] > 0
    for k, s in enumerate(result["snapshots"]):
        assert equilibrium_residual(model, s) <= EQUILIBRIUM_TOL, (k, equilibrium_residual(model, s))
    # the top moved along x beyond what friction holds: at the end the whole bottom slips
    last = result["snapshots"][-1]
    assert (last["status"] == 2).all(), last["status"]


@pytest.mark.parametrize("slip_turn", [0.05, 0.4])
def test_the_facets_hold_at_other_angles(slip_turn):
    model = model_of(TURNING.format(slip_turn=slip_turn, mu=MU))
    result = _engine.solve(model, False)
    assert result["stop"]["kind"] == "completed", result["stop"]
    assert_facets_hold(model, result, slip_turn)


def loaded_contact_node(pull: float):
    """The box of tests/space3d.py, its top clamped instead of its bottom, one bottom node (the
    centre of the bottom face) on a rigid frictional flat at zero gap and zero force, a
    tangential point load on it (off the mesh's axes, its normal component `pull` upwards) and
    nothing else: the pair is closed and stuck, carrying nothing."""
    clamped_top = BOX.replace('face = "bottom"\nfix', 'face = "top"\nfix')
    assert clamped_top != BOX
    model = model_of(clamped_top + f"""
[output]
snapshots = "events"
[[point_load]]
at = [1.0, 0.5, 0.0]
force = [2.0, 1.0, {pull}]
[[contact]]
kind = "rigid_plane"
body = "b"
face = "bottom"
mu = 0.3
x_min = 0.9
x_max = 1.1
y_min = 0.4
y_max = 0.6
""")
    assert len(model["pairs"]["node_a"]) == 1
    return model


# The node's normal load: zero to round-off, of either sign (the engine's force noise is 1e-12
# of the load): the trial's normal force rate on the stuck pair is then round-off too.
@pytest.mark.parametrize("pull", [-1e-13, 0.0, 1e-13])
def test_a_tangential_load_on_a_contact_node_without_normal_force_slips_it(pull):
    """A stuck pair at zero normal force has no capacity: the load slips it at once (zero
    length) and the node moves with the load, the block carrying it; before, a pair pulled by
    round-off (Δλ_n ≤ 0 within the noise) kept it stuck beyond Coulomb's cone and the run ended
    with "an event was missed"."""
    model = loaded_contact_node(pull)
    result = _engine.solve(model, False)
    assert result["stop"]["kind"] == "completed", result["stop"]
    kinds = Counter(result["events"]["kind"])
    assert kinds["stick_to_slip"] + kinds["separate"] >= 1, kinds
    assert_facets_hold(model, result, SLIP_TURN)
    for k, s in enumerate(result["snapshots"]):
        assert equilibrium_residual(model, s) <= EQUILIBRIUM_TOL, (k, equilibrium_residual(model, s))
    last = result["snapshots"][-1]
    node = int(model["pairs"]["node_a"][0])
    force = np.array([2.0, 1.0, 0.0])
    assert last["status"][0] != 1  # not stuck
    assert last["u"][node] @ force > 0  # the load does positive work on its node
    # what the pair carries is bounded by Coulomb (above) and the rest is the clamped top's:
    # the pair cannot hold the load, so the reactions carry most of it
    assert np.linalg.norm(last["lambda_t"][0]) < np.linalg.norm(force)
