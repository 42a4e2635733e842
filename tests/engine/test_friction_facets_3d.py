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
force), which slips at once (before, "an event was missed"); and an elastoplastic quarter block
pressed by a Vickers pyramid and unloaded, where a pair closes at a round-off λ_n and must slip
at once (before, it stayed stuck far outside its cone).
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
    worst = friction_in_space(model, snaps, slip_turn, (length, force), result["events"])
    assert worst["outside_round"] <= force and worst["outside_polygon"] <= force, worst
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
        assert equilibrium_residual(model, s) <= EQUILIBRIUM_TOL, (
            k,
            equilibrium_residual(model, s),
        )
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
    model = model_of(
        clamped_top
        + f"""
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
"""
    )
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
        assert equilibrium_residual(model, s) <= EQUILIBRIUM_TOL, (
            k,
            equilibrium_residual(model, s),
        )
    last = result["snapshots"][-1]
    node = int(model["pairs"]["node_a"][0])
    force = np.array([2.0, 1.0, 0.0])
    assert last["status"][0] != 1  # not stuck
    assert last["u"][node] @ force > 0  # the load does positive work on its node
    # what the pair carries is bounded by Coulomb (above) and the rest is the clamped top's:
    # the pair cannot hold the load, so the reactions carry most of it
    assert np.linalg.norm(last["lambda_t"][0]) < np.linalg.norm(force)


PYRAMID = """
[analysis]
dimension = 3
[output]
snapshots = {snapshots}
[[stage]]
name = "load"
factors = {{ press = 1.0 }}
[[stage]]
name = "unload"
factors = {{ press = 0.0 }}
[[body]]
name = "block"
[body.mesh]
generator = "box"
x0 = 0.0
y0 = 0.0
z0 = -3.0
width = 3.0
depth = 3.0
height = 3.0
h_contact = 0.1
contact_zone = 0.6
h_max = 1.0
growth = 0.3
focus = [0.0, 0.0, 0.0]
[body.material]
E = {E}
nu = 0.3
Sy = 500.0
H = 2000.0
[[bc]]
body = "block"
face = "bottom"
fix = ["x", "y", "z"]
[[bc]]
body = "block"
face = "left"
symmetry = true
[[bc]]
body = "block"
face = "front"
symmetry = true
[[contact]]
name = "press"
kind = "rigid_surface"
indenter = "vickers"
tip = [0.0, 0.0, 0.0]
size = 1.0
body = "block"
face = "top"
x_max = 1.0
y_max = 1.0
mu = {mu}
motion = [0.0, 0.0, -{depth}]
"""

PYRAMID_E, PYRAMID_DEPTH = 200000.0, 0.05
# The round-off floor the checks allow: 1e-12 of Σ_pairs E D |motion|, D the mesh's diameter
# — the engine's own floor for a round-off force rate was 1e-12 of that sum; it is now 1e-12 of
# the motion's punch force E |motion| ℓ (rust/src/driver/problem.rs, motion_forces), smaller,
# so the sum bounds it. A pair whose rates within one step are below the floor is not
# switched, so one step moves a stuck pair towards the outside of its cone by at most (1 + μ)
# × that (λ_t and μ λ_n each by the floor), and a switch whose force jump is below it is not
# rebalanced (rust/src/driver/mod.rs, `settle`): it leaves an out-of-balance force up to the
# floor. An event missed moves a pair by the order of its force (on the Vickers block ~0.1,
# the reactions ~40): four and six orders above these.
ENGINE_FORCE_NOISE = 1e-12


def assert_indented_admissibly(
    model: dict, result: dict, young: float, depth: float, every_event: bool
):
    """An indentation by an obstacle's motion (its material's E `young`, the motion's length
    `depth`), completed, checked at every snapshot from the result arrays: Coulomb (stuck pairs
    on or inside the round cone, or their polygon once they slipped, slipping ones on their
    facets: μλ_n ≤ |λ_t| ≤ μλ_n/cos slip_turn), no tension, equilibrium recomputed; at `every_event` also no work produced by a
    slip over a step (its argument holds over one step: tests/physics.py)."""
    assert result["stop"]["kind"] == "completed", result["stop"]
    snaps, slip_turn = result["snapshots"], model["options"]["slip_turn"]
    mu = float(np.max(model["pairs"]["mu"]))
    diameter = np.linalg.norm(np.ptp(np.asarray(model["nodes"]), axis=0))
    noise = ENGINE_FORCE_NOISE * len(model["pairs"]["mu"]) * young * diameter * depth
    umax = max(np.abs(s["u"]).max() for s in snaps)
    worst = friction_in_space(model, snaps, slip_turn, (LENGTH_TOL * umax, noise), result["events"])
    assert (
        worst["outside_round"] <= (1 + mu) * noise and worst["outside_polygon"] <= (1 + mu) * noise
    ), worst
    assert worst["beyond_facet"] <= (1 + mu) * noise, worst
    # on its facet λ_t·e = μ λ_n holds exactly (a row of the solve), so a slipping pair is short
    # of μ λ_n only by the round-off of its forces; a pair slipping with no direction carries
    # no friction at all, short by μ λ_n, of the order of the forces
    assert worst["inside_facet"] <= (1 + mu) * noise, worst
    if every_event:
        assert worst["work"] <= noise * umax, worst
    for k, s in enumerate(snaps):
        assert (s["lambda_n"][s["status"] > 0] >= -noise).all(), (k, "tension", s["lambda_n"].min())
        reactions = np.linalg.norm(s["reaction"])  # the residual's scale (tests/physics.py)
        off_balance = equilibrium_residual(model, s) * reactions
        assert off_balance <= EQUILIBRIUM_TOL * reactions + noise, (k, off_balance)


