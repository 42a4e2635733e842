"""slipstep vs dolfinx on one scene: the comparisons of the tests and of
``slipstep crosscheck CASE.toml --out DIR``.

What is compared depends on the scene:

- no contact pairs, elastic: one dolfinx linear solve; displacement and element stresses;
- no contact pairs, elastoplastic: dolfinx with N = 5, 10, 20, 50 (``steps``) equal load
  steps; differences against N; plus Hill's closed form when the scene is a quarter annulus
  under internal pressure (perfectly plastic, plane strain);
- contact pairs: the contact state is replayed in dolfinx (:mod:`.replay`) at every
  snapshot (elastic) or through all snapshots in order (elastoplastic).

Differences are relative: max |a - b| / max |b| over all nodes (elements), b = slipstep.
Axisymmetric scenes go the same way on the ring forms (:class:`.forms.RingSection`); contact
pressures are forces over ``scene.pair_area`` (the ring areas there).
"""

from __future__ import annotations

import contextlib
import json
import math
import shutil
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from ..idealisation import Axisymmetric, Plane, Solid
from ..output.fields import polar
from ..measures.references import (
    thick_cylinder_displacement,
    thick_cylinder_radius,
    thick_cylinder_stresses,
    thick_sphere_outer_displacement,
    thick_sphere_plastic_radius,
    thick_sphere_stresses,
)
from ..output.fields import spherical
from .bulk import BulkProblem, relative_difference

DEFAULT_STEPS = (5, 10, 20, 50)


def is_plastic(scene) -> bool:
    return any(m.get("Sy") not in (None, math.inf) for m in scene.model["materials"])


def engine_result(scene, events: bool = False, fractions=(1.0,)) -> tuple[dict, float]:
    """Run the engine with snapshots at every event (``events``) or at ``fractions`` of the
    load."""
    from ..runner import engine

    model = dict(scene.model)
    options = dict(model["options"])
    if events:
        options["output"] = "events"
        options.pop("fractions", None)
    else:
        options["output"] = "fractions"
        options["fractions"] = np.asarray(fractions, dtype=float)
    model["options"] = options
    t0 = time.perf_counter()
    result = engine().solve(model, False)
    if result["stop"]["kind"] in ("limit_load", "event_bound", "interrupted"):
        raise RuntimeError(f"slipstep stopped early: {result['stop']['message'] or 'interrupted'}")
    return result, time.perf_counter() - t0


def bulk_differences(snapshot: dict, res) -> dict:
    out = {
        "u": relative_difference(res.u, snapshot["u"]),
        "stress": relative_difference(res.stress, snapshot["stress"]),
    }
    ep = np.asarray(snapshot.get("plastic_strain", np.zeros(1)))
    if np.abs(ep).max(initial=0.0) > 0:
        out["plastic_strain"] = relative_difference(res.plastic_strain, ep)
        out["n_plastic_slipstep"] = int((ep > 0).sum())
        out["n_plastic_dolfinx"] = int((res.plastic_strain > 0).sum())
    return out


# --------------------------------------------------------------------------- Hill
def hill_setup(scene) -> dict | None:
    """(shape, a, b, p, E, nu, Sy) when the scene is one of Hill's problems: one perfectly plastic
    body under a pressure on ``inner`` and no other load nor contact, a ``quarter_annulus`` in
    plane strain (the thick cylinder) or, in 3D, a ``shell`` (the thick sphere); else None."""
    case = scene.case.record
    if len(case.body) != 1 or case.contact or case.point_load or case.load is not None:
        return None
    body = case.body[0]
    mesh, mat = body.mesh, body.material
    hill = comparisons(scene).hill
    if (
        hill is None
        or body.generator != hill[0]
        or case.analysis.plane != "strain"  # (a 3D case keeps this default)
        or mat.Sy is None
        or (mat.H or 0) != 0
    ):
        return None
    loads = [bc for bc in case.bc if bc.pressure != 0 or any(bc.traction)]
    if len(loads) != 1 or loads[0].boundary_tag != "inner" or any(loads[0].traction):
        return None
    return {
        "shape": hill[1],
        "a": mesh["a"],
        "b": mesh["b"],
        "p": loads[0].pressure,
        "E": mat.E,
        "nu": mat.nu,
        "Sy": mat.Sy,
    }


