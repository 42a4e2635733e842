"""The graded block (issue 14): ``generator = "block"`` with ``h_contact`` meshes the rectangle
unstructured by gmsh, fine around ``focus``; without ``h_contact`` it stays the structured
block, bit for bit."""

from __future__ import annotations

import hashlib

import numpy as np
import pytest
from conftest import needs_gmsh

from slipstep.mesh import triangles as M
from slipstep.mesh import triangle_generators as generators
from slipstep.case import CaseError, parse_case
from slipstep.builders.section import mesh_body

#: the issue's scene: a 100 x 100 block standing for a half-space, fine at the top middle
W, H, HC, ZONE, HMAX = 100.0, 100.0, 0.25, 10.0, 10.0


@pytest.fixture(scope="module")
def half_space():
    return generators.graded_block(W, H, HC, ZONE, HMAX)


def side_counts(mesh: M.Mesh) -> tuple[np.ndarray, np.ndarray]:
    """Every triangle side once (node pairs, sorted) and how many triangles share it."""
    t = mesh.triangles
    return np.unique(
        np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1),
        axis=0,
        return_counts=True,
    )


def sides(mesh: M.Mesh) -> tuple[np.ndarray, np.ndarray]:
    """Every triangle side once: its length and its midpoint."""
    pairs, _ = side_counts(mesh)
    p, q = mesh.nodes[pairs[:, 0]], mesh.nodes[pairs[:, 1]]
    return np.linalg.norm(q - p, axis=1), 0.5 * (p + q)


def assert_edges_are_the_boundary(mesh: M.Mesh) -> None:
    """Conforming (no side shared by three triangles), and the tagged segments are exactly
    the boundary sides of the triangulation, each once."""
    uniq, counts = side_counts(mesh)
    assert counts.max() == 2
    boundary = {tuple(s) for s in uniq[counts == 1]}
    tagged = [tuple(s) for tag in mesh.edges for s in np.sort(mesh.edges[tag], axis=1)]
    assert len(tagged) == len(set(tagged)) and set(tagged) == boundary


def segment_lengths(mesh: M.Mesh, tag: str) -> np.ndarray:
    s = mesh.edges[tag]
    return np.linalg.norm(mesh.nodes[s[:, 1]] - mesh.nodes[s[:, 0]], axis=1)


def size_law(d, h_contact=HC, zone=ZONE, h_max=HMAX, growth=0.1):
    return np.minimum(h_contact + growth * np.maximum(d - zone, 0.0), h_max)


# --------------------------------------------------------------------------- the mesh
@needs_gmsh
def test_node_count_of_the_half_space_block(half_space):
    """The point of the graded block: the structured block at h = 0.25 has 401^2 = 160 801
    nodes; the graded one must stay below 20 000 (measured: 5 468, gmsh 4.15)."""
    print(
        f"graded 100 x 100 block, h_contact = 0.25: {half_space.n_nodes} nodes, "
        f"{half_space.n_elements} triangles"
    )
    assert half_space.n_nodes < 20_000, half_space.n_nodes


@needs_gmsh
def test_element_size_near_focus_and_far_away(half_space):
    focus = np.array([W / 2, H])
    L, mid = sides(half_space)
    d = np.linalg.norm(mid - focus, axis=1)
    # near focus: gmsh aims at sides of length h_contact; a frontal-Delaunay triangulation
    # spreads the sides of its near-equilateral triangles about that target (measured 0.70 to
    # 1.27 h_contact, mean 0.99), so the mean is held to 10 % and every side to 1.5 h_contact
    near = d < 0.8 * ZONE
    assert abs(L[near].mean() / HC - 1.0) < 0.10
    assert L[near].max() <= 1.5 * HC
    # along the top edge, within contact_zone of focus, the spacing is h_contact: gmsh's 1D
    # mesher rounds the number of segments up, so they are at most h_contact; 1.2 allows for
    # a segment that straddles the end of the zone (the bound)
    seg = half_space.edges["top"]
    ends = half_space.nodes[seg]
    within = np.linalg.norm(ends - focus, axis=2).max(axis=1) <= ZONE
    top = segment_lengths(half_space, "top")
    assert within.sum() >= 2 * ZONE / (1.2 * HC)  # the whole zone on both sides of focus
    assert top[within].max() <= 1.2 * HC
    # far away the sides follow h_contact + growth (d - contact_zone): the mean ratio to the
    # law within 15 % (measured 0.94 to 0.96 per band; the law is taken at the side's
    # midpoint while gmsh integrates the size along the side, which biases the ratio a little
    # below 1 where the size grows)
    for lo, hi in ((20.0, 40.0), (40.0, 60.0), (60.0, 120.0)):
        band = (d >= lo) & (d < hi)
        assert band.sum() > 50  # enough sides for a mean (measured 392 to 1576)
        ratio = L[band] / size_law(d[band])
        assert abs(ratio.mean() - 1.0) < 0.15, (lo, hi, ratio.mean())
    # the far sides are coarse: at least 10 h_contact (measured 16), at most h_max + 25 %
    # (measured 1.03 h_max: sides scatter about the target as near focus; the cylinder's
    # test uses the same bound)
    assert L[d > 60.0].min() >= 10 * HC
    assert L.max() <= 1.25 * HMAX


