"""The Python API (issue 17): slipstep.run -> Result, cases and meshes from Python, progress and
interruption from Python, notebook-safe figures.

The Result's arrays are checked against what is independent of them: the files the run wrote
(results.xdmf read back with h5py, events.csv and contact_profile.csv with csv), equilibrium
recomputed from the arrays (tests/physics.py), and closed forms (the contact force of a
quarter Hertz model is P/2 times the load factor; a block pressed on a frictionless flat by a
uniform pressure q carries sigma_y = -q everywhere).
"""

from __future__ import annotations

import csv
import json
import os
import subprocess
import sys
import textwrap
import tomllib

import numpy as np
import pytest

from conftest import CASES, ROOT, needs_gmsh
from physics import EQUILIBRIUM_TOL, equilibrium_residual

import slipstep
from slipstep import Case, InputError, Result, from_arrays, from_meshio, load_case

# The quarter Hertz model carries P/2 = 500 N/mm; the engine balances it to equilibrium_tol
# (1e-9 relative, docs/engine_api.md), so sums of contact forces match to that.
HALF_P = 500.0
COARSE = ["mesh.h_contact=0.2"]


@pytest.fixture(scope="module")
def staged(tmp_path_factory):
    """An elastoplastic load-unload run (two stages, plastic fields, reactions) with its files."""
    out = tmp_path_factory.mktemp("api") / "lu"
    r = slipstep.run(
        "hertz_load_unload",
        out=out,
        progress=False,
        overrides=COARSE + ["output.snapshots=[0.5, 1.0, 1.5, 2.0]"],
    )
    return r, out


# --------------------------------------------------------------------------- the result object
def test_run_returns_a_result_that_knows_its_run(staged):
    r, out = staged
    assert isinstance(r, Result) and r.completed and r.out == out
    assert r.case.name == "hertz_load_unload" and r.summary["n_stages"] == 2
    assert list(r.times) == [0.5, 1.0, 1.5, 2.0]  # as asked (exact: the engine's own times)
    assert r.nodes.shape[1] == 2 and r.triangles.shape[1] == 3
    text = repr(r)
    assert text.startswith("<slipstep.Result hertz_load_unload:") and str(out) in text
    html = r._repr_html_()
    assert "<table>" in html and f"{r.summary['n_events']}:" in html and "yield" in html


def test_fields_equal_the_xdmf_contents(staged):
    """Every time step of results.xdmf, read with h5py (meshio's layout: one HDF5 dataset per
    array and step, named in the XDMF), against fields(t) and to_meshio(t): the same float64
    numbers, so equal exactly."""
    h5py = pytest.importorskip("h5py")
    import xml.etree.ElementTree as ET

    r, out = staged
    grids = ET.parse(out / "results.xdmf").getroot().iter("Grid")
    steps = [g for g in grids if g.find("Time") is not None]
    assert len(steps) == len(r.times)
    with h5py.File(out / "results.h5") as h5:

        def read(item):
            return h5[item.text.split(":")[1]][()]

        for k, grid in enumerate(steps):
            t = float(grid.find("Time").get("Value"))
            assert t == r.times[k]
            stage = int(r.raw["snapshots"][k]["stage"]) + 1
            f, m = r.fields(t, stage=stage), r.to_meshio(t, stage=stage)
            arrays = {a.get("Name"): read(a.find("DataItem")) for a in grid.iter("Attribute")}
            assert np.array_equal(arrays["u"][:, :2], f["u"]) and not arrays["u"][:, 2].any()
            assert np.array_equal(arrays["reaction"][:, :2], f["reaction"])
            for j, name in enumerate(("sigma_x", "sigma_y", "sigma_z", "tau_xy")):
                assert np.array_equal(arrays[name].ravel(), f["stress"][:, j])
            for name in ("von_mises", "plastic_strain", "yield_drift"):
                assert np.array_equal(arrays[name].ravel(), f[name])
            assert np.array_equal(arrays["plastic"].ravel(), f["plastic"].astype(float))
            assert set(m.point_data) | set(m.cell_data) == set(arrays)
            for name, values in m.point_data.items():
                assert np.array_equal(values, arrays[name])
            for name, blocks in m.cell_data.items():
                assert np.array_equal(blocks[0], arrays[name].reshape(blocks[0].shape))


