"""The history of increments (issue 38): what the engine records at every increment (each
contact's resultant force and moment, each support's reaction, each force pattern's work),
history.csv, the summary's driving force and the resultant ``force`` beside the old
``total_normal_force``, checked against the result's own arrays recomputed here (tests/physics.py
helpers, not the package's):

- at every snapshot (every event a snapshot, so each increment has one at its t): a contact's
  force Σ_p (λ_n n + λ_t t) and moment Σ_p x_p × f_p (x_p node a, or a weighted row's
  contactor point), to 1e-12 of the forces' size (round-off of summing the same terms); a
  support group's reaction against the sum of the snapshot's ``reaction`` over the group's
  DOFs (the full space: the same internal force, 1e-12; the reduced elastic space: a
  functional of the contact forces against the snapshot's reconstructed fields, measured at
  most 5e-12 of the reactions on the 3D Mindlin sphere, where a prescribed displacement's
  terms cancel to the reaction: 1e-10); a pattern's work P·u, 1e-10 of |P||u|;
- every body in balance at every increment whose reactions are known (all but the contact
  sub-steps of grouped plastic increments): Σ (applied + contact + reaction) = 0 per
  component, EQUILIBRIUM_TOL (the engine's contract) of the forces' scale over the run;
- the Vickers quarter of the issue: its resultant along z (the whole indenter's, mirrored
  across x = 0 and y = 0) is what pushes the indenter, below Σ λ_n (each pair's along its own
  normal, 22 degrees off z on the faces).
"""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest
from conftest import CASES, needs_gmsh, write_case
from physics import EQUILIBRIUM_TOL, applied_load, node_body, tangent_basis

from slipstep import prepare, solve
from slipstep.output.results import write_results
from slipstep.measures.resultants import step_history
from slipstep.output.summary import one_line, summarize
from slipstep.loads.supports import support_groups

ROUND_OFF = 1e-12

# 2D: a rigid line on a plastic block (full space, grouped increments: times output keeps its
# contact sub-steps), a rigid line on an elastic cylinder loaded and unloaded (reduced space),
# two elastic bodies pressed then sheared (node to segment, a prescribed displacement and a
# traction); 3D: the Vickers quarter (plastic, full space), the Mindlin sphere coarsened
# (reduced space, two bodies, friction in space).
CASES_2D = {
    "paper_block_plastic": [],
    "hertz_load_unload": ["mesh.h_contact=0.05"],
    "cattaneo_mindlin": ["body.roller.mesh.h_contact=0.2", "body.block.mesh.h_contact=0.2"],
}
CASES_3D = {
    "vickers_indentation_3d": [],
    "mindlin_sphere_3d": ["body.sphere.mesh.h_contact=0.09", "body.block.mesh.h_contact=0.12"],
}


@pytest.fixture(scope="module", params=[*CASES_2D, *CASES_3D])
def run_events(request):
    """(scene, result) of a case with every event a snapshot."""
    pytest.importorskip("gmsh")
    name = request.param
    extra = CASES_2D.get(name, CASES_3D.get(name))
    scene = prepare(
        CASES / f"{name}.toml", ["output.figures=false", "output.snapshots=events", *extra]
    )
    result = solve(scene)
    assert result["stop"]["kind"] == "completed", result["stop"]
    return scene, result


def pair_forces(model: dict, snap: dict) -> np.ndarray:
    """(P, 3) each pair's force on its contactor side, from the model's frames."""
    n = np.asarray(model["pairs"]["normal"], dtype=float)
    lam_n = np.asarray(snap["lambda_n"], dtype=float)
    if model.get("dimension", 2) == 3:
        t1, t2 = tangent_basis(n, model["pairs"].get("tangent"))
        lt = np.asarray(snap["lambda_t"], dtype=float).reshape(-1, 2)
        return lam_n[:, None] * n + lt[:, :1] * t1 + lt[:, 1:] * t2
    t = np.stack([-n[:, 1], n[:, 0]], axis=1)
    f = lam_n[:, None] * n + np.asarray(snap["lambda_t"], dtype=float)[:, None] * t
    return np.column_stack([f, np.zeros(len(f))])