@needs_gmsh
@pytest.mark.parametrize(
    "focus, on",
    [
        ((50.0, 100.0), ("top",)),
        ((100.0, 30.0), ("right",)),
        ((12.5, 0.0), ("bottom",)),
        ((0.0, 100.0), ("top", "left")),
        ((30.0, 40.0), ()),
    ],
)
def test_a_node_sits_exactly_at_focus(focus, on):
    """On an edge (it is split there), at a corner, and inside (an embedded point)."""
    m = generators.graded_block(W, H, 1.0, 5.0, 20.0, focus=focus)
    at = np.flatnonzero((m.nodes[:, 0] == focus[0]) & (m.nodes[:, 1] == focus[1]))
    assert len(at) == 1
    assert m.node_sets["focus"].tolist() == at.tolist()
    for tag in ("bottom", "right", "top", "left"):
        assert (at[0] in m.edge_nodes(tag)) == (tag in on), tag
    # the fine size reaches the focus wherever it is: sides within 2 h_contact of it are at
    # most 1.5 h_contact (the spread of a frontal-Delaunay mesh about its target, as above)
    L, mid = sides(m)
    assert L[np.linalg.norm(mid - focus, axis=1) < 2.0].max() <= 1.5 * 1.0


@needs_gmsh
def test_edge_tags_cover_the_boundary(half_space):
    m = half_space
    lengths = {tag: segment_lengths(m, tag).sum() for tag in ("bottom", "right", "top", "left")}
    # each side's segments are chords of a straight line whose nodes lie exactly on it
    # (snapped): their lengths add up to the side length up to round-off of ~100 additions
    for tag, side in (("bottom", W), ("right", H), ("top", W), ("left", H)):
        assert abs(lengths[tag] - side) <= 1e-12 * side, tag
    assert abs(sum(lengths.values()) - 2 * (W + H)) <= 1e-12 * 2 * (W + H)
    # the tagged segments are exactly the boundary sides of the triangulation
    assert_edges_are_the_boundary(m)
    # the nodes of a side lie exactly on its line; outward normals (body on the left)
    expected = {
        "bottom": (1, 0.0, [0, -1]),
        "right": (0, W, [1, 0]),
        "top": (1, H, [0, 1]),
        "left": (0, 0.0, [-1, 0]),
    }
    for tag, (axis, value, n) in expected.items():
        assert np.all(m.nodes[m.edge_nodes(tag), axis] == value), tag
        assert np.allclose(M.outward_normals(m.nodes, m.edges[tag]), n, atol=1e-12), tag
        s = m.edges[tag]
        assert np.array_equal(s[1:, 0], s[:-1, 1]), tag  # one chain, in order
    corners = {
        "corner_bottom_left": [0.0, 0.0],
        "corner_bottom_right": [W, 0.0],
        "corner_top_right": [W, H],
        "corner_top_left": [0.0, H],
    }
    for name, xy in corners.items():
        assert m.nodes[m.node_sets[name]].tolist() == [xy], name


