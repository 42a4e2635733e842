"""Output: summary numbers, CSV/JSON/XDMF/PNG writers, atomic writing, and the CLI around them.

The engine result is the synthetic frictionless Hertz one of conftest.py (exact layout of
docs/engine_api.md, values known in closed form), so these tests run without the engine --
except the XDMF read-back, which needs non-zero fields: an elastoplastic engine run.
"""

from __future__ import annotations

import csv
import dataclasses
import json
import math

import numpy as np
import pytest
from conftest import CASES, synthetic_hertz_result

from slipstep import cli
from slipstep.measures import contact_edges as contact_measures
from slipstep.output import writers as output
from slipstep.output.summary import one_line, summarize
from slipstep.case import load_case
from slipstep.measures.contact_edges import contact_profile
from slipstep.build import build_scene
from slipstep.output.results import write_results


CONTACT_FIELDS = (
    "contact_pressure",
    "contact_tangential_stress",
    "contact_gap",
    "contact_status",
    "contact_slip",
)


@pytest.fixture(scope="module")
def hertz():
    scene = build_scene(load_case(None))
    return scene, synthetic_hertz_result(scene)


# --------------------------------------------------------------------------- numbers
def test_contact_half_width_interpolates_in_load_fraction():
    x = np.array([0.0, 1.0, 2.0, 3.0])
    status = np.array([2, 2, 0, 0])
    closure = np.array([0.0, 0.4, np.nan, np.nan])
    predicted = np.array([np.nan, np.nan, 1.6, 3.0])
    # a = x_c + (x_o - x_c)(f - f_c)/(f_o - f_c) = 1 + (1 - 0.4)/(1.6 - 0.4)
    assert contact_measures.contact_half_width(x, status, closure, predicted, 1.0) == pytest.approx(
        1.5, abs=1e-15
    )
    assert contact_measures.contact_half_width(x, status, closure, predicted, 0.4) == 1.0
    predicted[2] = np.inf  # not closing: the edge stays at the last closed node
    assert contact_measures.contact_half_width(x, status, closure, predicted, 1.0) == 1.0
    assert contact_measures.contact_half_width(x, np.zeros(4, int), closure, predicted, 1.0) == 0.0


def test_stick_half_width():
    x = np.array([0.0, 1.0, 2.0, 3.0, 4.0])
    assert contact_measures.stick_half_width(x, np.array([1, 1, 2, 2, 0]), 3.5) == 1.5
    assert (
        contact_measures.stick_half_width(x, np.array([1, 1, 1, 0, 0]), 2.5) == 2.5
    )  # all closed stick
    assert (
        contact_measures.stick_half_width(x, np.array([2, 2, 2, 0, 0]), 2.5) == 0.0
    )  # nothing sticks


def test_von_mises():
    s = np.array([[100.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 10.0], [50.0, 50.0, 50.0, 0.0]])
    assert np.allclose(output.von_mises(s), [100.0, 10.0 * math.sqrt(3.0), 0.0], rtol=1e-14)


def test_summary_of_the_synthetic_hertz_result(hertz):
    scene, result = hertz
    s = summarize(scene, result, wall_time_s=1.5)
    h = 0.03  # h_contact of the default case
    assert abs(s["contact_half_width"] - 1.4384) <= h / 2
    assert abs(s["peak_pressure"] - 442.6) <= 0.05
    assert s["stick_half_width"] == 0.0  # frictionless: everything closed slips
    assert s["n_events"] == len(result["events"]["step"])
    assert s["final_load_fraction"] == 1.0 and s["interrupted"] is False
    assert s["n_dofs"] == 2 * s["n_nodes"] == 2 * len(scene.nodes)
    assert s["n_elements"] == len(scene.triangles)
    assert s["contact_reached_last_candidate"] is False
    # the quarter model carries P/2 = 500 N/mm: the lumped Hertz pressure sums to it within
    # the quadrature error of the nodal lumping
    assert abs(s["total_normal_force"] - 500.0) <= 0.5
    assert abs(s["hertz"]["a_rel_error"]) < 0.02