def test_fields_are_in_equilibrium_and_carry_the_load(staged):
    """Independent of the files: equilibrium recomputed from the fields' stresses and contact
    forces (tests/physics.py) at every snapshot, and the contact force equal to the load on the
    quarter model, P/2 x the load factor (1 at t = 1, 1/2 at t = 0.5 and 1.5, 0 at t = 2)."""
    r, _ = staged
    for t, factor in ((0.5, 0.5), (1.0, 1.0), (1.5, 0.5), (2.0, 0.0)):
        f = r.fields(t)
        assert equilibrium_residual(r.scene.model, f) <= EQUILIBRIUM_TOL, t
        assert f["lambda_n"].sum() == pytest.approx(factor * HALF_P, abs=EQUILIBRIUM_TOL * HALF_P)


def test_a_stage_end_holds_both_states(staged):
    """With a snapshot at every event, t = 1 holds the end of stage 1 (load reached, elements
    plastic) and the start of stage 2 (the zero-length switch that unloads them); stage=
    chooses, the default is the latest."""
    r = slipstep.run("hertz_load_unload", overrides=COARSE, progress=False)
    assert list(r.times).count(1.0) == 2
    end, start = r.fields(1.0, stage=1), r.fields(1.0)
    assert end["stage"] == 1 and end["plastic"].any()
    assert start["stage"] == 2 and not start["plastic"].any()
    for state in (end, start):  # both at the full load: P/2 on the flat, in equilibrium
        assert state["lambda_n"].sum() == pytest.approx(HALF_P, abs=EQUILIBRIUM_TOL * HALF_P)
        assert equilibrium_residual(r.scene.model, state) <= EQUILIBRIUM_TOL
    with pytest.raises(InputError, match="no snapshot at t = 0.7; snapshots are at t = 0.5"):
        staged[0].fields(0.7)


def test_events_and_profile_equal_the_csv_files(staged):
    r, out = staged
    with open(out / "events.csv") as fh:
        rows = list(csv.DictReader(fh))
    ev = r.events
    assert len(rows) == len(ev) > 0
    for row, e in zip(rows, ev):
        assert (
            int(row["step"]),
            row["kind"],
            int(row["entity"]),
            row["entity_kind"],
            int(row["stage"]),
        ) == (e["step"], e["kind"], e["entity"], e["entity_kind"], e["stage"])
        assert [float(row[k]) for k in ("t", "load_fraction", "x", "y")] == [
            e["t"],
            e["load_fraction"],
            e["x"],
            e["y"],
        ]
    with open(out / "contact_profile.csv") as fh:
        prof_rows = list(csv.DictReader(fh))
    prof = r.profile()
    assert [float(x["pressure"]) for x in prof_rows] == list(prof["pressure"])
    assert [float(x["rtd"]) for x in prof_rows] == list(prof["rtd"])
    # fields() holds the same per pair, in the engine's pair order
    f = r.fields()
    assert np.array_equal(f["pressure"][prof["pair"]], prof["pressure"])


def test_run_case_is_the_two_dict_form(tmp_path):
    raw, summary = slipstep.run_case(None, overrides=COARSE + ["output.snapshots=[1.0]"])
    assert set(raw) >= {"events", "steps", "snapshots", "stop"}
    assert summary["case"] == "hertz_cylinder" and raw["stop"]["kind"] == "completed"


# --------------------------------------------------------------------------- cases from Python
def test_case_from_toml_and_from_dict_equal_the_file():
    for path in sorted(CASES.glob("*.toml")):
        text = path.read_text()
        from_file = load_case(path)
        assert Case.from_toml(text, base_dir=path.parent).data == from_file.data, path
        assert (
            Case.from_dict(tomllib.loads(text), base_dir=path.parent).data == from_file.data
        ), path


def test_case_from_dict_takes_numpy_and_tuples_and_overrides():
    data = tomllib.loads((CASES / "hertz_cylinder.toml").read_text())
    data["contact"][0]["normal"] = np.array([0.0, 1.0])
    data["body"][0]["material"]["E"] = np.float64(70000.0)
    data["contact"][0]["point"] = (0.0, 0.0)
    case = Case.from_dict(data, overrides=["contact.mu=0.25"])
    assert case.data["contact"][0]["mu"] == 0.25 and case.data["contact"][0]["normal"] == [0, 1]
    assert case.units == {"length": "mm", "force": "N", "stress": "MPa"}
    with pytest.raises(InputError, match=r"<dict>: material.nu = 0.5 is not allowed"):
        Case.from_dict(data, overrides=["material.nu=0.5"])


