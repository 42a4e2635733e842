"""Rigid obstacles of any shape, small sliding (issue 14, part 2): ``kind = "rigid_circle"``
and ``kind = "rigid_polyline"`` (cases/README.md, [[contact]]).

Geometry against hand computation (the gap and normal of chosen nodes, the vertex rule, the
end points that project nowhere), the one-line errors, ``--set`` on the new keys, a huge circle
against the rigid line it approximates, the contact coordinate s, an end-to-end run with every
output, and the physics: a rigid cylinder (R = 50) indenting an elastic block against Hertz.

Tolerances:
- hand computations: 1e-12 (absolute, on numbers of order 1: a few round-offs of sqrt and
  division; nothing else separates the code's arithmetic from the closed form);
- the huge circle (R = 1e6) against the line: normals within |x - x_c| / R, the angle
  between them, and gaps within (x - x_c)^2 / (2R), the circle's sag, each plus 1e-9 for the
  round-off of |x - c| - R at magnitude R (1e6 x 2.2e-16 ~ 2e-10);
- Hertz: the peak pressure p0 on two meshes, its error falling at first order and its
  Richardson value within 1 % of Hertz's for the measured force; the half-width within one
  element (the reasons are in test_rigid_cylinder_indenting_a_block_follows_hertz);
- equilibrium: tests/physics.py EQUILIBRIUM_TOL (the engine's contract).
"""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest
from conftest import CASES, needs_gmsh, write_case
from physics import EQUILIBRIUM_TOL, observed_order, richardson, worst_equilibrium
from slipstep.measures.references import hertz_line

from slipstep import build_scene, parse_case, solve
from slipstep import schema
from slipstep.case import CaseError
from slipstep.measures.contact_edges import contact_axis, force_displacement, pair_coordinate
from slipstep.contact.edges import polyline_closest
from slipstep.runner import run_case
from slipstep.output.summary import summarize

SOURCE = "rigid"
ROUND_OFF = 1e-12

# a 4 x 1 block, 4 x 1 cells: its top edge has nodes at x = 0, 1, 2, 3, 4 (y = 1)
BLOCK = """
[case]
name = "rigid"
[output]
figures = false
[[body]]
name = "b"
[body.mesh]
generator = "block"
width = 4.0
height = 1.0
nx = {nx}
ny = 1
[body.material]
E = 1000.0
nu = 0.3
[[bc]]
body = "b"
edge = "bottom"
fix = ["x", "y"]
[[contact]]
name = "die"
body = "b"
edge = "top"
"""


def case(contact: str, sets=(), nx: int = 4):
    return parse_case(BLOCK.format(nx=nx) + contact, source=SOURCE, overrides=list(sets))


def scene_of(contact: str, sets=(), nx: int = 4):
    return build_scene(case(contact, sets, nx))


def error_of(contact: str, sets=(), build: bool = False) -> str:
    with pytest.raises(CaseError) as info:
        c = case(contact, sets)
        if build:
            build_scene(c)
    return str(info.value)


def pairs_by_x(scene) -> dict:
    """{x of node a: (normal, gap)} of a scene's pairs."""
    p = scene.model["pairs"]
    return {
        round(float(x), 9): (np.asarray(n), float(g))
        for (x, _), n, g in zip(scene.pair_xy, p["normal"], p["gap"])
    }


CIRCLE_OUT = 'kind = "rigid_circle"\ncentre = [2.0, 3.0]\nradius = 1.5\n'
CIRCLE_IN = 'kind = "rigid_circle"\ncentre = [2.0, 0.5]\nradius = 3.0\nside = "inside"\n'
# a V above the block, its vertex (2, 1.5) 0.5 above the top; the body below is on its right
POLY_V = 'kind = "rigid_polyline"\npoints = [[0.0, 2.0], [2.0, 1.5], [4.0, 2.0]]\nside = "right"\n'