def test_the_summary_line_names_and_units_its_quantities(hertz):
    """The line the CLI prints names each number and gives it the case's unit ([case] units =
    "mm, N, MPa" in the shipped Hertz case); a case without units prints none.  The numbers
    are the summary's, formatted to four digits."""
    scene, result = hertz
    s = summarize(scene, result, wall_time_s=1.5)
    assert s["units"] == {"length": "mm", "force": "N", "stress": "MPa"}
    line = one_line(s)
    a, c, p0 = s["contact_half_width"], s["stick_half_width"], s["peak_pressure"]
    h = s["hertz"]
    for part in (
        "f = 1 load fraction",
        f"a = {a:.4g} mm contact half-width",
        f"p0 = {p0:.4g} MPa peak pressure",
        f"(Hertz a = {h['a_hertz_at_final']:.4g} mm, p0 = " f"{h['p0_hertz_at_final']:.4g} MPa)",
    ):
        assert part in line, (part, line)
    assert s["frictionless"] and "stick" not in line  # mu = 0: no stick zone to name
    assert f"c = {c:.4g} mm stick half-width" in one_line(dict(s, frictionless=False))
    bare = one_line(dict(s, units={}))
    assert f"a = {a:.4g} contact half-width" in bare and "mm" not in bare and "MPa" not in bare


def test_a_case_without_units_has_none_in_its_summary(hertz):
    scene, result = hertz
    for note, units in (("", {}), ("m, kN, kPa", {"length": "m", "force": "kN", "stress": "kPa"})):
        case = load_case(None, [f'case.units="{note}"'])
        s = summarize(dataclasses.replace(scene, case=case), result)
        assert s["units"] == units
        assert ("kPa peak pressure" in one_line(s)) == bool(units)


def test_growth_curve_replays_the_events(hertz):
    scene, result = hertz
    f, a = contact_measures.contact_growth(scene, result)
    assert f[0] == 0.0 and a[0] == 0.0 and f[-1] == 1.0
    assert np.all(np.diff(f) >= 0) and np.all(np.diff(a) >= 0)
    # each closure step is at f = (x / a_H)^2, so x = a_H sqrt(f) on the steps
    assert np.allclose(a[1:], scene.reference["a_hertz"] * np.sqrt(f[1:]), atol=0.031)