def hill_differences(scene, u, stress, plastic_strain) -> dict | None:
    """Differences to Hill's closed form: outer radial displacement (relative), sigma_r and
    sigma_theta at the element centroids (max and RMS, / Sy), plastic radius (largest
    centroid radius of a plastic element) against c."""
    h = hill_setup(scene)
    if h is None:
        return None
    a, b, p, Sy = (h[k] for k in ("a", "b", "p", "Sy"))
    if h["shape"] == "sphere":
        ur, rc, sr, st = spherical(scene.nodes, u, stress, scene.elements)
        c, ub, (hr, ht) = hill_sphere(rc, h)
    else:
        ur, rc, sr, st = polar(scene.nodes, u, stress, scene.triangles)
        c, ub, (hr, ht) = hill_cylinder(rc, h)
    outer = np.abs(np.linalg.norm(scene.nodes, axis=1) - b) <= 1e-9 * b
    plastic = plastic_strain > 0
    return {
        "u_outer": float(ur[outer].mean() / ub - 1.0),
        "sigma_r_max": float(np.abs(sr - hr).max() / Sy),
        "sigma_t_max": float(np.abs(st - ht).max() / Sy),
        "sigma_r_rms": float(np.sqrt(np.mean((sr - hr) ** 2)) / Sy),
        "sigma_t_rms": float(np.sqrt(np.mean((st - ht) ** 2)) / Sy),
        "plastic_radius": float(rc[plastic].max()) if plastic.any() else a,
        "hill_c": c,
        "hill_u_outer": float(ub),
        "shape": h["shape"],
    }


def hill_cylinder(r, h: dict):
    """Hill's thick cylinder (plane strain, k = Sy/sqrt 3): c, u(b), (sigma_r, sigma_theta)(r)."""
    k = h["Sy"] / math.sqrt(3.0)
    a, b, p = h["a"], h["b"], h["p"]
    return (
        float(thick_cylinder_radius(p, a, b, k)),
        thick_cylinder_displacement(b, p, a, b, h["E"], h["nu"], h["Sy"]),
        thick_cylinder_stresses(r, p, a, b, h["Sy"]),
    )


def hill_sphere(rho, h: dict):
    """Hill's thick sphere (Y = Sy): c, u(b), (sigma_R, sigma_t)(rho)."""
    a, b, p, Y = h["a"], h["b"], h["p"], h["Sy"]
    return (
        thick_sphere_plastic_radius(p, a, b, Y),
        thick_sphere_outer_displacement(p, a, b, h["E"], h["nu"], Y),
        thick_sphere_stresses(rho, p, a, b, Y),
    )


# --------------------------------------------------------------------------- drivers
def elastic_bulk(scene, bulk: BulkProblem | None = None) -> dict:
    bulk = bulk or BulkProblem(scene)
    result, t_engine = engine_result(scene)
    t0 = time.perf_counter()
    res = bulk.solve_elastic()
    row = {
        "what": "elastic, no contact",
        "t_slipstep": t_engine,
        "t_dolfinx": time.perf_counter() - t0,
        **bulk_differences(result["snapshots"][-1], res),
    }
    return {"rows": [row], "snapshot": result["snapshots"][-1], "dolfinx": res}


def plastic_bulk(scene, steps=DEFAULT_STEPS, bulk: BulkProblem | None = None) -> dict:
    bulk = bulk or BulkProblem(scene)
    result, t_engine = engine_result(scene)
    snap = result["snapshots"][-1]
    rows, last = [], None
    for n in steps:
        t0 = time.perf_counter()
        res = bulk.solve_plastic(n_steps=n)
        rows.append(
            {
                "what": f"elastoplastic, dolfinx N = {n}",
                "steps": n,
                "newton_iterations": sum(x["iterations"] for x in res.newton),
                "t_slipstep": t_engine,
                "t_dolfinx": time.perf_counter() - t0,
                **bulk_differences(snap, res),
            }
        )
        last = res
    out = {
        "rows": rows,
        "snapshot": snap,
        "dolfinx": last,
        "n_events": int(len(result["events"]["kind"])),
    }
    hs = hill_differences(scene, snap["u"], snap["stress"], snap["plastic_strain"])
    if hs is not None:
        out["hill"] = {
            "slipstep": hs,
            "dolfinx": hill_differences(scene, last.u, last.stress, last.plastic_strain),
        }
    return out


def contact_replay(scene, bulk: BulkProblem | None = None, substeps: int = 1) -> dict:
    from .replay import replay_elastic, replay_plastic

    bulk = bulk or BulkProblem(scene)
    result, t_engine = engine_result(scene, events=True)
    t0 = time.perf_counter()
    plastic = is_plastic(scene)
    rows, last = (
        replay_plastic(scene, result, bulk, substeps)
        if plastic
        else replay_elastic(scene, result, bulk)
    )
    t_dolfinx = time.perf_counter() - t0
    return {
        "rows": rows,
        "snapshot": result["snapshots"][-1],
        "dolfinx": last,
        "plastic": plastic,
        "t_slipstep": t_engine,
        "t_dolfinx": t_dolfinx,
        "result": result,
    }