# --------------------------------------------------------------------------- geometry
def test_circle_outside_gap_and_normal_by_hand():
    got = pairs_by_x(scene_of(CIRCLE_OUT))
    assert sorted(got) == [0.0, 1.0, 2.0, 3.0, 4.0]
    for x in got:  # node (x, 1), centre (2, 3): d = (x - 2, -2)
        d = np.array([x - 2.0, -2.0])
        n, gap = got[x]
        assert np.allclose(n, d / np.linalg.norm(d), rtol=0, atol=ROUND_OFF)
        assert gap == pytest.approx(math.hypot(x - 2.0, 2.0) - 1.5, abs=ROUND_OFF)
    assert got[2.0][1] == pytest.approx(0.5, abs=ROUND_OFF)
    assert np.allclose(got[1.0][0], [-1 / math.sqrt(5), -2 / math.sqrt(5)], atol=ROUND_OFF)


def test_circle_inside_gap_and_normal_by_hand():
    got = pairs_by_x(scene_of(CIRCLE_IN))
    for x in got:  # node (x, 1) in the hole of radius 3 about (2, 0.5): normal (c - x)/|x - c|
        d = np.array([x - 2.0, 0.5])
        n, gap = got[x]
        assert np.allclose(n, -d / np.linalg.norm(d), rtol=0, atol=ROUND_OFF)
        assert gap == pytest.approx(3.0 - np.linalg.norm(d), abs=ROUND_OFF)
    assert got[2.0][1] == pytest.approx(2.5, abs=ROUND_OFF)
    assert got[4.0][1] == pytest.approx(3.0 - math.sqrt(4.25), abs=ROUND_OFF)


def test_polyline_segment_and_vertex_by_hand():
    got = pairs_by_x(scene_of(POLY_V))
    # node (1, 1): closest point inside the first segment (0, 2)-(2, 1.5), d = (2, -0.5);
    # its right normal (d_y, -d_x)/|d| and the distance to the line 0.5 x + 2 y - 4 = 0
    n, gap = got[1.0]
    assert np.allclose(n, np.array([-0.5, -2.0]) / math.sqrt(4.25), atol=ROUND_OFF)
    assert gap == pytest.approx(1.5 / math.sqrt(4.25), abs=ROUND_OFF)
    # node (2, 1): the closest point is the vertex (2, 1.5); the average of (-0.5, -2) and
    # (0.5, -2), normalised, is (0, -1); gap (x - vertex).n = 0.5
    n, gap = got[2.0]
    assert np.allclose(n, [0.0, -1.0], atol=ROUND_OFF)
    assert gap == pytest.approx(0.5, abs=ROUND_OFF)
    n, gap = got[3.0]  # the mirror image of node (1, 1)
    assert np.allclose(n, np.array([0.5, -2.0]) / math.sqrt(4.25), atol=ROUND_OFF)
    assert gap == pytest.approx(1.5 / math.sqrt(4.25), abs=ROUND_OFF)


def test_convex_vertex_resists_along_the_direction_to_the_node():
    """A convex vertex (the obstacle's corner points into the body) between a sloped and a
    flat segment: a node whose closest point is the vertex is resisted along the direction
    from the vertex to it, the gap its distance (the closest-point normal; the average of the
    two segments' normals would tilt node (2, 1) by 7 degrees and cut the gap)."""
    points = [[0.0, 2.0], [2.0, 1.5], [4.0, 1.5]]
    got = pairs_by_x(scene_of(f'kind = "rigid_polyline"\npoints = {points}\nside = "right"\n'))
    n, gap = got[2.0]  # straight below the vertex
    assert np.allclose(n, [0.0, -1.0], atol=ROUND_OFF)
    assert gap == pytest.approx(0.5, abs=ROUND_OFF)
    assert got[3.0][1] == pytest.approx(0.5, abs=ROUND_OFF)  # on the flat: the distance
    # (1.9, 1): beyond the sloped segment's end (its projection parameter 4.3/4.25 > 1) and
    # before the flat one's start: in the vertex's cone
    near = polyline_closest(np.array(points), "right", np.array([[1.9, 1.0]]))
    r = np.array([-0.1, -0.5])
    assert near["vertex"][0] == 1
    assert np.allclose(near["normal"][0], r / np.linalg.norm(r), atol=ROUND_OFF)
    assert near["gap"][0] == pytest.approx(np.linalg.norm(r), abs=ROUND_OFF)


