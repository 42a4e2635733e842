"""Termination of a chain of ever shorter increments (a Zeno chain) in space.

cases/mindlin_sphere_45_3d.toml on a coarse mesh (sphere h_contact 0.08, block 0.12), pressing
stage only: a pair at the edge of the growing contact closed, slipped and separated at one
instant, then closed again after an increment a third as long, and so on, 1.2e-5 of the stage
down to 1e-13, ended only by round-off: a slipping neighbour's turn of its held slip direction
is a force jump whose correction opened the pair again, and the turns shrank threefold.  Each
increment advanced the load, so the anti-cycling rule, which counts zero-length increments
only, never saw it.  A turn of the slip direction is now an event at which the force is
continuous but for a radial drop (rust/src/contact.rs: the facet of the round cone), so no
correction opens a pair that just closed, and the chain is gone.

Checked from the arrays: the closure times of every pair contain no long chain of intervals
that halve (the bound below), and the pressed state at the stage's end is in equilibrium
(recomputed from the stresses), without penetration or tension, inside Coulomb's cone.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import CASES, needs_gmsh
from physics import EQUILIBRIUM_TOL, equilibrium_residual

import slipstep

# Pressed monotonically, the contact grows (Hertz's radius with the load), so a pair closes once;
# one at the contact's edge may open and close again once as its neighbours' slip redistributes
# the pressure.  Two successive halving intervals between one pair's closures allow that; the
# chain before the facet design ran 17 (pair 2, t = 0.405676 .. 0.4056936).
LONGEST_CHAIN = 2
# Round-off tolerances relative to the scene's scales, as tests/engine/test_termination.py's:
# forces to the largest normal force (the engine's own contact check allows 1e-9 of its force
# scale), gaps to the largest displacement (the solves' round-off, ~1e-12, amplified by the
# mortar weights).
FORCE_TOL = 1e-9
GAP_TOL = 1e-8


def longest_halving_chain(events) -> int:
    """The most successive intervals between one pair's closures that each at most halve."""
    t, kind, entity = (np.asarray(events[k]) for k in ("t", "kind", "entity"))
    longest = 0
    for p in np.unique(entity[kind == "close"]):
        gaps = np.diff(np.sort(t[(kind == "close") & (entity == p)]))
        run = 1
        for before, after in zip(gaps[:-1], gaps[1:]):
            run = run + 1 if 0 < after <= 0.5 * before else 1
            longest = max(longest, run)
    return longest


@pytest.fixture(scope="module")
def pressed():
    pytest.importorskip("gmsh")
    overrides = [
        "body.sphere.mesh.h_contact=0.08",
        "body.block.mesh.h_contact=0.12",
        "output.snapshots=[1.0]",
    ]
    # the pressing stage is the scene: stop once the shear stage has begun
    return slipstep.run(
        CASES / "mindlin_sphere_45_3d.toml", overrides=overrides, progress=lambda p: p.t <= 1.0
    )


@needs_gmsh
def test_no_zeno_chain_while_the_sphere_is_pressed(pressed):
    assert pressed.raw["stop"]["t"] > 1.0, pressed.raw["stop"]
    assert longest_halving_chain(pressed.raw["events"]) <= LONGEST_CHAIN


@needs_gmsh
def test_the_pressed_sphere_is_balanced_and_admissible(pressed):
    model = pressed.scene.model
    snap = next(s for s in pressed.raw["snapshots"] if s["t"] == 1.0)
    assert equilibrium_residual(model, snap) <= EQUILIBRIUM_TOL
    closed = snap["status"] > 0
    ln, lt = np.asarray(snap["lambda_n"]), np.asarray(snap["lambda_t"])
    force = FORCE_TOL * ln.max()
    gap = GAP_TOL * np.abs(snap["u"]).max()
    assert (
        closed.any() and (snap["gap"] >= -gap).all() and (np.abs(snap["gap"][closed]) <= gap).all()
    )
    assert (ln[~closed] == 0).all() and (ln[closed] >= -force).all()
    # Coulomb: a stuck pair inside the round cone, a slipping pair on the facet of the cone at
    # its direction, up to mu lambda_n / cos(slip_turn) (rust/src/contact.rs)
    slip_turn = pressed.case.data["solver"]["slip_turn"]
    capacity = (
        np.asarray(model["pairs"]["mu"])
        * ln
        / np.where(snap["status"] == 2, np.cos(slip_turn), 1.0)
    )
    assert (np.linalg.norm(lt, axis=1) <= capacity + force).all()
