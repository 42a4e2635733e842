"""``slipstep study stability``: where the usual methods fail, what slipstep does.

Each scenario runs one scene (or a small family) and reports: completed or failed (with the
error line), events, max equilibrium residual, max drift, an error against a reference where
one exists, wall time.  Writes ``report.md``, ``stability.csv`` and ``stability.png``.

Scenarios
- ``H0``: perfect plasticity H' = 0 (the paper's compliance form A.2 divides by H'; the
  engine's stiffness form does not): thick cylinder vs Hill, Hertz cylinder Sy = 200, H = 0.
- ``incompressible``: thick cylinder loaded to 1.1 x Hill's limit pressure 2k ln(b/a) with
  nu = 0.3 ... 0.499 on the gmsh CST mesh, a structured 2-triangle mesh and the crossed
  "union jack" mesh (4 CST per quad through its centre), the standard remedy for volumetric
  locking of CST meshes.
- ``friction``: Hertz, elastic, mu = 0.5, 1, 2.
- ``ties``: two_blocks (symmetric matching mesh); a flat block pulled onto a rigid flat with
  equal gaps (all pairs close at the same load fraction).
- ``receding``: zero initial gaps: two_blocks, paper_block_elastic.
- ``grading``: quarter cylinder with h_max / h_contact = 1e4.
- ``newton``: dolfinx fixed-step Newton (slipstep.fenicsx.bulk) on the thick cylinder at
  1, 2, 5, 10 load steps, below and near the limit pressure.
"""

from __future__ import annotations

import math
import tempfile
import time
import traceback
from pathlib import Path

import numpy as np

from . import runner, shipped
from .case import load_case
from .output.fields import centroids
from .measures.references import thick_cylinder_radius
from .mesh.triangles import checked_mesh
from .output.summary import contact_text, summarize
from .stability_report import figure, markdown_table, write_csv


def _case(name: str) -> str:
    """A shipped case (:mod:`slipstep.shipped`: works from an installed wheel)."""
    return str(shipped.path(name))


# --------------------------------------------------------------------------- meshes
def structured_annulus(a: float, b: float, nr: int, nt: int, crossed: bool = True):
    """Structured quarter annulus a <= r <= b, 0 <= theta <= pi/2: nr x nt quads, each cut
    into 4 CST through its centre (``crossed``, "union jack") or 2 (alternating diagonals)."""
    r = np.linspace(a, b, nr + 1)
    t = np.linspace(0.0, 0.5 * math.pi, nt + 1)
    R, T = np.meshgrid(r, t, indexing="ij")
    nodes = np.column_stack([(R * np.cos(T)).ravel(), (R * np.sin(T)).ravel()])
    grid = np.arange((nr + 1) * (nt + 1)).reshape(nr + 1, nt + 1)
    p00, p10 = grid[:-1, :-1].ravel(), grid[1:, :-1].ravel()
    p11, p01 = grid[1:, 1:].ravel(), grid[:-1, 1:].ravel()
    if crossed:
        rc = 0.5 * (r[:-1] + r[1:])
        tc = 0.5 * (t[:-1] + t[1:])
        RC, TC = np.meshgrid(rc, tc, indexing="ij")
        c = len(nodes) + np.arange(nr * nt)
        nodes = np.vstack(
            [nodes, np.column_stack([(RC * np.cos(TC)).ravel(), (RC * np.sin(TC)).ravel()])]
        )
        tris = np.vstack(
            [
                np.column_stack(x)
                for x in ((p00, p10, c), (p10, p11, c), (p11, p01, c), (p01, p00, c))
            ]
        )
    else:
        alt = ((np.arange(nr)[:, None] + np.arange(nt)[None, :]) % 2 == 0).ravel()
        t1 = np.where(
            alt[:, None], np.column_stack([p00, p10, p11]), np.column_stack([p00, p10, p01])
        )
        t2 = np.where(
            alt[:, None], np.column_stack([p00, p11, p01]), np.column_stack([p10, p11, p01])
        )
        tris = np.vstack([t1, t2])

    def seg(ids):
        return np.column_stack([ids[:-1], ids[1:]])

    edges = {
        "inner": seg(grid[0, :]),
        "outer": seg(grid[-1, :]),
        "x_axis": seg(grid[:, 0]),
        "y_axis": seg(grid[:, -1]),
    }
    node_sets = {k: np.unique(v) for k, v in edges.items()}
    return checked_mesh(
        nodes, tris, edges, node_sets, where="structured quarter annulus", flip_clockwise=True
    )