# a punch face y = 0 for 0 <= x <= 1 with its side x = 1 rising from the corner (1, 0)
PUNCH = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])


def test_node_on_a_convex_corner_is_pressed_along_its_own_normal_clamped_to_the_corner():
    """A node sitting on a convex corner has no direction to it: the obstacle pushes along the
    direction of the corner's cone of normals nearest to minus the body's own outward normal
    there: a punch's edge node along the punch face's normal (its normal lies on the cone's
    edge), a body against the punch's side along the side's, a block's top under a wedge's
    tip along the block's normal (inside the cone), the cone's middle without a normal.
    Sitting means within ``touch``; a node off the corner in its cone gets the direction
    from the corner."""
    at = np.array([[1.0, 0.0]])
    for outward, force in (
        ([0.0, 1.0], [0.0, -1.0]),  # a block's top under the punch
        ([-1.0, 0.0], [1.0, 0.0]),  # a body against the punch's side
        ([1.0, 4.0], [0.0, -1.0]),  # tilted past the face: the face
        ([-1.0, 3.0], [1.0, -3.0]),  # tilted into the cone: itself
        ([0.0, 0.0], [1.0, -1.0]),
    ):  # none: the middle
        near = polyline_closest(PUNCH, "right", at, np.array([outward]))
        expected = np.array(force) / np.linalg.norm(force)
        assert np.allclose(near["normal"][0], expected, atol=ROUND_OFF), outward
        assert near["gap"][0] == 0.0
    wedge = np.array([[0.0, 0.0], [1.0, 1.0], [0.0, 2.0], [-1.0, 1.0], [0.0, 0.0]])  # closed
    near = polyline_closest(wedge, "right", np.array([[0.0, 0.0]]), np.array([[0.0, 1.0]]))
    assert np.allclose(near["normal"][0], [0.0, -1.0], atol=ROUND_OFF)
    off = np.array([[1.0 + 5e-10, 0.0], [1.1, 0.0], [1.1, -0.1]])
    near = polyline_closest(PUNCH, "right", off, np.tile([0.0, 1.0], (3, 1)), touch=1e-9)
    assert np.allclose(
        near["normal"], [[0.0, -1.0], [1.0, 0.0], [math.sqrt(0.5), -math.sqrt(0.5)]], atol=ROUND_OFF
    )
    # the sitting node's gap along its face normal: 0 (it lies on the face's line)
    assert near["gap"] == pytest.approx([0.0, 0.1, 0.1 * math.sqrt(2.0)], abs=ROUND_OFF)


def test_concave_vertex_keeps_the_average_of_its_faces():
    """A concave vertex (the body in the obstacle's corner, pressed by both faces): the
    normalised average of the two segments' normals; a closed polygon with the body outside
    has convex corners (the direction from the corner), with the body inside concave ones."""
    groove = np.array([[-1.0, 1.0], [0.0, 0.0], [1.0, 1.0]])  # a V, the body inside it
    near = polyline_closest(groove, "left", np.array([[0.0, 0.0]]), np.array([[0.0, -1.0]]))
    assert np.allclose(near["normal"][0], [0.0, 1.0], atol=ROUND_OFF)
    square = np.array([[1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0], [1.0, -1.0], [1.0, 1.0]])
    outside = polyline_closest(square, "right", np.array([[2.0, 3.0]]))  # walked ccw
    assert np.allclose(outside["normal"][0], np.array([1.0, 2.0]) / math.sqrt(5.0), atol=ROUND_OFF)
    assert outside["gap"][0] == pytest.approx(math.sqrt(5.0), abs=ROUND_OFF)