@needs_gmsh
def test_triangles_are_counter_clockwise_and_fill_the_rectangle(half_space):
    m = half_space
    assert (M.signed_areas(m.nodes, m.triangles) > 0).all()
    M.check_triangles(m.nodes, m.triangles)  # no exception
    # straight sides with exact nodes: the area is exact up to round-off of ~10^4 terms
    assert abs(m.area() - W * H) <= 1e-10 * W * H


@needs_gmsh
def test_offset_block_and_determinism():
    a = generators.graded_block(3.0, 2.0, 0.1, 0.5, 0.4, growth=0.3, x0=-1.0, y0=5.0)
    b = generators.graded_block(3.0, 2.0, 0.1, 0.5, 0.4, growth=0.3, x0=-1.0, y0=5.0)
    assert np.array_equal(a.nodes, b.nodes) and np.array_equal(a.triangles, b.triangles)
    # the default focus is the middle of the top edge
    assert a.nodes[a.node_sets["focus"]].tolist() == [[0.5, 7.0]]
    assert a.nodes[:, 0].min() == -1.0 and a.nodes[:, 0].max() == 2.0
    assert a.nodes[:, 1].min() == 5.0 and a.nodes[:, 1].max() == 7.0


def test_graded_block_refuses_bad_arguments():
    with pytest.raises(M.MeshError, match=r"need 0 < h_contact <= h_max"):
        generators.graded_block(1.0, 1.0, 0.5, 0.2, 0.1)
    with pytest.raises(M.MeshError, match=r"contact_zone = 0, growth = 0.1: both must be > 0"):
        generators.graded_block(1.0, 1.0, 0.05, 0.0, 0.1)
    with pytest.raises(M.MeshError, match=r"focus \(2, 0.5\) lies outside the block"):
        generators.graded_block(1.0, 1.0, 0.05, 0.2, 0.1, focus=(2.0, 0.5))


# --------------------------------------------------------------------------- the case file
CASE = """
[[body]]
name = "b"
[body.mesh]
generator = "block"
x0 = -1.5
y0 = 2.25
width = 3.0
height = 1.7
{mesh}
[body.material]
E = 1000.0
nu = 0.25

[[bc]]
body = "b"
edge = "bottom"
fix = ["x", "y"]

[[bc]]
body = "b"
edge = "top"
pressure = 1.0
"""


def digest(mesh: M.Mesh) -> str:
    h = hashlib.sha256()
    h.update(mesh.nodes.tobytes())
    h.update(mesh.triangles.tobytes())
    for k in sorted(mesh.edges):
        h.update(k.encode())
        h.update(mesh.edges[k].tobytes())
    return h.hexdigest()


@pytest.mark.parametrize(
    "size, nx, ny, expected",
    [
        (
            "nx = 7\nny = 3",
            7,
            3,
            "c42b2bf555994e0e8c7b0f81ea65715508e8e37387feb38e3b4c4d32e281032f",
        ),
        ("h = 0.3", 10, 6, "93c0cd95f77a57c39670a857e29eb747b48d292adfd49a4209ddb34ac2b38559"),
    ],
)
def test_structured_block_is_unchanged_without_h_contact(size, nx, ny, expected):
    """Shipped block cases must not change: the digests were taken with the code before the
    graded block existed (commit e32158a); the arrays are compared bit for bit."""
    case = parse_case(CASE.format(mesh=size))
    assert case.data["body"][0]["mesh"]["h_contact"] == 0.0
    m = mesh_body(case, 0)
    ref = generators.block(3.0, 1.7, nx, ny, -1.5, 2.25)
    assert np.array_equal(m.nodes, ref.nodes) and np.array_equal(m.triangles, ref.triangles)
    assert digest(m) == expected


