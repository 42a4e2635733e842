"""Outputs of multi-stage load paths (issue 13): events.csv t/stage, XDMF time = t with the
support reactions, summary.json stage records, reactions per [[bc]], the path history and the
load-path figures.

The results are synthetic (the layout of docs/engine_api.md, values chosen by hand), on a tiny
block pressed onto a rigid flat by a prescribed displacement of its top (stage "press") and
released (stage "release"); the Scene attributes of the load path (load_names, factors,
support_dofs, prescribed, motions, ...) are set here, so no engine is needed.  The same result
stripped of the new keys stands for today's engine: one stage, t = load fraction.
"""

from __future__ import annotations

import copy
import csv
import json
import types

import numpy as np
import pytest

from slipstep.measures import contact_edges as contact_measures
from slipstep.output import history, writers as output
from slipstep.output.summary import one_line
from slipstep.case import parse_case
from slipstep.build import build_scene
from slipstep.output.results import write_results
from slipstep.output.summary import summarize

BLOCK = """
[case]
name = "press_release"
[output]
figures = false
xdmf = false
[[body]]
name = "block"
[body.mesh]
generator = "block"
width = 4.0
height = 2.0
nx = 4
ny = 2
[body.material]
E = 1000.0
nu = 0.3
[[bc]]
name = "top"
body = "block"
edge = "top"
traction = [0.0, -1.0]
[[bc]]
name = "left"
body = "block"
edge = "left"
fix = ["x"]
[[contact]]
name = "flat"
kind = "rigid_line"
body = "block"
edge = "bottom"
normal = [0.0, 1.0]
mu = 0.5
"""

OLD_COLUMNS = ["step", "load_fraction", "kind", "entity", "entity_kind", "x", "y"]
T = [0.5, 1.0, 1.5, 2.0]  # snapshot path times
PRESS = [10.0, 20.0, 8.0, 0.0]  # force of the press at them: unloading below loading
U_TOP = -0.01  # prescribed y displacement of the top at factor 1


def nodes_of(scene, tag: str) -> np.ndarray:
    return np.unique(scene.global_edge("block", tag))


@pytest.fixture(scope="module")
def bare():
    """The scene as today's model.py builds it: no load-path attributes."""
    return build_scene(parse_case(BLOCK))


@pytest.fixture(scope="module")
def scene():
    scene = build_scene(parse_case(BLOCK))
    top, left = nodes_of(scene, "top"), nodes_of(scene, "left")
    scene.load_names = ["load", "press"]
    scene.stage_names = ["press", "release"]
    scene.n_stages = 2
    scene.factors = np.array([[0.0, 0.0], [0.0, 1.0], [0.0, 0.0]])
    scene.support_dofs = {"top": 2 * top + 1, "left": 2 * left}
    scene.prescribed = {"press": {"dofs": 2 * top + 1, "values": np.full(len(top), U_TOP)}}
    scene.motions = {}
    return scene


def staged_result(scene) -> dict:
    """Two stages: the press closes all 5 pairs in stick (P = 20 at t = 1), the release lets
    the outer pairs separate at t = 1.2 and the rest at t = 2 (P = 8 at t = 1.5, 0 at t = 2)."""
    n, m, p = len(scene.nodes), len(scene.triangles), len(scene.pair_xy)
    top, left = nodes_of(scene, "top"), nodes_of(scene, "left")
    rng = np.random.default_rng(13)
    snaps = []
    for t, force in zip(T, PRESS):
        status = np.ones(p, np.int8)
        if t == 1.5:
            status[[0, 4]] = 0
        if t == 2.0:
            status[:] = 0
        lam = np.where(status > 0, force / max(int(status.sum()), 1), 0.0)
        reaction = np.zeros((n, 2))
        reaction[top, 1] = -force / len(top)
        reaction[left, 0] = rng.normal(size=len(left))
        stage = 0 if t <= 1.0 else 1
        snaps.append(
            {
                "t": t,
                "stage": stage,
                "load_fraction": t - stage,
                "u": rng.normal(size=(n, 2)),
                "stress": np.zeros((m, 4)),
                "plastic_strain": np.zeros(m),
                "plastic": np.zeros(m, np.int8),
                "lambda_n": lam,
                "lambda_t": 0.1 * lam,
                "status": status,
                "gap": np.zeros(p),
                "rtd": np.zeros(p),
                "reaction": reaction,
            }
        )
    events = {
        "step": np.array([1, 2, 2, 3, 3, 3]),
        "t": np.array([0.5, 1.2, 1.2, 2.0, 2.0, 2.0]),
        "stage": np.array([0, 1, 1, 1, 1, 1]),
        "kind": ["stick_to_slip"] + ["separate"] * 5,
        "entity": np.array([0, 0, 4, 1, 2, 3]),
    }
    events["load_fraction"] = events["t"] - events["stage"]
    steps = {
        "t": np.array(T),
        "stage": np.array([0, 0, 1, 1]),
        "load_fraction": np.array([0.5, 1.0, 0.5, 1.0]),
    }
    return {
        "events": events,
        "steps": steps,
        "snapshots": snaps,
        "closure_fraction": np.zeros(p),
        "predicted_closure": np.full(p, np.inf),
        "n_stages": 2,
        "stage_names": ["press", "release"],
        "stop": {"kind": "completed", "message": None, "load_fraction": 1.0, "t": 2.0},
        "interrupted": False,
        "stop_reason": None,
        "max_equilibrium_residual": 1e-13,
        "timings": {},
    }