# --------------------------------------------------------------------------- files
def test_write_results(hertz, tmp_path):
    import meshio

    scene, result = hertz
    summary = summarize(scene, result, 1.0)
    written = write_results(tmp_path, scene, result, summary)
    names = sorted(p.name for p in written)
    assert names == [
        "case.toml",
        "contact_growth.png",
        "contact_interface.png",
        "contact_profile.csv",
        "events.csv",
        "history.csv",
        "results.h5",
        "results.xdmf",
        "summary.json",
    ]
    assert not list(tmp_path.glob(".partial-*"))

    with open(tmp_path / "events.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == len(result["events"]["step"])
    first = rows[0]
    pair = int(first["entity"])
    assert first["kind"] == "close"
    assert float(first["x"]) == scene.pair_xy[pair, 0]

    with open(tmp_path / "contact_profile.csv") as fh:
        prof = list(csv.DictReader(fh))
    xs = [float(r["x"]) for r in prof]
    assert xs == sorted(xs) and len(prof) == len(scene.pair_xy)
    assert {r["status"] for r in prof} == {"open", "slip"}
    assert float(prof[0]["pressure"]) == pytest.approx(summary["peak_pressure"], rel=1e-12)

    data = json.loads((tmp_path / "summary.json").read_text())
    for key in (
        "n_events",
        "final_load_fraction",
        "contact_half_width",
        "stick_half_width",
        "peak_pressure",
        "total_normal_force",
        "max_equilibrium_residual",
        "wall_time_s",
        "n_nodes",
        "n_elements",
        "n_dofs",
        "n_factorizations",
        "interrupted",
    ):
        assert key in data, key

    with meshio.xdmf.TimeSeriesReader(str(tmp_path / "results.xdmf")) as reader:
        points, cells = reader.read_points_cells()
        assert points.shape == (len(scene.nodes), 2)
        assert cells[0].type == "triangle" and len(cells[0].data) == len(scene.triangles)
        assert reader.num_steps == len(result["snapshots"])
        t, point_data, cell_data = reader.read_data(reader.num_steps - 1)
    assert t == 1.0
    assert point_data["u"].shape == (len(scene.nodes), 3)
    assert set(cell_data) == {"sigma_x", "sigma_y", "sigma_z", "tau_xy", "stress", "von_mises"}
    assert set(point_data) == {"u", "nodal_stress", "nodal_von_mises", *CONTACT_FIELDS}


def test_xdmf_reads_back_every_step_of_an_elastoplastic_run(tmp_path):
    """results.xdmf/.h5 read back (meshio's TimeSeriesReader) against the run's snapshots at
    every time step: mesh, time = load fraction, u, the stress components and the plastic
    fields are copies (float64 into HDF5 and back: bit-exact); von Mises and the yield drift
    are derived, recomputed here from the stresses (tests/physics.py) to round-off: 1e-12 of
    the largest stress (a few operations in double precision)."""
    import meshio
    from physics import von_mises

    from slipstep import prepare, solve

    sy, hp = 200.0, 700.0
    scene = prepare(
        None,
        [
            f"material.Sy={sy}",
            f"material.H={hp}",
            "mesh.h_contact=0.15",
            "contact.mu=0.3",
            "output.snapshots=[0.6, 0.7, 0.8, 0.9, 1.0]",
        ],
    )
    result = solve(scene)
    snaps = result["snapshots"]
    assert len(snaps) >= 5 and max(s["plastic_strain"].max() for s in snaps) > 0
    output.write_xdmf(tmp_path, scene, result)
    stress_scale = max(np.abs(s["stress"]).max() for s in snaps)
    with meshio.xdmf.TimeSeriesReader(str(tmp_path / "results.xdmf")) as reader:
        points, cells = reader.read_points_cells()
        assert np.array_equal(points[:, :2], scene.nodes)
        assert len(cells) == 1 and cells[0].type == "triangle"
        assert np.array_equal(cells[0].data, scene.triangles)
        assert reader.num_steps == len(snaps)
        for k, snap in enumerate(snaps):
            t, point_data, cell_data = reader.read_data(k)
            assert t == snap["load_fraction"], k
            u = point_data["u"]
            assert u.shape == (len(scene.nodes), 3)
            assert np.array_equal(u[:, :2], snap["u"]) and np.all(u[:, 2] == 0.0), k
            assert set(cell_data) == {
                "sigma_x",
                "sigma_y",
                "sigma_z",
                "tau_xy",
                "stress",
                "von_mises",
                "plastic_strain",
                "plastic",
                "yield_drift",
            }, k
            stress = np.asarray(snap["stress"])
            for col, key in enumerate(("sigma_x", "sigma_y", "sigma_z", "tau_xy")):
                assert np.array_equal(cell_data[key][0], stress[:, col]), (k, key)
            # the tensor, row by row xx xy xz / yx yy yz / zx zy zz, z out of the plane
            tensor = cell_data["stress"][0].reshape(-1, 3, 3)
            assert np.array_equal(tensor[:, [0, 1, 2, 0], [0, 1, 2, 1]], stress), k
            assert np.array_equal(tensor, tensor.transpose(0, 2, 1)), k
            assert not tensor[:, [0, 1], 2].any(), k
            # contact fields on node a of each pair (contact_profile.csv's numbers), 0 elsewhere
            prof = contact_profile(scene, snap)
            for name, column in (
                ("contact_pressure", "pressure"),
                ("contact_gap", "gap"),
                ("contact_tangential_stress", "tangential_stress"),
                ("contact_status", "status"),
                ("contact_slip", "rtd"),
            ):
                values = point_data[name]
                assert np.array_equal(values[prof["node_a"]], prof[column]), (k, name)
                others = np.setdiff1d(np.arange(len(scene.nodes)), prof["node_a"])
                assert not values[others].any(), (k, name)
            assert np.array_equal(cell_data["plastic_strain"][0], snap["plastic_strain"]), k
            assert np.array_equal(cell_data["plastic"][0], np.asarray(snap["plastic"], float)), k
            vm = von_mises(stress)
            assert np.abs(cell_data["von_mises"][0] - vm).max() <= 1e-12 * stress_scale, k
            current = sy + hp * np.asarray(snap["plastic_strain"])
            plastic = np.asarray(snap["plastic"]) > 0
            drift = np.where(plastic, np.abs(vm - current) / current, 0.0)
            assert np.abs(cell_data["yield_drift"][0] - drift).max() <= 1e-12 * stress_scale / sy, k


def test_the_xdmf_records_the_case_units(hertz, tmp_path):
    """An Information element of the Domain (XDMF 3) holds [case] units; meshio's reader
    still finds every time step; a case without units gets no element."""
    import xml.etree.ElementTree as ET

    import meshio

    scene, result = hertz
    output.write_xdmf(tmp_path, scene, result)
    domain = ET.parse(tmp_path / "results.xdmf").getroot().find("Domain")
    (info,) = domain.findall("Information")
    assert info.attrib == {"Name": "units", "Value": "length: mm, force: N, stress: MPa"}
    with meshio.xdmf.TimeSeriesReader(str(tmp_path / "results.xdmf")) as reader:
        reader.read_points_cells()
        assert reader.num_steps == len(result["snapshots"])
    bare = dataclasses.replace(scene, case=load_case(None, ['case.units=""']))
    output.write_xdmf(tmp_path, bare, result)
    assert ET.parse(tmp_path / "results.xdmf").getroot().find("Domain/Information") is None


def test_a_result_writes_a_vtu_with_3d_points(hertz, tmp_path, capsys):
    """Result.to_meshio gives points with z = 0, so meshio's VTU writer takes them as they
    are (with 2D points it printed "VTU requires 3D points"); read back, the file holds the
    fields of Result.fields."""
    import meshio

    from slipstep import Result

    scene, raw = hertz
    r = Result(scene, raw, summarize(scene, raw))
    r.to_meshio().write(tmp_path / "m.vtu")
    assert "3D points" not in capsys.readouterr().err
    m = meshio.read(tmp_path / "m.vtu")
    assert np.array_equal(m.points[:, :2], scene.nodes) and not m.points[:, 2].any()
    f = r.fields()
    assert np.array_equal(
        m.point_data["nodal_stress"].reshape(-1, 3, 3)[:, [0, 1, 2, 0], [0, 1, 2, 1]],
        f["nodal_stress"],
    )
    assert np.array_equal(m.cell_data["von_mises"][0], f["von_mises"])


def test_failed_write_leaves_the_previous_results(hertz, tmp_path, monkeypatch):
    scene, result = hertz
    summary = summarize(scene, result, 1.0)
    (tmp_path / "summary.json").write_text('{"old": true}\n')

    def broken(*args, **kwargs):
        raise RuntimeError("disk full")

    monkeypatch.setattr(output, "write_xdmf", broken)
    with pytest.raises(RuntimeError, match="disk full"):
        write_results(tmp_path, scene, result, summary, figures=False)
    assert (tmp_path / "summary.json").read_text() == '{"old": true}\n'
    assert sorted(p.name for p in tmp_path.iterdir()) == ["summary.json"]


def test_interrupted_run_writes_what_it_has(hertz, tmp_path):
    scene, _ = hertz
    partial = synthetic_hertz_result(scene, final_fraction=0.5, interrupted=True)
    summary = summarize(scene, partial, 1.0)
    assert summary["interrupted"] is True and summary["final_load_fraction"] == 0.5
    # Hertz at f = 0.5: a sqrt(0.5)
    assert abs(summary["contact_half_width"] - 1.4384 * math.sqrt(0.5)) <= 0.015
    write_results(tmp_path, scene, partial, summary, xdmf=False, figures=False)
    data = json.loads((tmp_path / "summary.json").read_text())
    assert data["interrupted"] is True
    assert data["hertz"]["a_hertz_at_final"] == pytest.approx(1.4384 * math.sqrt(0.5), rel=1e-4)


# --------------------------------------------------------------------------- CLI
def test_cli_errors_are_one_line_with_exit_2(tmp_path, capsys):
    assert cli.main(["run", str(tmp_path / "none.toml")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("slipstep: error: ")
    assert "none.toml: no such case file" in err

    assert cli.main(["check", "--set", "contact.muu=0.3"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("slipstep: error: --set contact.muu=0.3: unknown key 'muu'")


def test_cli_check_prints_the_size(capsys):
    assert cli.main(["check", str(CASES / "two_blocks.toml")]) == 0
    out = capsys.readouterr().out
    assert out.startswith("two_blocks: 3552 nodes, 6800 elements, 7104 dofs, 21 contact pairs")


def test_cli_run_with_a_stand_in_engine(hertz, tmp_path, monkeypatch, capsys):
    """The CLI plumbing (not the engine): summary line, files, exit codes 0 and 130."""
    import types

    from slipstep import runner

    scene, result = hertz
    # the prepared mesh, with the case as loaded by the CLI (so its --set applies); the CLI
    # runs through runner.run_case, which meshes with runner.build_scene and solves with
    # runner.engine().solve
    monkeypatch.setattr(
        runner, "build_scene", lambda case, meshes=None: dataclasses.replace(scene, case=case)
    )
    answer = {"result": result}
    monkeypatch.setattr(
        runner,
        "engine",
        lambda: types.SimpleNamespace(
            solve=lambda model, progress, report_interval: answer["result"]
        ),
    )
    assert cli.main(["run", "--out", str(tmp_path / "a"), "--set", "output.xdmf=false"]) == 0
    line = capsys.readouterr().out
    assert line.startswith("hertz_cylinder: ") and line.count("\n") == 1
    assert (tmp_path / "a" / "summary.json").exists()

    answer["result"] = synthetic_hertz_result(scene, final_fraction=0.3, interrupted=True)
    assert (
        cli.main(["run", "--out", str(tmp_path / "b"), "--quiet", "--set", "output.xdmf=false"])
        == 130
    )
    captured = capsys.readouterr()
    assert captured.out == "" and "interrupted at load fraction 0.3" in captured.err
    assert json.loads((tmp_path / "b" / "summary.json").read_text())["interrupted"] is True


def test_run_case_api_with_a_stand_in_engine(hertz, tmp_path, monkeypatch):
    """run_case(path or None, out, overrides) -> (result, summary), through runner.engine()."""
    import types

    from slipstep import runner

    scene, result = hertz
    seen = {}

    def solve(model, progress, report_interval):
        seen["model"], seen["progress"] = model, progress
        return result

    monkeypatch.setattr(runner, "engine", lambda: types.SimpleNamespace(solve=solve))
    got, summary = runner.run_case(
        None, out=tmp_path, overrides=["output.xdmf=false", "output.figures=false"]
    )
    assert got is result and seen["progress"] is False
    assert seen["model"]["load"].shape == (2 * len(scene.nodes),)
    assert summary["case"] == "hertz_cylinder" and summary["wall_time_s"] > 0
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "case.toml",
        "contact_profile.csv",
        "events.csv",
        "history.csv",
        "summary.json",
    ]


def test_reached_last_candidate_only_for_a_cut_candidate_window(hertz):
    scene, result = hertz
    final = dict(result["snapshots"][-1])
    assert scene.contact_truncated == [True]  # x_max = 3 cuts the arc
    assert contact_measures.reached_last_candidate(scene, final) is False
    final["status"] = np.full(len(scene.pair_xy), 2)
    assert contact_measures.reached_last_candidate(scene, final) is True
    blocks = build_scene(load_case(CASES / "two_blocks.toml"))
    assert blocks.contact_truncated == [False]  # the whole punch bottom is a candidate
    closed = {"status": np.full(len(blocks.pair_xy), 1)}
    assert contact_measures.reached_last_candidate(blocks, closed) is False