def _block_case(q: float) -> dict:
    """A block on a frictionless rigid flat y = 0, uniform pressure q on its top, x held at
    one corner node set: the exact solution is uniform, sigma_y = -q, sigma_x = sigma_xy = 0
    (plane stress, so sigma_z = 0 too), which CST elements represent exactly."""
    return {
        "case": {"name": "block_from_arrays", "units": "mm, N, MPa"},
        "analysis": {"plane": "stress"},
        "output": {"snapshots": [1.0], "figures": False, "xdmf": False},
        "body": [{"name": "block", "material": {"E": 1000.0, "nu": 0.3}}],
        "bc": [
            {"body": "block", "edge": "top", "pressure": q},
            {"body": "block", "nodes": "corner", "fix": ["x"]},
        ],
        "contact": [{"kind": "rigid_line", "body": "block", "edge": "bottom"}],
    }


def _grid(nx: int = 6, ny: int = 3, w: float = 3.0, h: float = 1.5):
    """Nodes, counter-clockwise triangles and tagged edges of a w x h grid (no generator)."""
    x, y = np.meshgrid(np.linspace(0, w, nx + 1), np.linspace(0, h, ny + 1))
    nodes = np.column_stack([x.ravel(), y.ravel()])
    ids = np.arange(len(nodes)).reshape(ny + 1, nx + 1)
    a, b, c, d = (
        ids[:-1, :-1].ravel(),
        ids[:-1, 1:].ravel(),
        ids[1:, 1:].ravel(),
        ids[1:, :-1].ravel(),
    )
    triangles = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    bottom = np.column_stack([ids[0, :-1], ids[0, 1:]])
    top = np.column_stack([ids[-1, 1:], ids[-1, :-1]])
    return nodes, triangles, {"bottom": bottom, "top": top}


@pytest.mark.parametrize("route", ["arrays", "meshio"])
def test_a_scene_from_arrays_or_meshio_without_files(route):
    meshio = pytest.importorskip("meshio")
    nodes, triangles, edges = _grid()
    if route == "arrays":
        mesh = from_arrays(nodes, triangles[:, ::-1], edges, node_sets={"corner": [0]})
    else:  # the same as gmsh would hand it over: line cells tagged by physical group ids
        lines = np.concatenate([edges["bottom"], edges["top"]])
        tags = np.repeat([1, 2], [len(edges["bottom"]), len(edges["top"])])
        m = meshio.Mesh(
            np.column_stack([nodes, np.zeros(len(nodes))]),
            [("triangle", triangles), ("line", lines)],
            cell_data={"gmsh:physical": [np.zeros(len(triangles), int), tags]},
            field_data={"bottom": np.array([1, 1]), "top": np.array([2, 1])},
        )
        mesh = from_meshio(m)
        mesh.node_sets["corner"] = np.array([0])
    q = 2.0
    r = slipstep.run(_block_case(q), meshes={"block": mesh}, progress=False)
    stress = r.fields()["stress"]
    # exact for CST: round-off of the solve relative to q (1e-9, the equilibrium tolerance)
    assert np.allclose(stress[:, 1], -q, rtol=0, atol=1e-9 * q)
    assert np.allclose(stress[:, [0, 2, 3]], 0.0, rtol=0, atol=1e-9 * q)
    assert r.fields()["lambda_n"].sum() == pytest.approx(q * 3.0, rel=1e-9)  # q x width x t


def test_a_given_mesh_that_is_not_given_is_one_clear_error():
    case = _block_case(1.0)
    case["body"][0]["mesh"] = {"generator": "given"}
    with pytest.raises(
        InputError,
        match=r'mesh.generator = "given": pass its mesh from Python, '
        r'slipstep.run\(case, meshes=\{"block": mesh\}\)',
    ):
        slipstep.run(case, progress=False)


def test_a_shipped_case_by_name():
    r = slipstep.run("two_blocks", progress=False, overrides=["output.snapshots=[1.0]"])
    assert r.case.name == "two_blocks" and r.completed


# --------------------------------------------------------------------------- progress, interrupt
# The elastoplastic Hertz cylinder event by event (group_tol = 0): 100+ increments to report on.
# The tests ask for a report after every increment (REPORT_INTERVAL_S = 0), so which increment a
# report or an interrupt lands on does not depend on the machine's speed.
ELASTOPLASTIC = [
    "mesh.h_contact=0.1",
    "output.snapshots=events",
    "material.Sy=200",
    "material.H=700",
    "solver.group_tol=0",
]