def test_polyline_nodes_that_project_nowhere_are_not_candidates():
    """A polyline over 1 <= x <= 3: the nodes x = 0 and 4 lie beyond its end points; x = 1
    and 3 project exactly onto them and stay."""
    scene = scene_of(
        'kind = "rigid_polyline"\npoints = [[1.0, 1.5], [3.0, 1.5]]\n' 'side = "right"\n'
    )
    assert sorted(pairs_by_x(scene)) == [1.0, 2.0, 3.0]
    assert scene.contact_truncated == [True]
    msg = error_of(
        'kind = "rigid_polyline"\npoints = [[10.0, 1.5], [12.0, 1.5]]\n' 'side = "right"\n',
        build=True,
    )
    assert msg == (
        f"{SOURCE}: contact.points: no candidate node of edge 'top' of body 'b' "
        f"projects onto the rigid polyline (a contactor node that projects nowhere "
        f"is not a candidate): extend the polyline (points) or widen the window "
        f"(x_min/x_max/y_min/y_max)"
    )


def test_closed_polyline_has_no_free_ends():
    """A closed polygon (last point = first): every point projects somewhere; the joint is a
    vertex like the others (a square around the origin, a point outside its corner)."""
    square = np.array([[1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0], [1.0, -1.0], [1.0, 1.0]])
    near = polyline_closest(square, "left", np.array([[2.0, 2.0], [3.0, 0.0]]))
    assert near["onto"].all()
    assert near["vertex"][0] in (0, 4)  # the joint (1, 1)
    # walking counter-clockwise the interior is on the left: the normals point inwards, so
    # the outside point has a negative gap (it would be an initial penetration)
    assert np.allclose(near["normal"][0], [-1 / math.sqrt(2), -1 / math.sqrt(2)])
    assert near["gap"][0] == pytest.approx(-math.sqrt(2), abs=ROUND_OFF)
    assert np.allclose(near["normal"][1], [-1.0, 0.0]) and near["gap"][1] == pytest.approx(-2.0)


def test_huge_circle_approximates_the_rigid_line():
    """A circle of radius 1e6 whose lowest point is (2, 1.1), against the line y = 1.1 with
    normal (0, -1): same pairs, normals within the angle |x - 2|/R, gaps within the sag
    (x - 2)^2/(2R), and the same coordinate s (along the same tau) within O(|x - 2|/R)."""
    R = 1.0e6
    line = scene_of('kind = "rigid_line"\npoint = [2.0, 1.1]\nnormal = [0.0, -1.0]\n', nx=8)
    circle = scene_of(f'kind = "rigid_circle"\ncentre = [2.0, {1.1 + R!r}]\nradius = {R!r}\n', nx=8)
    pl, pc = line.model["pairs"], circle.model["pairs"]
    assert np.array_equal(pl["node_a"], pc["node_a"])
    dx = np.abs(line.pair_xy[:, 0] - 2.0)
    assert (np.linalg.norm(pl["normal"] - pc["normal"], axis=1) <= dx / R + 1e-9).all()
    assert (np.abs(pl["gap"] - pc["gap"]) <= dx**2 / (2 * R) + 1e-9).all()
    # s on the circle is -R atan(dx/(R + 0.1)) (the nodes are 0.1 off it), on the line -dx:
    # apart by 0.1 dx/R plus the arc-against-tangent term dx^3/(3 R^2)
    assert (
        np.abs(pair_coordinate(line) - pair_coordinate(circle))
        <= 0.1 * dx / R + dx**3 / R**2 + 1e-9
    ).all()
    assert np.allclose(contact_axis(circle, 0)[1], contact_axis(line, 0)[1])


def test_contact_coordinate_follows_tau_for_every_kind():
    """s increases along tau = (n_y, -n_x) (the body on the left), as for the rigid line: under
    a circle or a polyline above the block (n ~ (0, -1)) s decreases with x."""
    for contact in (CIRCLE_OUT, POLY_V):
        scene = scene_of(contact)
        s = pair_coordinate(scene)
        order = np.argsort(scene.pair_xy[:, 0])
        assert (np.diff(s[order]) < 0).all()
    s = pair_coordinate(scene_of(CIRCLE_OUT))  # R theta from the top node (2, 1)
    x = scene_of(CIRCLE_OUT).pair_xy[:, 0]
    assert np.allclose(s, -1.5 * np.arctan2(x - 2.0, 2.0), atol=ROUND_OFF)
    # the polyline: minus the arc length from (0, 2) ("right"); node (2, 1) is at the vertex
    scene = scene_of(POLY_V)
    s = dict(zip(scene.pair_xy[:, 0].round(9), pair_coordinate(scene)))
    assert s[2.0] == pytest.approx(-math.sqrt(4.25), abs=ROUND_OFF)