# --------------------------------------------------------------------------- running
def _run(path, overrides=(), mesh=None):
    """(scene, result, summary, error line, wall seconds); ``mesh`` replaces the mesh of the
    case's single body.  The error line is the exception's, or why the engine stopped early."""
    t0 = time.perf_counter()
    scene = result = summary = None
    error = ""
    try:
        case = load_case(path, list(overrides))
        meshes = None if mesh is None else {case.record.body[0].name: mesh}
        scene = runner.prepare(case, meshes=meshes)
        result = runner.solve(scene)
        summary = summarize(scene, result, time.perf_counter() - t0)
        error = result["stop_reason"] or ""  # the message of a limit-load/event-bound stop
    except Exception as exc:  # noqa: BLE001 - a failure is a result of the study
        error = f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}"
    return scene, result, summary, error, time.perf_counter() - t0


def _row(
    name,
    group,
    summary,
    error,
    wall,
    reference="",
    rel_error=float("nan"),
    note="",
    status=None,
    run=(None, None),
):
    """One row of the table; ``run``: the (scene, result) it came from, kept under ``_run`` for
    checks on the arrays (not written)."""
    s = summary or {}
    if status is None:
        status = "failed" if summary is None else STATUS_OF_STOP[s["stop"]["kind"]]
    return {
        "scenario": name,
        "group": group,
        "status": status,
        "error": error,
        "n_events": s.get("n_events", ""),
        "n_steps": s.get("n_steps", ""),
        "final_load_fraction": s.get("final_load_fraction", float("nan")),
        "max_residual": s.get("max_equilibrium_residual", float("nan")),
        "max_drift": s.get("max_drift", float("nan")),
        "reference": reference,
        "rel_error": rel_error,
        "note": note,
        "wall_s": wall,
        "_run": run,
    }


#: A row's status for each way the engine ends a run (``result["stop"]["kind"]``); a limit
#: load is the expected end of a run loaded beyond collapse.
STATUS_OF_STOP = {
    "completed": "completed",
    "first_yield": "completed",
    "limit_load": "limit load",
    "event_bound": "stopped",
    "support_lost": "support lost",
    "interrupted": "stopped",
}


def _centroid_radius(scene):
    return np.linalg.norm(centroids(scene.nodes, scene.triangles), axis=1)


def _outer_ur(scene, u, b):
    r = np.linalg.norm(scene.nodes, axis=1)
    outer = np.abs(r - b) <= 1e-9 * b
    return float(np.mean(np.sum(u[outer] * scene.nodes[outer], axis=1) / r[outer]))


def _hill(p, a, b, Sy):
    return thick_cylinder_radius(p, a, b, Sy / math.sqrt(3.0))


# --------------------------------------------------------------------------- scenarios
def thick_mesh(quick: bool) -> list[str]:
    return ["mesh.h=0.5", "mesh.h_outer=1.0"] if quick else ["mesh.h=0.25", "mesh.h_outer=0.8"]