def old_result(scene, final: float = 1.0) -> dict:
    """The press stage alone in today's layout: no t, stage, reaction, n_stages, stop.t."""
    r = copy.deepcopy(staged_result(scene))
    keep = r["events"]["stage"] == 0
    r["events"] = {
        k: (np.asarray(v)[keep] if k != "kind" else [x for x, y in zip(v, keep) if y])
        for k, v in r["events"].items()
        if k not in ("t", "stage")
    }
    r["snapshots"] = [s for s in r["snapshots"] if s["t"] <= final]
    for s in r["snapshots"]:
        for key in ("t", "stage", "reaction"):
            del s[key]
    r["steps"] = {"load_fraction": np.array([s["load_fraction"] for s in r["snapshots"]])}
    for key in ("n_stages", "stage_names"):
        del r[key]
    r["stop"] = {
        "kind": "completed" if final == 1.0 else "interrupted",
        "message": None,
        "load_fraction": final,
    }
    return r


def read_csv(path) -> list[dict]:
    with open(path) as fh:
        return list(csv.DictReader(fh))


# --------------------------------------------------------------------------- events.csv
def test_events_csv_appends_t_and_the_1_based_stage(scene, tmp_path):
    result = staged_result(scene)
    output.write_events_csv(tmp_path / "events.csv", scene, result)
    with open(tmp_path / "events.csv") as fh:
        assert next(csv.reader(fh)) == OLD_COLUMNS + ["t", "stage"]
    rows = read_csv(tmp_path / "events.csv")
    assert [float(r["t"]) for r in rows] == list(result["events"]["t"])
    assert [int(r["stage"]) for r in rows] == [1, 2, 2, 2, 2, 2]
    assert [float(r["load_fraction"]) for r in rows] == list(result["events"]["load_fraction"])


def test_events_csv_of_a_result_without_stages(bare, tmp_path):
    result = old_result(bare)
    output.write_events_csv(tmp_path / "events.csv", bare, result)
    rows = read_csv(tmp_path / "events.csv")
    assert len(rows) == 1 and rows[0]["t"] == rows[0]["load_fraction"] == "0.5"
    assert rows[0]["stage"] == "1"


# --------------------------------------------------------------------------- XDMF
def read_xdmf(folder):
    import meshio

    with meshio.xdmf.TimeSeriesReader(str(folder / "results.xdmf")) as reader:
        reader.read_points_cells()
        return [reader.read_data(k) for k in range(reader.num_steps)]


def test_xdmf_time_is_t_with_the_reactions(scene, tmp_path):
    result = staged_result(scene)
    output.write_xdmf(tmp_path, scene, result)
    steps = read_xdmf(tmp_path)
    assert [t for t, _, _ in steps] == T
    for (_, point_data, _), snap in zip(steps, result["snapshots"]):
        assert {"u", "reaction", "contact_pressure", "nodal_stress"} <= set(point_data)
        r = point_data["reaction"]
        assert r.shape == (len(scene.nodes), 3) and np.all(r[:, 2] == 0.0)
        assert np.array_equal(r[:, :2], snap["reaction"])
        assert np.array_equal(point_data["u"][:, :2], snap["u"])


def test_xdmf_has_one_step_per_time_the_last_state_there(scene, tmp_path):
    """A stage end with a zero-length switch after it holds two snapshots at t = 1 (the end of
    stage 1, then the start of stage 2): the XDMF keeps one step there (ParaView reads a
    repeated time as an empty frame), the later state; events.csv keeps both stages' rows."""
    result = staged_result(scene)
    after = copy.deepcopy(result["snapshots"][1])
    after.update(stage=1, load_fraction=0.0, u=after["u"] + 1.0)
    result["snapshots"].insert(2, after)
    assert history.distinct_time_snapshots(result) == [0, 2, 3, 4]
    output.write_xdmf(tmp_path, scene, result)
    steps = read_xdmf(tmp_path)
    assert [t for t, _, _ in steps] == T
    assert np.array_equal(steps[1][1]["u"][:, :2], after["u"])


