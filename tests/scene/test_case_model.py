"""Case -> engine model: supports, consistent nodal loads, contact pairs, the model layout."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import CASES, MINIMAL, needs_gmsh, write_case

from slipstep.mesh import triangles as M
from slipstep.mesh import triangle_generators as generators
from slipstep.case import CaseError, load_case, parse_case
from slipstep.build import build_scene
from slipstep.contact.edges import tributary_lengths
from slipstep.loads.vectors import edge_load


@pytest.fixture(scope="module")
def hertz():
    return build_scene(load_case(None))


@pytest.fixture(scope="module")
def blocks():
    return build_scene(load_case(CASES / "two_blocks.toml"))


# --------------------------------------------------------------------------- loads
@pytest.mark.parametrize("q, t", [(10.0, 1.0), (3.7, 2.5), (-1.25, 0.3)])
def test_pressure_on_a_straight_edge_sums_to_q_L_t(q, t):
    b = generators.block(7.3, 2.0, 13, 4)
    f = edge_load(b.nodes, b.edges["top"], b.n_nodes, t, pressure=q)
    expected = -q * 7.3 * t  # acts against the outward normal (0, 1)
    assert abs(f[1::2].sum() - expected) <= 1e-12 * abs(expected)
    assert f[0::2].sum() == 0.0
    # linear edges: each end node gets half of q L t of each segment
    h = 7.3 / 13
    top = b.nodes[:, 1] == 2.0
    inner = top & (b.nodes[:, 0] > 1e-9) & (b.nodes[:, 0] < 7.3 - 1e-9)
    assert np.allclose(f[1::2][inner], -q * h * t, rtol=1e-12)
    corners = top & ~inner
    assert np.allclose(f[1::2][corners], -q * h * t / 2, rtol=1e-12)


def test_traction_on_a_polyline_sums_to_traction_L_t():
    nodes = np.array([[0.0, 0.0], [1.0, 0.5], [2.5, 0.2], [3.0, 1.0]])
    segs = np.array([[0, 1], [1, 2], [2, 3]])
    L = np.linalg.norm(np.diff(nodes, axis=0), axis=1).sum()
    f = edge_load(nodes, segs, 4, 2.0, traction=(1.5, -4.0))
    assert abs(f[0::2].sum() - 1.5 * L * 2.0) <= 1e-12 * 1.5 * L * 2.0
    assert abs(f[1::2].sum() + 4.0 * L * 2.0) <= 1e-12 * 4.0 * L * 2.0


def test_block_case_pressure_resultant(blocks):
    f = blocks.model["load"]
    # two_blocks: 10 MPa on the 10 mm punch top, thickness 1
    assert abs(f[1::2].sum() + 100.0) <= 1e-12 * 100.0
    assert f[0::2].sum() == 0.0


@needs_gmsh
def test_hertz_load_is_P_over_2R_on_the_cut(hertz):
    """q = P/(2R) on the cut y = R of length R: the quarter carries P/2 (per unit thickness)."""
    f = hertz.model["load"]
    assert abs(f[1::2].sum() + 500.0) <= 1e-12 * 500.0
    assert abs(f[0::2].sum()) <= 1e-12 * 500.0
    loaded = np.flatnonzero(f[1::2] != 0.0)
    assert np.all(hertz.nodes[loaded, 1] == 125.0)


def test_point_load_goes_to_the_nearest_node(tmp_path):
    text = (
        MINIMAL + "\n[[point_load]]\nat = [1.02, 0.49]\nforce = [0.0, -3.0]\n"
        "\n[analysis]\nthickness = 2.0\n"
    )
    scene = build_scene(parse_case(text))
    f = scene.model["load"]
    node = np.flatnonzero(f != 0.0)
    assert len(node) == 1 and node[0] % 2 == 1
    assert np.allclose(scene.nodes[node[0] // 2], [1.0, 0.5])
    assert f[node[0]] == -6.0


# --------------------------------------------------------------------------- supports
@needs_gmsh
def test_symmetry_fixes_the_normal_component(hertz):
    fixed = hertz.model["fixed_dofs"]
    assert np.all(fixed % 2 == 0)  # x components only
    nodes = fixed // 2
    assert np.all(hertz.nodes[nodes, 0] == 0.0)
    assert len(nodes) == len(hertz.meshes["cylinder"].edge_nodes("symmetry"))


def test_fix_and_symmetry_in_blocks(blocks):
    fixed = set(blocks.model["fixed_dofs"].tolist())
    bottom = np.unique(blocks.global_edge("foundation", "bottom"))
    assert all(2 * n in fixed and 2 * n + 1 in fixed for n in bottom)
    for body in ("punch", "foundation"):
        for n in np.unique(blocks.global_edge(body, "left")):
            assert 2 * n in fixed
    top = np.unique(blocks.global_edge("punch", "top"))
    assert not any(2 * n + 1 in fixed for n in top)


def test_symmetry_on_an_inclined_edge_is_refused(tmp_path):
    import meshio

    nodes = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    m = meshio.Mesh(
        nodes,
        [("triangle", np.array([[0, 1, 2]])), ("line", np.array([[1, 2]]))],
        cell_data={"tag": [np.array([0]), np.array([7])]},
    )
    meshio.write(tmp_path / "tri.xdmf", m)
    text = (
        MINIMAL.split("[body.mesh]")[0]
        + '[body.mesh]\nfile = "tri.xdmf"\n'
        + "[body.material]"
        + MINIMAL.split("[body.material]")[1].split("[[bc]]")[0]
        + '[[bc]]\nbody = "b"\nedge = "7"\nsymmetry = true\n'
    )
    path = write_case(tmp_path, text)
    with pytest.raises(CaseError, match=r"bc.symmetry: edge '7' is not a straight line parallel"):
        build_scene(load_case(path))


def test_unknown_tag_of_a_file_mesh_is_found_after_reading(tmp_path):
    import meshio

    nodes = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    meshio.write(tmp_path / "tri.xdmf", meshio.Mesh(nodes, [("triangle", np.array([[0, 1, 2]]))]))
    text = MINIMAL.replace(
        'generator = "block"\nwidth = 2.0\nheight = 1.0\nnx = 4\nny = 2', 'file = "tri.xdmf"'
    )
    path = write_case(tmp_path, text)
    with pytest.raises(CaseError) as info:
        build_scene(load_case(path))
    assert 'bc.edge = "bottom" is not allowed: body "b" has no edge with that tag' in str(
        info.value
    )


# --------------------------------------------------------------------------- contact
@needs_gmsh
def test_hertz_pairs_against_the_flat(hertz):
    pairs = hertz.model["pairs"]
    a = pairs["node_a"]
    xy = hertz.nodes[a]
    assert np.all(pairs["node_b"] == -1)
    assert np.allclose(pairs["normal"], [0.0, 1.0])
    assert np.array_equal(pairs["gap"], xy[:, 1])  # gap = y above the flat y = 0
    assert np.all(xy[:, 0] <= 3.0) and xy[:, 0].max() > 2.9
    assert np.count_nonzero(pairs["gap"] == 0.0) == 1  # only (0, 0) starts closed
    assert np.all(pairs["mu"] == 0.0)
    # tributary lengths: half segments; the symmetry node gets one half only
    arc = hertz.global_edge("cylinder", "arc")
    assert np.allclose(hertz.pair_length, tributary_lengths(hertz.nodes, arc, a))
    origin = np.flatnonzero((xy == 0.0).all(axis=1))[0]
    first = np.sort(np.linalg.norm(xy, axis=1))[1]
    assert abs(hertz.pair_length[origin] - first / 2) <= 1e-3 * first


def test_node_to_node_pairs_of_the_blocks(blocks):
    pairs = blocks.model["pairs"]
    xa, xb = blocks.nodes[pairs["node_a"]], blocks.nodes[pairs["node_b"]]
    assert len(xa) == 21
    assert np.abs(xa - xb).max() <= 1e-12
    assert np.all(pairs["gap"] == 0.0)
    assert np.allclose(pairs["normal"], [0.0, 1.0])  # foundation's outward normal
    assert np.all(pairs["mu"] == 0.2)
    assert np.all(pairs["node_a"] < blocks.offsets["foundation"])  # a = punch
    assert np.all(pairs["node_b"] >= blocks.offsets["foundation"])


@needs_gmsh
def test_initial_penetration_is_an_error():
    with pytest.raises(CaseError) as info:
        build_scene(load_case(None, ["contact.point=[0.0, 0.001]"]))
    msg = str(info.value)
    assert "contact: initial penetration at node" in msg and "by 0.001" in msg
    assert "\n" not in msg


def test_empty_candidate_window_is_an_error():
    with pytest.raises(CaseError, match=r"contact.x_max: no node of edge 'top'"):
        build_scene(parse_case(MINIMAL, overrides=["contact.x_max=-5.0"]))


# --------------------------------------------------------------------------- layout
def test_model_matches_the_engine_contract(blocks):
    m = blocks.model
    n = len(m["nodes"])
    assert m["nodes"].dtype == np.float64 and m["nodes"].shape == (n, 2)
    assert m["triangles"].dtype == np.int64 and m["triangles"].shape[1] == 3
    assert m["element_material"].dtype == np.int64
    assert m["element_material"].shape == (len(m["triangles"]),)
    assert m["materials"] == [{"E": 70000.0, "nu": 0.3}, {"E": 70000.0, "nu": 0.3}]
    assert m["plane"] == "strain" and m["thickness"] == 1.0
    assert m["fixed_dofs"].dtype == np.int64 and np.all(np.diff(m["fixed_dofs"]) > 0)
    assert m["load"].shape == (2 * n,) and m["load"].dtype == np.float64
    p = m["pairs"]
    assert p["node_a"].dtype == p["node_b"].dtype == np.int64
    assert p["normal"].shape == (len(p["node_a"]), 2)
    assert np.all(p["gap"] >= 0.0)
    assert m["options"]["output"] == "events"
    assert (M.signed_areas(m["nodes"], m["triangles"]) > 0).all()


def test_fraction_snapshots_always_include_one():
    scene = build_scene(parse_case(MINIMAL, overrides=["output.snapshots=[0.25, 0.5]"]))
    assert scene.model["options"]["output"] == "fractions"
    assert scene.model["options"]["fractions"].tolist() == [0.25, 0.5, 1.0]


def test_plastic_material_is_passed_through():
    scene = build_scene(parse_case(MINIMAL, overrides=["material.Sy=200.0"]))
    assert scene.model["materials"] == [{"E": 1000.0, "nu": 0.25, "Sy": 200.0, "H": 0.0}]


@needs_gmsh
def test_hertz_reference_values(hertz):
    ref = hertz.reference
    assert abs(ref["a_hertz"] - 1.4384) <= 1e-4
    assert abs(ref["p0_hertz"] - 442.6) <= 0.05


def test_model_names_bodies_and_contacts_for_the_engine(blocks):
    """The contract's naming keys: body_names in case order, element_body indexing them,
    contact_names (the [[contact]]'s name, else "contact <i>") and pairs.contact indexing
    those."""
    m = blocks.model
    assert m["body_names"] == ["punch", "foundation"]
    eb = m["element_body"]
    assert eb.dtype == np.int64 and eb.shape == (len(m["triangles"]),)
    # the punch's elements come first: as many as its own mesh has
    assert np.count_nonzero(eb == 0) == blocks.meshes["punch"].n_elements
    assert np.array_equal(
        eb,
        np.repeat(
            [0, 1], [blocks.meshes["punch"].n_elements, blocks.meshes["foundation"].n_elements]
        ),
    )
    assert m["contact_names"] == ["contact 0"]  # two_blocks' contact has no name
    contact = m["pairs"]["contact"]
    assert contact.dtype == np.int64 and np.all(contact == 0)
    assert len(contact) == len(m["pairs"]["node_a"])


def test_contact_names_come_from_the_case():
    text = MINIMAL.replace(
        '[[contact]]\nkind = "rigid_line"', '[[contact]]\nname = "lid"\nkind = "rigid_line"'
    )
    text += (
        '\n[[contact]]\nkind = "rigid_line"\nbody = "b"\nedge = "right"\n'
        'point = [2.0, 0.0]\nnormal = [-1.0, 0.0]\ny_min = 0.5\n'
    )
    m = build_scene(parse_case(text)).model
    assert m["contact_names"] == ["lid", "contact 1"]
    top, right = 4 + 1, 2  # nx = 4, ny = 2: the top nodes, the right ones at y >= 0.5
    assert m["pairs"]["contact"].tolist() == [0] * top + [1] * right


def test_build_scene_takes_a_ready_mesh_for_a_body():
    """A body whose mesh is given is not meshed: the scene holds exactly that mesh (here 3 x 5
    divisions where the case says 4 x 2)."""
    given = generators.block(2.0, 1.0, 3, 5)
    scene = build_scene(parse_case(MINIMAL), meshes={"b": given})
    assert scene.meshes["b"] is given
    assert np.array_equal(scene.model["nodes"], given.nodes)
    assert np.array_equal(scene.model["triangles"], given.triangles)
    assert len(scene.model["pairs"]["node_a"]) == 3 + 1  # the top edge of the given mesh


def test_build_scene_refuses_a_mesh_for_an_unknown_body():
    from slipstep.errors import InputError

    with pytest.raises(InputError, match=r"meshes given for 'nope'.*its bodies: b"):
        build_scene(parse_case(MINIMAL), meshes={"nope": generators.block(1.0, 1.0, 1, 1)})
