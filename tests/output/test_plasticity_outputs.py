"""What an elastoplastic run writes: summary.json first-yield fields (and Johnson's reference for
the Hertz case), events.csv element rows at centroids, XDMF plastic cell data, von_mises.png.

Small fast cases: the thick cylinder on a 1 mm mesh (~200 yield events) and the elastoplastic
Hertz cylinder (Sy = 200, H' = 700 MPa) on a coarse mesh stopped at its first yield event.
"""

from __future__ import annotations

import csv
import json
import types

import numpy as np
import pytest
from conftest import CASES, needs_gmsh, synthetic_hertz_result

from slipstep import cli, prepare, solve
from slipstep.output import writers as output
from slipstep.output.summary import element_depth, one_line, summarize
from slipstep.mesh import triangle_generators as generators
from slipstep.case import CaseError, load_case
from slipstep.figures.section import zone_boundary, zoom_window
from slipstep.build import build_scene
from slipstep.output.results import write_results

SY, H = 200.0, 700.0


def run_and_write(case, overrides, out):
    scene = prepare(case, overrides)
    result = solve(scene)
    summary = summarize(scene, result, wall_time_s=0.0)
    write_results(out, scene, result, summary)
    return scene, result, summary


def read_events(out):
    with open(out / "events.csv") as fh:
        return list(csv.DictReader(fh))


@pytest.fixture(scope="module")
def cylinder(tmp_path_factory):
    out = tmp_path_factory.mktemp("cylinder")
    return (
        out,
        *run_and_write(
            CASES / "thick_cylinder.toml",
            ["mesh.h=1.0", "mesh.h_outer=1.0", "output.snapshots=[0.7, 1.0]"],
            out,
        ),
    )


@pytest.fixture(scope="module")
def hertz(tmp_path_factory):
    out = tmp_path_factory.mktemp("hertz")
    return (
        out,
        *run_and_write(
            None,
            [
                f"material.Sy={SY}",
                f"material.H={H}",
                "mesh.h_contact=0.2",
                "output.snapshots=[1.0]",
                "solver.stop_at_first_yield=true",
            ],
            out,
        ),
    )


# --------------------------------------------------------------------------- bulk-only
@needs_gmsh
def test_cylinder_summary_first_yield_fields(cylinder):
    out, scene, result, summary = cylinder
    data = json.loads((out / "summary.json").read_text())
    ev = result["events"]
    k = list(ev["kind"]).index("yield")
    e = int(ev["entity"][k])
    centroid = scene.nodes[scene.triangles[e]].mean(axis=0)
    assert data["first_yield_load_fraction"] == float(ev["load_fraction"][k])
    assert data["first_yield_element"] == e
    assert data["first_yield_x"] == pytest.approx(centroid[0], abs=1e-12)
    # no contact: the depth is the centroid's y
    assert data["first_yield_depth"] == pytest.approx(centroid[1], abs=1e-12)
    last = result["snapshots"][-1]
    assert data["n_plastic_elements"] == int(np.count_nonzero(last["plastic"])) > 0
    assert data["n_plastic_elements"] == int(result["steps"]["n_plastic"][-1])
    assert data["max_drift"] == result["max_drift"]
    assert data["stop_reason"] is None and data["final_load_fraction"] == 1.0
    assert "hertz" not in data and data["n_pairs"] == 0


@needs_gmsh
def test_a_load_unload_counts_the_plastic_zone_and_the_yielding_elements_apart(tmp_path):
    """After unloading nothing yields (unloading is elastic) but the plastic zone stays:
    plastic strain never decreases, so the elements with plastic strain > 0 at the end are
    those of the peak.  The summary and its line count both, recomputed here from the
    snapshots; the record of the loading stage is its own end, where elements still yield."""
    scene, result, summary = run_and_write(
        CASES / "hertz_load_unload.toml",
        ["mesh.h_contact=0.4", "output.figures=false", "output.xdmf=false"],
        tmp_path,
    )
    peak = next(s for s in result["snapshots"] if s["stage"] == 0 and s["load_fraction"] == 1)
    last = result["snapshots"][-1]
    yielded = int(np.count_nonzero(np.asarray(last["plastic_strain"]) > 0))
    assert yielded == int(np.count_nonzero(np.asarray(peak["plastic_strain"]) > 0)) > 0
    assert summary["n_yielded_elements"] == yielded and summary["n_plastic_elements"] == 0
    loading, unloading = summary["stages"]
    assert loading["n_plastic_elements"] == int(np.count_nonzero(peak["plastic"])) > 0
    assert loading["n_yielded_elements"] == unloading["n_yielded_elements"] == yielded
    assert unloading["n_plastic_elements"] == 0
    assert f"{yielded} elements yielded (plastic strain > 0), 0 yielding now" in one_line(summary)


