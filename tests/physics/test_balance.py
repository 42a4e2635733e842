"""Every body in balance and every rigid obstacle against the bodies it touches, recomputed from
the result arrays at every snapshot, for every shipped case and for scenes of every contact
kind (rigid line, circle, polyline with convex and concave corners, closed polylines with the
body outside and inside, node_to_segment, node_to_node), plane and axisymmetric.

Per body B (tests/physics.py ``balance_terms``): Σ contact forces (λ_n n + λ_t t per pair in
the pair frames the run was given, the opposite on node b, node-to-segment rows spread by
their weights) + applied load at the snapshot's path time + support reactions (the result's
``reaction``) = 0, each component (in axisymmetry the axial one: ring forces have no radial
resultant).  Per rigid obstacle k touching the bodies T: its total force on them
Σ_k (λ_n n + λ_t t) = −Σ_T (load + reaction + the other contacts' forces), so the obstacle's
contact force equals minus the reactions it causes.  And the reactions themselves recomputed
from the stresses (internal force − load − contact at the held DOFs).  And a flat punch posed
with its sides presses exactly like the punch face alone (the sides touch nothing).

Tolerances:
- balance: EQUILIBRIUM_TOL (the engine's equilibrium contract) relative to the body's largest
  scale over the run, Σ |nodal terms| (the size of the numbers summed; the run's largest, so
  that an unloaded end state with residual forces near round-off is not divided by its own
  round-off).  A body's internal forces sum to zero exactly (each element's do, to
  round-off), so its balance is the sum of the engine's unbalanced force over its free DOFs,
  which the contract bounds; measured at most 3e-13.  A force in the wrong frame (a normal or
  weight not the engine's, a sign of t) or a reaction not the supports' is O(1).
- the reactions recomputed: 1e-12 relative to the largest |force| of the snapshot, round-off
  of summing a few element forces per DOF (measured at most 7e-17).
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from conftest import CASES, needs_gmsh, shipped_cases
from physics import (
    EQUILIBRIUM_TOL,
    balance_terms,
    body_sums,
    contact_force,
    node_body,
    obstacle_force,
    recomputed_reaction,
)

from slipstep import build_scene, parse_case, prepare, solve

ROUND_OFF = 1e-12

# The shipped cases, coarsened where a shipped mesh takes seconds (the balance holds on any
# mesh), every event a snapshot. The 3D cases' balance is the 3D physics tests' (their meshes
# need coarsening of their own).
COARSE = {
    "cattaneo_mindlin": ["body.roller.mesh.h_contact=0.2", "body.block.mesh.h_contact=0.2"],
    "sphere_on_flat_plastic": ["mesh.h_contact=0.02"],
}
SHIPPED = [p.stem for p in shipped_cases(2)]


def assert_balanced(scene, result) -> None:
    """The body and obstacle balances and the recomputed reactions at every snapshot."""
    model, snaps = scene.model, result["snapshots"]
    assert snaps and "reaction" in snaps[0]
    terms = [balance_terms(model, s) for s in snaps]
    scale = np.max([t["scale"] for t in terms], axis=0)  # (B, 2) over the run
    axes = [1] if model["plane"] == "axisymmetric" else [0, 1]
    for k, (snap, t) in enumerate(zip(snaps, terms)):
        where = f"snapshot {k} (t = {snap.get('t', snap['load_fraction']):.6g})"
        total = t["contact"] + t["load"] + t["reaction"]
        bad = np.abs(total[:, axes]) > EQUILIBRIUM_TOL * scale[:, axes]
        assert not bad.any(), (
            f"{where}: body balance {total[:, axes]} against the forces' " f"scale {scale[:, axes]}"
        )
        _assert_obstacles(model, snap, t, scale, axes, where)
        reaction = np.asarray(snap["reaction"], dtype=float).reshape(-1)
        size = max(np.abs(reaction).max(), np.abs(t["load"]).max(), np.abs(t["contact"]).max())
        diff = np.abs(recomputed_reaction(model, snap) - reaction).max()
        assert diff <= ROUND_OFF * size, f"{where}: reaction off its stresses by {diff:.3g}"


def _assert_obstacles(model, snap, terms, scale, axes, where) -> None:
    """Each rigid [[contact]] k: its force on the bodies it touches = −(their loads, reactions
    and the forces of the other contacts on them)."""
    pairs, body = model["pairs"], node_body(model)
    contact = np.asarray(pairs["contact"])
    for k in np.unique(contact[np.asarray(pairs["node_b"]) < 0]):
        mine = contact == k
        touched = np.unique(body[np.asarray(pairs["node_a"])[mine]])
        others = contact_force(
            len(body), pairs, _zeroed(snap["lambda_n"], mine), _zeroed(snap["lambda_t"], mine)
        )
        rest = terms["load"] + terms["reaction"] + body_sums(model, others)
        f = obstacle_force(model, snap, int(k))
        gap = f + rest[touched].sum(axis=0)
        tol = EQUILIBRIUM_TOL * scale[touched].sum(axis=0)
        assert (np.abs(gap[axes]) <= tol[axes]).all(), (
            f"{where}: contact {k}'s force {f} against minus the reactions and loads of the "
            f"bodies it touches {-rest[touched].sum(axis=0)}"
        )


def _zeroed(values, mask) -> np.ndarray:
    """``values`` with the entries of ``mask`` set to 0."""
    out = np.asarray(values, dtype=float).copy()
    out[mask] = 0.0
    return out


# --------------------------------------------------------------------------- shipped cases
@needs_gmsh
@pytest.mark.parametrize("name", SHIPPED)
def test_shipped_case_is_in_balance(name):
    scene = prepare(
        CASES / f"{name}.toml",
        ["output.figures=false", "output.snapshots=events", *COARSE.get(name, [])],
    )
    result = solve(scene)
    assert result["stop"]["kind"] == "completed", result["stop"]
    assert_balanced(scene, result)


# --------------------------------------------------------------------------- obstacle scenes
BLOCK = """
[case]
name = "{name}"
[analysis]
plane = "{plane}"
[output]
snapshots = "events"
figures = false
xdmf = false
[[body]]
name = "block"
[body.mesh]
generator = "block"
x0 = {x0}
y0 = -4.0
width = {width}
height = 4.0
h = 0.25
[body.material]
E = 1000.0
nu = 0.3
[[bc]]
name = "base"
body = "block"
edge = "bottom"
fix = ["x", "y"]
[[contact]]
name = "tool"
body = "block"
edge = "top"
mu = 0.3
motion = {motion}
{shape}
[[stage]]
name = "press"
factors = {{tool = 1.0}}
[[stage]]
name = "release"
factors = {{tool = 0.4}}
"""
# each pressed into the top y = 0 of the block, partly released; oblique where the scene is
# not held in x by an axis, so that pairs stick and slip
TOOLS = {
    "line": 'kind = "rigid_line"\npoint = [0.0, 0.02]\nnormal = [0.002, -1.0]',
    "circle": 'kind = "rigid_circle"\ncentre = [0.0, 5.0]\nradius = 5.0',
    # convex corners at (-1, 0) and (1, 0): nodes sitting on them
    "trapezoid": 'kind = "rigid_polyline"\nside = "right"\n'
    'points = [[-3.0, 1.0], [-1.0, 0.0], [1.0, 0.0], [3.0, 1.0]]',
    "punch with sides": 'kind = "rigid_polyline"\nside = "right"\n'
    'points = [[-1.0, 1.0], [-1.0, 0.0], [1.0, 0.0], [1.0, 1.0]]',
    # a closed square standing on a corner, walked counter-clockwise, the body outside
    "closed, body outside": 'kind = "rigid_polyline"\nside = "right"\n'
    'points = [[0.0, 0.0], [1.0, 1.0], [0.0, 2.0], [-1.0, 1.0], '
    '[0.0, 0.0]]',
}


def block_scene(
    name: str,
    shape: str,
    plane: str = "strain",
    motion: str = "[0.01, -0.05]",
    x0: float = -4.0,
    width: float = 8.0,
    extra: str = "",
    sets=(),
):
    """The block (x0, width; 0.25 elements) under a tool of ``shape``; ``extra`` TOML added."""
    text = (
        BLOCK.format(
            name=re.sub(r"\W+", "_", name),
            plane=plane,
            x0=x0,
            width=width,
            motion=motion,
            shape=shape,
        )
        + extra
    )
    return build_scene(parse_case(text, source=name, overrides=list(sets)))


@pytest.mark.parametrize("name", TOOLS)
def test_rigid_obstacle_scene_is_in_balance(name):
    scene = block_scene(name, TOOLS[name])
    result = solve(scene)
    assert result["stop"]["kind"] == "completed", result["stop"]
    status = np.concatenate([s["status"] for s in result["snapshots"]])
    assert (status > 0).any(), "the tool must touch the block"
    assert_balanced(scene, result)


def test_axisymmetric_punch_with_its_side_is_in_balance():
    """A flat punch of radius 1 with its side, on the axis (only the axial balance)."""
    scene = block_scene(
        "axisymmetric punch",
        'kind = "rigid_polyline"\nside = "right"\n' 'points = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]',
        plane="axisymmetric",
        motion="[0.0, -0.05]",
        x0=0.0,
        width=4.0,
    )
    result = solve(scene)
    assert result["stop"]["kind"] == "completed", result["stop"]
    assert_balanced(scene, result)


@pytest.mark.parametrize("plane, mu", [("axisymmetric", 0.0), ("strain", 0.3)])
def test_a_punch_posed_with_its_sides_presses_like_the_open_punch(plane, mu):
    """A flat punch of half-width 1 pressed into the block whose top it touches, posed as its
    face alone (the nodes beyond the face project nowhere) and with its sides rising from the
    corners (those nodes then see the corner): the sides touch nothing, so the contact forces
    are the same at every snapshot, and the total normal force is the base reaction.
    Tolerance EQUILIBRIUM_TOL of the force (the two runs differ only by the open pairs beside
    the corners).  With the averaged 45-degree normal at the corner nodes the axisymmetric
    punch gave Σ λ_n 166.5 against a base reaction of 142.7 (+17 %), the plane one 56.4
    against 54.8."""
    face = [[0.0, 0.0], [1.0, 0.0]] if plane == "axisymmetric" else [[-1.0, 0.0], [1.0, 0.0]]
    sides = [*face, [1.0, 1.0]] if plane == "axisymmetric" else [[-1.0, 1.0], *face, [1.0, 1.0]]
    x0, width = (0.0, 4.0) if plane == "axisymmetric" else (-4.0, 8.0)
    runs = {}
    for name, points in (("open", face), ("sides", sides)):
        scene = block_scene(
            name,
            f'kind = "rigid_polyline"\nside = "right"\npoints = {points}',
            plane=plane,
            motion="[0.0, -0.05]",
            x0=x0,
            width=width,
            sets=[f"contact.mu={mu}"],
        )
        result = solve(scene)
        assert result["stop"]["kind"] == "completed"
        base = scene.support_dofs["base"]
        runs[name] = [
            (
                {
                    tuple(xy): (ln, lt)
                    for xy, ln, lt in zip(scene.pair_xy.round(9), s["lambda_n"], s["lambda_t"])
                },
                float(np.sum(s["lambda_n"])),
                float(np.asarray(s["reaction"]).reshape(-1)[base[base % 2 == 1]].sum()),
            )
            for s in result["snapshots"]
        ]
    assert len(runs["open"]) == len(runs["sides"])
    scale = max(force for _, force, _ in runs["open"])
    for (open_pairs, open_force, _), (side_pairs, side_force, side_base) in zip(*runs.values()):
        assert abs(side_force - side_base) <= EQUILIBRIUM_TOL * scale, (side_force, side_base)
        assert abs(side_force - open_force) <= EQUILIBRIUM_TOL * scale, (side_force, open_force)
        for xy, forces in open_pairs.items():
            assert side_pairs[xy] == pytest.approx(forces, abs=EQUILIBRIUM_TOL * scale), xy
        beyond = [side_pairs[xy][0] for xy in side_pairs if xy not in open_pairs]
        assert beyond and not any(beyond), "the sides touch nothing"


BOX = (
    BLOCK.split("[[bc]]")[0]
    + """