# --------------------------------------------------------------------------- errors
def test_initial_penetration_names_node_position_and_depth():
    msg = error_of('kind = "rigid_circle"\ncentre = [2.0, 2.2]\nradius = 1.5\n', build=True)
    assert re.fullmatch(
        rf"{SOURCE}: contact: initial penetration at node \d+ \(2, 1\) by 0\.3: "
        r"move the body or the circle \(contact\.centre, contact\.radius\) so "
        r"that they do not overlap",
        msg,
    ), msg
    msg = error_of(
        'kind = "rigid_polyline"\npoints = [[0.0, 1.5], [2.0, 0.8], [4.0, 1.5]]\n'
        'side = "right"\n',
        build=True,
    )
    # inside the V the closest point is on a segment: depth 0.2 cos(atan(0.35)) = 0.189
    assert re.search(
        r"initial penetration at node \d+ \(2, 1\) by 0\.189: move the body or "
        r"the polyline \(contact\.points\)",
        msg,
    ), msg


def test_node_at_the_centre_is_an_error_naming_it():
    msg = error_of('kind = "rigid_circle"\ncentre = [2.0, 1.0]\nradius = 0.5\n', build=True)
    assert re.fullmatch(
        rf"{SOURCE}: contact\.centre: node \d+ \(2, 1\) lies at the centre of "
        r"the rigid circle, where the normal .* is undefined: move the centre, "
        r"or leave the node out of the candidates \(x_min/x_max/y_min/y_max\)",
        msg,
    ), msg


def test_wrong_side_is_caught():
    """The polyline along the block's top, walked right to left: the body is on its left, so
    side = "right" puts the normals upwards, out of the touching body: the facing check."""
    msg = error_of(
        'kind = "rigid_polyline"\npoints = [[4.0, 1.0], [0.0, 1.0]]\nside = "right"\n', build=True
    )
    assert "points the wrong way" in msg and "check contact.side" in msg, msg
    scene_of('kind = "rigid_polyline"\npoints = [[4.0, 1.0], [0.0, 1.0]]\nside = "left"\n')


@pytest.mark.parametrize(
    "contact, expected",
    [
        (
            'kind = "rigid_circle"\ncentre = [2.0, 3.0]\nradius = 0.0\n',
            "contact.radius = 0.0 is not allowed: the radius must be > 0",
        ),
        (
            'kind = "rigid_circle"\ncentre = [2.0, 3.0]\nradius = -1\n',
            "contact.radius = -1 is not allowed: the radius must be > 0",
        ),
        (
            'kind = "rigid_circle"\nradius = 1.0\n',
            "contact.centre is missing: centre [x, y] of the rigid circle [length]",
        ),
        (
            'kind = "rigid_circle"\ncentre = [2.0, 3.0]\nradius = 1.0\nside = "left"\n',
            'contact.side = "left" is not allowed: use "outside" or "inside"',
        ),
        (
            'kind = "rigid_polyline"\npoints = [[0.0, 2.0]]\nside = "right"\n',
            "contact.points = [[0.0, 2.0]] is not allowed: a polyline needs at least 2 points, got 1",
        ),
        (
            'kind = "rigid_polyline"\npoints = [[0.0, 2.0], [1.0, 2.0], [1.0, 2.0]]\nside = "right"\n',
            "contact.points = [[0.0, 2.0], [1.0, 2.0], [1.0, 2.0]] is not allowed: points 1 and 2 are "
            "both [1.0, 2.0]: a zero-length segment; remove one of them",
        ),
        (
            'kind = "rigid_polyline"\npoints = [[0.0, 2.0], [2.0, 2.0], [1.0, 2.0]]\nside = "right"\n',
            "is not allowed: the segments before and after point 1 fold back onto each other",
        ),
        (
            'kind = "rigid_polyline"\npoints = [0.0, 2.0]\nside = "right"\n',
            "contact.points = [0.0, 2.0] is not allowed: expected a list of [x, y] points",
        ),
        (
            'kind = "rigid_polyline"\npoints = [[0.0, 2.0], [4.0, 2.0]]\nside = "below"\n',
            'contact.side = "below" is not allowed: use "left" or "right"',
        ),
        (
            'kind = "rigid_polyline"\npoints = [[0.0, 2.0], [4.0, 2.0]]\n',
            "contact.side is missing: the side the body lies on",
        ),
        (
            'kind = "rigid_circle"\ncentre = [2.0, 3.0]\nradius = 1.0\npoints = [[0.0, 2.0]]\n',
            'unknown key contact.points in [[contact]] of kind "rigid_circle"',
        ),
    ],
)
def test_bad_values_are_one_line_errors(contact, expected):
    msg = error_of(contact)
    assert expected in msg and "\n" not in msg, msg
    assert msg.startswith(f"{SOURCE}: ")