def scenario_h0(quick: bool) -> list[dict]:
    rows = []
    a, b, Sy, p = 10.0, 20.0, 250.0, 175.0
    scene, res, s, err, wall = _run(_case("thick_cylinder"), thick_mesh(quick))
    c_ref, c = _hill(p, a, b, Sy), float("nan")
    if s:
        snap = res["snapshots"][-1]
        plastic = np.asarray(snap["plastic_strain"]) > 0
        c = float(_centroid_radius(scene)[plastic].max()) if plastic.any() else a
    rows.append(
        _row(
            "H'=0 thick cylinder p=175",
            "H0",
            s,
            err,
            wall,
            run=(scene, res),
            reference=f"Hill plastic radius c = {c_ref:.3f}",
            rel_error=c / c_ref - 1,
            note=f"plastic radius {c:.3f} (outermost plastic centroid)",
        )
    )
    ov = ["material.Sy=200", "material.H=0", "mesh.h_contact=0.15"]
    scene, res, s, err, wall = _run(None, ov)
    hz = (s or {}).get("hertz", {})
    rows.append(
        _row(
            "H'=0 Hertz Sy=200 h_c=0.15",
            "H0",
            s,
            err,
            wall,
            run=(scene, res),
            reference="Johnson first yield 0.60 p0/Sy",
            rel_error=hz.get("first_yield_rel_error", float("nan")) or float("nan"),
            note=f"{(s or {}).get('n_plastic_elements', 0)} plastic elements, "
            f"a/a_Hertz-1 = {hz.get('a_rel_error', float('nan')):+.3f}",
        )
    )
    return rows


def _cylinder_curve(scene, res, p, b):
    lf = np.array([sn["load_fraction"] for sn in res["snapshots"]])
    ur = np.array([_outer_ur(scene, np.asarray(sn["u"]), b) for sn in res["snapshots"]])
    return lf * p, ur


def scenario_incompressible(quick: bool) -> tuple[list[dict], dict]:
    a, b, Sy = 10.0, 20.0, 250.0
    k = Sy / math.sqrt(3.0)
    p_lim = 2 * k * math.log(b / a)
    p = 1.1 * p_lim
    fr = np.round(np.linspace(0.025, 1.0, 40), 6).tolist()
    base = [f"bc.bore.pressure={p!r}", f"output.snapshots={fr}", "output.figures=false"]
    nus = (0.3, 0.45, 0.49, 0.499)
    nr, nt = (10, 24) if quick else (20, 48)
    meshes = {
        "gmsh CST": None,
        "structured 2-tri": structured_annulus(a, b, nr, nt, crossed=False),
        "union jack": structured_annulus(a, b, nr, nt, crossed=True),
    }
    if quick:
        nus = (0.3, 0.499)
        meshes.pop("structured 2-tri")
    rows, curves = [], {}
    for mname, mesh in meshes.items():
        for nu in nus:
            ov = base + [f"material.nu={nu}"] + (thick_mesh(quick) if mesh is None else [])
            scene, res, s, err, wall = _run(_case("thick_cylinder"), ov, mesh=mesh)
            note, rel, p_full_v = "", float("nan"), float("nan")
            if s:
                pp, ur = _cylinder_curve(scene, res, p, b)
                curves[(mname, nu)] = (pp, ur)
                ne = len(scene.triangles)
                n_pl = np.asarray(res["steps"]["n_plastic"])
                lf = np.asarray(res["steps"]["load_fraction"])
                rc = _centroid_radius(scene)
                full = np.nonzero(n_pl >= ne)[0]
                p_full_v = float(lf[full[0]] * p) if len(full) else float("nan")
                p_full = f"{p_full_v:.1f}" if len(full) else "never"
                p_end = float(s["final_load_fraction"] * p)
                # collapse indicator: tangent stiffness dp/du_b over the last 10 % of the
                # load path against the elastic one (Hill: 0 at the limit pressure)
                k_el = pp[0] / ur[0]
                sel = pp >= pp[-1] - 0.1 * p
                k_end = np.polyfit(ur[sel], pp[sel], 1)[0] if sel.sum() >= 2 else float("nan")
                outer_ring = rc >= rc.max() - 1e-9 - (b - a) / max(nr, 1)
                plast = np.asarray(res["snapshots"][-1]["plastic_strain"]) > 0
                rel = p_full_v / p_lim - 1
                note = (
                    f"carried p = {p_end:.1f} (limit {p_lim:.1f}); all elements plastic "
                    f"at p = {p_full}; final stiffness / elastic = {k_end / k_el:.3f}; "
                    f"outer ring plastic {plast[outer_ring].mean():.0%}"
                )
                curves[(mname, nu)] += (k_end / k_el, p_end, p_full_v)
                E = 200000.0
                u_hill = (1 + nu) * k * (2 - 2 * nu) * b / E  # Hill's u(b) at p_lim (c = b)
                note += f"; u(b)/u_Hill(b, p_lim) = {ur[-1] / u_hill:.2f}"
            rows.append(
                _row(
                    f"nu={nu} {mname} p=1.1 p_lim",
                    "incompressible",
                    s,
                    err,
                    wall,
                    run=(scene, res),
                    reference="p(all elements plastic) / p_lim - 1",
                    rel_error=rel,
                    note=note,
                )
            )
            rows[-1]["p_full"] = p_full_v
            rows[-1]["nu"] = nu
            rows[-1]["mesh"] = mname
    return rows, {"curves": curves, "p_lim": p_lim}