def contactor_points(model: dict) -> np.ndarray:
    """(P, 3) node a, or a weighted row's Σ c_i x_i over its positive weights."""
    pairs, x = model["pairs"], np.asarray(model["nodes"], dtype=float)
    x = np.column_stack([x, np.zeros(len(x))]) if x.shape[1] == 2 else x
    out = x[np.asarray(pairs["node_a"])].copy()
    ptr = np.asarray(pairs.get("weight_ptr", np.zeros(len(out) + 1, np.int64)))
    for k in np.flatnonzero(np.diff(ptr) > 0):
        nodes = np.asarray(pairs["weight_node"])[ptr[k] : ptr[k + 1]]
        c = np.asarray(pairs["weight_value"])[ptr[k] : ptr[k + 1]]
        out[k] = (c[c > 0, None] * x[nodes[c > 0]]).sum(axis=0) / c[c > 0].sum()
    return out


@needs_gmsh
def test_the_history_is_the_snapshots_arrays_summed(run_events):
    scene, result = run_events
    model, steps, snaps = scene.model, result["steps"], result["snapshots"]
    dim = model.get("dimension", 2)
    h = step_history(scene, result)
    assert len(h["t"]) == len(steps["t"]) + 1 and h["t"][0] == 0.0
    assert np.all(h["contact_force"][0] == 0) and np.all(h["reaction"][0] == 0)
    contact = np.asarray(model["pairs"]["contact"])
    points = contactor_points(model)
    groups = support_groups(scene)
    forces = [np.asarray(model["load"], float)] + [
        np.asarray(p.get("force", 0.0), float) for p in model.get("patterns", [])
    ]
    checked = 0
    for snap in snaps[1:]:
        rows = np.flatnonzero(np.abs(h["t"] - snap["t"]) <= 1e-14 * max(1.0, snap["t"]))
        assert len(rows), f"no increment ends at the snapshot's t = {snap['t']}"
        k = rows[-1]
        f = pair_forces(model, snap)
        size = np.abs(f).sum() + 1e-300
        for c in range(len(model["contact_names"])):
            mine = contact == c
            assert np.abs(h["contact_force"][k, c] - f[mine].sum(axis=0)).max() <= ROUND_OFF * size
            moment = np.cross(points[mine], f[mine]).sum(axis=0)
            arm = np.abs(points).max()
            assert (
                np.abs(
                    h["contact_moment"][k, c] - (moment if dim == 3 else [0, 0, moment[2]])
                ).max()
                <= ROUND_OFF * size * arm
            )
        reaction = np.asarray(snap["reaction"], dtype=float).reshape(-1)
        scale = np.abs(reaction).sum() + 1e-300
        for g, dofs in enumerate(groups.values()):
            for comp in range(dim):
                expected = reaction[dofs[dofs % dim == comp]].sum()
                assert abs(h["reaction"][k, g, comp] - expected) <= 1e-10 * scale, (g, comp)
        u = np.asarray(snap["u"], dtype=float).reshape(-1)
        for j, p in enumerate(forces):
            if np.ndim(p) and np.any(p):
                work = p @ u
                assert abs(h["load_work"][k, j] - work) <= 1e-10 * (np.abs(p) @ np.abs(u) + 1e-300)
        checked += 1
    assert checked == len(snaps) - 1