def test_motion_stays_refused_on_node_to_node():
    text = (CASES / "two_blocks.toml").read_text()
    with pytest.raises(
        CaseError, match=r"contact.motion is not allowed: motion on a " r"deformable-pair contact"
    ):
        parse_case(text, source=SOURCE, overrides=["contact.motion=[0.0, 0.1]"])


def test_set_reaches_the_new_keys():
    c = case(
        CIRCLE_OUT,
        [
            "contact.radius=1.0",
            "contact.centre=[2, 2.5]",
            "contact.side=outside",
            "contact.motion=[0.0, -0.1]",
        ],
    )
    die = c.data["contact"][0]
    assert (die["radius"], die["centre"], die["motion"]) == (1.0, [2.0, 2.5], [0.0, -0.1])
    assert [x.label for x in c.path.patterns] == ["die"]  # the motion is a load
    c = case(POLY_V, ["contact.points=[[0, 3], [4, 3]]", "contact.side=right"])
    assert c.data["contact"][0]["points"] == [[0.0, 3.0], [4.0, 3.0]]
    with pytest.raises(CaseError, match=r"contact.side = \"up\" is not allowed"):
        case(POLY_V, ["contact.side=up"])
    with pytest.raises(
        CaseError,
        match=r"unknown key 'point' in \[\[contact\]\]; valid keys: "
        r"kind, name, mu, body, edge, centre, radius, side",
    ):
        case(CIRCLE_OUT, ["contact.point=[0, 1]"])


def test_readme_documents_the_new_keys():
    readme = (CASES / "README.md").read_text()
    keys = {*schema.RIGID_CIRCLE_KEYS, *schema.RIGID_POLYLINE_KEYS}
    missing = sorted(k for k in keys if f"`{k}`" not in readme)
    assert not missing, f"cases/README.md does not document {missing}"
    assert "a contactor node that projects nowhere is not a candidate" in readme.lower()


def test_oblique_normal_on_a_symmetry_node_is_refused():
    """With mu > 0 a node on a symmetry line (u_x held) whose normal is not along y would stick
    with both conditions on u_y alone; a polyline starting there with a slope is refused with
    the fix, one starting flat is fine."""

    def contact(points: str) -> str:
        return (
            f'kind = "rigid_polyline"\nside = "right"\nmu = 0.2\npoints = {points}\n'
            f'[[bc]]\nbody = "b"\nedge = "left"\nsymmetry = true\n'
        )

    msg = error_of(contact("[[0.0, 1.0], [4.0, 1.2]]"), build=True)
    assert re.search(
        r"contact: node \d+ \(0, 1\) is held in x by supports and its contact "
        r"normal \(0\.0499376, -0\.998752\) is oblique to y, its free component",
        msg,
    ), msg
    scene_of(contact("[[0.0, 1.0], [1.0, 1.0], [4.0, 1.2]]"))


