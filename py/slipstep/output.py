"""Results on disk: XDMF/HDF5 time series, events.csv, contact_profile.csv, summary.json.

All files are first written to a staging folder inside the output folder and then renamed
into place, so a run that fails half-way leaves the previous results intact.

Contact quantities per candidate pair (engine sign conventions, docs/engine_api.md):
pressure = lambda_n / (L t) and tangential stress = lambda_t / (L t), with L the tributary
length of node a on its edge and t the thickness; the tangential direction is
t = (-n_y, n_x), i.e. (-1, 0) for a flat with normal (0, 1).
"""

from __future__ import annotations

import contextlib
import csv
import json
import math
import os
import shutil
from pathlib import Path

import numpy as np

STATUS_NAMES = ("open", "stick", "slip")
#: Event kinds whose entity is an element (the others are contact pairs).
ELEMENT_EVENTS = ("yield", "unload", "frozen_element")


# --------------------------------------------------------------------------- derived quantities
def von_mises(stress: np.ndarray) -> np.ndarray:
    """Equivalent stress of (M, 4) rows sigma_x, sigma_y, sigma_z, tau_xy."""
    sx, sy, sz, txy = stress.T
    return np.sqrt(0.5 * ((sx - sy) ** 2 + (sy - sz) ** 2 + (sz - sx) ** 2) + 3.0 * txy ** 2)


def contact_profile(scene, snapshot: dict) -> dict:
    """Per candidate pair at one snapshot, sorted by x of node a: x, y, pressure, tangential
    stress, RTD, status (0 open, 1 stick, 2 slip), gap."""
    t = scene.model["thickness"]
    order = np.lexsort((scene.pair_xy[:, 1], scene.pair_xy[:, 0]))
    area = scene.pair_length * t
    return {
        "pair": order,
        "node_a": scene.model["pairs"]["node_a"][order],
        "x": scene.pair_xy[order, 0],
        "y": scene.pair_xy[order, 1],
        "pressure": (np.asarray(snapshot["lambda_n"]) / area)[order],
        "tangential_stress": (np.asarray(snapshot["lambda_t"]) / area)[order],
        "rtd": np.asarray(snapshot["rtd"])[order],
        "status": np.asarray(snapshot["status"]).astype(int)[order],
        "gap": np.asarray(snapshot["gap"])[order],
    }


def contact_half_width(x, status, closure, predicted, f) -> float:
    """Contact half-width a at load fraction f, between the outermost closed pair (x_c, closed at
    f_c = closure) and the next open pair (x_o, predicted to close at f_o): linear in the load
    fraction, a = x_c + (x_o - x_c) (f - f_c) / (f_o - f_c), clipped to [x_c, x_o]."""
    closed = status > 0
    if not closed.any():
        return 0.0
    ic = np.flatnonzero(closed)[np.argmax(x[closed])]
    xc, fc = x[ic], closure[ic]
    beyond = np.flatnonzero(~closed & (x > xc))
    if len(beyond) == 0:
        return float(xc)
    io = beyond[np.argmin(x[beyond])]
    xo, fo = x[io], predicted[io]
    if not (np.isfinite(fo) and np.isfinite(fc)) or fo <= fc:
        return float(xc)
    s = min(max((f - fc) / (fo - fc), 0.0), 1.0)
    return float(xc + (xo - xc) * s)


def stick_half_width(x, status, a) -> float:
    """Half-width c of the central stick zone: the midpoint between the outermost stick pair and
    the first slip pair beyond it; ``a`` if every closed pair out to the edge sticks; 0 if
    nothing sticks."""
    stick = status == 1
    if not stick.any():
        return 0.0
    xs = x[stick].max()
    beyond = np.flatnonzero((status > 0) & (x > xs))
    if len(beyond) == 0:
        return float(a)
    return float(0.5 * (xs + x[beyond].min()))


