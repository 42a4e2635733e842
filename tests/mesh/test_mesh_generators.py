"""Meshes: the quarter cylinder, structured blocks, file readers, and the element checks."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import CASES, needs_gmsh

from slipstep.mesh import triangles as M
from slipstep.mesh import triangle_generators as generators
from slipstep.mesh import triangle_files as mesh_files
from slipstep.case import load_case
from slipstep.build import build_scene


@pytest.fixture(scope="module")
def default_cylinder():
    """The mesh of the default Hertz case (R = 125, h_contact = 0.03 over 2.5 mm)."""
    spec = load_case(None).data["body"][0]["mesh"]
    return spec, generators.quarter_cylinder(
        spec["R"], spec["h_contact"], spec["contact_zone"], spec["h_max"], spec["growth"]
    )


@needs_gmsh
def test_arc_nodes_lie_on_the_circle(default_cylinder):
    spec, mesh = default_cylinder
    R = spec["R"]
    arc = mesh.edge_nodes("arc")
    r = np.linalg.norm(mesh.nodes[arc] - [0.0, R], axis=1)
    assert np.max(np.abs(r - R)) <= 1e-9 * R
    assert len(arc) > 2.5 / spec["h_contact"]  # the fine zone is resolved on the arc


@needs_gmsh
def test_there_is_a_node_exactly_at_the_origin(default_cylinder):
    _, mesh = default_cylinder
    at_origin = np.flatnonzero((mesh.nodes[:, 0] == 0.0) & (mesh.nodes[:, 1] == 0.0))
    assert len(at_origin) == 1
    assert at_origin[0] in mesh.edge_nodes("arc") and at_origin[0] in mesh.edge_nodes("symmetry")


@needs_gmsh
def test_triangles_are_counter_clockwise(default_cylinder):
    _, mesh = default_cylinder
    assert (M.signed_areas(mesh.nodes, mesh.triangles) > 0).all()
    M.check_triangles(mesh.nodes, mesh.triangles)  # no exception


@needs_gmsh
def test_area_is_the_quarter_disc_minus_the_circular_segments(default_cylinder):
    """Mesh area + sum of the circular segments cut off by the arc chords = pi R^2 / 4.
    A chord of length L on radius R cuts a segment of area R^2/2 (theta - sin theta),
    theta = 2 asin(L / 2R): that is exactly the polygonal-approximation error."""
    spec, mesh = default_cylinder
    R = spec["R"]
    segs = mesh.edges["arc"]
    L = np.linalg.norm(mesh.nodes[segs[:, 1]] - mesh.nodes[segs[:, 0]], axis=1)
    theta = 2.0 * np.arcsin(L / (2.0 * R))
    assert abs(theta.sum() - math.pi / 2) <= 1e-9  # the chords span the quarter circle
    deficit = np.sum(0.5 * R**2 * (theta - np.sin(theta)))
    exact = math.pi * R**2 / 4
    assert deficit > 0 and deficit < 1e-3 * exact
    assert abs(mesh.area() + deficit - exact) <= 1e-9 * exact


@needs_gmsh
def test_edges_are_oriented_with_the_body_on_the_left(default_cylinder):
    spec, mesh = default_cylinder
    R = spec["R"]
    sym = M.outward_normals(mesh.nodes, mesh.edges["symmetry"])
    top = M.outward_normals(mesh.nodes, mesh.edges["top"])
    assert np.allclose(sym, [-1.0, 0.0], atol=1e-12) and np.allclose(top, [0.0, 1.0], atol=1e-12)
    segs = mesh.edges["arc"]
    mid = 0.5 * (mesh.nodes[segs[:, 0]] + mesh.nodes[segs[:, 1]])
    radial = (mid - [0.0, R]) / np.linalg.norm(mid - [0.0, R], axis=1, keepdims=True)
    n = M.outward_normals(mesh.nodes, segs)
    assert np.all(np.einsum("ij,ij->i", n, radial) > 0.999)
    assert np.all(mesh.nodes[mesh.edge_nodes("symmetry"), 0] == 0.0)
    assert np.all(mesh.nodes[mesh.edge_nodes("top"), 1] == R)


@needs_gmsh
def test_element_size_is_graded_from_the_contact_point(default_cylinder):
    spec, mesh = default_cylinder
    segs = mesh.edges["arc"]
    p, q = mesh.nodes[segs[:, 0]], mesh.nodes[segs[:, 1]]
    L = np.linalg.norm(q - p, axis=1)
    d = np.linalg.norm(0.5 * (p + q), axis=1)
    fine = d < 0.8 * spec["contact_zone"]
    assert np.all(np.abs(L[fine] / spec["h_contact"] - 1.0) < 0.25)
    assert L.max() <= 1.25 * spec["h_max"]
    assert L.max() > 0.5 * spec["h_max"]


@needs_gmsh
def test_small_cylinder_generator_is_deterministic():
    a = generators.quarter_cylinder(10.0, 0.2, 1.0, 2.0, 0.3)
    b = generators.quarter_cylinder(10.0, 0.2, 1.0, 2.0, 0.3)
    assert np.array_equal(a.nodes, b.nodes) and np.array_equal(a.triangles, b.triangles)


# --------------------------------------------------------------------------- disc
DISC = dict(R=10.0, h_contact=0.1, contact_zone=1.0, h_max=2.0, growth=0.3)


@pytest.fixture(scope="module")
def disc():
    return generators.disc(**DISC)


@needs_gmsh
def test_disc_tags_points_and_orientation(disc):
    """The whole circle, centre (0, R): arc nodes on it, the three point nodes exactly at the
    bottom, top and centre, the lower and upper arcs meeting at (+-R, R) and making up the
    circle, every segment's outward normal pointing away from the centre."""
    R = DISC["R"]
    assert (M.signed_areas(disc.nodes, disc.triangles) > 0).all()
    for name, xy in (
        ("bottom_point", (0.0, 0.0)),
        ("top_point", (0.0, 2 * R)),
        ("centre_point", (0.0, R)),
    ):
        (k,) = disc.node_sets[name]
        assert disc.nodes[k].tolist() == list(xy), name
    ring = disc.edge_nodes("circle")
    assert np.abs(np.linalg.norm(disc.nodes[ring] - [0.0, R], axis=1) - R).max() <= 1e-12 * R
    lower, upper = disc.edge_nodes("lower_arc"), disc.edge_nodes("upper_arc")
    assert (disc.nodes[lower, 1] <= R).all() and (disc.nodes[upper, 1] >= R).all()
    assert sorted(np.intersect1d(lower, upper).tolist()) == sorted(
        ring[np.abs(disc.nodes[ring, 1] - R) <= 1e-12 * R].tolist()
    )  # (-R, R) and (R, R)
    assert len(disc.edges["circle"]) == len(disc.edges["lower_arc"]) + len(disc.edges["upper_arc"])
    segs = disc.edges["circle"]
    mid = 0.5 * (disc.nodes[segs[:, 0]] + disc.nodes[segs[:, 1]]) - [0.0, R]
    radial = mid / np.linalg.norm(mid, axis=1, keepdims=True)
    assert np.all(np.einsum("ij,ij->i", M.outward_normals(disc.nodes, segs), radial) > 0.999)
    # the closed chain of chords spans the full turn; the area is the circle minus the
    # segments the chords cut off, R^2/2 (theta - sin theta) each (as for the quarter)
    L = np.linalg.norm(disc.nodes[segs[:, 1]] - disc.nodes[segs[:, 0]], axis=1)
    theta = 2.0 * np.arcsin(L / (2.0 * R))
    assert abs(theta.sum() - 2 * math.pi) <= 1e-9
    deficit = np.sum(0.5 * R**2 * (theta - np.sin(theta)))
    assert abs(disc.area() + deficit - math.pi * R**2) <= 1e-9 * math.pi * R**2