def scenario_friction(quick: bool) -> list[dict]:
    rows = []
    for mu in (0.5, 1.0, 2.0):
        ov = [f"contact.mu={mu}", "mesh.h_contact=0.06", "output.figures=false"]
        scene, res, s, err, wall = _run(None, ov)
        note, rel = "", float("nan")
        if s:
            excess = 0.0
            for sn in res["snapshots"]:
                ln, lt = np.asarray(sn["lambda_n"]), np.asarray(sn["lambda_t"])
                scale = max(float(ln.max()), 1e-300)
                excess = max(excess, float(np.max(np.abs(lt) - mu * ln)) / scale)
            rel = (s.get("hertz") or {}).get("a_rel_error", float("nan"))
            note = (
                f"final: {s['n_stick']} stick / {s['n_slip']} slip pairs, "
                f"{contact_text(s)}; max(|lt| - mu ln)/max ln = {excess:.1e}"
            )
            s["coulomb_excess"] = excess
        rows.append(
            _row(
                f"Hertz elastic mu={mu}",
                "friction",
                s,
                err,
                wall,
                run=(scene, res),
                reference="Hertz a",
                rel_error=rel,
                note=note,
            )
        )
        rows[-1]["_summary"] = s
    return rows


EQUAL_GAP_BLOCK = """
[case]
name = "equal_gap_block"
description = "Block 10 x 4, top held, pulled down by a traction on its bottom onto a rigid flat"
[analysis]
plane = "strain"
[output]
snapshots = [1.0]
figures = false
[[body]]
name = "block"
[body.mesh]
generator = "block"
width = 10.0
height = 4.0
h = {h}
[body.material]
E = 200000.0
nu = 0.3
[[bc]]
body = "block"
edge = "top"
fix = ["y"]
[[bc]]
body = "block"
edge = "left"
symmetry = true
[[bc]]
body = "block"
edge = "right"
symmetry = true
[[bc]]
name = "pull"
body = "block"
edge = "bottom"
traction = [0.0, -100.0]
[[contact]]
kind = "rigid_line"
body = "block"
edge = "bottom"
point = [0.0, -{gap}]
normal = [0.0, 1.0]
mu = 0.3
"""