@pytest.fixture
def every_increment(monkeypatch):
    monkeypatch.setattr(slipstep.progress, "REPORT_INTERVAL_S", 0.0)


def _interrupted_is_consistent(r: Result) -> None:
    """A partial result: stopped before the end, its last snapshot in equilibrium at its own t
    with the load of that t (P/2 x t for the single-stage Hertz scene)."""
    assert r.stop["kind"] == "interrupted" and not r.completed
    assert 0.0 < r.stop["t"] < 1.0
    last = r.fields()
    assert last["t"] == pytest.approx(r.stop["t"], rel=1e-12)
    assert equilibrium_residual(r.scene.model, last) <= EQUILIBRIUM_TOL
    assert last["lambda_n"].sum() == pytest.approx(last["t"] * HALF_P, abs=EQUILIBRIUM_TOL * HALF_P)


def test_a_progress_callable_sees_the_run_and_can_stop_it(every_increment):
    seen = []

    def progress(p: slipstep.Progress):
        seen.append(p)
        return len(seen) < 5  # stop at the fifth report

    r = slipstep.run(None, overrides=ELASTOPLASTIC, progress=progress)
    _interrupted_is_consistent(r)
    # one report per increment: the fifth stopped the run where it was, after five increments
    assert len(seen) == 5 and seen[-1].t == pytest.approx(r.stop["t"], rel=1e-12)
    assert [p.steps for p in seen] == [1, 2, 3, 4, 5] and len(r.raw["steps"]["load_fraction"]) == 5
    assert all(a.t <= b.t and a.events <= b.events for a, b in zip(seen, seen[1:]))
    assert seen[-1].events == len(r.events) and seen[-1].n_stages == 1


def test_a_keyboard_interrupt_from_the_callback_keeps_the_partial_result(every_increment):
    def progress(p):
        raise KeyboardInterrupt

    _interrupted_is_consistent(slipstep.run(None, progress=progress, overrides=ELASTOPLASTIC))


def test_another_exception_from_the_callback_propagates(every_increment):
    def progress(p):
        raise ZeroDivisionError("a bug in my callback")

    with pytest.raises(ZeroDivisionError, match="a bug in my callback"):
        slipstep.run(None, progress=progress, overrides=ELASTOPLASTIC)


def _run_in_a_fresh_interpreter(tmp_path, trigger: str) -> dict:
    """slipstep.run with the bar on in a fresh interpreter, whose engine raises a real SIGINT
    (what Jupyter's interrupt sends) at a known point of the run: SLIPSTEP_TEST_INTERRUPT."""
    code = textwrap.dedent("""
        import json, slipstep
        r = slipstep.run(None, overrides=["mesh.h_contact=0.05", "material.Sy=200",
                                          "material.H=700", "output.snapshots=[1.0]"])
        steps = r.events["step"]
        print(json.dumps({"stop": r.stop, "events": len(r.events), "t": r.fields()["t"],
                          "events_before_last_increment": int((steps < steps.max()).sum())}))
    """)
    env = dict(
        os.environ, MPLBACKEND="Agg", PYTHONPATH=str(ROOT / "py"), SLIPSTEP_TEST_INTERRUPT=trigger
    )
    proc = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        env=env,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_a_sigint_stops_the_engine_like_a_notebook_interrupt(tmp_path):
    """SIGINT while the engine runs (raised by the engine at its 30th event): run() returns the
    partial result instead of raising, stopped right after the increment that recorded that
    event (a grouped increment records several)."""
    got = _run_in_a_fresh_interpreter(tmp_path, "event=30")
    assert got["stop"]["kind"] == "interrupted" and 0 < got["stop"]["t"] < 1, got
    assert got["events_before_last_increment"] < 30 <= got["events"], got
    assert got["t"] == pytest.approx(got["stop"]["t"], rel=1e-12)  # the last snapshot is there


def test_a_sigint_as_the_engine_completes_returns_the_complete_result(tmp_path):
    """SIGINT after the engine's last increment (nothing left to stop): run() returns the
    complete result and says the interrupt came late, and no KeyboardInterrupt follows."""
    got = _run_in_a_fresh_interpreter(tmp_path, "end")
    assert got["stop"]["kind"] == "completed" and got["stop"]["late_interrupt"] is True, got
    assert got["t"] == 1.0