@needs_gmsh
def test_case_with_a_graded_block():
    case = parse_case(CASE.format(mesh="h_contact = 0.05\ncontact_zone = 0.4\nh_max = 0.5"))
    spec = case.data["body"][0]["mesh"]
    assert spec["growth"] == 0.1 and spec["focus"] is None
    m = mesh_body(case, 0)
    assert m.nodes[m.node_sets["focus"]].tolist() == [[0.0, 3.95]]  # the middle of the top
    assert set(m.edges) == {"bottom", "right", "top", "left"}
    assert (M.signed_areas(m.nodes, m.triangles) > 0).all()
    # a focus on the left edge, through the case file
    case = parse_case(
        CASE.format(
            mesh="h_contact = 0.05\ncontact_zone = 0.4\nh_max = 0.5\n" "focus = [-1.5, 3.0]"
        )
    )
    m = mesh_body(case, 0)
    at = m.node_sets["focus"]
    assert m.nodes[at].tolist() == [[-1.5, 3.0]] and at[0] in m.edge_nodes("left")


GRADED = "h_contact = 0.05\ncontact_zone = 0.4\nh_max = 0.5"


def error_of(mesh: str, overrides=()) -> str:
    with pytest.raises(CaseError) as info:
        parse_case(CASE.format(mesh=mesh), source="x.toml", overrides=overrides)
    message = str(info.value)
    assert "\n" not in message, "errors must be one line"
    return message


@pytest.mark.parametrize(
    "mesh, words",
    [
        (
            "h_contact = 0.6\ncontact_zone = 0.4\nh_max = 0.5",
            "x.toml: mesh.h_contact = 0.6 is not allowed: it must not exceed h_max = 0.5",
        ),
        (
            GRADED.replace("0.4", "0.0"),
            "x.toml: mesh.contact_zone = 0.0 is not allowed: contact_zone must be > 0",
        ),
        (
            GRADED.replace("0.4", "-1.0"),
            "x.toml: mesh.contact_zone = -1.0 is not allowed: contact_zone must be > 0",
        ),
        (
            "h_contact = 0.05\nh_max = 0.5",
            "x.toml: mesh.contact_zone is missing: the graded block (h_contact = 0.05) needs the "
            "radius of the fine zone around focus [length]; add `contact_zone = ...` to [body.mesh]",
        ),
        (
            "h_contact = 0.05\ncontact_zone = 0.4",
            "x.toml: mesh.h_max is missing: the graded block (h_contact = 0.05) needs the largest "
            "element size [length]",
        ),
        (
            GRADED + "\nfocus = [1.6, 3.0]",
            "x.toml: mesh.focus = [1.6, 3.0] is not allowed: it lies outside the block [-1.5, 1.5] x "
            "[2.25, 3.95]; move it inside or onto the boundary",
        ),
        (
            GRADED + "\nfocus = [0.0, 4.0]",
            "mesh.focus = [0.0, 4.0] is not allowed: it lies outside",
        ),
        (
            GRADED + "\nnx = 10",
            "x.toml: mesh.nx = 10 is not allowed together with h_contact = 0.05: nx/ny/h make the "
            "structured block, h_contact the graded one; drop nx (or h_contact)",
        ),
        (GRADED + "\nny = 4", "mesh.ny = 4 is not allowed together with h_contact = 0.05"),
        (GRADED + "\nh = 0.1", "mesh.h = 0.1 is not allowed together with h_contact = 0.05"),
        (
            "h = 0.1\ncontact_zone = 0.4",
            "x.toml: mesh.contact_zone = 0.4 is not allowed without h_contact: it shapes the graded "
            "block (h_contact > 0); add h_contact or drop contact_zone",
        ),
        ("h = 0.1\nfocus = [0.0, 3.0]", "mesh.focus = [0.0, 3.0] is not allowed without h_contact"),
        ("h = 0.1\ngrowth = 0.2", "mesh.growth = 0.2 is not allowed without h_contact"),
        (
            "nx = 4",
            "x.toml: mesh.ny is missing: give ny (divisions along height) or h (element "
            "size), or h_contact (a graded gmsh mesh)",
        ),
        (
            GRADED.replace("0.05", "-0.05"),
            "mesh.h_contact = -0.05 is not allowed: h_contact must " "be >= 0",
        ),
    ],
)
def test_validation_errors_name_the_key_and_the_fix(mesh, words):
    assert words in error_of(mesh)