def test_contact_point_data_sits_on_the_contactor_nodes():
    """Each pair's numbers on its node a, 0 on the other nodes; a node in two contacts (the
    bottom edge against two flats) shows the pair with the larger pressure."""
    scene = build_scene(
        parse_case(
            BLOCK
            + BLOCK[BLOCK.index("[[contact]]") :]
            .replace('"flat"', '"far"')
            .replace("mu = 0.5", "mu = 0.5\npoint = [0.0, -1.0]")
        )
    )
    bottom = np.unique(scene.global_edge("block", "bottom"))
    p = len(scene.pair_xy)
    assert p == 2 * len(bottom)  # every bottom node is node a of one pair per flat
    near = scene.pair_contact == 0
    lam = np.where(near, 1.0, 0.0) * (1.0 + np.arange(p))
    snap = {
        "lambda_n": lam,
        "lambda_t": 0.1 * lam,
        "status": (lam > 0).astype(np.int8),
        "gap": np.where(near, 0.0, 1.0),
        "rtd": np.zeros(p),
        "u": np.zeros((len(scene.nodes), 2)),
    }
    fields = output.contact_point_data(scene, snap)
    prof = contact_measures.contact_profile(scene, snap)
    mine = prof["contact"] == 0
    for name, column in output.CONTACT_POINT_DATA.items():
        values = fields[name]
        assert np.array_equal(values[prof["node_a"][mine]], prof[column][mine]), name
        assert not np.delete(values, bottom).any(), name
    snap["lambda_n"] = lam[::-1].copy() * np.where(near, 0.0, 1.0)  # now the far flat presses
    fields = output.contact_point_data(scene, snap)
    far = prof["contact"] == 1
    assert np.array_equal(
        fields["contact_pressure"][prof["node_a"][far]],
        contact_measures.contact_profile(scene, snap)["pressure"][far],
    )


def test_xdmf_of_a_result_without_stages(bare, tmp_path):
    result = old_result(bare)
    output.write_xdmf(tmp_path, bare, result)
    steps = read_xdmf(tmp_path)
    assert [t for t, _, _ in steps] == [0.5, 1.0]
    assert all("u" in point_data and "reaction" not in point_data for _, point_data, _ in steps)


# --------------------------------------------------------------------------- reactions
def test_reactions_sum_the_dofs_of_each_bc(scene):
    snap = staged_result(scene)["snapshots"][1]
    left = nodes_of(scene, "left")
    r = history.reactions(scene, snap)
    assert set(r) == {"top", "left"}
    assert r["top"] == (0.0, pytest.approx(-20.0, rel=1e-14))
    assert r["left"] == (pytest.approx(snap["reaction"][left, 0].sum(), rel=1e-14), 0.0)
    assert r["left"][0] != 0.0
    assert history.reactions(scene, old_result(scene)["snapshots"][0]) == {}


def test_reactions_without_support_dofs_are_empty(scene):
    before = types.SimpleNamespace()  # a Scene from before the load paths: no support_dofs
    assert history.reactions(before, staged_result(scene)["snapshots"][0]) == {}


# --------------------------------------------------------------------------- summary.json
def test_summary_has_one_record_per_stage(scene, tmp_path):
    result = staged_result(scene)
    s = summarize(scene, result, 0.0)
    assert s["n_stages"] == 2 and s["stage_names"] == ["press", "release"]
    assert s["final_t"] == 2.0 and s["stop"]["t"] == 2.0 and s["stop"]["load_fraction"] == 1.0
    press, release = s["stages"]
    assert (press["stage"], press["name"], press["t_end"], press["n_events"]) == (
        1,
        "press",
        1.0,
        1,
    )
    assert (release["stage"], release["name"], release["t_end"], release["n_events"]) == (
        2,
        "release",
        2.0,
        5,
    )
    assert press["total_normal_force"] == pytest.approx(20.0, rel=1e-14)
    assert press["total_tangential_force"] == pytest.approx(2.0, rel=1e-14)
    assert press["reactions"]["top"] == [0.0, pytest.approx(-20.0, rel=1e-14)]
    assert press["contacts"]["flat"]["closed_extent"] == [0.0, 4.0]
    assert press["contacts"]["flat"]["n_closed"] == 5 and press["n_plastic_elements"] == 0
    assert release["total_normal_force"] == 0.0 and release["reactions"]["top"] == [0.0, 0.0]
    assert release["contacts"]["flat"]["closed_extent"] is None
    assert s["total_normal_force"] == s["total_tangential_force"] == 0.0
    assert s["reactions"] == release["reactions"]
    assert "t = 2 of 2 stages" in one_line(s)
    output.write_summary_json(tmp_path / "summary.json", s)
    data = json.loads((tmp_path / "summary.json").read_text())
    assert data["stages"][0]["reactions"]["top"] == press["reactions"]["top"]


