"""Contact nodes on symmetry planes in space: a quarter block pressed by a Vickers pyramid.

The node at the block's corner (0, 0, 0) lies on both symmetry planes, so only its z is free.
With the pyramid's tip on it, the contact normal there is the pyramid's axis (the pyramid is
symmetric about it, and so is the body's surface): a face's normal (the rule before) tilted the
pair, whose tangential rows then acted on the same single free DOF as its normal row, and the
contact system was singular at the first instant. With the tip moved off the corner (a model no
longer symmetric, but a well-posed discrete problem) a face's tilted normal acts there, and on
the nodes of each symmetry plane: a tangential row whose free part only repeats the normal's is
the support's, not a constraint.

Checked from the result arrays: equilibrium recomputed from the stresses at every snapshot
(tests/physics.py, to its stated EQUILIBRIUM_TOL), Signorini (no penetration, no tension) and
Coulomb's cone on every pair whose tangential DOFs are free (for a slipping pair the facet it
slips on), and the pyramid carrying
load (the pressed block pushes back).
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import needs_gmsh
from physics import EQUILIBRIUM_TOL, worst_equilibrium
from space3d import VICKERS_QUARTER

from slipstep import build_scene, parse_case, solve


# Forces here are of order E h^2 x strain ~ 1; a round-off of the engine's small systems is
# ~1e-12 of that, and Coulomb's cone is held to the same relative size.
FORCE_TOL = 1e-9


def run(tip: str):
    scene = build_scene(
        parse_case(VICKERS_QUARTER.format(tip=tip, h_contact=0.1, motion=-0.12), "vickers.toml")
    )
    return scene, solve(scene)


@needs_gmsh
def test_the_normal_under_a_pyramid_tip_is_its_axis():
    scene = build_scene(
        parse_case(
            VICKERS_QUARTER.format(tip="[0.0, 0.0, 0.0]", h_contact=0.1, motion=-0.12), "v.toml"
        )
    )
    pairs = scene.model["pairs"]
    corner = np.flatnonzero(np.linalg.norm(scene.nodes[pairs["node_a"]], axis=1) == 0.0)
    assert len(corner) == 1
    # the obstacle's normal points to the body, which lies below the pyramid
    assert np.allclose(pairs["normal"][corner[0]], [0.0, 0.0, -1.0], atol=1e-12)


@needs_gmsh
@pytest.mark.parametrize(
    "tip",
    ["[0.0, 0.0, 0.0]", "[0.01, 0.013, 0.0]"],
    ids=["tip_on_the_corner", "tip_off_the_corner"],
)
def test_a_pyramid_on_a_corner_node_of_two_symmetry_planes_runs_in_balance(tip):
    scene, result = run(tip)
    assert result["stop"]["kind"] == "completed", result["stop"]
    model, snaps = scene.model, result["snapshots"]
    residual, k, f = worst_equilibrium(model, snaps)
    assert residual <= EQUILIBRIUM_TOL, (residual, k, f)
    held = np.zeros((len(scene.nodes), 3), dtype=bool)
    held.reshape(-1)[np.asarray(model["fixed_dofs"], dtype=np.int64)] = True
    pairs = model["pairs"]
    tangent = np.asarray(pairs["tangent"])
    node_held = held[pairs["node_a"]]
    # a tangent is the support's when its free part has nothing across the normal's free part
    free_n = np.where(node_held, 0.0, pairs["normal"])
    free_side = [
        np.linalg.norm(
            np.where(node_held, 0.0, tangent[:, j])
            - np.einsum("pk,pk->p", np.where(node_held, 0.0, tangent[:, j]), free_n)[:, None]
            * free_n
            / np.einsum("pk,pk->p", free_n, free_n)[:, None],
            axis=1,
        )
        > 1e-9
        for j in (0, 1)
    ]
    last = snaps[-1]
    ln = np.asarray(last["lambda_n"])
    lt = np.asarray(last["lambda_t"]).reshape(-1, 2)
    assert (ln >= -FORCE_TOL).all(), ln.min()
    assert (np.asarray(last["gap"]) >= -FORCE_TOL).all()
    carried = np.where(np.stack(free_side, axis=1), lt, 0.0)
    size = np.linalg.norm(carried, axis=1)
    # a slipping pair slips on the facet of the cone at its direction, up to 1/cos(slip_turn)
    # of mu lambda_n (rust/src/contact.rs; slip_turn at its default 0.1)
    capacity = 0.3 * ln / np.where(np.asarray(last["status"]) == 2, np.cos(0.1), 1.0)
    assert (size <= capacity + FORCE_TOL * max(1.0, ln.max())).all(), (size - capacity).max()
    assert ln.sum() > 0.0