def scenario_ties(quick: bool) -> list[dict]:
    rows = []
    scene, res, s, err, wall = _run(
        _case("two_blocks"), ["output.snapshots=[1.0]", "output.figures=false"]
    )
    note = ""
    if s:
        steps = np.asarray(res["events"]["step"])
        per = np.bincount(steps) if len(steps) else np.zeros(1, int)
        note = (
            f"{len(per.nonzero()[0])} increments, up to {per.max()} simultaneous events; "
            f"final {s['n_stick']} stick / {s['n_slip']} slip / {s['n_open']} open"
        )
    rows.append(
        _row(
            "two_blocks (symmetric matching mesh)",
            "ties",
            s,
            err,
            wall,
            run=(scene, res),
            note=note,
        )
    )
    # uniaxial strain: u_y(bottom) = -q H / (lambda + 2G), the same at every bottom node
    E, nu, q, H = 200000.0, 0.3, 100.0, 4.0
    m = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    gap = 0.5 * q * H / m
    with tempfile.TemporaryDirectory() as td:
        path = Path(td) / "equal_gap_block.toml"
        path.write_text(EQUAL_GAP_BLOCK.format(h=1.0 if quick else 0.25, gap=repr(gap)))
        scene, res, s, err, wall = _run(path)
    note, rel = "", float("nan")
    if s:
        ev = res["events"]
        kinds = np.asarray(ev["kind"])
        close = kinds == "close"
        steps_close = np.unique(np.asarray(ev["step"])[close])
        lf_close = np.asarray(ev["load_fraction"])[close]
        n_pairs = s["n_pairs"]
        note = (
            f"{close.sum()} of {n_pairs} pairs close, in {len(steps_close)} increment(s), at "
            f"f = {lf_close.min() if close.any() else float('nan'):.6f} (exact 0.5)"
        )
        rel = float(lf_close.max() / 0.5 - 1) if close.any() else float("nan")
        s["closed_in_one_increment"] = bool(close.sum() == n_pairs and len(steps_close) == 1)
    rows.append(
        _row(
            "flat block on rigid flat, equal gaps",
            "ties",
            s,
            err,
            wall,
            run=(scene, res),
            reference="closure at f = 0.5",
            rel_error=rel,
            note=note,
        )
    )
    rows[-1]["_summary"] = s
    return rows


def scenario_receding(quick: bool) -> list[dict]:
    rows = []
    for name, ov in (
        ("two_blocks", []),
        (
            "paper_block_elastic",
            ["body.punch.mesh.h=1.0", "body.halfspace.mesh.h=1.0"] if quick else [],
        ),
    ):
        scene, res, s, err, wall = _run(
            _case(name), ov + ["output.snapshots=[1.0]", "output.figures=false"]
        )
        note = ""
        if s:
            note = (
                f"{contact_text(s)}; final {s['n_stick']} stick / {s['n_slip']} slip / "
                f"{s['n_open']} open of {s['n_pairs']}"
            )
        rows.append(
            _row(
                f"{name} (zero gaps, start in stick)",
                "receding",
                s,
                err,
                wall,
                run=(scene, res),
                note=note,
            )
        )
    return rows


def scenario_grading(quick: bool) -> list[dict]:
    ov = [
        "mesh.h_contact=0.001",
        "mesh.contact_zone=0.02",
        "mesh.h_max=10",
        "mesh.growth=0.3",
        "contact.x_max=3.0",
        "output.snapshots=[1.0]",
        "output.figures=false",
    ]
    scene, res, s, err, wall = _run(None, ov)
    note, rel = "", float("nan")
    if s:
        tri = scene.nodes[scene.triangles]
        edge = np.linalg.norm(tri - np.roll(tri, 1, axis=1), axis=2).max(axis=1)
        ratio = edge.max() / edge.min()
        rel = s["hertz"]["a_rel_error"]
        note = f"{s['n_elements']} elements, longest/shortest edge = {ratio:.2e}"
        s["size_ratio"] = float(ratio)
    rows = [
        _row(
            "Hertz, h_contact=0.001, h_max=10",
            "grading",
            s,
            err,
            wall,
            run=(scene, res),
            reference="Hertz a",
            rel_error=rel,
            note=note,
        )
    ]
    rows[-1]["_summary"] = s
    return rows


