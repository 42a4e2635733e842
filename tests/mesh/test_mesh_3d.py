"""Tetrahedron meshes (slipstep.mesh.tetrahedra): the generators of the 3D scenes, the element checks
(inverted and flat tetrahedra refused by index), face tags oriented outwards, and the .msh /
.xdmf / .stl readers.  Checked against geometry computed here: exact volumes of polyhedral
bodies, radii of nodes on curved faces, face areas, mirror symmetry."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import needs_gmsh

from slipstep.mesh import MeshError
from slipstep.mesh import tetrahedron_generators as generators
from slipstep.contact.indenters import pyramid, write_stl
from slipstep.mesh.tetrahedra import boundary_faces, signed_volumes, triangle_normals
from slipstep.mesh import from_tetrahedra
from slipstep.mesh.tetrahedron_files import read_surface, read_tet_mesh


def face_area(mesh, tag):
    return float(triangle_normals(mesh.nodes, mesh.faces[tag])[1].sum())


def assert_outward(mesh):
    """Every tagged triangle points away from its tetrahedron: the fourth node of the
    tetrahedron it bounds lies behind it (checked from the elements, not the tagging)."""
    centroid = mesh.nodes[mesh.tetrahedra].mean(axis=1)
    for tag, tris in mesh.faces.items():
        n, _ = triangle_normals(mesh.nodes, tris)
        centre = mesh.nodes[tris].mean(axis=1)
        # the element a face bounds is the one whose centroid is nearest behind it
        nearest = np.argmin(np.linalg.norm(centroid[None] - centre[:, None], axis=2), axis=1)
        assert (np.einsum("ij,ij->i", centroid[nearest] - centre, n) < 0).all(), tag


def test_structured_box_is_the_box_conforming_and_positive():
    mesh = generators.box(2.0, 1.0, 0.5, 4, 3, 2, corner=(1.0, -1.0, 0.0))
    vol = signed_volumes(mesh.nodes, mesh.tetrahedra)
    assert (vol > 0).all()
    assert abs(vol.sum() - 1.0) <= 1e-14  # 2 x 1 x 0.5, exact: the cells tile the box
    assert len(mesh.tetrahedra) == 6 * 4 * 3 * 2
    # a conforming mesh's boundary is the box's surface only: 2 triangles per cell face
    assert len(boundary_faces(mesh.tetrahedra)) == 2 * 2 * (4 * 3 + 3 * 2 + 4 * 2)
    for tag, area in (
        ("bottom", 2.0),
        ("top", 2.0),
        ("left", 0.5),
        ("right", 0.5),
        ("front", 1.0),
        ("back", 1.0),
    ):
        assert abs(face_area(mesh, tag) - area) <= 1e-14, tag
    assert_outward(mesh)
    # node coordinates on the grid, so boxes of the same spacing match on a common face
    assert set(np.round(mesh.nodes[:, 0], 12)) == {1.0, 1.5, 2.0, 2.5, 3.0}


def test_structured_box_has_no_preferred_diagonal():
    """The cells are mirrored by parity: the mesh of an even grid is mirror symmetric about
    the box's middle planes (the Kuhn split of every cell alike is not)."""
    mesh = generators.box(2.0, 2.0, 2.0, 2, 2, 2)
    key = {tuple(sorted(map(tuple, np.round(mesh.nodes[t], 9)))) for t in mesh.tetrahedra}
    for axis in range(3):
        flipped = mesh.nodes.copy()
        flipped[:, axis] = 2.0 - flipped[:, axis]
        image = {tuple(sorted(map(tuple, np.round(flipped[t], 9)))) for t in mesh.tetrahedra}
        assert image == key, axis


@needs_gmsh
@pytest.mark.parametrize("portion, mirrors", [("eighth", 0), ("quarter", 1), ("half", 2)])
def test_sphere_nodes_faces_and_symmetry(portion, mirrors):
    R = 10.0
    mesh = generators.sphere(R, 0.4, 1.5, 3.0, 0.4, portion)
    assert (signed_volumes(mesh.nodes, mesh.tetrahedra) > 0).all()
    bottom = mesh.node_sets["bottom_point"]
    assert len(bottom) == 1 and (mesh.nodes[bottom[0]] == 0.0).all()  # a node exactly there
    surface = mesh.face_nodes("surface")
    r = np.linalg.norm(mesh.nodes[surface] - [0.0, 0.0, R], axis=1)
    assert np.abs(r - R).max() <= 1e-9 * R  # on the sphere
    assert (mesh.nodes[mesh.face_nodes("top"), 2] == R).all()
    expected = {"surface", "top", *("symmetry_x", "symmetry_y")[mirrors:]}
    assert set(mesh.faces) == expected
    for tag in expected - {"surface", "top"}:
        axis = "xy".index(tag[-1])
        assert (mesh.nodes[mesh.face_nodes(tag), axis] == 0.0).all()
    # the cut is its share of the disc (polygon inscribed in the circle: within h^2/R)
    share = (0.25, 0.5, 1.0)[mirrors] * math.pi * R**2
    assert -(3.0**2) / R * 2 * math.pi * R <= face_area(mesh, "top") - share <= 0.0
    assert_outward(mesh)
    if mirrors:  # mirrored: every node's image across x = 0 is a node
        image = mesh.nodes * [-1.0, 1.0, 1.0]
        have = {tuple(p) for p in np.round(mesh.nodes, 10)}
        assert all(tuple(p) in have for p in np.round(image, 10))


