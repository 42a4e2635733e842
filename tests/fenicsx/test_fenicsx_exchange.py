"""Mesh exchange slipstep <-> XDMF/HDF5 <-> dolfinx, with the explicit node/dof/cell maps."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import CASES, needs_gmsh
from slipstep import build_scene, load_case
from slipstep.fenicsx import exchange as ex
from slipstep.mesh.triangle_files import read_mesh

pytest.importorskip("dolfinx")

COARSE_HERTZ = ["mesh.h_contact=0.4", "mesh.h_max=12.0", "mesh.contact_zone=3.0"]


@pytest.fixture(scope="module", params=["hertz", "two_blocks"])
def scene(request):
    if request.param == "hertz":
        return build_scene(load_case(None, COARSE_HERTZ))
    return build_scene(
        load_case(
            CASES / "two_blocks.toml", ["body.punch.mesh.h=1.0", "body.foundation.mesh.h=1.0"]
        )
    )


def _edge_sets(segments, tags, names):
    out = {}
    for value, name in names.items():
        segs = segments[tags == value]
        out[name] = {tuple(sorted(s)) for s in segs.tolist()}
    return out


def _scene_edge_sets(scene):
    data = ex.scene_mesh_data(scene)
    return _edge_sets(data.segments, data.edge_tags, data.edge_names)


@needs_gmsh
def test_h5py_round_trip_is_exact(scene, tmp_path):
    xdmf, edges, h5 = ex.write_scene_xdmf(scene, tmp_path / "m.xdmf")
    assert xdmf.exists() and edges.exists() and h5.exists()
    back = ex.read_xdmf_h5(xdmf)
    assert np.array_equal(back.nodes, scene.nodes)
    assert np.array_equal(back.triangles, scene.triangles)
    assert np.array_equal(back.cell_tags - 1, scene.model["element_material"])
    assert _edge_sets(back.segments, back.edge_tags, back.edge_names) == _scene_edge_sets(scene)
    assert back.cell_names == {i + 1: b for i, b in enumerate(scene.bodies)}


@needs_gmsh
def test_slipstep_and_meshio_read_the_files_with_tag_names(scene, tmp_path):
    """The pair of files is also a slipstep file mesh (case `file` + `edge_file`)."""
    xdmf, edges, _ = ex.write_scene_xdmf(scene, tmp_path / "m.xdmf")
    mesh = read_mesh(xdmf, edges)
    assert np.array_equal(mesh.nodes, scene.nodes)
    assert np.array_equal(mesh.triangles, scene.triangles)
    got = {k: {tuple(sorted(s)) for s in v.tolist()} for k, v in mesh.edges.items()}
    assert got == _scene_edge_sets(scene)


@needs_gmsh
def test_dolfinx_reads_the_mesh_and_the_maps_are_explicit(scene, tmp_path):
    from slipstep.fenicsx import dolfinx_api as api

    dm = ex.scene_to_dolfinx(scene, tmp_path)
    msh = dm.mesh
    assert api.mesh_kind(msh) == ("triangle", 1, 2)  # 2D points -> gdim 2
    N, M = len(scene.nodes), len(scene.triangles)
    assert dm.n_nodes == N and dm.n_cells == M
    # node map, both directions: dolfinx coordinates are the slipstep ones, exactly
    x = api.node_coordinates(msh)
    assert np.array_equal(x, scene.nodes[dm.node_of_geom])
    assert np.array_equal(dm.geom_of_node[dm.node_of_geom], np.arange(N))
    assert np.array_equal(x[dm.geom_of_node], scene.nodes)
    # cell map, both directions: same node triples, same local order
    assert np.array_equal(dm.slipstep_triangles(), scene.triangles[dm.element_of_cell])
    assert np.array_equal(dm.cell_of_element[dm.element_of_cell], np.arange(M))
    assert not np.array_equal(dm.element_of_cell, np.arange(M)) or M < 50  # dolfinx reorders
    # cell tags -> materials
    indices, values = api.tag_arrays(dm.cell_tags)
    tag = np.zeros(M, np.int64)
    tag[indices] = values
    assert np.array_equal(tag[dm.cell_of_element] - 1, scene.model["element_material"])
    # facet tags: every tagged segment arrives, on the right nodes
    got = {
        name: {
            tuple(sorted(pair))
            for pair in dm.node_of_geom[api.facet_nodes(msh, api.tagged(dm.facet_tags, value))]
        }
        for value, name in dm.edge_names.items()
    }
    assert got == _scene_edge_sets(scene)
    # dof maps: P1 vector blocks and DG0 dofs sit at the slipstep nodes / centroids (the dof
    # coordinates are computed by dolfinx from its element: 1e-12 is round-off on mm scales)
    V = api.function_space(msh, "Lagrange", 1, (2,))
    block = dm.block_of_node(V)
    assert np.allclose(api.dof_coordinates(V)[block, :2], scene.nodes, rtol=0, atol=1e-12)
    W = api.function_space(msh, "DG", 0)
    centroid = scene.nodes[scene.triangles].mean(axis=1)
    assert np.allclose(
        api.dof_coordinates(W)[dm.dg0_dof_of_element(W), :2], centroid, rtol=0, atol=1e-12
    )
    # Function <-> slipstep arrays
    u = api.function(V)
    values = np.random.default_rng(0).normal(size=(N, 2))
    dm.set_vector_function(u, values)
    assert np.array_equal(dm.vector_function_values(u), values)
    assert np.array_equal(api.dof_values(u).reshape(-1, 2)[block], values)


@needs_gmsh
def test_a_dolfinx_written_mesh_reads_back_and_maps_to_slipstep(scene, tmp_path):
    dm = ex.scene_to_dolfinx(scene, tmp_path)
    path = ex.write_dolfinx_xdmf(dm, tmp_path / "dolfinx_mesh.xdmf")
    back = ex.read_xdmf_h5(path)  # dolfinx layout: mesh, cell_tags, facet_tags in one file
    # dolfinx writes its geometry order: node_of_geom maps it back
    assert np.array_equal(back.nodes, scene.nodes[dm.node_of_geom])
    tris = dm.node_of_geom[back.triangles]
    assert np.array_equal(tris, scene.triangles[dm.element_of_cell])
    assert np.array_equal(back.cell_tags - 1, scene.model["element_material"][dm.element_of_cell])
    segs = dm.node_of_geom[back.segments]
    names = dm.edge_names
    assert _edge_sets(segs, back.edge_tags, names) == _scene_edge_sets(scene)
    # without the map, the original coordinates recover it (where nodes are distinct)
    if len(np.unique(scene.nodes, axis=0)) == len(scene.nodes):
        assert np.array_equal(ex.map_by_coordinates(scene.nodes, back.nodes), dm.node_of_geom)


def test_overlapping_edge_tags_are_refused(tmp_path):
    data = ex.MeshData(
        nodes=np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]),
        triangles=np.array([[0, 1, 2]]),
        cell_tags=np.array([1], np.int32),
        segments=np.array([[0, 1], [1, 0]]),
        edge_tags=np.array([1, 2], np.int32),
        edge_names={1: "a", 2: "b"},
    )
    with pytest.raises(ValueError, match="several edge tags"):
        ex.write_mesh_xdmf(tmp_path / "x.xdmf", data)
