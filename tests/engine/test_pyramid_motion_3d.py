"""A pyramid pressed into a block by its motion, in space: zero-length runs at zero force.

A Vickers pyramid moved 0.2 into a block (E = 1000, mu = 0.3, the quarter with its symmetry
planes, a coarse mesh of 18 candidate pairs): its tip pair closes and slips at once at zero
force, and the statuses cycle at that instant: the rate problem settles them
(rust/src/driver/rate_problem.rs, handed back to the facet design of friction).  Before that
hand-back the anti-cycling rule's last resort froze the tip pair at t = 0.468, and a slipping
pair then produced work (friction along its slip, 7e-3).

The scene must complete without the last resort and its result satisfy, from the arrays at every
event: Signorini (no tension, no penetration), Coulomb (a stuck pair inside the round cone, a
slipping pair on the facet of the cone at its direction, tests/physics.py
``friction_in_space``), friction never producing work, and equilibrium recomputed from the
stresses.
"""

from __future__ import annotations

from collections import Counter

from physics import EQUILIBRIUM_TOL, equilibrium_residual, friction_in_space
from space3d import VICKERS_QUARTER

from slipstep import _engine
from slipstep.build import build_scene
from slipstep.case import parse_case

VICKERS = VICKERS_QUARTER.format(tip="[0.0, 0.0, 0.0]", h_contact=0.25, motion=-0.2)
MOTION = 0.2

# Round-off, relative to the force the scene carries (its final reaction): the engine's own
# contact check is 1e-9 of its force scale, of the order of that reaction; gaps relative to the
# motion, as the solves' round-off on this small mesh is ~1e-12 of the displacements.
FORCE_TOL = 1e-9
GAP_TOL = 1e-8


def test_a_pyramid_pressed_by_its_motion_is_admissible_at_every_event():
    model = build_scene(parse_case(VICKERS, "vickers.toml")).model
    model["options"] = {**model.get("options", {}), "output": "events"}
    result = _engine.solve(model, False)
    assert result["stop"]["kind"] == "completed", result["stop"]
    assert "frozen" not in Counter(
        result["events"]["kind"]
    ), "the last resort fired on a well-posed press"
    snaps = result["snapshots"]
    reaction = snaps[-1]["lambda_n"].sum()
    assert reaction > 0, "the pyramid presses the block"
    force, gap = FORCE_TOL * reaction, GAP_TOL * MOTION
    for k, s in enumerate(snaps):
        closed = s["status"] > 0
        assert (s["lambda_n"][closed] >= -force).all(), (k, "tension", s["lambda_n"].min())
        assert (s["gap"] >= -gap).all(), (k, "penetration", s["gap"].min())
        assert equilibrium_residual(model, s) <= EQUILIBRIUM_TOL, (
            k,
            equilibrium_residual(model, s),
        )
    friction = friction_in_space(
        model, snaps, model["options"]["slip_turn"], (gap, force), result["events"]
    )
    assert friction["outside_round"] <= force and friction["outside_polygon"] <= force, friction
    assert friction["inside_facet"] <= force and friction["beyond_facet"] <= force, friction
    # friction opposes the slip: the work λ_t·Δrtd of a slipping pair is never positive beyond
    # the round-off of a force times a displacement
    assert friction["work"] <= force * MOTION, friction