@needs_gmsh
def test_cylinder_files(cylinder):
    out, *_ = cylinder
    names = sorted(p.name for p in out.iterdir())
    assert names == [
        "case.toml",
        "events.csv",
        "history.csv",
        "results.h5",
        "results.xdmf",
        "summary.json",
        "von_mises.png",
    ]
    assert (out / "von_mises.png").stat().st_size > 10_000


@needs_gmsh
def test_events_csv_element_rows_are_at_centroids(cylinder):
    out, scene, result, _ = cylinder
    rows = read_events(out)
    assert len(rows) == len(result["events"]["step"]) > 0
    centroids = scene.nodes[scene.triangles].mean(axis=1)
    for row in rows:
        assert row["kind"] == "yield" and row["entity_kind"] == "element"
        x, y = centroids[int(row["entity"])]
        assert (float(row["x"]), float(row["y"])) == (x, y)


@needs_gmsh
def test_xdmf_has_the_plastic_cell_data(cylinder):
    import meshio

    out, scene, result, _ = cylinder
    with meshio.xdmf.TimeSeriesReader(str(out / "results.xdmf")) as reader:
        reader.read_points_cells()
        assert reader.num_steps == len(result["snapshots"]) == 2
        t, _, cells = reader.read_data(reader.num_steps - 1)
    last = result["snapshots"][-1]
    assert t == 1.0
    assert {"von_mises", "plastic_strain", "plastic"} <= set(cells)
    assert np.allclose(cells["von_mises"][0], output.von_mises(np.asarray(last["stress"])))
    assert np.array_equal(cells["plastic"][0], np.asarray(last["plastic"], dtype=float))
    assert np.array_equal(cells["plastic_strain"][0], np.asarray(last["plastic_strain"]))
    assert cells["plastic_strain"][0].max() > 0


@needs_gmsh
def test_cylinder_map_shows_the_whole_body(cylinder):
    _, scene, _, summary = cylinder
    assert zoom_window(scene, summary) is None


@needs_gmsh
def test_a_case_without_contact_validates_and_checks(capsys):
    assert load_case(CASES / "thick_cylinder.toml").data["contact"] == []
    assert cli.main(["check", str(CASES / "thick_cylinder.toml")]) == 0
    assert "0 contact pairs" in capsys.readouterr().out


# --------------------------------------------------------------------------- Hertz
@needs_gmsh
def test_hertz_johnson_reference_and_first_yield(hertz):
    out, scene, result, summary = hertz
    data = json.loads((out / "summary.json").read_text())
    p0 = scene.reference["p0_hertz"]
    f_johnson = (1.79 * SY / p0) ** 2
    assert data["hertz"]["f_yield_johnson"] == pytest.approx(f_johnson, rel=1e-12)
    assert f_johnson == pytest.approx(0.654, abs=5e-4)
    f = data["first_yield_load_fraction"]
    assert data["hertz"]["first_yield_rel_error"] == pytest.approx(f / f_johnson - 1, rel=1e-12)
    # stopped at the first yield: complete, not an error
    assert data["final_load_fraction"] == f and data["stop_reason"] is None
    # the flat is y = 0 with normal (0, 1): the depth is the centroid's y, below the contact
    centroid = scene.nodes[scene.triangles[data["first_yield_element"]]].mean(axis=0)
    assert data["first_yield_depth"] == pytest.approx(centroid[1], abs=1e-12)
    assert data["first_yield_x"] == pytest.approx(centroid[0], abs=1e-12)
    assert 0.0 < data["first_yield_depth"] < 2.0 * scene.reference["a_hertz"]


@needs_gmsh
def test_hertz_events_csv_tells_pairs_from_elements(hertz):
    out, scene, _, _ = hertz
    rows = read_events(out)
    pairs = [r for r in rows if r["entity_kind"] == "pair"]
    elements = [r for r in rows if r["entity_kind"] == "element"]
    assert pairs and all(r["kind"] == "close" for r in pairs)
    for r in pairs:
        assert (float(r["x"]), float(r["y"])) == tuple(scene.pair_xy[int(r["entity"])])
    assert [r["kind"] for r in elements] == ["yield"]
    e = int(elements[0]["entity"])
    assert float(elements[0]["x"]) == scene.nodes[scene.triangles[e]].mean(axis=0)[0]