def contact_growth(scene, result) -> tuple[np.ndarray, np.ndarray]:
    """Outermost closed node x after each step, replaying the close/separate events
    (initially closed pairs, gap = 0, start closed).  Returns (load_fraction, x) from f = 0."""
    x = scene.pair_xy[:, 0]
    closed = set(np.flatnonzero(np.asarray(scene.model["pairs"]["gap"]) == 0.0).tolist())

    def outer():
        return max((x[i] for i in closed), default=0.0)

    fs, xs = [0.0], [outer()]
    ev = result["events"]
    steps = np.asarray(ev["step"])
    for k in range(len(steps)):
        kind, entity = ev["kind"][k], int(ev["entity"][k])
        if kind == "close":
            closed.add(entity)
        elif kind == "separate":
            closed.discard(entity)
        if k + 1 == len(steps) or steps[k + 1] != steps[k]:
            fs.append(float(ev["load_fraction"][k]))
            xs.append(outer())
    final = final_load_fraction(result)
    if final > fs[-1]:
        fs.append(final)
        xs.append(xs[-1])
    return np.asarray(fs), np.asarray(xs)


def reached_last_candidate(scene, snapshot) -> bool:
    """True if a contact whose candidates are only part of its edge (x/y window, unpaired
    nodes) has its outermost (largest x) candidate closed: the contact may be cut short."""
    status = np.asarray(snapshot["status"])
    for i, truncated in enumerate(scene.contact_truncated):
        mine = np.flatnonzero(scene.pair_contact == i)
        if truncated and len(mine) and status[mine[np.argmax(scene.pair_xy[mine, 0])]] > 0:
            return True
    return False


def is_elastoplastic(scene) -> bool:
    """True when some material has a yield stress (the run can have plasticity events)."""
    return any(m.get("Sy") is not None for m in scene.model["materials"])


def yield_drift(scene, snap) -> np.ndarray:
    """Per element |sigma_e - sigma_y(eps_p)| / sigma_y(eps_p) for plastic elements, 0 elsewhere:
    how far the stored stress sits off the hardening yield surface (the engine's drift measure)."""
    mats = scene.model["materials"]
    index = np.asarray(scene.model["element_material"])
    sy = np.array([m.get("Sy") or np.inf for m in mats], dtype=float)[index]
    hp = np.array([m.get("H") or 0.0 for m in mats], dtype=float)[index]
    current = sy + hp * np.asarray(snap["plastic_strain"], dtype=float)
    se = von_mises(np.asarray(snap["stress"], dtype=float).reshape(-1, 4))
    plastic = (np.asarray(snap["plastic"]) > 0) & np.isfinite(current)  # elastic bodies: Sy = inf
    drift = np.zeros(len(se))
    drift[plastic] = np.abs(se[plastic] - current[plastic]) / current[plastic]
    return drift


def centroids(scene) -> np.ndarray:
    """(M, 2) element centroids."""
    return scene.nodes[scene.triangles].mean(axis=1)


def element_depth(scene, element: int) -> float:
    """Depth of an element's centroid below the initial contact surface of its body.

    The surface near the element is taken as the tangent line at the nearest candidate pair of a
    contact on the element's body: through the target point (node b, or for a rigid line the
    foot of node a on the line, x_a - gap n) with the pair's normal n, so for a ``rigid_line``
    contact this is the distance from the line.  Without contact on the body: the centroid's y.
    """
    c = centroids(scene)[element]
    pairs = scene.model["pairs"]
    node_a, node_b = np.asarray(pairs["node_a"]), np.asarray(pairs["node_b"])
    if len(node_a):
        lo = scene.offsets[scene.bodies[scene.element_body[element]]]
        hi = lo + scene.meshes[scene.bodies[scene.element_body[element]]].n_nodes
        mine = ((node_a >= lo) & (node_a < hi)) | ((node_b >= lo) & (node_b < hi))
        if mine.any():
            idx = np.flatnonzero(mine)
            k = idx[np.argmin(np.linalg.norm(scene.pair_xy[idx] - c, axis=1))]
            n = np.asarray(pairs["normal"])[k]
            target = (scene.nodes[node_b[k]] if node_b[k] >= 0
                      else scene.pair_xy[k] - pairs["gap"][k] * n)
            return float(abs((c - target) @ n))
    return float(c[1])