def summarize_rows(rows: list[dict], keys) -> dict:
    """Max over rows of each difference key present."""
    return {k: max(r[k] for r in rows if k in r) for k in keys if any(k in r for r in rows)}


# --------------------------------------------------------------------------- report
REPLAY_KEYS = ("u", "stress", "plastic_strain", "lambda_n", "lambda_t_stick", "coulomb_slip")


def run(case_path, out: str | Path, overrides=(), steps=DEFAULT_STEPS, substeps: int = 1) -> dict:
    """Run both codes on a case and write ``DIR/crosscheck.md``, ``crosscheck.json``,
    ``crosscheck.png``, the exchanged mesh (``mesh.xdmf``, ``mesh_edges.xdmf``) and the
    dolfinx results (``dolfinx.xdmf``, written by dolfinx)."""
    from ..case import load_case
    from ..build import build_scene

    t0 = time.perf_counter()
    scene = build_scene(load_case(case_path, overrides))
    n_pairs = int(len(scene.model["pairs"]["node_a"]))
    if n_pairs and not comparisons(scene).contact:
        raise NotImplementedError(
            f"{scene.case.name}: the 3D cross-check compares the bulk (no [[contact]]); the "
            f"contact replay is planar and axisymmetric: remove the contacts (and load the body "
            f"by [[bc]]) to cross-check its bulk"
        )
    with _removed_on_failure(Path(out)) as out:
        return _compared(scene, out, steps, substeps, t0)


@contextlib.contextmanager
def _removed_on_failure(out: Path):
    """``out`` (created when missing); the files a failed comparison wrote there (the exchanged
    mesh, say, when the replay refuses the scene) are removed, and the folders it created."""
    made = [p for p in (out, *out.parents) if not p.exists()]  # the deepest first
    out.mkdir(parents=True, exist_ok=True)
    before = set(out.iterdir())
    try:
        yield out
    except BaseException:
        for path in set(out.iterdir()) - before:
            shutil.rmtree(path) if path.is_dir() else path.unlink()
        for folder in made:
            folder.rmdir()
        raise


def _compared(scene, out: Path, steps, substeps: int, t0: float) -> dict:
    """:func:`run` on a built scene, into the folder ``out``."""
    from .exchange import read_dolfinx, write_scene_xdmf

    write_scene_xdmf(scene, out / "mesh.xdmf")
    dm = read_dolfinx(out / "mesh.xdmf")
    bulk = BulkProblem(scene, dm)
    report = {
        "case": scene.case.name,
        "source": scene.case.source,
        "n_nodes": len(scene.nodes),
        "n_elements": len(scene.elements),
        "n_pairs": int(len(scene.model["pairs"]["node_a"])),
        "plane": scene.model.get("plane", "none (3D)"),
        "plastic": is_plastic(scene),
    }
    if report["n_pairs"]:
        rep = contact_replay(scene, bulk, substeps)
        report["mode"] = "contact replay" + (" (elastoplastic)" if rep["plastic"] else "")
        report["replay"] = rep["rows"]
        report["max"] = summarize_rows(rep["rows"], REPLAY_KEYS)
        report["timings"] = {"slipstep": rep["t_slipstep"], "dolfinx": rep["t_dolfinx"]}
        snap, last = rep["snapshot"], rep["dolfinx"]
    elif report["plastic"]:
        pb = plastic_bulk(scene, steps, bulk)
        report["mode"] = "elastoplastic bulk (no contact)"
        report["rows"] = pb["rows"]
        report["n_events"] = pb["n_events"]
        if "hill" in pb:
            report["hill"] = pb["hill"]
        snap, last = pb["snapshot"], pb["dolfinx"]
    else:
        eb = elastic_bulk(scene, bulk)
        report["mode"] = "elastic bulk (no contact)"
        report["rows"] = eb["rows"]
        snap, last = eb["snapshot"], eb["dolfinx"]
    if last is not None:
        bulk.write_xdmf(out / "dolfinx.xdmf", [last])
    report["timings_total_s"] = time.perf_counter() - t0
    report["timings_dolfinx_setup_s"] = bulk.timings["setup"]
    _figure(out / "crosscheck.png", scene, report, snap, last)
    (out / "crosscheck.json").write_text(json.dumps(report, indent=2, default=_json) + "\n")
    (out / "crosscheck.md").write_text(markdown(report))
    return report


