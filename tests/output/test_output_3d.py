"""The files of a 3D run, written from a stand-in result shaped as docs/engine_api.md's 3D
section says (tests/space3d.py: Hertz's pressure and Mindlin's traction put on the pairs of a
quarter sphere; NOT a solver): results.xdmf (tetrahedra, the stress tensor, von Mises, the
contact fields), contact_profile.csv (both tangential components, the slip direction),
summary.json (areas and radii of the full contact, resultants), the two figures.  Every
expected number is recomputed here from the stand-in's inputs and the mesh."""

from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest
from conftest import needs_gmsh
from space3d import QUARTER, SPHERE, mindlin_stand_in

from slipstep.build import build_scene
from slipstep.case import parse_case
from slipstep.output.results import write_results
from slipstep.mesh.tetrahedra import triangle_normals
from slipstep.output.summary import one_line, summarize

A, C, P0, MU = 0.9, 0.55, 100.0, 0.3


@pytest.fixture(scope="module")
def quarter():
    pytest.importorskip("gmsh")
    scene = build_scene(parse_case(QUARTER, "q.toml"))
    # a uniaxial stress sigma_xx = 50 plus a shear tau_yz = 10: von Mises sqrt(50^2 + 3 10^2)
    result = mindlin_stand_in(scene, A, C, P0, MU, stress=[50.0, 0, 0, 10.0, 0, 0])
    return scene, result


def areas_by_node(scene):
    """int N_a dA of every node over the sphere's face, from its triangles (a third each)."""
    face = scene.global_boundary("sphere", "surface")
    _, area = triangle_normals(scene.nodes, face)
    out = np.zeros(len(scene.nodes))
    for k in range(3):
        np.add.at(out, face[:, k], area / 3)
    return out


@needs_gmsh
def test_the_summary_reports_the_full_contact(quarter):
    scene, result = quarter
    s = summarize(scene, result, 0.0)
    snap = result["snapshots"][0]
    x = scene.pair_xy
    r = np.hypot(x[:, 0], x[:, 1])
    area = areas_by_node(scene)[scene.model["pairs"]["node_a"]]
    # the quarter is half the contact (mirror y = 0): areas and forces double, Fy cancels
    assert s["contacts"]["contact 0"]["symmetry_planes"] == ["y = 0"]
    assert math.isclose(s["contact_area"], 2 * area[r < A].sum(), rel_tol=1e-12)
    assert math.isclose(
        s["contact_radius"], math.sqrt(2 * area[r < A].sum() / math.pi), rel_tol=1e-12
    )
    assert math.isclose(
        s["stick_radius"], math.sqrt(2 * area[r < C].sum() / math.pi), rel_tol=1e-12
    )
    assert math.isclose(s["total_normal_force"], 2 * snap["lambda_n"].sum(), rel_tol=1e-12)
    q = (
        MU * snap["lambda_n"]
        - MU * P0 * (C / A) * np.sqrt(np.clip(1 - (r / C) ** 2, 0, None)) * area
    )
    assert np.allclose(s["tangential_force"], [2 * q.sum(), 0.0, 0.0], rtol=1e-12, atol=1e-9)
    assert math.isclose(s["total_tangential_force"], 2 * q.sum(), rel_tol=1e-12)
    # against the closed forms, within what the mesh resolves: the discs' radii within a
    # node spacing (h_contact = 0.3), and the resultants within the nodal rule's error
    assert abs(s["contact_radius"] - A) <= 0.3 and abs(s["stick_radius"] - C) <= 0.3
    full_p = 2 * math.pi * P0 * A**2 / 3  # int p dA of the Hertz profile
    assert abs(s["total_normal_force"] / full_p - 1) <= 0.2
    assert math.isclose(s["peak_pressure"], P0, rel_tol=1e-12)  # the node at r = 0
    assert s["n_stick"] == int((r < C).sum()) and s["n_slip"] == int(((r >= C) & (r < A)).sum())
    # the stand-in's case is frictionless (mu = 0, the default): its line names no stick zone
    assert "contact radius" in one_line(s) and "stick" not in one_line(s)
    assert "stick radius" in one_line(dict(s, frictionless=False))
    assert math.isclose(s["max_von_mises"], math.sqrt(50.0**2 + 3 * 10.0**2), rel_tol=1e-12)