def scenario_newton(quick: bool) -> tuple[list[dict], str]:
    try:
        from .fenicsx import require_dolfinx

        require_dolfinx()
        from .fenicsx.bulk import BulkProblem
    except Exception as exc:  # noqa: BLE001
        return [], f"not run: dolfinx unavailable ({str(exc).splitlines()[0]})"
    if quick:
        return [], "not run in --quick (dolfinx Newton runs take minutes; run without --quick)"
    rows = []
    a, b, Sy = 10.0, 20.0, 250.0
    p_lim = 2 * Sy / math.sqrt(3.0) * math.log(b / a)
    for p in (175.0, round(0.99 * p_lim, 2), round(1.1 * p_lim, 2)):
        ov = [f"bc.bore.pressure={p!r}", "output.snapshots=[1.0]", "output.figures=false"]
        ov += thick_mesh(False)
        scene, res, s, err, wall = _run(_case("thick_cylinder"), ov)
        c_ref = _hill(p, a, b, Sy) if p < p_lim else b
        u_ss = np.asarray(res["snapshots"][-1]["u"]) if s else None
        if s:
            plastic = np.asarray(res["snapshots"][-1]["plastic_strain"]) > 0
            c = float(_centroid_radius(scene)[plastic].max())
            ub = _outer_ur(scene, u_ss, b)
            rows.append(
                _row(
                    f"slipstep thick cylinder p={p:g}",
                    "newton",
                    s,
                    err,
                    wall,
                    run=(scene, res),
                    reference=f"Hill c = {c_ref:.3f}",
                    rel_error=c / c_ref - 1,
                    note=f"plastic radius {c:.3f}; u(b) = {ub:.4e}",
                )
            )
        try:
            bulk = BulkProblem(scene)
        except Exception as exc:  # noqa: BLE001
            return rows, f"dolfinx setup failed: {exc}"
        for n in (1, 2, 5, 10):
            t0 = time.perf_counter()
            try:
                r = bulk.solve_plastic(n_steps=n, tol=1e-10, max_iter=40)
                its = [x["iterations"] for x in r.newton]
                resid = [x.get("residual", float("nan")) for x in r.newton]
                ok = all(x <= 1e-10 for x in resid)
                plastic = np.asarray(r.plastic_strain) > 0
                c = float(_centroid_radius(scene)[plastic].max()) if plastic.any() else a
                du = (
                    (np.linalg.norm(r.u - u_ss) / np.linalg.norm(u_ss))
                    if u_ss is not None
                    else float("nan")
                )
                ub = _outer_ur(scene, r.u, b)
                row = {
                    "scenario": f"dolfinx Newton {n} step(s) p={p:g}",
                    "group": "newton",
                    "status": "converged" if ok else "not converged",
                    "error": ""
                    if ok
                    else f"residual {max(resid):.1e} after " f"{max(its)} iterations",
                    "n_events": "",
                    "n_steps": n,
                    "final_load_fraction": 1.0,
                    "max_residual": max(resid),
                    "max_drift": float("nan"),
                    "reference": f"Hill c = {c_ref:.3f}",
                    "rel_error": c / c_ref - 1,
                    "note": f"Newton iterations {its}; plastic radius {c:.3f}; "
                    f"|u - u_slipstep|/|u_slipstep| = {du:.1e}; u(b) = {ub:.4e}",
                    "wall_s": time.perf_counter() - t0,
                }
            except Exception as exc:  # noqa: BLE001
                row = _row(
                    f"dolfinx Newton {n} step(s) p={p:g}",
                    "newton",
                    None,
                    f"{type(exc).__name__}: {exc}".splitlines()[0],
                    time.perf_counter() - t0,
                    status="not converged",
                )
            rows.append(row)
    return rows, ""