@needs_gmsh
def test_disc_is_mirror_symmetric_and_fine_at_both_poles(disc):
    R, h = DISC["R"], DISC["h_contact"]
    mirrored = disc.nodes * [-1.0, 1.0]
    gap = np.linalg.norm(mirrored[:, None, :] - disc.nodes[None, :, :], axis=2).min(axis=1)
    assert gap.max() <= 1e-12 * R  # every node's mirror image is a node
    segs = disc.edges["circle"]
    p, q = disc.nodes[segs[:, 0]], disc.nodes[segs[:, 1]]
    L = np.linalg.norm(q - p, axis=1)
    mid = 0.5 * (p + q)
    near = np.minimum(np.linalg.norm(mid, axis=1), np.linalg.norm(mid - [0.0, 2 * R], axis=1))
    fine = near < 0.8 * DISC["contact_zone"]
    # ~0.8 contact_zone / h segments on each side of each pole (gmsh's sizes are targets)
    assert fine.sum() >= 0.75 * 4 * 0.8 * DISC["contact_zone"] / h
    assert np.all(np.abs(L[fine] / h - 1.0) < 0.25)
    assert L.max() <= 1.25 * DISC["h_max"]


DISC_CASE = """
[case]
name = "disc"
units = "mm, N, MPa"
[output]
snapshots = [1.0]
figures = false
xdmf = false
[[body]]
name = "disc"
[body.mesh]
generator = "disc"
R = 10.0
h_contact = 0.02
contact_zone = 0.3
h_max = {h_max}
growth = 0.2
[body.material]
E = 70000.0
nu = 0.3
[[bc]]
body = "disc"
nodes = "top_point"
fix = ["x"]
[[bc]]
body = "disc"
nodes = "centre_point"
fix = ["x"]
[[point_load]]
at = [0.0, 20.0]
force = [0.0, -{P}]
[[contact]]
name = "flat"
kind = "rigid_line"
body = "disc"
edge = "lower_arc"
x_min = -1.0
x_max = 1.0
"""


