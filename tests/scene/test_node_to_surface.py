"""Node-to-surface contact in space (slipstep.contact.node_to_surface): mortar-weighted rows on triangles
between independently meshed bodies.  The kinematic half of the 3D contact patch test on
non-matching faces (the weights sum to 1 and -1, and a linear displacement field gives zero
relative displacement in every row, to round-off), the static half's loads (lambda_j = p S_j
spreads into the consistent nodal forces of p on both faces), and a curved contactor's gaps
against int N_j z dA / int N_j dA computed here triangle by triangle."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import needs_gmsh
from space3d import BOX, assert_contract

from slipstep.build import build_scene
from slipstep.case import parse_case
from slipstep.errors import CaseError
from slipstep.loads.faces import face_load
from slipstep.mesh.tetrahedra import triangle_normals

LID = (
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
ny = {ny}
nz = 1
[body.material]
E = 1000.0
nu = 0.25
[[contact]]
kind = "node_to_surface"
body_a = "lid"
face_a = "bottom"
body_b = "b"
face_b = "top"
mu = 0.3
"""
)


def rows(pairs):
    ptr = pairs["weight_ptr"]
    return [
        (pairs["weight_node"][ptr[k] : ptr[k + 1]], pairs["weight_value"][ptr[k] : ptr[k + 1]])
        for k in range(len(ptr) - 1)
    ]


@pytest.mark.parametrize("nx, ny", [(3, 5), (5, 3), (7, 1)])
def test_the_kinematic_patch_test_on_non_matching_faces(nx, ny):
    scene = build_scene(parse_case(LID.format(nx=nx, ny=ny), "lid.toml"))
    assert_contract(scene.model)
    pairs = scene.model["pairs"]
    lid = np.arange(scene.meshes["lid"].n_nodes) + scene.offsets["lid"]
    assert len(pairs["node_a"]) == (nx + 1) * (ny + 1)  # every bottom node of the lid
    rng = np.random.default_rng(nx * 10 + ny)
    a, B = rng.normal(size=3), rng.normal(size=(3, 3))
    u = a + scene.nodes @ B.T  # a linear field: its relative displacement vanishes
    for nodes, w in rows(pairs):
        mine = np.isin(nodes, lid)
        assert abs(w[mine].sum() - 1.0) <= 1e-12 and abs(w[~mine].sum() + 1.0) <= 1e-12
        assert np.abs(w @ u[nodes]).max() <= 1e-12 * np.abs(u).max()
    assert (pairs["gap"] == 0.0).all() and (pairs["normal"] == [0.0, 0.0, 1.0]).all()
    assert np.isclose(scene.pair_area.sum(), 2.0, rtol=1e-13)  # int N_j dA: the whole face


def test_a_uniform_pressure_gives_both_faces_their_consistent_loads():
    """lambda_j = p S_j on every row: the forces on the contactor, sum_j lambda_j c_jk, are p
    times its consistent nodal areas, and those on the target minus p times its own (the
    target face is covered by the contactor face)."""
    scene = build_scene(parse_case(LID.format(nx=3, ny=4), "lid.toml"))
    pairs, p = scene.model["pairs"], 2.5
    force = np.zeros(len(scene.nodes))
    for lam, (nodes, w) in zip(p * scene.pair_area, rows(pairs)):
        np.add.at(force, nodes, lam * w)
    n = len(scene.nodes)
    for body, face, sign in (("lid", "bottom", 1.0), ("b", "top", -1.0)):
        cells = scene.global_boundary(body, face)
        consistent = face_load(scene.nodes, cells, n, pressure=p).reshape(-1, 3)
        ids = np.unique(cells)
        # a pressure pushes each face inwards, as the contact does: up on the lid, down on b
        assert np.allclose(force[ids], consistent[ids, 2], rtol=1e-12, atol=1e-12)
        assert (np.sign(force[ids]) == sign).all()


@needs_gmsh
def test_a_sphere_on_a_box_gets_its_mean_gaps():
    text = (
        BOX.replace(
            'width = 2.0\ndepth = 1.0\nheight = 1.0\nnx = 4\nny = 2\nnz = 2',
            'x0 = -3.0\ny0 = -3.0\nz0 = -1.0\nwidth = 6.0\ndepth = 6.0\nheight = 1.0\n'
            'nx = 5\nny = 5\nnz = 1',
        )
        + """
[[body]]
name = "ball"
[body.mesh]
generator = "sphere"
R = 5.0
portion = "half"
h_contact = 0.3
contact_zone = 1.0
h_max = 2.0
growth = 0.5
[body.material]
E = 1000.0
nu = 0.25
[[contact]]
kind = "node_to_surface"
body_a = "ball"
face_a = "surface"
body_b = "b"
face_b = "top"
z_max = 0.3
"""
    )
    scene = build_scene(parse_case(text, "ball.toml"))
    assert_contract(scene.model)
    pairs = scene.model["pairs"]
    # the triangles around the window's nodes (z <= 0.3) reach r ~ 2.2 < 3: the block under
    # them covers each whole, so every one projects and counts in full
    face = scene.global_boundary("ball", "surface")
    _, area = triangle_normals(scene.nodes, face)
    z = scene.nodes[:, 2]
    for k, j in enumerate(pairs["node_a"]):
        around = np.flatnonzero((face == j).any(axis=1))
        # int N_j z dA = A (2 z_j + z_k + z_l) / 12 over each triangle (z linear on it)
        first = sum(area[t] * (z[face[t]].sum() + z[j]) / 12.0 for t in around)
        mean = first / (area[around].sum() / 3.0)
        expected = (
            0.0
            if j == scene.offsets["ball"] + scene.meshes["ball"].node_sets["bottom_point"][0]
            else mean
        )
        assert abs(pairs["gap"][k] - expected) <= 1e-12 * 5.0, j
    assert np.allclose(pairs["normal"], [0.0, 0.0, 1.0])
    assert (pairs["gap"] == 0.0).sum() == 1  # the lowest point touches: its row starts closed


def test_no_projection_and_penetration_are_one_line_errors():
    text = LID.format(nx=3, ny=3)
    with pytest.raises(
        CaseError,
        match=r"lid.toml: contact.face_b: no node of lid:bottom in "
        r"the candidate window projects onto b:top",
    ):
        build_scene(
            parse_case(
                text.replace("z0 = 1.0\nwidth = 2.0", "z0 = 1.0\nx0 = 5.0\n" "width = 2.0"),
                "lid.toml",
            )
        )
    with pytest.raises(
        CaseError,
        match=r"lid.toml: contact: initial penetration at node \d+ "
        r"\(.*\) by 0.1: move body 'lid' away from body 'b'",
    ):
        build_scene(parse_case(text.replace("z0 = 1.0", "z0 = 0.9"), "lid.toml"))