def run(out: str | Path, quick: bool = False, progress=print) -> dict:
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    rows: list[dict] = []
    inc: dict = {}
    newton_note = ""
    for name, fn in (
        ("H0", scenario_h0),
        ("incompressible", scenario_incompressible),
        ("friction", scenario_friction),
        ("ties", scenario_ties),
        ("receding", scenario_receding),
        ("grading", scenario_grading),
        ("newton", scenario_newton),
    ):
        t = time.perf_counter()
        try:
            got = fn(quick)
        except Exception as exc:  # noqa: BLE001
            got = [
                _row(
                    f"{name} (scenario crashed)",
                    name,
                    None,
                    traceback.format_exception_only(type(exc), exc)[-1].strip(),
                    0.0,
                )
            ]
        if name == "incompressible" and isinstance(got, tuple):
            got, inc = got
        if name == "newton" and isinstance(got, tuple):
            got, newton_note = got
        rows.extend(got)
        if progress:
            progress(f"stability: {name}: {len(got)} run(s) in {time.perf_counter() - t:.1f} s")
    write_csv(out / "stability.csv", rows)
    figure(out / "stability.png", rows, inc)
    md = [
        f"# Stability study{' (--quick)' if quick else ''}",
        "",
        "Scenarios where the usual methods fail. `max residual` is the "
        "engine's max over events of |K u - f - contact forces| / |f|; `max drift` the max "
        "of |sigma_e - sigma_y| / sigma_y before the return; `error vs ref` is "
        "described per row (Hill plastic radius, Hertz a, Johnson first yield, exact "
        "closure fraction; for completed near-incompressible runs the final tangent "
        "stiffness / elastic stiffness — Hill's exact answer is 0 at the limit pressure).",
        "",
        markdown_table(rows),
        "",
        "![stability](stability.png)",
        "",
        "## Notes",
        "",
        "- H' = 0: the engine assembles the elastoplastic *stiffness* (Prandtl-Reuss tangent "
        "D_ep), which stays finite at H' = 0; the paper's compliance form (A.2) divides by "
        "H' and cannot be used.",
        "- Near-incompressibility (thick cylinder, plane strain, H' = 0, loaded to "
        "1.1 x Hill's limit 2k ln(b/a)): plastic flow is isochoric and constant-strain "
        "triangles lock as nu -> 1/2: the pressure at which every element is plastic rises "
        "above Hill's limit (or is never reached) on the free (gmsh) CST mesh, and on "
        "coarse meshes the stiffness after the limit stays positive. A structured "
        "2-triangle polar grid, aligned with the radial flow, locks much less. The crossed \"union jack\" mesh "
        "(4 CST per quad through its centre; `slipstep.stability.structured_annulus`) "
        "is fully plastic at the limit for every nu. Rows: p(all plastic) / p_lim - 1 in "
        "`error vs ref`.",
        "- Beyond the limit load slipstep stops at collapse: once the current stiffness of "
        "the remaining load falls below 1e-3 of the initial one the run ends with a "
        "`limit load reached` reason at the load it carried (status `limit load`; the "
        "results up to there are kept), instead of running on along a nearly singular "
        "tangent. Where locking keeps the mesh stiff (CST at nu = 0.499) the stop comes "
        "late or the ill-conditioning error comes first (see the error lines).",
        f"- dolfinx fixed-step Newton (full Newton, consistent tangent, backward-Euler "
        f"radial return): {newton_note or 'see the newton rows: below the limit it converges for 1, 2, 5 and 10 steps (radial loading, so one step already gives the same answer within its tolerance), beyond the limit it diverges for every step count, where slipstep runs on (above)'}.",
        "",
        "Failed or stopped runs: "
        + (
            ", ".join(
                f"{r['scenario']} ({r['error']})"
                for r in rows
                if r["status"] not in ("completed", "converged", "limit load")
            )
            or "none"
        )
        + ".",
        "",
        f"Total wall time {time.perf_counter() - t0:.1f} s.",
    ]
    (out / "report.md").write_text("\n".join(md) + "\n")
    return {"rows": rows, "incompressible": inc, "newton_note": newton_note}


def main(args) -> int:
    report = run(args.out, quick=args.quick)
    bad = [r for r in report["rows"] if r["status"] == "failed"]
    print(f"stability: {len(report['rows'])} runs ({len(bad)} failed) -> {args.out}/report.md")
    return 0