def test_a_sigint_while_the_results_are_written_keeps_them(tmp_path, monkeypatch):
    """A Ctrl-C once the engine has returned (raised here as the files start to be written)
    waits for the files: they are complete, and the stop says the interrupt came late."""
    import signal

    write = slipstep.runner.write_results

    def interrupted_write(*args, **kwargs):
        signal.raise_signal(signal.SIGINT)
        return write(*args, **kwargs)

    monkeypatch.setattr(slipstep.runner, "write_results", interrupted_write)
    r = slipstep.run(None, out=tmp_path / "o", progress=False, overrides=COARSE)
    assert r.completed and r.stop["late_interrupt"] is True
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert summary["final_load_fraction"] == 1.0 and (tmp_path / "o" / "results.xdmf").exists()


def test_progress_rejects_what_it_cannot_call():
    with pytest.raises(TypeError, match="progress = 3"):
        slipstep.run(None, overrides=COARSE, progress=3)


# --------------------------------------------------------------------------- figures
def test_figures_draw_on_the_callers_axes(staged):
    """Result.figure(name, ax=...) draws into the caller's own figure: the von Mises panel's
    colours are the last snapshot's von Mises stresses (element values, read from the arrays),
    the interface's pressure panel reaches the largest contact pressure; a wrong number of
    panels is one clear ValueError."""
    from matplotlib.figure import Figure

    r, _ = staged
    fig = Figure()
    ax = fig.subplots()
    assert r.figure("von_mises", ax=ax) is fig and len(fig.axes) == 2  # the panel + its bar
    drawn = ax.collections[0].get_array()
    vm = r.fields()["von_mises"]
    assert drawn.max() <= vm.max() and drawn.max() == pytest.approx(vm.max(), rel=1e-12)
    fig = Figure()
    panels = fig.subplots(3)
    assert r.figure("contact_interface", ax=panels) is fig and len(fig.axes) == 3
    peak = max(line.get_ydata().max() for line in panels[0].lines if len(line.get_ydata()))
    assert peak == pytest.approx(r.fields()["pressure"].max(), rel=1e-12)
    with pytest.raises(ValueError, match="draws 2 panel"):
        r.figure("contact_extent", ax=Figure().subplots())


def test_figures_leave_pyplot_and_the_backend_alone(tmp_path):
    """A notebook has its backend and its pyplot figures: a run that writes figures, and
    Result.figures(), neither import pyplot nor switch the backend."""
    code = textwrap.dedent("""
        import sys, matplotlib
        matplotlib.use("svg")
        import slipstep
        r = slipstep.run(None, out="o", progress=False,
                         overrides=["mesh.h_contact=0.2", "material.Sy=200",
                                    "material.H=700", "output.snapshots=[1.0]"])
        figs = r.figures()
        print(matplotlib.get_backend(), "matplotlib.pyplot" in sys.modules, sorted(figs))
        print(figs["von_mises"].axes[1].get_ylabel(), "|", figs["contact_interface"].axes[0].get_ylabel())
    """)
    env = {k: v for k, v in os.environ.items() if k != "MPLBACKEND"}
    env["PYTHONPATH"] = str(ROOT / "py")
    proc = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=tmp_path,
        env=env,
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    first, second = proc.stdout.strip().splitlines()[-2:]
    assert first == "svg False ['contact_growth', 'contact_interface', 'von_mises']"
    # the colour bar and the pressure axis carry the case's stress unit
    assert second == "von Mises stress [MPa] | contact pressure [MPa]"
    assert {p.name for p in (tmp_path / "o").glob("*.png")} == {
        "contact_growth.png",
        "contact_interface.png",
        "von_mises.png",
    }


@needs_gmsh
def test_quarter_annulus_coarser_at_the_bore_meshes():
    """h > h_outer (grading outwards to finer elements) used to abort the process inside
    gmsh ("+ -0.02" in the size formula): the mesh now follows h(r) from h at the bore to
    h_outer at r = b.  Mean edge length of the elements touching each circle within 30 % of
    its target (unstructured triangles scatter about the size field)."""
    from slipstep.mesh.triangle_generators import quarter_annulus

    m = quarter_annulus(10.0, 20.0, 1.0, 0.4)
    for tag, target in (("inner", 1.0), ("outer", 0.4)):
        segs = m.edges[tag]
        length = np.linalg.norm(m.nodes[segs[:, 0]] - m.nodes[segs[:, 1]], axis=1).mean()
        assert length == pytest.approx(target, rel=0.3), tag