@needs_gmsh
def test_a_disc_compressed_between_its_top_and_a_flat():
    """A disc R = 10 loaded at its top node by P = 100 N/mm onto a frictionless rigid flat
    (plane strain, E = 70 GPa, nu = 0.3; x held at the top and centre nodes, which symmetry
    leaves unloaded).  The flat carries P (equilibrium, to the engine's 1e-9); the contact is
    Hertz's (Johnson §4.3): p0 = sqrt(P E*/(pi R)) within 1 %, the edge a = sqrt(4PR/(pi E*))
    within one contact element (a/R = 0.013); at the centre, the diametrically compressed disc
    (Timoshenko & Goodier §41: sigma_x = 2P/(pi D), sigma_y = -6P/(pi D), D = 2R; the contact
    width changes them by O((a/R)^2) ~ 2e-4) in the recovered nodal stress within 2.5 % at
    element size R/10 there, the error of a first-order recovery (tests/output/test_nodal_stress.py)
    at least 1.7 times smaller at R/20 (2 for exactly first order; gmsh's sizes are targets)."""
    from slipstep import Case, run

    P, R, E_star = 100.0, 10.0, 70000.0 / (1 - 0.3**2)
    errors = []
    for h_max in (1.0, 0.5):
        r = run(Case.from_toml(DISC_CASE.format(h_max=h_max, P=P)), progress=False)
        s, f = r.summary, r.fields()
        assert s["total_normal_force"] == pytest.approx(P, rel=1e-9)
        assert all(abs(rx) <= 1e-9 * P for rx, _ in s["reactions"].values())
        assert s["peak_pressure"] == pytest.approx(math.sqrt(P * E_star / (math.pi * R)), rel=0.01)
        lo, hi = s["contacts"]["flat"]["closed_extent"]
        a = math.sqrt(4 * P * R / (math.pi * E_star))
        assert abs(hi - a) <= 0.02 and lo == pytest.approx(-hi, rel=1e-12)
        centre = f["nodal_stress"][r.scene.meshes["disc"].node_sets["centre_point"][0]]
        exact = np.array([2 * P, -6 * P]) / (math.pi * 2 * R)
        errors.append(np.abs(centre[:2] / exact - 1).max())
    assert errors[0] <= 0.025 and errors[1] <= errors[0] / 1.7, errors


# --------------------------------------------------------------------------- quarter annulus
@needs_gmsh
def test_quarter_annulus_geometry_tags_and_grading():
    a, b, h, h_outer = 10.0, 20.0, 0.5, 1.0
    m = generators.quarter_annulus(a, b, h, h_outer)
    assert (M.signed_areas(m.nodes, m.triangles) > 0).all()
    r = np.linalg.norm(m.nodes, axis=1)
    assert np.max(np.abs(r[m.edge_nodes("inner")] - a)) <= 1e-12 * a
    assert np.max(np.abs(r[m.edge_nodes("outer")] - b)) <= 1e-12 * b
    assert r.min() >= a * (1 - 1e-12) and r.max() <= b * (1 + 1e-12)
    # the axes are exact and span [a, b]; outward normals (body on the left)
    for tag, axis, n in (("x_axis", 1, [0.0, -1.0]), ("y_axis", 0, [-1.0, 0.0])):
        ids = m.edge_nodes(tag)
        assert np.all(m.nodes[ids, axis] == 0.0)
        assert sorted(r[ids])[0] == pytest.approx(a) and sorted(r[ids])[-1] == pytest.approx(b)
        assert np.allclose(M.outward_normals(m.nodes, m.edges[tag]), n, atol=1e-12)
    for tag, sign in (("inner", -1.0), ("outer", 1.0)):  # outward = -radial at the bore
        segs = m.edges[tag]
        mid = 0.5 * (m.nodes[segs[:, 0]] + m.nodes[segs[:, 1]])
        radial = mid / np.linalg.norm(mid, axis=1, keepdims=True)
        assert np.all(
            sign * np.einsum("ij,ij->i", M.outward_normals(m.nodes, segs), radial) > 0.999
        )
    # area = quarter ring minus the segments cut by the chords of both arcs (inner ones add)
    assert abs(m.area() - math.pi / 4 * (b * b - a * a)) <= 1e-3 * m.area()
    # grading: boundary segments are about h at the bore and h_outer at r = b
    lengths = {
        t: np.linalg.norm(np.diff(m.nodes[m.edges[t]], axis=1)[:, 0], axis=1).mean()
        for t in ("inner", "outer")
    }
    assert lengths["inner"] == pytest.approx(h, rel=0.1)
    assert lengths["outer"] == pytest.approx(h_outer, rel=0.1)
    with pytest.raises(M.MeshError, match="need 0 < a < b"):
        generators.quarter_annulus(2.0, 1.0, 0.1)