def first_yield(scene, result) -> dict:
    """The first ``yield`` event: load fraction, element, its centroid x and depth
    (:func:`element_depth`); every value None when nothing yielded."""
    kinds = list(result["events"]["kind"])
    if "yield" not in kinds:
        return {"first_yield_load_fraction": None, "first_yield_element": None,
                "first_yield_x": None, "first_yield_depth": None}
    k = kinds.index("yield")
    e = int(result["events"]["entity"][k])
    return {"first_yield_load_fraction": float(result["events"]["load_fraction"][k]),
            "first_yield_element": e,
            "first_yield_x": float(centroids(scene)[e, 0]),
            "first_yield_depth": element_depth(scene, e)}


def johnson_first_yield(scene) -> float | None:
    """Johnson (Contact Mechanics §4.3/§6.2): a frictionless line contact first yields (von
    Mises, nu = 0.3) below the surface when p0 = 1.79 Sy; p0 grows as sqrt(f), so at the load
    fraction f = (1.79 Sy / p0_hertz)^2 with p0_hertz at full load.  None if the body is elastic."""
    ref = scene.reference
    if not ref:
        return None
    sy = scene.case.body(scene.case.data["load"]["body"])["material"]["Sy"]
    return None if sy is None else (1.79 * sy / ref["p0_hertz"]) ** 2


def final_load_fraction(result) -> float:
    steps = result.get("steps", {}).get("load_fraction", [])
    if len(steps):
        return float(steps[-1])
    snaps = result.get("snapshots", [])
    return float(snaps[-1]["load_fraction"]) if snaps else 0.0


def summarize(scene, result, wall_time_s: float = float("nan")) -> dict:
    """The numbers of a run, for summary.json and the one-line report."""
    model = scene.model
    snaps = result.get("snapshots", [])
    f = final_load_fraction(result)
    summary = {
        "case": scene.case.name,
        "n_events": int(len(result["events"]["step"])),
        "n_steps": int(len(result["steps"]["load_fraction"])),
        "final_load_fraction": f,
        "interrupted": bool(result.get("interrupted", False)),
        "n_nodes": int(len(model["nodes"])),
        "n_elements": int(len(model["triangles"])),
        "n_dofs": int(2 * len(model["nodes"])),
        "n_pairs": int(len(model["pairs"]["node_a"])),
        "n_factorizations": int(result.get("n_factorizations", 0)),
        "n_solves": int(result.get("n_solves", 0)),
        "max_equilibrium_residual": float(result.get("max_equilibrium_residual", float("nan"))),
        "max_drift": float(result.get("max_drift", 0.0)),
        "stop_reason": result.get("stop_reason"),
        "wall_time_s": float(wall_time_s),
        "engine_timings_s": {k: float(v) for k, v in result.get("timings", {}).items()},
    }
    if snaps:
        last = snaps[-1]
        stress = np.asarray(last["stress"], dtype=float).reshape(-1, 4)
        summary["max_von_mises"] = float(von_mises(stress).max()) if len(stress) else 0.0
    if is_elastoplastic(scene):
        summary.update(first_yield(scene, result))
        if snaps and "plastic" in snaps[-1]:
            summary["n_plastic_elements"] = int(np.count_nonzero(snaps[-1]["plastic"]))
    if snaps and len(scene.pair_xy):
        last = snaps[-1]
        prof = contact_profile(scene, last)
        x, status = prof["x"], prof["status"]
        closure = np.asarray(result["closure_fraction"], dtype=float)[prof["pair"]]
        predicted = np.asarray(result["predicted_closure"], dtype=float)[prof["pair"]]
        a = contact_half_width(x, status, closure, predicted, float(last["load_fraction"]))
        summary.update({
            "snapshot_load_fraction": float(last["load_fraction"]),
            "contact_half_width": a,
            "stick_half_width": stick_half_width(x, status, a),
            "peak_pressure": float(prof["pressure"].max()),
            "total_normal_force": float(np.sum(last["lambda_n"])),
            "n_open": int((status == 0).sum()),
            "n_stick": int((status == 1).sum()),
            "n_slip": int((status == 2).sum()),
            "contact_reached_last_candidate": reached_last_candidate(scene, last),
        })
    if scene.reference:
        ref = dict(scene.reference)
        # Hertz at the reached load fraction: a ~ sqrt(f), p0 ~ sqrt(f)
        ref["a_hertz_at_final"] = ref["a_hertz"] * math.sqrt(max(f, 0.0))
        ref["p0_hertz_at_final"] = ref["p0_hertz"] * math.sqrt(max(f, 0.0))
        if "contact_half_width" in summary and ref["a_hertz_at_final"] > 0:
            ref["a_rel_error"] = summary["contact_half_width"] / ref["a_hertz_at_final"] - 1.0
            ref["p0_rel_error"] = summary["peak_pressure"] / ref["p0_hertz_at_final"] - 1.0
        f_johnson = johnson_first_yield(scene)
        if f_johnson is not None:
            ref["f_yield_johnson"] = f_johnson
            f_fe = summary.get("first_yield_load_fraction")
            ref["first_yield_rel_error"] = None if f_fe is None else f_fe / f_johnson - 1.0
        summary["hertz"] = ref
    return summary