# --------------------------------------------------------------------------- runs
E2E = """
[case]
name = "{name}"
[output]
snapshots = "events"
[[body]]
name = "block"
[body.mesh]
generator = "block"
width = 10.0
height = 5.0
nx = 50
ny = 25
[body.material]
E = 70000.0
nu = 0.3
[[bc]]
body = "block"
edge = "bottom"
fix = ["x", "y"]
[[bc]]
body = "block"
edge = "left"
symmetry = true
[[contact]]
name = "press"
body = "block"
edge = "top"
mu = 0.2
motion = [0.0, -0.02]
{shape}
[[stage]]
name = "in"
factors = {{press = 1.0}}
[[stage]]
name = "out"
factors = {{press = 0.3}}
"""
CYLINDER = 'kind = "rigid_circle"\ncentre = [0.0, 55.0]\nradius = 50.0'
# a flat-bottomed die, y = 5 + max(x - 0.5, 0)^2 / 100 sampled: flat where it crosses the
# symmetry line x = 0 (its normal there along y, as a frictional symmetry node needs)
PARABOLA = (
    'kind = "rigid_polyline"\nside = "right"\npoints = ['
    + ", ".join(
        f"[{x}, {5.0 + max(x - 0.5, 0.0) ** 2 / 100.0!r}]" for x in (0.0, 0.5, 1.0, 2.0, 3.0, 4.0)
    )
    + "]"
)


@pytest.mark.parametrize("name, shape", [("cylinder", CYLINDER), ("parabola", PARABOLA)])
def test_end_to_end_with_a_moving_obstacle(tmp_path, name, shape):
    """Press and partly release (two stages), friction 0.2, a half model: every output file is
    written, the summary names the kind and recognises the half model, the contact profile
    carries s, the force-displacement curve is the resultant along the motion, equilibrium
    holds on every snapshot."""
    path = write_case(tmp_path, E2E.format(name=name, shape=shape))
    out = tmp_path / "out"
    result, summary = run_case(path, out=out)
    assert summary["stop"]["kind"] == "completed"
    for f in (
        "summary.json",
        "events.csv",
        "contact_profile.csv",
        "results.xdmf",
        "contact_interface.png",
        "contact_extent.png",
        "force_displacement.png",
    ):
        assert (out / f).is_file(), f
    press = json.loads((out / "summary.json").read_text())["contacts"]["press"]
    assert press["kind"] == ("rigid_circle" if name == "cylinder" else "rigid_polyline")
    assert press["half_model"] and press["n_closed"] > 0 and "hertz" not in summary
    assert press["origin"] == [0.0, 5.0]
    assert summary["contact_half_width"] > 0
    header = (out / "contact_profile.csv").read_text().splitlines()[0].split(",")
    assert "s" in header

    scene = build_scene(parse_case(path.read_text(), source=str(path)))
    curves = force_displacement(scene, result)
    last = result["snapshots"][-1]
    assert curves["press"]["what"] == "contact force along the motion"
    assert curves["press"]["displacement"][-1] == pytest.approx(0.3 * 0.02, rel=1e-12)
    p = scene.model["pairs"]
    resultant = -(last["lambda_n"] @ p["normal"][:, 1] + last["lambda_t"] @ p["normal"][:, 0])
    assert curves["press"]["force"][-1] == pytest.approx(resultant, rel=1e-12)
    worst, k, f = worst_equilibrium(scene.model, result["snapshots"])
    assert worst <= EQUILIBRIUM_TOL, f"recomputed residual {worst:.2e} at snapshot {k}"


CYLINDER_ON_BLOCK = """
[case]
name = "cylinder_on_block"
[analysis]
plane = "strain"
[output]
snapshots = [1.0]
figures = false
xdmf = false
[[body]]
name = "block"
[body.mesh]
generator = "block"
x0 = -20.0
width = 40.0
height = 20.0
h = {h}
refine_box = [-2.0, 17.0, 2.0, 20.0]
h_max = 4.0
growth = 0.3
[body.material]
E = 70000.0
nu = 0.3
[[bc]]
body = "block"
edge = "bottom"
fix = ["x", "y"]
[[contact]]
name = "cylinder"
kind = "rigid_circle"
body = "block"
edge = "top"
centre = [0.0, 70.0]
radius = 50.0
x_min = -2.0
x_max = 2.0
motion = [0.0, -0.03]
"""


