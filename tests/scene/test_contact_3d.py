"""Contact pairs in space (slipstep.contact.faces): a rigid plane, sphere, cylinder and
triangulated surface (a Vickers pyramid, an STL file), node to node between matching boxes, and
the one-line refusals (initial penetration, an open surface where closedness is needed, an
obstacle that starts inside a body, a node on an obstacle's centre).  Normals and gaps are
recomputed here from the closed-form geometry of each obstacle."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import needs_gmsh
from space3d import BOX, SPHERE, assert_contract

from slipstep.build import build_scene
from slipstep.case import parse_case
from slipstep.errors import CaseError
from slipstep.contact.indenters import pyramid, write_stl


def scene_of(text: str, sets=(), base_dir="."):
    return build_scene(parse_case(text, "c.toml", base_dir, overrides=list(sets)))


def contact(kind: str, **keys) -> str:
    lines = [f'[[contact]]\nkind = "{kind}"\nbody = "b"\nface = "top"\nmu = 0.2']
    lines += [f"{k} = {v}" for k, v in keys.items()]
    return "\n".join(lines) + "\n"


@needs_gmsh
def test_a_sphere_on_a_rigid_plane_pairs_its_nodes_by_height():
    """On a flat z = 0 the normal is e_z and the gap of a node of the sphere is its height z
    (the node lies on the sphere: z = R - sqrt(R^2 - r^2), checked too)."""
    scene = build_scene(parse_case(SPHERE, "s.toml"))
    assert_contract(scene.model)
    pairs = scene.model["pairs"]
    x = scene.nodes[pairs["node_a"]]
    assert (pairs["normal"] == [0.0, 0.0, 1.0]).all() and (pairs["node_b"] == -1).all()
    assert np.allclose(pairs["gap"], x[:, 2], rtol=0, atol=1e-9)  # tolerance: snapped to 0
    r = np.hypot(x[:, 0], x[:, 1])
    assert np.allclose(x[:, 2], 10.0 - np.sqrt(100.0 - r**2), atol=1e-12)
    assert (x[:, 2] <= 0.1).all() and len(pairs["gap"]) >= 10  # the window z <= z_max
    assert (pairs["gap"] == 0.0).sum() == 1  # the contact point, a node: starts closed
    # the contract's own tangent basis: e = x (least aligned with e_z), t1 = e x n = -e_y
    assert np.allclose(scene.pair_tangent[:, 0], [0, -1, 0]) and np.allclose(
        scene.pair_tangent[:, 1], [1, 0, 0]
    )
    # consistent tributary areas: over the whole face they sum to its area
    face = scene.global_boundary("sphere", "surface")
    assert (scene.pair_area > 0).all()


def test_a_rigid_sphere_above_a_box():
    text = BOX + contact("rigid_sphere", centre="[1.0, 0.5, 3.5]", radius=2.5)
    scene = scene_of(text)
    assert_contract(scene.model)
    pairs = scene.model["pairs"]
    d = scene.nodes[pairs["node_a"]] - [1.0, 0.5, 3.5]
    r = np.linalg.norm(d, axis=1)
    assert np.allclose(pairs["normal"], d / r[:, None], atol=1e-15)
    assert np.allclose(pairs["gap"], r - 2.5, atol=1e-9)
    assert pairs["gap"].min() == 0.0  # the node under the centre touches: starts closed
    assert (pairs["mu"] == 0.2).all()
    # the top's 5 x 3 nodes, each with its consistent area; they sum to the face's 2 x 1
    assert len(pairs["gap"]) == 15 and math.isclose(scene.pair_area.sum(), 2.0, rel_tol=1e-14)


def test_a_rigid_cylinder_inside_its_bore_and_outside():
    text = BOX + contact(
        "rigid_cylinder", point="[0.0, 0.5, 2.0]", axis="[1.0, 0.0, 0.0]", radius=1.0
    )
    pairs = scene_of(text).model["pairs"]
    x = scene_of(text).nodes[pairs["node_a"]]
    radial = x - [0.0, 0.5, 2.0]
    radial[:, 0] = 0.0
    r = np.linalg.norm(radial, axis=1)
    assert np.allclose(pairs["normal"], radial / r[:, None]) and (pairs["normal"][:, 0] == 0).all()
    assert np.allclose(pairs["gap"], r - 1.0, atol=1e-9)


def test_a_node_on_the_axis_has_no_normal():
    text = BOX + contact(
        "rigid_cylinder",
        point="[0.0, 0.5, 1.0]",
        axis="[1.0, 0.0, 0.0]",
        radius=0.2,
        side='"inside"',
    )
    with pytest.raises(
        CaseError,
        match=r"c.toml: contact.radius: node \d+ lies on the axis of " r"the rigid obstacle",
    ):
        scene_of(text)


def test_a_vickers_indenter_above_a_box():
    """The pyramid's tip 0.1 above the middle of the top face: the node under the tip has gap
    0.1 and normal -e_z... from the pyramid into the body: straight down from the tip."""
    text = BOX + contact("rigid_surface", indenter='"vickers"', tip="[1.0, 0.5, 1.1]", size=0.3)
    scene = scene_of(text)
    assert_contract(scene.model)
    pairs = scene.model["pairs"]
    x = scene.nodes[pairs["node_a"]]
    middle = np.flatnonzero((x == [1.0, 0.5, 1.0]).all(axis=1))[0]
    assert math.isclose(pairs["gap"][middle], 0.1, rel_tol=1e-12)
    assert np.allclose(pairs["normal"][middle], [0.0, 0.0, -1.0])
    # every gap is the distance to the pyramid, sampled here on its four faces
    points, tris = pyramid("vickers", [1.0, 0.5, 1.1], 0.3)
    u, v = np.meshgrid(np.linspace(0, 1, 301), np.linspace(0, 1, 301))
    keep = u + v <= 1
    samples = np.concatenate(
        [
            points[t[0]]
            + u[keep, None] * (points[t[1]] - points[t[0]])
            + v[keep, None] * (points[t[2]] - points[t[0]])
            for t in tris
        ]
    )
    nearest = np.linalg.norm(x[:, None] - samples[None], axis=2).min(axis=1)
    assert np.allclose(pairs["gap"], nearest, atol=0.3 / 300 * 1.5)  # the sampling's step


def test_an_open_surface_where_a_closed_one_is_needed(tmp_path):
    points, tris = pyramid("vickers", [1.0, 0.5, 1.1], 0.3)
    write_stl(tmp_path / "cup.stl", points, tris[:4])  # the four faces, no lid
    text = BOX + contact("rigid_surface", file='"cup.stl"')
    with pytest.raises(
        CaseError,
        match=r"c.toml: contact.file: the surface is not closed: its "
        r"edge between vertices \d+ and \d+ belongs to 1 "
        r"triangle\(s\), not 2; side = \"outside\" needs a closed "
        r"surface",
    ):
        scene_of(text, base_dir=tmp_path)
    scene = scene_of(text, ['contact.side="front"'], base_dir=tmp_path)  # below its faces
    assert math.isclose(scene.model["pairs"]["gap"].min(), 0.1, rel_tol=1e-12)


def test_an_obstacle_inside_the_body_is_refused():
    """A plane through the box's middle, facing up: the top face's nodes are 0.5 above it, a
    positive gap, but the plane runs through the body."""
    text = BOX + contact("rigid_plane", point="[0.0, 0.0, 0.5]", normal="[0.0, 0.0, 1.0]")
    with pytest.raises(
        CaseError,
        match=r"c.toml: contact: the rigid plane starts inside body "
        r"'b': its point \(.*\) closest to node \d+ lies inside "
        r"the body \(element \d+\): move the rigid plane out",
    ):
        scene_of(text)


def test_initial_penetration_names_the_node_and_depth():
    text = BOX + contact("rigid_sphere", centre="[1.0, 0.5, 1.5]", radius=0.6)
    with pytest.raises(
        CaseError,
        match=r"contact: initial penetration at node \d+ \(1, 0.5, 1\) "
        r"by 0.1: move the body or the sphere",
    ):
        scene_of(text)


def test_a_rigid_plane_facing_away_is_refused():
    """The plane z = 1 touches the top face, but its normal says the body is above it."""
    text = BOX + contact("rigid_plane", point="[0.0, 0.0, 1.0]", normal="[0.0, 0.0, 1.0]")
    with pytest.raises(
        CaseError,
        match=r"contact: the contact normal \(0, 0, 1\) at node \d+ "
        r".* points the wrong way \(the contactor surface faces "
        r"away from the target\)",
    ):
        scene_of(text)
    lid = scene_of(
        BOX + contact("rigid_plane", point="[0.0, 0.0, 1.0]", normal="[0.0, 0.0, -1.0]")
    )  # a lid on the box: fine
    assert (lid.model["pairs"]["gap"] == 0.0).all()


TWO_BOXES = (
    BOX
    + """