@needs_gmsh
def test_sphere_is_graded_towards_the_contact_point():
    mesh = generators.sphere(10.0, 0.2, 1.0, 3.0, 0.5)
    p = mesh.nodes[mesh.tetrahedra]
    longest = np.max(
        [np.linalg.norm(p[:, i] - p[:, j], axis=1) for i in range(4) for j in range(i)], axis=0
    )
    d = np.linalg.norm(p.mean(axis=1), axis=1)
    # gmsh aims at the size field within a factor ~1.5-2 (its edges, not its elements)
    assert np.median(longest[d < 0.5]) <= 2.0 * 0.2
    assert np.median(longest[d > 8.0]) >= 0.5 * 3.0


@needs_gmsh
def test_sphere_volume_converges_to_the_hemisphere_quarter():
    """Inscribed polyhedra: the deficit falls with h (second order: chord sag h^2/(8R))."""
    exact = 2.0 / 3.0 * math.pi * 10.0**3 / 4
    deficits = [exact - generators.sphere(10.0, h, 1.0, h, 0.5).volume() for h in (4.0, 2.0)]
    assert 0 < deficits[1] < deficits[0] / 2.5


@needs_gmsh
def test_shell_and_its_faces():
    a, b = 1.0, 2.0
    mesh = generators.shell(a, b, 0.25, 0.4)
    assert set(mesh.faces) == {"inner", "outer", "symmetry_x", "symmetry_y", "symmetry_z"}
    for tag, radius in (("inner", a), ("outer", b)):
        r = np.linalg.norm(mesh.nodes[mesh.face_nodes(tag)], axis=1)
        assert np.abs(r - radius).max() <= 1e-9
    exact = (b**3 - a**3) * math.pi / 6
    assert 0 < exact - mesh.volume() < 0.03 * exact  # inscribed faces
    assert_outward(mesh)


@needs_gmsh
def test_roller_and_punch_faces():
    roller = generators.roller(5.0, 8.0, 0.5, 1.0, 2.0, 0.5)
    assert set(roller.faces) == {"surface", "top", "end", "symmetry_x", "symmetry_y"}
    assert (roller.nodes[roller.face_nodes("end"), 1] == 4.0).all()
    # the contact line x = z = 0 is a line of nodes at the fine spacing
    line = np.flatnonzero((roller.nodes[:, 0] == 0.0) & (np.abs(roller.nodes[:, 2]) <= 1e-12))
    assert len(line) >= 4.0 / 0.5
    square = generators.punch(1.0, 2.0, 0.2, 0.3, 0.5, 0.5, shape="square", portion="whole")
    assert abs(square.volume() - 2.0 * 2.0 * 2.0) <= 1e-12  # a prism: exact
    assert set(square.faces) == {"bottom", "side", "top"}
    assert abs(face_area(square, "bottom") - 4.0) <= 1e-12
    round_ = generators.punch(1.0, 2.0, 0.2, 0.3, 0.5, 0.5)
    assert set(round_.faces) == {"bottom", "side", "top", "symmetry_x", "symmetry_y"}
    assert (round_.nodes[round_.face_nodes("bottom"), 2] == 0.0).all()


@needs_gmsh
@pytest.mark.parametrize("focus", [None, [0.0, 0.0, 0.0], [0.0, 2.0, -2.0]])
def test_graded_box_has_a_node_at_focus(focus):
    mesh = generators.graded_box(
        10.0, 5.0, 4.0, 0.4, 1.0, 2.0, 0.5, focus=focus, corner=(-5.0, 0.0, -4.0)
    )
    want = [0.0, 2.5, 0.0] if focus is None else focus
    assert (mesh.nodes[mesh.node_sets["focus"]] == want).all()
    assert abs(mesh.volume() - 200.0) <= 1e-9
    assert abs(face_area(mesh, "top") - 50.0) <= 1e-9


# --------------------------------------------------------------------------- checks
UNIT = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]])


def test_an_inverted_tetrahedron_is_refused_by_its_index():
    second = [1, 2, 3, 4]
    if signed_volumes(UNIT, np.array([second]))[0] > 0:
        second = [2, 1, 3, 4]  # negatively oriented
    assert signed_volumes(UNIT, np.array([[0, 1, 2, 3], second]))[0] > 0
    with pytest.raises(MeshError, match=r"element 1 is inverted \(signed volume -0.333"):
        from_tetrahedra(UNIT, [[0, 1, 2, 3], second])