# --------------------------------------------------------------------------- blocks
def test_block_geometry_and_tags():
    b = generators.block(4.0, 2.0, 8, 5, x0=1.0, y0=-2.0)
    assert b.n_nodes == 9 * 6 and b.n_elements == 2 * 8 * 5
    assert (M.signed_areas(b.nodes, b.triangles) > 0).all()
    assert abs(b.area() - 8.0) <= 1e-12 * 8.0
    expected = {"bottom": [0, -1], "right": [1, 0], "top": [0, 1], "left": [-1, 0]}
    for tag, n in expected.items():
        assert np.allclose(M.outward_normals(b.nodes, b.edges[tag]), n)
    assert np.allclose(b.nodes[b.edge_nodes("top"), 1], 0.0)
    assert np.allclose(b.nodes[b.node_sets["corner_top_right"]], [[5.0, 0.0]])


def test_stacked_blocks_have_matching_interface_nodes():
    scene = build_scene(load_case(CASES / "two_blocks.toml"))
    punch = scene.nodes[np.unique(scene.global_edge("punch", "bottom"))]
    found = scene.nodes[np.unique(scene.global_edge("foundation", "top"))]
    d = np.linalg.norm(punch[:, None, :] - found[None, :, :], axis=2).min(axis=1)
    assert len(punch) == 21
    assert d.max() <= 1e-12


# --------------------------------------------------------------------------- checks
def test_inverted_triangle_is_named_by_its_element_id():
    b = generators.block(2.0, 1.0, 4, 2)
    tris = b.triangles.copy()
    tris[5] = tris[5, [0, 2, 1]]
    with pytest.raises(M.MeshError) as info:
        M.check_triangles(b.nodes, tris, where="m.msh")
    msg = str(info.value)
    assert msg.startswith("m.msh: element 5 is inverted (signed area -0.125)")
    assert "reorder its nodes counter-clockwise" in msg


def test_degenerate_triangle_is_named():
    nodes = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [0.0, 1.0]])
    tris = np.array([[0, 1, 3], [0, 1, 2]])
    with pytest.raises(M.MeshError, match=r"element 1 is degenerate"):
        M.check_triangles(nodes, tris)


def test_tagging_an_interior_side_is_an_error():
    b = generators.block(2.0, 1.0, 2, 1)
    interior = b.triangles[0, [0, 2]]  # the diagonal of cell 0
    with pytest.raises(M.MeshError, match=r"is inside the mesh"):
        M.orient_edges(b.triangles, {"bad": interior[None, :]})


# --------------------------------------------------------------------------- files
def _square_triangles():
    nodes = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]])
    tris = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
    return nodes, tris


def test_xdmf_mesh_with_line_tags(tmp_path):
    import meshio

    nodes, tris = _square_triangles()
    lines = np.array([[1, 0], [3, 2]])  # bottom (reversed on purpose), top
    m = meshio.Mesh(
        nodes,
        [("triangle", tris), ("line", lines)],
        cell_data={"tags": [np.zeros(4, np.int32), np.array([1, 3], np.int32)]},
    )
    path = tmp_path / "sq.xdmf"
    meshio.write(path, m)
    mesh = mesh_files.read_mesh(path)
    assert set(mesh.edges) == {"1", "3"}
    assert np.allclose(M.outward_normals(mesh.nodes, mesh.edges["1"]), [[0, -1]])
    assert np.allclose(M.outward_normals(mesh.nodes, mesh.edges["3"]), [[0, 1]])