def test_override_to_graded_says_which_key_to_drop():
    message = error_of(
        "nx = 7\nny = 3",
        overrides=["mesh.h_contact=0.05", "mesh.contact_zone=0.4", "mesh.h_max=0.5"],
    )
    assert "mesh.nx = 7 is not allowed together with h_contact = 0.05" in message
    # setting nx and ny to 0 drops them: the override then gives a graded block
    case = parse_case(
        CASE.format(mesh="nx = 7\nny = 3"),
        overrides=[
            "mesh.h_contact=0.05",
            "mesh.contact_zone=0.4",
            "mesh.h_max=0.5",
            "mesh.nx=0",
            "mesh.ny=0",
        ],
    )
    assert case.data["body"][0]["mesh"]["h_contact"] == 0.05


def test_focus_on_the_boundary_is_allowed():
    for focus in ("[-1.5, 2.25]", "[1.5, 3.0]", "[0.0, 3.95]", "[0.0, 3.0]"):
        case = parse_case(CASE.format(mesh=f"{GRADED}\nfocus = {focus}"))
        assert case.data["body"][0]["mesh"]["focus"] is not None


@needs_gmsh
def test_uniform_edges_put_nodes_where_a_structured_body_has_them():
    """A 100 x 100 half-space graded around the punch corner (10, 0) with uniform_edges: its top
    nodes on [0, 10] are exactly the structured punch's (x = 0, 1, ..., 10, to round-off of the
    coordinates, 1e-12 of the block size), so node_to_node contact can pair them."""
    mesh = generators.graded_block(
        100.0,
        100.0,
        1.0,
        10.0,
        10.0,
        0.12,
        focus=(10.0, 0.0),
        x0=0.0,
        y0=-100.0,
        uniform_edges=True,
    )
    top = np.unique(mesh.edges["top"])
    x = np.sort(mesh.nodes[top, 0])
    near = x[x <= 10.0 + 1e-9]
    assert np.abs(near - np.arange(11.0)).max() <= 1e-12 * 100.0
    # beyond the zone the side is graded as before: fewer nodes than a uniform division
    assert len(x) < 11 + 90


# --------------------------------------------------------------------------- the refined block
#: the paper blocks' half-space at h 1: the structured grid kept inside a box under the punch
BOX, GROWTH = [0.0, -15.0, 15.0, 0.0], 0.15


@pytest.fixture(scope="module")
def refined():
    return generators.refined_block(W, H, 100, 100, BOX, HMAX, GROWTH, 0.0, -100.0)


def triangles_by_position(mesh: M.Mesh, keep) -> set:
    """The triangles whose centroid satisfies keep(x, y), each as its corners' coordinates
    (rotated to start at the smallest corner, so the orientation is kept)."""
    out = set()
    for t in mesh.triangles:
        corners = [tuple(p) for p in mesh.nodes[t].tolist()]
        c = np.mean(corners, axis=0)
        if keep(*c):
            k = corners.index(min(corners))
            out.add(tuple(corners[k:] + corners[:k]))
    return out


@needs_gmsh
@pytest.mark.parametrize("box", [BOX, [0.0, -16.0, 16.0, 0.0], [30.0, -61.0, 47.0, -40.0]])
def test_inside_the_box_the_mesh_is_the_structured_block(box):
    """Same node coordinates (bit for bit) and the same triangles, diagonals included, as
    block(): for boxes starting at odd (j = 85) and even (j = 84) rows, and inside (a hole)."""
    m = generators.refined_block(W, H, 100, 100, box, HMAX, GROWTH, 0.0, -100.0)
    ref = generators.block(W, H, 100, 100, 0.0, -100.0)

    def inside(x, y):
        return box[0] < x < box[2] and box[1] < y < box[3]

    mine, theirs = triangles_by_position(m, inside), triangles_by_position(ref, inside)
    assert len(theirs) == 2 * (box[2] - box[0]) * (box[3] - box[1])
    assert mine == theirs