# The snapshots cut increments: at three times the run meets the pair as described below; at
# every event it is checked everywhere (its path differs, its pairs close at other forces).
@pytest.mark.parametrize("snapshots", ["[0.5, 1.0, 2.0]", '"events"'])
def test_a_pair_closing_under_a_pyramids_edge_slips_where_it_leaves_the_cone(snapshots):
    """A quarter block, elastoplastic, pressed by a Vickers pyramid and unloaded (1.6k DOFs).
    A pair under the pyramid's edge closes inside a plastic increment; the correction at fixed
    load leaves its λ_n a round-off below zero, so it starts the next increment outside its
    cone by round-off, where the squared cone's test looks at the cone's mirror image: it stayed
    stuck while its friction force grew to four times μ λ_n (before, the run ended with
    "violates Coulomb's law ... after the equilibrium correction" at t = 0.787)."""
    model = model_of(PYRAMID.format(E=PYRAMID_E, depth=PYRAMID_DEPTH, mu=0.3, snapshots=snapshots))
    result = _engine.solve(model, False)
    kinds = Counter(result["events"]["kind"])
    assert kinds["yield"] > 0 and kinds["stick_to_slip"] > 0, kinds
    assert_indented_admissibly(model, result, PYRAMID_E, PYRAMID_DEPTH, snapshots == '"events"')


@pytest.mark.parametrize("mu", [0.1, 0.5])
def test_a_pair_that_slips_as_it_closes_carries_its_friction_once_loaded(mu):
    """The pyramid of the test above, every event a snapshot, at other friction coefficients.
    A pair under the pyramid closes at the end of a plastic increment and slips at once, at
    zero force, so it has no friction force to take its slip direction from; the equilibrium
    correction at fixed load that follows then presses it (λ_n up to ~1e-3 of the largest).
    It must slip on its facet, its friction force μ λ_n against its slip (before, it took its
    direction only at the next increment's trial and carried no friction in between: at
    μ = 0.1 five snapshots, at 0.5 two, showed a slipping pair with λ_n up to 3e-3 and
    λ_t = 0)."""
    model = model_of(PYRAMID.format(E=PYRAMID_E, depth=PYRAMID_DEPTH, mu=mu, snapshots='"events"'))
    result = _engine.solve(model, False)
    slipping = sum(
        int(((s["status"] == 2) & (s["lambda_n"] > 0)).sum()) for s in result["snapshots"]
    )
    assert slipping > 0  # pressed pairs do slip
    assert_indented_admissibly(model, result, PYRAMID_E, PYRAMID_DEPTH, every_event=True)


BERKOVICH = """
[analysis]
dimension = 3
[output]
snapshots = [0.5, 1.0]
[[body]]
name = "block"
[body.mesh]
generator = "box"
x0 = -2.0
y0 = -2.0
z0 = -2.0
width = 4.0
depth = 4.0
height = 2.0
h_contact = 0.16
contact_zone = 0.5
h_max = 0.8
growth = 0.3
focus = [0.0, 0.0, 0.0]
[body.material]
E = 1000.0
nu = 0.3
Sy = 5.0
[[bc]]
body = "block"
face = "bottom"
fix = ["x", "y", "z"]
[[contact]]
kind = "rigid_surface"
indenter = "berkovich"
tip = [0.0, 0.0, 0.0]
size = 1.0
body = "block"
face = "top"
x_min = -0.8
x_max = 0.8
y_min = -0.8
y_max = 0.8
mu = 0.2
motion = [0.0, 0.0, -0.1]
"""


def test_a_slip_switched_below_the_force_noise_inside_contact_substeps_keeps_the_path():
    """A whole block under a Berkovich pyramid, perfectly plastic (1.5k DOFs). Inside a plastic
    window's contact sub-steps a stuck pair outside its cone by round-off slips at once, and its
    force is put on the cone: a jump below the force noise, so the sub-steps go on. The whole
    increment takes the end forces with that jump, which no sub-step moved (before, the run
    ended with "contact sub-steps: the increment's displacement differs from its sub-steps'" at
    t = 0.756)."""
    model = model_of(BERKOVICH)
    result = _engine.solve(model, False)
    assert_indented_admissibly(model, result, 1000.0, 0.1, False)


def test_zero_length_contact_substeps_with_jumps_below_the_noise_pass_the_path_check():
    """The Berkovich block above at μ = 0.5. Inside a plastic window a run of contact
    sub-steps all of zero length switches pairs whose force jumps stay below the force noise
    (put on their cones): the whole increment is zero, and its path check compared the jumps'
    displacement (4e-10) with a largest displacement of zero (before, the run ended with
    "contact sub-steps: the increment's displacement differs from its sub-steps' by 4.3e-10
    (of 0.0e0)" at t = 0.898)."""
    model = model_of(BERKOVICH.replace("mu = 0.2", "mu = 0.5"))
    result = _engine.solve(model, False)
    assert_indented_admissibly(model, result, 1000.0, 0.1, False)