@needs_gmsh
def test_the_contact_csv_has_both_tangential_components_and_the_slip_direction(quarter, tmp_path):
    scene, result = quarter
    write_results(tmp_path, scene, result, summarize(scene, result, 0.0), figures=False, xdmf=False)
    with open(tmp_path / "contact_profile.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == len(scene.pair_xy)
    for row in rows:
        x, y = float(row["x"]), float(row["y"])
        r = math.hypot(x, y)
        p = P0 * math.sqrt(max(1 - (r / A) ** 2, 0.0))
        q = MU * p - MU * P0 * (C / A) * math.sqrt(max(1 - (r / C) ** 2, 0.0))
        assert math.isclose(float(row["pressure"]), p, rel_tol=1e-12, abs_tol=1e-9)
        assert math.isclose(float(row["tangential_stress_x"]), q, rel_tol=1e-12, abs_tol=1e-9)
        assert abs(float(row["tangential_stress_y"])) <= 1e-9
        # the pair's basis: t1 = -y, t2 = x for the flat's normal z (the contract's rule)
        assert math.isclose(float(row["tangential_stress_2"]), q, rel_tol=1e-12, abs_tol=1e-9)
        assert row["status"] == ("stick" if r < C else "slip" if r < A else "open")
        direction = [float(row[f"slip_direction_{c}"]) for c in "xyz"]
        # a slipping pair slips against its friction force: -x here; the others 0
        assert direction == (
            [-1.0, 0.0, 0.0] if row["status"] == "slip" and q > 0 else [0.0, 0.0, 0.0]
        )


#: The quarter sphere on a block of its own (the half y >= 0), node_to_surface: mortar rows
ON_BLOCK = QUARTER.replace(
    """[[contact]]
kind = "rigid_plane"
body = "sphere"
face = "surface"
z_max = 0.1""",
    """[[body]]
name = "block"
[body.mesh]
generator = "box"
x0 = -3.0
y0 = 0.0
z0 = -2.0
width = 6.0
depth = 3.0
height = 2.0
h_contact = 0.4
contact_zone = 1.0
h_max = 1.0
growth = 0.5
focus = [0.0, 0.0, 0.0]
[body.material]
E = 70000.0
nu = 0.3
[[bc]]
body = "block"
face = "bottom"
fix = ["x", "y", "z"]
[[bc]]
body = "block"
face = "front"
symmetry = true
[[contact]]
kind = "node_to_surface"
body_a = "sphere"
face_a = "surface"
body_b = "block"
face_b = "top"
z_max = 0.1""",
)


@needs_gmsh
def test_a_node_to_surface_contact_covers_its_closed_rows_supports():
    """Mortar rows (node_to_surface): a contact's area is that of the contactor triangles with a
    closed row at a corner, its stick area those with a stuck row (cases/README.md), for the
    full contact (mirrored across y = 0); a rigid plane's stays its pairs' tributary areas
    (test_the_summary_reports_the_full_contact above)."""
    pytest.importorskip("gmsh")
    scene = build_scene(parse_case(ON_BLOCK, "q.toml"))
    assert scene.case.data["contact"][0]["kind"] == "node_to_surface"
    s = summarize(scene, mindlin_stand_in(scene, A, C, P0, MU), 0.0)
    assert s["contacts"]["contact 0"]["symmetry_planes"] == ["y = 0"]
    node_a = scene.model["pairs"]["node_a"]
    r = np.hypot(scene.pair_xy[:, 0], scene.pair_xy[:, 1])
    face = scene.global_boundary("sphere", "surface")
    _, area = triangle_normals(scene.nodes, face)
    for key, inside in (("contact", r < A), ("stick", r < C)):
        touched = np.isin(face, node_a[inside]).any(axis=1)
        assert math.isclose(s[f"{key}_area"], 2 * area[touched].sum(), rel_tol=1e-12)
        assert math.isclose(
            s[f"{key}_radius"], math.sqrt(s[f"{key}_area"] / math.pi), rel_tol=1e-12
        )
        # the rows' own tributary areas end short of them, by less than a spacing (0.3)
        tributary = math.sqrt(2 * areas_by_node(scene)[node_a[inside]].sum() / math.pi)
        assert 0 < s[f"{key}_radius"] - tributary <= 0.3, (key, s[f"{key}_radius"], tributary)


@needs_gmsh
def test_the_xdmf_holds_tetrahedra_stress_tensors_and_contact_fields(quarter, tmp_path):
    meshio = pytest.importorskip("meshio")
    scene, result = quarter
    write_results(tmp_path, scene, result, summarize(scene, result, 0.0), figures=False)
    with meshio.xdmf.TimeSeriesReader(str(tmp_path / "results.xdmf")) as reader:
        points, cells = reader.read_points_cells()
        t, point_data, cell_data = reader.read_data(0)
    assert t == 1.0 and cells[0].type == "tetra" and len(cells[0].data) == len(scene.tetrahedra)
    assert points.shape == (len(scene.nodes), 3)
    tensor = cell_data["stress"][0]
    assert tensor.shape == (len(scene.tetrahedra), 9)
    assert np.allclose(tensor[0].reshape(3, 3), [[50, 0, 0], [0, 0, 10], [0, 10, 0]])
    assert np.allclose(cell_data["von_mises"][0], math.sqrt(50.0**2 + 3 * 10.0**2))
    pressure = point_data["contact_pressure"]
    node_a = scene.model["pairs"]["node_a"]
    r = np.hypot(*scene.nodes[node_a, :2].T)
    assert np.allclose(pressure[node_a], P0 * np.sqrt(np.clip(1 - (r / A) ** 2, 0, None)))
    assert point_data["contact_tangential_stress"].shape == (len(scene.nodes), 3)
    assert point_data["u"].shape == (len(scene.nodes), 3)
    others = np.setdiff1d(np.arange(len(scene.nodes)), node_a)
    assert (pressure[others] == 0).all()


@needs_gmsh
def test_the_figures_are_written(quarter, tmp_path):
    scene, result = quarter
    written = write_results(tmp_path, scene, result, summarize(scene, result, 0.0), xdmf=False)
    names = {p.name for p in written}
    assert {
        "contact_area.png",
        "contact_pressure_line.png",
        "summary.json",
        "events.csv",
        "contact_profile.csv",
        "case.toml",
    } <= names
    for name in ("contact_area.png", "contact_pressure_line.png"):
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["n_dofs"] == 3 * len(scene.nodes)


@needs_gmsh
def test_the_pressure_line_interpolates_the_nodal_pressures(quarter):
    """Along x through the centre of pressure (the origin: the pressure is symmetric about x = 0
    and y = 0 is a mirror plane): the linear interpolant of the nodal pressures; at the nodes on
    that line it is their pressure exactly."""
    from slipstep.measures.contact_faces import pressure_line

    scene, result = quarter
    line = pressure_line(scene, result["snapshots"][0], 0, samples=401)
    # the centre in the contact plane (its height, the candidates' mean, does not enter the line)
    assert np.allclose(line["origin"][:2], 0.0) and np.allclose(line["direction"], [1, 0, 0])
    on_line = np.flatnonzero((np.abs(scene.pair_xy[:, 1]) <= 1e-12))
    xs = np.sort(scene.pair_xy[on_line, 0])
    # between two samples the interpolant moves at most P0 / (the shortest step between the
    # line's nodes) per unit length: that, times the sample step, bounds reading it at a node
    bound = P0 / np.diff(xs).min() * (line["s"][1] - line["s"][0])
    for k in on_line:
        x = scene.pair_xy[k, 0]
        p = P0 * math.sqrt(max(1 - (math.hypot(*scene.pair_xy[k, :2]) / A) ** 2, 0))
        assert abs(np.interp(x, line["s"], line["pressure"]) - p) <= bound, x


@needs_gmsh
def test_slipstep_run_of_a_3d_scene_through_a_stand_in_engine(quarter, monkeypatch, tmp_path):
    """The plumbing of run and Result in 3D (a stand-in engine answers with the stand-in
    result; the model it is handed is the scene's): fields, profile, to_meshio, figures."""
    import types

    import slipstep
    from slipstep import runner

    scene, result = quarter
    handed = {}

    def solve(model, progress, interval):
        handed["model"] = model
        return result

    monkeypatch.setattr(runner, "engine", lambda: types.SimpleNamespace(solve=solve))
    r = slipstep.run(scene, out=tmp_path, progress=False)
    assert handed["model"] is scene.model and r.out == tmp_path
    f = r.fields()
    n, m, p = len(scene.nodes), len(scene.tetrahedra), len(scene.pair_xy)
    assert f["u"].shape == (n, 3) and f["stress"].shape == (m, 6)
    assert f["lambda_t"].shape == (p, 2) and f["tangential_stress"].shape == (p, 3)
    assert np.allclose(f["pressure"] * scene.pair_area, result["snapshots"][0]["lambda_n"])
    assert r.profile()["position"].shape == (p, 3) and r.profile()["y"].shape == (p,)
    mesh = r.to_meshio()
    assert mesh.cells[0].type == "tetra" and mesh.points.shape == (n, 3)
    assert set(r.figures()) == {"contact_area", "contact_pressure_line"}
    assert "contact radius" in repr(r)


@needs_gmsh
def test_the_peak_pressure_is_recovered_from_scattered_nodal_pressures():
    """Hertz's p0 sqrt(1 - r^2/a^2) on the contact nodes of an eighth sphere (a/h = 14).  Exact
    samples: the recovered peak (a quadratic fit within 4 spacings < a/2, where the profile's
    r^4 term is below p0 (1/4)^2/8 = 0.8 %) is within 1 % of p0.  Each sample scattered by a
    random +-5 % (the node-to-node scatter of nodal pressures on unstructured tetrahedra), over
    20 draws: the raw maximum is off by nearly the scatter's bound every time, the fit averages
    ~50 nodes, so its rms error must be at most half the raw maximum's.  A pressure rising to the
    contact's edge (a flat punch's) has no smooth peak: its largest nodal value is kept."""
    from slipstep.measures.contact_faces import recovered_peak

    fine = SPHERE.replace("h_contact = 0.3", "h_contact = 0.1").replace(
        "contact_zone = 1.0", "contact_zone = 1.5"
    )
    scene = build_scene(parse_case(fine, "s.toml"))
    r = np.hypot(*scene.pair_xy[:, :2].T)
    a = 1.4  # the candidates reach r = sqrt(2 R z_max) = 1.41
    closed = r < a
    hertz = np.where(closed, P0 * np.sqrt(np.clip(1 - (r / a) ** 2, 0, None)), 0.0)
    profile = {
        "contact": np.zeros(len(r), dtype=int),
        "status": np.where(closed, 2, 0),
        "x": scene.pair_xy,
        "pressure": hertz,
    }
    assert abs(recovered_peak(scene, profile, 0, a) / P0 - 1) <= 0.01
    rng = np.random.default_rng(7)
    errors = []
    for _ in range(20):
        scattered = hertz * rng.uniform(0.95, 1.05, len(r))
        errors.append(
            (
                recovered_peak(scene, {**profile, "pressure": scattered}, 0, a) / P0 - 1,
                scattered.max() / P0 - 1,
            )
        )
    recovered, raw = np.sqrt(np.mean(np.square(errors), axis=0))
    assert recovered <= 0.5 * raw, (recovered, raw)
    punch = np.where(closed, P0 / np.sqrt(np.clip(1 - (r / a) ** 2, 0.01, None)), 0.0)
    assert recovered_peak(scene, {**profile, "pressure": punch}, 0, a) == punch.max()