def _json(x):
    if isinstance(x, np.generic):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    raise TypeError(type(x))


def _fmt(v) -> str:
    if isinstance(v, float):
        return f"{v:.3g}"
    return str(v)


def markdown(report: dict) -> str:
    lines = [
        f"# slipstep vs dolfinx: {report['case']}",
        "",
        f"{report['source']}: {report['n_nodes']} nodes, {report['n_elements']} elements, "
        f"{report['n_pairs']} contact pairs, plane {report['plane']}; mode: "
        f"**{report['mode']}**.",
        "",
        "Differences are max |dolfinx - slipstep| / max |slipstep| over the nodes "
        "(displacement) or elements (stress, plastic strain); contact forces are relative "
        "to the largest lambda_n.",
        "",
    ]
    if "rows" in report:
        keys = [
            k
            for k in (
                "steps",
                "newton_iterations",
                "u",
                "stress",
                "plastic_strain",
                "n_plastic_slipstep",
                "n_plastic_dolfinx",
                "t_slipstep",
                "t_dolfinx",
            )
            if any(k in r for r in report["rows"])
        ]
        lines += ["| what | " + " | ".join(keys) + " |", "|---|" + "---|" * len(keys)]
        for r in report["rows"]:
            lines.append(f"| {r['what']} | " + " | ".join(_fmt(r.get(k, "")) for k in keys) + " |")
        lines.append("")
    if "replay" in report:
        rows = report["replay"]
        keys = [
            k for k in ("n_closed", "n_stick", "n_slip", *REPLAY_KEYS) if any(k in r for r in rows)
        ]
        lines += [
            f"Contact replay at {len(rows)} snapshots (every event); max over them: "
            + ", ".join(f"{k} {v:.3g}" for k, v in report["max"].items()),
            "",
            "| load fraction | " + " | ".join(keys) + " |",
            "|---|" + "---|" * len(keys),
        ]
        pick = rows if len(rows) <= 30 else rows[:: max(1, len(rows) // 25)] + [rows[-1]]
        for r in pick:
            lines.append(
                f"| {r['load_fraction']:.4g} | "
                + " | ".join(_fmt(r.get(k, "")) for k in keys)
                + " |"
            )
        lines.append("")
        lines.append(
            f"Time: slipstep {report['timings']['slipstep']:.3g} s, dolfinx replay "
            f"{report['timings']['dolfinx']:.3g} s."
        )
        lines.append("")
    if "hill" in report:
        lines += [
            f"Against Hill's closed form (perfectly plastic thick "
            f"{report['hill']['slipstep']['shape']}):",
            "",
            "| quantity | slipstep | dolfinx (largest N) |",
            "|---|---|---|",
        ]
        for k in (
            "u_outer",
            "sigma_r_rms",
            "sigma_t_rms",
            "sigma_r_max",
            "sigma_t_max",
            "plastic_radius",
        ):
            lines.append(
                f"| {k} | {_fmt(report['hill']['slipstep'][k])} | "
                f"{_fmt(report['hill']['dolfinx'][k])} |"
            )
        lines += [
            "",
            f"(u_outer: relative difference of the mean outer radial displacement; "
            f"sigma_*: / Sy at element centroids; Hill's c = "
            f"{report['hill']['slipstep']['hill_c']:.4g})",
            "",
        ]
    lines += [
        f"Total {report['timings_total_s']:.3g} s (dolfinx set-up and JIT "
        f"{report['timings_dolfinx_setup_s']:.3g} s). Figure: crosscheck.png; dolfinx "
        f"fields: dolfinx.xdmf; exchanged mesh: mesh.xdmf + mesh_edges.xdmf.",
        "",
    ]
    return "\n".join(lines)


def _figure(path: Path, scene, report: dict, snap: dict, last) -> None:
    """crosscheck.png: the differences (left) and the final field or contact pressure (right).
    Drawn on a :class:`matplotlib.figure.Figure` (no pyplot: safe beside a notebook's)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(11, 4.5))
    axes = fig.subplots(1, 2)
    _differences_panel(axes[0], report)
    comparisons(scene).field_panel(fig, axes[1], scene, report, snap, last)
    fig.suptitle(f"{report['case']}: {report['mode']}")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def _differences_panel(ax, report: dict) -> None:
    if "replay" in report:
        rows = report["replay"]
        f = [r["load_fraction"] for r in rows]
        for k in REPLAY_KEYS:
            vals = np.array([r.get(k, np.nan) for r in rows], dtype=float)
            if (vals > 0).any():  # exact zeros have no place on a log axis
                ax.semilogy(f, np.where(vals > 0, vals, np.nan), ".-", label=k)
        ax.set_xlabel("load fraction")
        ax.set_title("contact replay: relative difference")
    elif len(report["rows"]) > 1:
        n = [r["steps"] for r in report["rows"]]
        for k in ("u", "stress", "plastic_strain"):
            ax.loglog(n, [r[k] for r in report["rows"]], "o-", label=k)
        ax.set_xlabel("dolfinx load steps N")
        ax.set_title("slipstep vs dolfinx: relative difference")
    else:
        r = report["rows"][0]
        ax.bar(["u", "stress"], [max(r["u"], 1e-17), max(r["stress"], 1e-17)])
        ax.set_yscale("log")
        ax.set_title("elastic: relative difference")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)


def _section_panel(fig, ax, scene, report: dict, snap: dict, last) -> None:
    """2D: the final contact pressure (replay: slipstep's nodal lambda_n / area and dolfinx's
    reactions over the same areas, scene.pair_area: t L in the plane, the ring's consistent
    area in axisymmetry), else the von Mises difference or slipstep's von Mises."""
    from matplotlib.tri import Triangulation

    from ..output.fields import von_mises

    tri = Triangulation(scene.nodes[:, 0], scene.nodes[:, 1], scene.triangles)
    if "replay" in report and last is not None:
        from .replay import replay_conditions

        _, _, info = replay_conditions(scene, snap)
        area, x = scene.pair_area, scene.pair_xy[:, 0]
        order = np.argsort(x)
        ax.plot(
            x[order],
            (np.asarray(snap["lambda_n"]) / area)[order],
            "-",
            lw=3,
            alpha=0.4,
            label="slipstep (engine)",
        )
        if len(info["closed"]):
            got = last.reaction[info["normal_dof"]] * info["normal_sign"]
            ax.plot(
                x[info["closed"]],
                got / area[info["closed"]],
                "k.",
                label="dolfinx reaction (replay)",
            )
        ax.set_xlabel("x of the contactor node")
        ax.set_ylabel("contact pressure")
        ax.set_title(f"final contact pressure ({len(x)} candidates)")
        ax.legend(fontsize=8)
        ax.grid(True, alpha=0.3)
        return
    if last is not None:
        d = von_mises(last.stress) - von_mises(np.asarray(snap["stress"]))
        pc = ax.tripcolor(
            tri, facecolors=d, cmap="coolwarm", vmin=-np.abs(d).max(), vmax=np.abs(d).max() or 1.0
        )
        ax.set_title("von Mises: dolfinx - slipstep")
    else:
        pc = ax.tripcolor(tri, facecolors=von_mises(np.asarray(snap["stress"])), cmap="viridis")
        ax.set_title("slipstep von Mises (final)")
    fig.colorbar(pc, ax=ax)
    ax.set_aspect("equal")


def _von_mises_panel(fig, ax, scene, report: dict, snap: dict, last) -> None:
    """3D: each element's von Mises stress, dolfinx's against slipstep's (on the diagonal when
    they agree), or slipstep's sorted when dolfinx has no final state."""
    from ..output.fields import von_mises_3d

    ours = von_mises_3d(np.asarray(snap["stress"]))
    if last is None:
        ax.plot(np.sort(ours), ".", ms=2)
        ax.set_ylabel("slipstep von Mises (final), sorted")
        return
    theirs = von_mises_3d(last.stress)
    top = max(ours.max(), theirs.max()) or 1.0
    ax.plot([0, top], [0, top], "k-", lw=0.6)
    ax.plot(ours, theirs, ".", ms=2, alpha=0.5)
    ax.set_xlabel("slipstep von Mises per element")
    ax.set_ylabel("dolfinx von Mises per element")
    ax.set_aspect("equal")
    ax.grid(True, alpha=0.3)


# --------------------------------------------------------------------------- per idealisation
@dataclass(frozen=True)
class Comparisons:
    """What the cross-check compares in one idealisation: Hill's problem, if any (the thick
    wall's generator, and the closed form's shape), whether a contact state is replayed in
    dolfinx (:mod:`.replay`: planar and axisymmetric), and crosscheck.png's field panel."""

    hill: tuple[str, str] | None
    contact: bool
    field_panel: Callable


COMPARISONS = {
    Plane: Comparisons(("quarter_annulus", "cylinder"), True, _section_panel),
    Axisymmetric: Comparisons(None, True, _section_panel),
    Solid: Comparisons(("shell", "sphere"), False, _von_mises_panel),
}


def comparisons(scene) -> Comparisons:
    """The :class:`Comparisons` of the scene's idealisation."""
    return COMPARISONS[type(scene.idealisation)]