@needs_gmsh
def test_rigid_cylinder_indenting_a_block_follows_hertz():
    """A rigid cylinder R = 50 pushed 0.03 into an elastic block 40 x 20 (plane strain,
    E = 70000, nu = 0.3, bottom fixed, frictionless), full model, structured at h = 0.1 and
    0.05 inside the box |x| <= 2, 3 below the top (refined block): the peak pressure p0 (node
    x = 0's force over its tributary length h t, recomputed here) against Hertz's for the
    measured force, p0 = sqrt(P E*/(pi R)) (E* = E/(1 - nu^2) of the block alone; P the
    vertical resultant of the contact forces).  p0 carries the stiffness: p0 ~ sqrt(E*) at a
    given P, so E off by 20 % moves it by 9.5 %, where a moves by less than one element.

    The nodal pressure converges at first order (measured errors -4.2 %, -2.3 %, -1.2 % at
    h = 0.1, 0.05, 0.025: order 0.9): the error must fall between the meshes at an order of at
    least 0.7, and the first-order Richardson value 2 p0(h/2) - p0(h) lie within 1 % of Hertz
    (measured -0.31 %; the Richardson remainder is the higher-order rest, below the 1 % that a
    2 % stiffness error would exceed).  What else separates the model from Hertz is far
    smaller: the finite block (a/H ~ 0.045, effects of order (a/H)^2 ~ 2e-3), Hertz's
    parabolic profile (a/R ~ 0.018, order (a/R)^2) and the fixed normals of small sliding.
    The contact half-width (half the closed extent, interpolated as the summary does) stays
    within one element of Hertz's a on the fine mesh."""
    p0, ref = {}, {}
    for h in (0.1, 0.05):
        scene = build_scene(parse_case(CYLINDER_ON_BLOCK.format(h=h), source="cylinder"))
        result = solve(scene)
        assert result["stop"]["kind"] == "completed"
        last = result["snapshots"][-1]
        n = scene.model["pairs"]["normal"]
        P = -float(last["lambda_n"] @ n[:, 1]) / scene.model["thickness"]
        centre = int(np.argmin(np.abs(scene.pair_xy[:, 0])))
        assert scene.pair_xy[centre, 0] == 0.0
        p0[h] = last["lambda_n"][centre] / (h * scene.model["thickness"])
        a_hertz, ref[h] = hertz_line(P, 50.0, 70000.0, 0.3)
        worst, k, f = worst_equilibrium(scene.model, result["snapshots"])
        assert worst <= EQUILIBRIUM_TOL, f"recomputed residual {worst:.2e} at snapshot {k}"
    errors = [p0[h] / ref[h] - 1.0 for h in (0.1, 0.05)]
    assert abs(errors[1]) < abs(errors[0]) and observed_order(*errors) >= 0.7, errors
    extrapolated = richardson(p0[0.1] / ref[0.1], p0[0.05] / ref[0.05], order=1.0)
    assert abs(extrapolated - 1.0) <= 0.01, f"p0 -> {extrapolated:.4f} p0_Hertz ({errors})"
    summary = summarize(scene, result)
    lo, hi = summary["contacts"]["cylinder"]["closed_extent"]
    # the mesh outside the box is gmsh's, not mirror-symmetric: the ends move by 4e-4 h
    # (measured); a contact off by one node would be off by h
    assert abs(hi + lo) <= 0.01 * 0.05, "the symmetric scene has a symmetric contact"
    assert a_hertz >= 10 * 0.05 and abs(0.5 * (hi - lo) - a_hertz) <= 0.05, (lo, hi, a_hertz)
    assert not summary["contact_reached_last_candidate"]
    assert "hertz" not in summary  # the Hertz block is the quarter-cylinder case's only