[[body]]
name = "lid"
[body.mesh]
generator = "box"
z0 = 1.0
width = 2.0
depth = 1.0
height = 0.5
nx = {nx}
ny = 2
nz = 1
[body.material]
E = 1000.0
nu = 0.25
[[contact]]
kind = "{kind}"
body_a = "lid"
face_a = "bottom"
body_b = "b"
face_b = "top"
"""
)


def test_matching_boxes_pair_node_to_node():
    scene = scene_of(TWO_BOXES.format(nx=4, kind="node_to_node"))
    assert_contract(scene.model)
    pairs = scene.model["pairs"]
    assert len(pairs["node_a"]) == 15
    assert (scene.nodes[pairs["node_a"]] == scene.nodes[pairs["node_b"]]).all()
    assert (pairs["normal"] == [0.0, 0.0, 1.0]).all() and (pairs["gap"] == 0.0).all()


def test_non_matching_boxes_are_refused_node_to_node():
    with pytest.raises(
        CaseError,
        match=r"contact.tolerance: non-matching interface: node \d+ "
        r"\(.*\) of lid:bottom lies on b:top",
    ):
        scene_of(TWO_BOXES.format(nx=3, kind="node_to_node"))


def test_a_moving_obstacle_is_a_pattern_with_a_3d_motion():
    """A rigid sphere's motion [dx, dy, dz] is a load pattern (docs/engine_api.md: motion (m, 3)
    of the obstacle of contact motion_contacts) scaled by the stages' factors."""
    text = (
        BOX
        + contact(
            "rigid_sphere",
            centre="[1.0, 0.5, 3.5]",
            radius=2.5,
            name='"press"',
            motion="[0.1, 0.0, -0.2]",
        )
        + '[[stage]]\nname = "in"\nfactors = {press = 1.0}\n'
        '[[stage]]\nname = "out"\nfactors = {press = 0.5}\n'
    )
    scene = scene_of(text)
    assert_contract(scene.model)
    (pattern,) = scene.model["patterns"]
    assert pattern["name"] == "press" and pattern["motion_contacts"].tolist() == [0]
    assert pattern["motion"].tolist() == [[0.1, 0.0, -0.2]]
    assert [s["factors"].tolist() for s in scene.model["stages"]] == [[0.0, 1.0], [0.0, 0.5]]