[[bc]]
name = "hold"
body = "block"
edge = "left"
fix = ["x"]
[[bc]]
name = "press"
body = "block"
edge = "top"
pressure = 5.0
[[bc]]
name = "push"
body = "block"
edge = "top"
traction = [2.0, 0.0]
[[contact]]
name = "box"
body = "block"
edge = "bottom"
mu = 0.3
kind = "rigid_polyline"
side = "left"
points = [[-5.0, -4.0], [4.0, -4.0], [4.0, 2.0], [-5.0, 2.0], [-5.0, -4.0]]
[[stage]]
name = "press"
factors = {{press = 1.0}}
[[stage]]
name = "push"
factors = {{press = 1.0, push = 1.0}}
"""
)


def test_closed_polyline_around_the_body_is_in_balance():
    """The block in a closed box (walked counter-clockwise, the body inside) whose floor and
    right wall meet at the block's bottom right corner, a concave corner of the box (the
    averaged normal); pressed, then pushed against the wall.  (The box's left wall stands off:
    the left side is held in x, and a corner there would stick on one free component.)"""
    scene = build_scene(
        parse_case(BOX.format(name="box", plane="strain", x0=-4.0, width=8.0), source="box")
    )
    result = solve(scene)
    assert result["stop"]["kind"] == "completed", result["stop"]
    corner = np.flatnonzero(np.all(scene.pair_xy == [4.0, -4.0], axis=1))
    assert np.allclose(scene.model["pairs"]["normal"][corner], [[-(0.5**0.5), 0.5**0.5]])
    assert result["snapshots"][-1]["lambda_n"][corner] > 0, "the corner must carry force"
    assert_balanced(scene, result)


def test_contact_force_on_a_held_dof_is_not_a_reaction():
    """A frictionless polyline sloping across the symmetry line x = 0 of a half block: node
    (0, 0) is held in x and pushed along the oblique normal (0.0995, -0.995)."""
    sym = '[[bc]]\nname = "symmetry"\nbody = "block"\nedge = "left"\nsymmetry = true\n'
    scene = block_scene(
        "oblique",
        'kind = "rigid_polyline"\nside = "right"\n' 'points = [[0.0, 0.0], [4.0, 0.4]]',
        motion="[0.0, -0.05]",
        x0=0.0,
        width=4.0,
        extra=sym,
        sets=["contact.mu=0"],
    )
    result = solve(scene)
    assert result["stop"]["kind"] == "completed", result["stop"]
    assert_balanced(scene, result)


TWO_BLOCKS = (CASES / "two_blocks.toml").read_text()


@pytest.mark.parametrize("kind, h_punch", [("node_to_node", "0.5"), ("node_to_segment", "0.4")])
def test_deformable_pairs_are_in_balance(kind, h_punch):
    """two_blocks with matching meshes (node_to_node) and a punch meshed on its own
    (node_to_segment, 0.4 on the foundation's 0.5), friction 0.5 so that pairs stick."""
    text = TWO_BLOCKS.replace('kind = "node_to_node"', f'kind = "{kind}"')
    if kind == "node_to_segment":
        text = re.sub(r"\ntolerance = [^\n]*", "", text)
    text = text.replace("height = 5.0\nh = 0.5", f"height = 5.0\nh = {h_punch}")
    scene = build_scene(
        parse_case(text, "two_blocks", CASES, ["output.figures=false", "contact.mu=0.5"])
    )
    result = solve(scene)
    assert result["stop"]["kind"] == "completed", result["stop"]
    assert_balanced(scene, result)