def test_clockwise_file_mesh_is_flipped_and_mixed_one_rejected(tmp_path):
    import meshio

    nodes, tris = _square_triangles()
    cw = tris[:, [0, 2, 1]]
    meshio.write(tmp_path / "cw.xdmf", meshio.Mesh(nodes, [("triangle", cw)]))
    assert (
        M.signed_areas(
            *(lambda m: (m.nodes, m.triangles))(mesh_files.read_mesh(tmp_path / "cw.xdmf"))
        )
        > 0
    ).all()
    mixed = tris.copy()
    mixed[2] = mixed[2, [0, 2, 1]]
    meshio.write(tmp_path / "mixed.xdmf", meshio.Mesh(nodes, [("triangle", mixed)]))
    with pytest.raises(M.MeshError, match=r"mixed.xdmf: element 2 is inverted"):
        mesh_files.read_mesh(tmp_path / "mixed.xdmf")


def test_multi_grid_xdmf_is_an_error_not_an_exit(tmp_path):
    import meshio

    nodes, tris = _square_triangles()
    path = tmp_path / "series.xdmf"
    import os

    cwd = os.getcwd()
    os.chdir(tmp_path)  # meshio's TimeSeriesWriter puts the .h5 in the working directory
    try:
        with meshio.xdmf.TimeSeriesWriter(path.name) as w:
            w.write_points_cells(nodes, [("triangle", tris)])
            w.write_data(0.0, point_data={"a": np.zeros(len(nodes))})
            w.write_data(1.0, point_data={"a": np.ones(len(nodes))})
    finally:
        os.chdir(cwd)
    with pytest.raises(M.MeshError, match=r"series.xdmf: meshio cannot read"):
        mesh_files.read_mesh(path)


@needs_gmsh
def test_msh_file_with_physical_names(tmp_path):
    import gmsh

    gmsh.initialize(["", "-v", "0"], interruptible=False)
    try:
        gmsh.model.add("sq")
        r = gmsh.model.occ.addRectangle(0, 0, 0, 2.0, 1.0)
        gmsh.model.occ.synchronize()
        bottom = [
            c
            for _, c in gmsh.model.getBoundary([(2, r)], oriented=False)
            if abs(gmsh.model.occ.getCenterOfMass(1, c)[1]) < 1e-9
        ]
        gmsh.model.setPhysicalName(1, gmsh.model.addPhysicalGroup(1, bottom), "base")
        gmsh.model.addPhysicalGroup(2, [r])
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.25)
        gmsh.model.mesh.generate(2)
        gmsh.write(str(tmp_path / "sq.msh"))
    finally:
        gmsh.finalize()
    mesh = mesh_files.read_mesh(tmp_path / "sq.msh", scale=10.0)
    assert set(mesh.edges) == {"base"}
    assert abs(mesh.area() - 200.0) <= 1e-9 * 200.0
    assert np.allclose(M.outward_normals(mesh.nodes, mesh.edges["base"]), [0, -1])
    assert np.allclose(mesh.nodes[mesh.edge_nodes("base"), 1], 0.0)


@needs_gmsh
def test_written_msh_reads_back_as_the_same_mesh(tmp_path):
    """write_msh (the bench hands slipstep's meshes to GetFEM with it) -> gmsh's reader: the
    same triangles, edge segments and node sets, compared by coordinates (gmsh renumbers the
    nodes by entity), exactly (coordinates are written with repr, which round-trips)."""
    mesh = generators.quarter_cylinder(10.0, 0.2, 1.0, 2.0, 0.3)
    tags = mesh_files.write_msh(mesh, tmp_path / "c.msh")
    back = mesh_files.read_mesh(tmp_path / "c.msh")

    def rows(m, ids):  # coordinates of each row of node ids, rows in a canonical order
        xy = m.nodes[np.asarray(ids)].reshape(len(ids), -1)
        return xy[np.lexsort(xy.T[::-1])]

    assert back.n_nodes == mesh.n_nodes
    assert np.array_equal(rows(back, back.triangles), rows(mesh, mesh.triangles))
    assert set(back.edges) == set(mesh.edges) == {"arc", "top", "symmetry"}
    for tag in mesh.edges:  # oriented alike: the body on the left of every segment
        assert np.array_equal(rows(back, back.edges[tag]), rows(mesh, mesh.edges[tag]))
    assert np.array_equal(rows(back, back.node_sets["bottom_point"][:, None]), [[0.0, 0.0]])
    assert sorted(tags.values()) == list(range(1, len(tags) + 1)) and "body" in tags


def test_unknown_mesh_format(tmp_path):
    (tmp_path / "m.stl").write_text("solid")
    with pytest.raises(M.MeshError, match=r"unknown mesh format '.stl'"):
        mesh_files.read_mesh(tmp_path / "m.stl")