def test_summary_of_a_result_without_stages(bare):
    result = old_result(bare)
    s = summarize(bare, result, 0.0)
    assert s["n_stages"] == 1 and s["stage_names"] == ["stage 1"]
    assert s["final_t"] == s["final_load_fraction"] == s["stop"]["t"] == 1.0
    (only,) = s["stages"]
    assert only["t_end"] == 1.0 and only["n_events"] == s["n_events"] == 1
    assert only["reactions"] == {} and "reactions" not in s
    assert only["total_normal_force"] == s["total_normal_force"] == pytest.approx(20.0)
    assert s["total_tangential_force"] == pytest.approx(2.0)
    assert s["snapshot_t"] == s["snapshot_load_fraction"] == 1.0
    assert one_line(s).startswith("press_release: 1 events, f = 1 load fraction, ")


def test_an_unfinished_stage_has_no_record(bare):
    s = summarize(bare, old_result(bare, final=0.5), 0.0)
    assert s["stages"] == [] and s["final_t"] == 0.5


def test_the_end_of_a_stage_is_found_by_t_too(scene):
    # times mode: the snapshot at t = 1 may come labelled as the start of the next stage
    result = staged_result(scene)
    result["snapshots"][1].update(stage=1, load_fraction=0.0)
    assert history.stage_ends(result, 2) == [(0, 1), (1, 3)]


# --------------------------------------------------------------------------- history, curves
def test_load_factor_interpolates_the_stage_factors(scene, bare):
    assert np.allclose(
        history.load_factor(scene, "press", [0.0, 0.5, 1.0, 1.25, 2.0]),
        [0.0, 0.5, 1.0, 0.75, 0.0],
        rtol=0,
        atol=1e-15,
    )
    assert history.load_factor(bare, "load", 0.3) == 0.3


def test_path_history(scene):
    h = contact_measures.path_history(scene, staged_result(scene))
    assert list(h["t"]) == T and list(h["stage"]) == [0, 0, 1, 1]
    assert np.allclose(h["total_normal_force"], PRESS, rtol=1e-14)
    assert np.allclose(h["total_tangential_force"], 0.1 * np.array(PRESS), rtol=1e-14)
    assert list(h["n_closed"][:, 0]) == [5, 5, 3, 0]
    # t = 1.5: the pairs at x = 0 and 4 separated at t = 1.2, those at 1 and 3 separate at 2;
    # each edge moves linearly between: 4 - (1.5 - 1.2)/(2 - 1.2) = 3.625, and 0.375
    assert h["extent"][2, 0] == pytest.approx([0.375, 3.625], abs=1e-15)
    assert np.isnan(h["extent"][3, 0]).all()
    # as the summary's stage record at t = 1 computes it
    s = summarize(scene, staged_result(scene), 0.0)
    assert h["extent"][1, 0].tolist() == s["stages"][0]["contacts"]["flat"]["closed_extent"]


def test_force_displacement_of_a_prescribed_displacement_and_a_motion(scene):
    result = staged_result(scene)
    curves = contact_measures.force_displacement(scene, result)
    press = curves["press"]
    assert list(press["t"]) == [0.0] + T
    assert np.allclose(press["displacement"], [0.0, 0.005, 0.01, 0.005, 0.0], atol=1e-15)
    assert np.allclose(press["force"], [0.0] + PRESS, rtol=1e-14)  # pushing down: positive
    moving = copy.copy(scene)
    moving.prescribed = {}
    moving.motions = {"press": {"contact": 0, "motion": [0.0, 0.02]}}
    (indent,) = contact_measures.force_displacement(moving, result).values()
    assert indent["what"] == "normal force"
    assert np.allclose(indent["displacement"], [0.0, 0.01, 0.02, 0.01, 0.0], atol=1e-15)
    assert np.allclose(indent["force"], [0.0] + PRESS, rtol=1e-14)


# --------------------------------------------------------------------------- files
def test_write_results_of_a_load_path(scene, tmp_path):
    result = staged_result(scene)
    written = write_results(
        tmp_path, scene, result, summarize(scene, result, 0.0), figures=True, xdmf=False
    )
    assert sorted(p.name for p in written) == [
        "case.toml",
        "contact_extent.png",
        "contact_interface.png",
        "contact_profile.csv",
        "events.csv",
        "force_displacement.png",
        "history.csv",
        "load_depth.png",
        "summary.json",
    ]


def test_write_results_without_stages_keeps_the_figures(bare, tmp_path):
    result = old_result(bare)
    written = write_results(
        tmp_path, bare, result, summarize(bare, result, 0.0), figures=True, xdmf=False
    )
    assert sorted(p.name for p in written) == [
        "case.toml",
        "contact_growth.png",
        "contact_interface.png",
        "contact_profile.csv",
        "events.csv",
        "history.csv",
        "summary.json",
    ]