def one_line(summary: dict) -> str:
    """The summary the CLI prints."""
    parts = [f"{summary['case']}: {summary['n_events']} events",
             f"f = {summary['final_load_fraction']:.4g}"]
    if "contact_half_width" in summary:
        parts += [f"a = {summary['contact_half_width']:.4g}",
                  f"c = {summary['stick_half_width']:.4g}",
                  f"p0 = {summary['peak_pressure']:.4g}"]
    if "hertz" in summary and "a_rel_error" in summary["hertz"]:
        h = summary["hertz"]
        parts.append(f"(Hertz a = {h['a_hertz_at_final']:.4g}, p0 = {h['p0_hertz_at_final']:.4g})")
    if summary.get("first_yield_load_fraction") is not None:
        parts.append(f"first yield at f = {summary['first_yield_load_fraction']:.4g}, "
                     f"{summary.get('n_plastic_elements', 0)} plastic elements")
    parts += [f"{summary['n_dofs']} dofs", f"{summary['wall_time_s']:.2f} s"]
    if summary["interrupted"]:
        parts.append("INTERRUPTED")
    return ", ".join(parts)


# --------------------------------------------------------------------------- writers
def write_events_csv(path: Path, scene, result) -> None:
    """One row per (event, entity): step, load_fraction, kind, entity, entity_kind (``pair`` or
    ``element``), x, y (node a of the pair; the element centroid for the element events yield,
    unload, frozen_element)."""
    ev = result["events"]
    centres = None
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["step", "load_fraction", "kind", "entity", "entity_kind", "x", "y"])
        for k in range(len(ev["step"])):
            kind, entity = ev["kind"][k], int(ev["entity"][k])
            if kind in ELEMENT_EVENTS:
                if centres is None:
                    centres = centroids(scene)
                x, y = centres[entity]
            else:
                x, y = scene.pair_xy[entity]
            w.writerow([int(ev["step"][k]), repr(float(ev["load_fraction"][k])), kind, entity,
                        "element" if kind in ELEMENT_EVENTS else "pair",
                        repr(float(x)), repr(float(y))])


def write_profile_csv(path: Path, scene, snapshot: dict) -> None:
    """contact_profile.csv: the candidate pairs at the final snapshot, sorted by x."""
    prof = contact_profile(scene, snapshot)
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["x", "y", "pressure", "tangential_stress", "rtd", "status", "gap", "pair",
                    "node_a"])
        for i in range(len(prof["x"])):
            w.writerow([repr(float(prof["x"][i])), repr(float(prof["y"][i])),
                        repr(float(prof["pressure"][i])),
                        repr(float(prof["tangential_stress"][i])),
                        repr(float(prof["rtd"][i])), STATUS_NAMES[prof["status"][i]],
                        repr(float(prof["gap"][i])), int(prof["pair"][i]),
                        int(prof["node_a"][i])])