def test_a_flat_tetrahedron_is_refused_by_its_index():
    nodes = np.vstack([UNIT[:4], [0.5, 0.5, 0.0]])  # node 4 in the plane of 0, 1, 2
    with pytest.raises(MeshError, match=r"element 1 is flat .*nodes \[0, 1, 2, 4\]"):
        from_tetrahedra(nodes, [[0, 1, 2, 3], [0, 1, 2, 4]])


def test_an_all_inverted_mesh_is_flipped_and_faces_turn_outwards():
    mesh = from_tetrahedra(UNIT[:4], [[0, 2, 1, 3]], {"base": [[0, 1, 2]]})
    assert signed_volumes(mesh.nodes, mesh.tetrahedra)[0] > 0
    n, _ = triangle_normals(mesh.nodes, mesh.faces["base"])
    assert np.allclose(n, [[0.0, 0.0, -1.0]])  # outward of the tetrahedron above z = 0


def test_a_tag_on_no_face_or_an_inner_face_is_refused():
    tets = [[0, 1, 2, 3], [1, 2, 3, 4]]
    tets = [t if signed_volumes(UNIT, np.array([t]))[0] > 0 else [t[1], t[0], *t[2:]] for t in tets]
    with pytest.raises(MeshError, match="is not a face of any tetrahedron"):
        from_tetrahedra(UNIT, tets, {"x": [[0, 1, 4]]})
    with pytest.raises(MeshError, match="inside the mesh"):
        from_tetrahedra(UNIT, tets, {"x": [[1, 2, 3]]})


# --------------------------------------------------------------------------- files
@needs_gmsh
def test_msh_tetrahedra_and_physical_surfaces_are_read(tmp_path):
    import gmsh

    from slipstep.mesh.gmsh_api import gmsh_session

    path = tmp_path / "cube.msh"
    with gmsh_session():
        gmsh.model.occ.addBox(0, 0, 0, 1, 2, 3)
        gmsh.model.occ.synchronize()
        bottom = [s for _, s in gmsh.model.getEntitiesInBoundingBox(-1, -1, -1e-6, 2, 3, 1e-6, 2)]
        gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, bottom), "base")
        gmsh.model.addPhysicalGroup(3, [1])
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.5)
        gmsh.model.mesh.generate(3)
        gmsh.write(str(path))
    mesh = read_tet_mesh(path, scale=2.0)
    assert abs(mesh.volume() - 48.0) <= 1e-9  # 2 x 4 x 6 after scaling
    assert set(mesh.faces) == {"base"} and abs(face_area(mesh, "base") - 8.0) <= 1e-9
    assert_outward(mesh)


def test_xdmf_tetrahedra_with_tagged_triangles_are_read(tmp_path):
    meshio = pytest.importorskip("meshio")
    box = generators.box(1.0, 1.0, 1.0, 2, 2, 2)
    tris = box.faces["top"][:, [0, 2, 1]]  # written inwards: the reader turns them out
    m = meshio.Mesh(
        box.nodes,
        [("tetra", box.tetrahedra), ("triangle", tris)],
        cell_data={
            "tag": [np.zeros(len(box.tetrahedra), np.int32), np.full(len(tris), 7, np.int32)]
        },
    )
    meshio.write(tmp_path / "box.xdmf", m)
    mesh = read_tet_mesh(tmp_path / "box.xdmf")
    assert set(mesh.faces) == {"7"}  # meshio's xdmf keeps no field_data: named by number
    assert np.allclose(triangle_normals(mesh.nodes, mesh.faces["7"])[0], [0, 0, 1])


def test_a_mixed_orientation_file_is_refused_naming_the_element(tmp_path):
    meshio = pytest.importorskip("meshio")
    box = generators.box(1.0, 1.0, 1.0, 1, 1, 1)
    tets = box.tetrahedra.copy()
    tets[3] = tets[3][[1, 0, 2, 3]]
    meshio.write(tmp_path / "bad.xdmf", meshio.Mesh(box.nodes, [("tetra", tets)]))
    with pytest.raises(MeshError, match=r"bad.xdmf: element 3 is inverted"):
        read_tet_mesh(tmp_path / "bad.xdmf")


def test_a_surface_mesh_is_no_volume_mesh(tmp_path):
    meshio = pytest.importorskip("meshio")
    points, tris = pyramid("vickers", [0, 0, 0], 1.0)
    meshio.write(tmp_path / "skin.xdmf", meshio.Mesh(points, [("triangle", tris)]))
    with pytest.raises(MeshError, match="no tetrahedra: a 3D case"):
        read_tet_mesh(tmp_path / "skin.xdmf")


def test_stl_surfaces_read_back_merged(tmp_path):
    points, tris = pyramid("berkovich", [1.0, 2.0, 3.0], 0.5)
    back_points, back_tris = read_surface(write_stl(tmp_path / "b.stl", points, tris))
    assert len(back_points) == 4 and len(back_tris) == 4  # 12 STL vertices merged into 4
    assert np.allclose(np.sort(back_points, axis=0), np.sort(points, axis=0))