def balance(scene, h: dict) -> tuple[np.ndarray, np.ndarray]:
    """(R, B, 3) Σ (applied + contacts + reactions) per body at every row, and (B, 3) the
    largest Σ |terms| over the run (the scale)."""
    model = scene.model
    dim = model.get("dimension", 2)
    body = node_body(model)
    n_b = int(np.max(model["element_body"])) + 1
    pairs = model["pairs"]
    a, b = np.asarray(pairs["node_a"]), np.asarray(pairs["node_b"])
    ptr = np.asarray(pairs.get("weight_ptr", np.zeros(len(a) + 1, np.int64)))
    contact = np.asarray(pairs["contact"])
    side = np.zeros((len(model["contact_names"]), n_b))  # +1 contactor body, -1 target body
    for c in range(len(side)):
        mine = np.flatnonzero(contact == c)
        for k in mine:
            side[c, body[a[k]]] = 1.0
            if ptr[k + 1] > ptr[k]:
                nodes = np.asarray(pairs["weight_node"])[ptr[k] : ptr[k + 1]]
                c_i = np.asarray(pairs["weight_value"])[ptr[k] : ptr[k + 1]]
                for i in nodes[c_i < 0]:
                    side[c, body[i]] = -1.0
            elif b[k] >= 0:
                side[c, body[b[k]]] = -1.0
    groups = list(support_groups(scene).values())
    group_body = [body[g[0] // dim] if len(g) else 0 for g in groups]
    total = np.zeros((len(h["t"]), n_b, 3))
    scale = np.zeros((len(h["t"]), n_b, 3))
    for k, t in enumerate(h["t"]):
        load = applied_load(model, t).reshape(-1, dim)
        for B in range(n_b):
            applied = np.zeros(3)
            applied[:dim] = load[body == B].sum(axis=0)
            terms = [
                applied,
                *(side[c, B] * h["contact_force"][k, c] for c in range(len(side))),
                *(h["reaction"][k, g] for g in range(len(groups)) if group_body[g] == B),
            ]
            total[k, B] = np.sum(terms, axis=0)
            scale[k, B] = np.abs(terms).sum(axis=0) + np.abs(load[body == B]).sum(axis=0).max()
    return total, np.nanmax(scale, axis=0)


@needs_gmsh
def test_every_body_is_in_balance_at_every_increment(run_events):
    scene, result = run_events
    h = step_history(scene, result)
    total, scale = balance(scene, h)
    axes = [1] if scene.model.get("plane") == "axisymmetric" else list(range(scene.dimension))
    known = ~np.isnan(h["reaction"]).any(axis=(1, 2))
    assert known.all(), "every event a snapshot: no contact sub-steps, every reaction known"
    bad = np.abs(total[:, :, axes]) > EQUILIBRIUM_TOL * scale[None, :, axes]
    assert not bad.any(), (np.argwhere(bad)[:3], total[bad][:3], scale)


@needs_gmsh
def test_grouped_plastic_increments_balance_where_their_reactions_are_known(tmp_path):
    """sphere_on_flat_plastic at its default output (requested times): its grouped increments
    take contact sub-steps, whose stresses are integrated only at the increment's end: their
    reactions are NaN; every other increment balances."""
    scene = prepare(
        CASES / "sphere_on_flat_plastic.toml", ["output.figures=false", "mesh.h_contact=0.02"]
    )
    result = solve(scene)
    h = step_history(scene, result)
    known = ~np.isnan(h["reaction"]).any(axis=(1, 2))
    assert result["n_contact_substeps"] == (~known).sum() > 0
    total, scale = balance(scene, h)
    assert np.all(np.abs(total[known][:, :, 1]) <= EQUILIBRIUM_TOL * scale[None, :, 1])


@needs_gmsh
def test_the_vickers_force_is_the_resultant_along_z(tmp_path):
    """The issue's example: on the Vickers quarter the indenter's force (the whole's, the
    quarter's resultant along z times 4) is below Σ λ_n (each pair's force along its own
    normal, 22 degrees off z on the faces); the summary reports both, the driving force along
    the motion, the Oliver–Pharr numbers of the unloading, and writes history.csv."""
    scene = prepare(CASES / "vickers_indentation_3d.toml", ["output.xdmf=false"])
    result = solve(scene)
    s = summarize(scene, result, 0.0)
    loaded = s["stages"][0]
    pyramid = loaded["contacts"]["pyramid"]
    snap = [x for x in result["snapshots"] if abs(x["t"] - 1.0) <= 1e-12][-1]
    f = pair_forces(scene.model, snap)
    assert pyramid["force"][:2] == [0.0, 0.0]  # across the mirror planes x = 0, y = 0
    assert np.isclose(pyramid["force"][2], 4 * f[:, 2].sum(), rtol=1e-12)
    assert np.isclose(pyramid["total_normal_force"], 4 * np.sum(snap["lambda_n"]), rtol=1e-12)
    P = -pyramid["force"][2]
    assert 0.9 * pyramid["total_normal_force"] < P < 0.97 * pyramid["total_normal_force"]
    drive = s["driving_forces"]["pyramid"]
    assert drive["kind"] == "motion" and drive["direction"] == [0.0, 0.0, -1.0]
    assert np.isclose(drive["max_force"], P, rtol=1e-12) and drive["displacement_at_max"] == 0.03
    assert loaded["driving_forces"]["pyramid"] == pytest.approx(P, rel=1e-12)
    assert abs(drive["force"]) <= 1e-9 * P  # drawn back: the pyramid has left the block
    op = s["indentation"]["pyramid"]
    assert op["P_max"] == pytest.approx(P, rel=1e-12) and op["h_max"] == 0.03
    assert 0 < op["h_f"] < op["h_c"] < op["h_max"]  # a plastic dent: h_f > 0
    # Tabor's hardness ~3 Sy and more with hardening, far below the elastic 110 Sy
    assert 3 * 400 < op["H"] < 10 * 400
    assert f"max {P:.4g} N at 0.03 mm" in one_line(s)
    out = write_results(tmp_path / "out", scene, result, s)
    names = {p.name for p in out}
    assert {"history.csv", "load_depth.png"} <= names and "q_delta.png" not in names
    with open(tmp_path / "out" / "history.csv") as fh:
        rows = list(csv.reader(fh))
    header, data = rows[0], np.array(rows[1:], dtype=float)
    assert len(data) == len(result["steps"]["t"]) + 1
    col = {name: data[:, i] for i, name in enumerate(header)}
    h = step_history(scene, result)
    assert np.array_equal(col["contact.pyramid.F_z [N]"], h["contact_force"][:, 0, 2])
    assert np.array_equal(col["t"], h["t"]) and np.array_equal(col["stage"], h["stage"] + 1)
    assert np.allclose(
        col["driver.pyramid.force [N]"], -4 * h["contact_force"][:, 0, 2], rtol=1e-14, atol=0
    )
    assert np.allclose(
        col["contact.pyramid.u_z [mm]"], -col["driver.pyramid.displacement [mm]"], rtol=0, atol=0
    )
    assert "bc.symmetry_x.R_x [N]" in header and "bc.symmetry_x.R_z [N]" not in header
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["driving_force"]["name"] == "pyramid"


SHEARED = """
[case]
name = "sheared_block"
units = "mm, N, MPa"
[output]
snapshots = "events"
figures = true
xdmf = false
[[stage]]
name = "press"
factors = {{ press = 1.0 }}
[[stage]]
name = "shear"
factors = {{ press = 1.0, shear = 1.0 }}
[[body]]
name = "block"
[body.mesh]
generator = "block"
width = 2.0
height = 1.0
h = 0.25
[body.material]
E = 1000.0
nu = 0.3
[[bc]]
name = "press"
body = "block"
edge = "top"
traction = [0.0, -10.0]
[[bc]]
name = "shear"
body = "block"
edge = "top"
traction = [{q}, 0.0]
[[contact]]
name = "flat"
kind = "rigid_line"
body = "block"
edge = "bottom"
point = [0.0, 0.0]
normal = [0.0, 1.0]
mu = 0.5
"""


@needs_gmsh
def test_a_tangential_load_gets_its_q_delta_curve(tmp_path):
    """A block pressed onto a frictional flat then sheared: the shear is a driver along the
    contact (q_delta.png), the press one into it (a load, no load_depth); the summary's driving
    force is the shear's (it moves in the last stage), Q = q × 2 along x; its displacement is
    the traction-weighted mean u_x of the top, P·u / |P|, recomputed from the last snapshot."""
    q = 2.0
    scene = prepare(write_case(tmp_path, SHEARED.format(q=q)))
    result = solve(scene)
    s = summarize(scene, result, 0.0)
    assert s["driving_force"]["name"] == "shear" and s["driving_force"]["kind"] == "load"
    assert s["driving_force"]["force"] == pytest.approx(2 * q, rel=1e-12)
    assert s["driving_forces"]["press"]["force"] == pytest.approx(20.0, rel=1e-12)
    top = np.unique(scene.global_edge("block", "top"))
    u = np.asarray(result["snapshots"][-1]["u"]).reshape(-1, 2)
    f = np.asarray(
        scene.model["patterns"][[p["name"] for p in scene.model["patterns"]].index("shear")][
            "force"
        ]
    ).reshape(-1, 2)
    assert s["driving_force"]["displacement"] == pytest.approx(
        (f[top, 0] @ u[top, 0]) / f[:, 0].sum(), rel=1e-10
    )
    names = {p.name for p in write_results(tmp_path / "out", scene, result, s)}
    assert "q_delta.png" in names and "load_depth.png" not in names
    with open(tmp_path / "out" / "history.csv") as fh:
        header = next(csv.reader(fh))
    assert "load.shear.F_x [N]" in header and "contact.flat.M_z [N mm]" in header
    assert "driver.shear.displacement [mm]" in header