@needs_gmsh
def test_refined_block_is_a_valid_mesh_with_side_chains(refined):
    m = refined
    assert (M.signed_areas(m.nodes, m.triangles) > 0).all()
    M.check_triangles(m.nodes, m.triangles)
    assert abs(m.area() - W * H) <= 1e-10 * W * H  # straight sides, exact corner nodes
    assert_edges_are_the_boundary(m)  # the box joins the gmsh part without hanging nodes
    expected = {
        "bottom": (1, -100.0, [0, -1]),
        "right": (0, W, [1, 0]),
        "top": (1, 0.0, [0, 1]),
        "left": (0, 0.0, [-1, 0]),
    }
    for tag, (axis, value, n) in expected.items():
        s = m.edges[tag]
        assert np.all(m.nodes[m.edge_nodes(tag), axis] == value), tag
        assert np.allclose(M.outward_normals(m.nodes, s), n, atol=1e-12), tag
        assert np.array_equal(s[1:, 0], s[:-1, 1]), tag  # one chain, in order
    for name, xy in {
        "corner_bottom_left": [0.0, -100.0],
        "corner_bottom_right": [W, -100.0],
        "corner_top_right": [W, 0.0],
        "corner_top_left": [0.0, 0.0],
    }.items():
        assert m.nodes[m.node_sets[name]].tolist() == [xy], name
    # the top inside the box: the structured nodes x = 0, 1, ..., 15 exactly (a structured
    # punch's nodes match them: node_to_node)
    x = np.sort(m.nodes[m.edge_nodes("top"), 0])
    assert np.array_equal(x[:16], np.arange(16.0))


@needs_gmsh
def test_refined_block_coarsens_away_from_the_box(refined):
    """Outside the box the sides follow h + growth d (d from the box), up to h_max: the mean
    ratio to the law within 15 % per band (as for the graded block above: gmsh spreads the
    sides of its near-equilateral triangles about the target)."""
    L, mid = sides(refined)
    dx = np.maximum(mid[:, 0] - BOX[2], 0.0)
    dy = np.maximum(BOX[1] - mid[:, 1], 0.0)
    d = np.hypot(dx, dy)
    law = np.minimum(1.0 + GROWTH * d, HMAX)
    for lo, hi in ((5.0, 20.0), (20.0, 40.0), (40.0, 150.0)):
        band = (d >= lo) & (d < hi)
        assert band.sum() > 50
        assert abs((L[band] / law[band]).mean() - 1.0) < 0.15, (lo, hi)
    # the point of it: ~9 % of the structured block's 10 201 nodes
    assert refined.n_nodes < 0.1 * 101**2


@needs_gmsh
def test_refined_box_is_rounded_out_to_grid_lines_and_may_cover_the_block():
    a = generators.refined_block(W, H, 100, 100, [0.3, -14.2, 14.6, 0.0], HMAX, GROWTH, 0.0, -100.0)
    b = generators.refined_block(W, H, 100, 100, BOX, HMAX, GROWTH, 0.0, -100.0)
    assert np.array_equal(a.nodes, b.nodes) and np.array_equal(a.triangles, b.triangles)
    whole = generators.refined_block(3.0, 1.7, 7, 3, [-1.5, 2.25, 1.5, 3.95], 0.5, x0=-1.5, y0=2.25)
    assert digest(whole) == digest(generators.block(3.0, 1.7, 7, 3, -1.5, 2.25))


@needs_gmsh
def test_a_box_across_the_block_splits_the_rest_in_two():
    """The box spans the block's height: gmsh meshes two pieces, joined to the box's sides."""
    m = generators.refined_block(20.0, 10.0, 20, 10, [5.0, 0.0, 8.0, 10.0], 4.0, 0.3)
    assert (M.signed_areas(m.nodes, m.triangles) > 0).all()
    assert abs(m.area() - 200.0) <= 1e-10 * 200.0
    assert_edges_are_the_boundary(m)
    for tag in ("bottom", "top"):  # the box's grid nodes x = 5..8 on both, coarser beside
        x = np.sort(m.nodes[m.edge_nodes(tag), 0])
        assert set(range(5, 9)) <= set(x.tolist()) and len(x) < 21, tag


def test_refined_block_refuses_bad_arguments():
    with pytest.raises(M.MeshError, match=r"refine_box \[2, 0, 1, 1\] is empty"):
        generators.refined_block(3.0, 3.0, 3, 3, [2.0, 0.0, 1.0, 1.0], 1.0)
    with pytest.raises(M.MeshError, match=r"reaches outside the block \[0, 3\] x \[0, 3\]"):
        generators.refined_block(3.0, 3.0, 3, 3, [1.0, 1.0, 4.0, 2.0], 1.0)
    with pytest.raises(M.MeshError, match=r"need h_max >= the grid spacing 1"):
        generators.refined_block(3.0, 3.0, 3, 3, [1.0, 1.0, 2.0, 2.0], 0.5)