@needs_gmsh
def test_hertz_map_is_zoomed_to_the_contact(hertz):
    out, scene, _, summary = hertz
    a = summary["contact_half_width"]
    (x0, x1), (y0, y1) = zoom_window(scene, summary)
    assert (x0, x1) == (0.0, pytest.approx(3 * a)) and (y0, y1) == (0.0, pytest.approx(2.5 * a))
    assert (out / "von_mises.png").stat().st_size > 10_000
    assert (out / "contact_interface.png").exists()


# --------------------------------------------------------------------------- pieces
def test_zoom_window_for_a_flat_above_the_body_and_without_a():
    line = types.SimpleNamespace(kind="rigid_line", point=(0.0, 2.0), normal=(0.0, -1.0))
    case = types.SimpleNamespace(record=types.SimpleNamespace(contact=(line,)))
    scene = types.SimpleNamespace(
        case=case, nodes=np.array([[-5.0, -9.0], [1.0, 2.0]]), reference={}
    )
    (x0, x1), (y0, y1) = zoom_window(scene, {"contact_half_width": 0.4})
    assert (x0, x1) == (pytest.approx(-1.2), 1.0) and (y0, y1) == (1.0, 2.0)
    assert zoom_window(scene, {}) is None  # no half-width known: the whole body


def test_zone_boundary_is_the_interface_between_the_sets():
    b = generators.block(4.0, 2.0, 4, 2)
    inside = b.nodes[b.triangles].mean(axis=1)[:, 0] < 2.0
    segs = zone_boundary(b.triangles, inside)
    assert len(segs) == 2 and np.all(b.nodes[segs][..., 0] == 2.0)
    assert len(zone_boundary(b.triangles, np.ones(len(b.triangles), bool))) == 0


def test_element_depth_below_a_node_to_node_interface():
    scene = build_scene(load_case(CASES / "two_blocks.toml"))
    centroids = scene.nodes[scene.triangles].mean(axis=1)
    for body, sign in (("foundation", -1.0), ("punch", 1.0)):
        mine = np.flatnonzero(scene.element_body == scene.bodies.index(body))
        e = mine[np.argmin(np.linalg.norm(centroids[mine] - [3.0, 20.0], axis=1))]
        assert element_depth(scene, e) == pytest.approx(sign * (centroids[e, 1] - 20.0))


def test_elastic_cases_have_no_plastic_outputs(tmp_path, monkeypatch):
    from slipstep.figures import section as figures

    scene = build_scene(load_case(None))
    result = synthetic_hertz_result(scene)
    summary = summarize(scene, result)
    assert not [k for k in summary if k.startswith("first_yield") or k == "n_plastic_elements"]
    assert "f_yield_johnson" not in summary["hertz"] and summary["stop_reason"] is None
    for name in ("interface_figure", "growth_figure"):  # not drawn: only the choice matters
        monkeypatch.setattr(figures, name, lambda path, *args: path)
    assert [p.name for p in figures.write_figures(tmp_path, scene, result, summary)] == [
        "contact_interface.png",
        "contact_growth.png",
    ]


@pytest.mark.parametrize(
    "override, key",
    [("mesh.b=10.0", "mesh.b"), ("mesh.h=11.0", "mesh.h"), ("mesh.h_outer=-1.0", "mesh.h_outer")],
)
def test_quarter_annulus_keys_are_checked(override, key):
    with pytest.raises(CaseError, match=rf"thick_cylinder.toml: {key} = .* is not allowed"):
        load_case(CASES / "thick_cylinder.toml", [override])


def test_readme_lists_the_plastic_summary_fields():
    readme = (CASES / "README.md").read_text()
    for key in (
        "first_yield_load_fraction",
        "first_yield_element",
        "first_yield_x",
        "first_yield_depth",
        "n_plastic_elements",
        "n_yielded_elements",
        "max_drift",
        "stop_reason",
        "f_yield_johnson",
        "first_yield_rel_error",
        "entity_kind",
        "von_mises.png",
        "thick_cylinder.toml",
        "stop_at_first_yield",
    ):
        assert key in readme, key