@contextlib.contextmanager
def _working_directory(path: Path):
    # meshio's TimeSeriesWriter creates its .h5 in the current directory, not beside the .xdmf
    old = os.getcwd()
    os.chdir(path)
    try:
        yield
    finally:
        os.chdir(old)


def write_xdmf(folder: Path, scene, result, name: str = "results") -> None:
    """``results.xdmf`` + ``results.h5``: a time series (time = load fraction) of point data
    ``u`` (padded to 3 components for ParaView) and cell data sigma_x, sigma_y, sigma_z, tau_xy,
    von_mises (plus plastic_strain, the equivalent plastic strain, and plastic, the 0/1 flag, in
    elastoplastic cases, with yield_drift = |sigma_e - sigma_y(eps_p)|/sigma_y per plastic element; and body, the body index, when there are several); 2D points."""
    import meshio

    cells = [("triangle", scene.triangles)]
    plastic_fields = ("plastic_strain", "plastic") if is_elastoplastic(scene) else ()
    n = len(scene.nodes)
    with _working_directory(folder):
        with meshio.xdmf.TimeSeriesWriter(f"{name}.xdmf") as writer:
            writer.write_points_cells(scene.nodes, cells)
            for snap in result["snapshots"]:
                u = np.zeros((n, 3))
                u[:, :2] = np.asarray(snap["u"]).reshape(n, 2)
                s = np.asarray(snap["stress"], dtype=float).reshape(-1, 4)
                cell_data = {"sigma_x": [s[:, 0]], "sigma_y": [s[:, 1]], "sigma_z": [s[:, 2]],
                             "tau_xy": [s[:, 3]], "von_mises": [von_mises(s)]}
                for key in plastic_fields:
                    if key in snap:
                        cell_data[key] = [np.asarray(snap[key], dtype=np.float64)]
                if plastic_fields and "plastic" in snap:
                    cell_data["yield_drift"] = [yield_drift(scene, snap)]
                if len(scene.bodies) > 1:
                    cell_data["body"] = [scene.element_body.astype(np.float64)]
                writer.write_data(float(snap["load_fraction"]), point_data={"u": u},
                                  cell_data=cell_data)


def write_results(out: str | Path, scene, result, summary: dict, figures: bool | None = None,
                  xdmf: bool | None = None) -> list[Path]:
    """Write every output file of a run into ``out`` (created if needed); returns the paths.

    Staged in ``out/.partial-<pid>`` and renamed into place at the end.
    """
    from . import figures as figs

    out = Path(out)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:  # a ValueError, so that the CLI reports it in one line
        why = "it is a regular file" if out.is_file() else exc.strerror
        raise ValueError(f"{out}: cannot write the results there ({why}): choose another "
                         f"--out folder") from None
    options = scene.case.data["output"]
    figures = options["figures"] if figures is None else figures
    xdmf = options["xdmf"] if xdmf is None else xdmf
    stage = out / f".partial-{os.getpid()}"
    if stage.exists():
        shutil.rmtree(stage)
    stage.mkdir()
    try:
        snaps = result.get("snapshots", [])
        write_events_csv(stage / "events.csv", scene, result)
        if snaps and len(scene.pair_xy):
            write_profile_csv(stage / "contact_profile.csv", scene, snaps[-1])
        if xdmf and snaps:
            write_xdmf(stage, scene, result)
        if figures:
            figs.write_figures(stage, scene, result, summary)
        with open(stage / "summary.json", "w") as fh:
            json.dump(_json_safe(summary), fh, indent=2)
            fh.write("\n")
        written = []
        for item in sorted(stage.iterdir()):
            os.replace(item, out / item.name)
            written.append(out / item.name)
        return written
    finally:
        shutil.rmtree(stage, ignore_errors=True)


def _json_safe(value):
    """NaN/inf are not JSON: write them as null."""
    if isinstance(value, dict):
        return {k: _json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_safe(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value