@needs_gmsh
def test_case_with_a_refined_block():
    case = parse_case(
        CASE.format(
            mesh="h = 0.1\nrefine_box = [-0.5, 3.0, 0.5, 3.95]\n" "h_max = 0.5\ngrowth = 0.3"
        )
    )
    spec = case.data["body"][0]["mesh"]
    assert spec["refine_box"] == [-0.5, 3.0, 0.5, 3.95] and spec["growth"] == 0.3
    m = mesh_body(case, 0)
    assert m.n_nodes < 30 * 17 + 1  # coarser than the structured 30 x 17 cells
    mine = triangles_by_position(m, lambda x, y: -0.5 < x < 0.5 and y > 3.0)
    assert mine == triangles_by_position(
        generators.block(3.0, 1.7, 30, 17, -1.5, 2.25), lambda x, y: -0.5 < x < 0.5 and y > 3.0
    )


REFINED = "h = 0.1\nrefine_box = [-0.5, 3.0, 0.5, 3.95]\nh_max = 0.5"


@pytest.mark.parametrize(
    "mesh, words",
    [
        (
            "h = 0.1\nrefine_box = [0.5, 3.0, -0.5, 3.95]\nh_max = 0.5",
            "x.toml: mesh.refine_box = [0.5, 3.0, -0.5, 3.95] is not allowed: write it [x0, y0, x1, "
            "y1] with x0 < x1 and y0 < y1",
        ),
        (
            "h = 0.1\nrefine_box = [-0.5, 3.0, 0.5, 4.0]\nh_max = 0.5",
            "x.toml: mesh.refine_box = [-0.5, 3.0, 0.5, 4.0] is not allowed: it reaches outside the "
            "block [-1.5, 1.5] x [2.25, 3.95]; keep it inside",
        ),
        (
            "h = 0.1\nrefine_box = [-0.5, 3.0, 0.5, 3.95]",
            "x.toml: mesh.h_max is missing: the refined block (refine_box) needs the largest element "
            "size [length]; add `h_max = ...` to [body.mesh]",
        ),
        (
            "h = 0.1\nrefine_box = [-0.5, 3.0, 0.5, 3.95]\nh_max = 0.05",
            "x.toml: mesh.h_max = 0.05 is not allowed: it must not be smaller than the grid spacing "
            "0.1 that the refined block grows from",
        ),
        (
            "h_contact = 0.05\ncontact_zone = 0.4\nh_max = 0.5\nrefine_box = [-0.5, 3.0, 0.5, 3.95]",
            "x.toml: mesh.refine_box = [-0.5, 3.0, 0.5, 3.95] is not allowed together with h_contact "
            "= 0.05: refine_box keeps the structured block (nx/ny or h) inside it, h_contact grades "
            "around focus; drop refine_box (or h_contact)",
        ),
        (
            REFINED + "\ncontact_zone = 0.4",
            "x.toml: mesh.contact_zone = 0.4 is not allowed with refine_box: it shapes the graded "
            "block (h_contact > 0), fine around focus; drop contact_zone",
        ),
        (
            REFINED + "\nfocus = [0.0, 3.95]",
            "mesh.focus = [0.0, 3.95] is not allowed with refine_box",
        ),
        (
            "h = 0.1\nh_max = 0.5",
            "x.toml: mesh.h_max = 0.5 is not allowed without h_contact or refine_box: it shapes the "
            "graded block (h_contact > 0) or the refined one (refine_box); add one of them or drop "
            "h_max",
        ),
        (
            "h = 0.1\nrefine_box = [0.0, 1.0, 2.0]\nh_max = 0.5",
            "x.toml: mesh.refine_box = [0.0, 1.0, 2.0] is not allowed: expected four numbers [x0, y0, "
            "x1, y1]",
        ),
    ],
)
def test_refined_block_validation_names_the_key_and_the_fix(mesh, words):
    assert words in error_of(mesh)
