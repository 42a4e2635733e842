"""The numbers of a run: the content of ``summary.json`` and the line the CLI prints.

Contacts are summarised one by one, keyed by their case name, along the coordinate s of
:mod:`slipstep.measures.contact_edges` (for a flat below the body, s = x - point_x).  The top-level
``contact_half_width`` a and ``stick_half_width`` c exist only for a symmetric half model
(:func:`half_model_side`); every key is documented in cases/README.md (Outputs).  A 3D scene's
contacts are areas, not extents: :func:`slipstep.measures.contact_faces.contact_numbers_3d`
(contact and stick areas, their equivalent radii, resultants of the full contact).
"""

from __future__ import annotations

import math

import numpy as np

from ..measures.contact_edges import (
    closed_extent,
    contact_axis,
    contact_profile,
    crossing_times,
    pair_coordinate,
    reached_last_candidate,
    stick_extent,
    target_points,
)
from .fields import centroids, is_elastoplastic
from .history import (
    event_times,
    final_load_fraction,
    final_time,
    load_factor,
    reactions,
    snapshot_time,
    stage_ends,
    stage_names,
)
from ..measures.references import JOHNSON_LINE_YIELD, sphere_axis_yield
from ..measures.resultants import (
    driving_forces,
    drivers,
    indentation,
    snapshot_resultants,
    step_history,
)
from ..section import AXIS_TOLERANCE, is_axisymmetric
from ..measures.contact_faces import contact_numbers_3d, reached_window_edge
from ..version import versions


def half_model_side(scene, index: int) -> int:
    """+1 (or -1) when [[contact]] ``index`` is one half of a scene mirrored across s = 0:
    every body it touches has a mirror lying on the line s = 0 (so that line is perpendicular
    to the contact surface and through its origin): a [[bc]] symmetry edge, or in axisymmetry
    its nodes on the axis x = 0 (then s = r and the half width is the contact radius); and
    every candidate pair lies at s >= 0 (or s <= 0); else 0."""
    case = scene.case.record
    origin, tau = contact_axis(scene, index)
    tol = 1e-9 * float(np.ptp(scene.nodes, axis=0).max())  # round-off of the node coordinates
    for body in case.contact[index].bodies:
        mirrors = [
            np.unique(scene.global_edge(body, bc.edge))
            for bc in case.bc
            if bc.symmetry and bc.body == body
        ]
        if is_axisymmetric(scene.case):
            mirrors.append(_axis_nodes(scene, body))
        on_line = [
            len(ids) and np.abs((scene.nodes[ids] - origin) @ tau).max() <= tol for ids in mirrors
        ]
        if not any(on_line):
            return 0
    s = pair_coordinate(scene)[scene.pair_contact == index]
    if (s >= -tol).all():
        return 1
    if (s <= tol).all():
        return -1
    return 0


def half_model_sides(scene) -> list[int]:
    """:func:`half_model_side` of every [[contact]]."""
    return [half_model_side(scene, i) for i in range(len(scene.case.record.contact))]


def _axis_nodes(scene, body: str) -> np.ndarray:
    """Global ids of a body's nodes on the axis x = 0 (axisymmetry; the engine's tolerance)."""
    ids = np.arange(scene.meshes[body].n_nodes) + scene.offsets[body]
    size = float(np.linalg.norm(np.ptp(scene.nodes, axis=0))) or 1.0
    return ids[np.abs(scene.nodes[ids, 0]) <= AXIS_TOLERANCE * size]


def contact_summaries(scene, result, snapshot: dict, sides: list[int]) -> dict[str, dict]:
    """Per [[contact]] (by name) at ``snapshot``: its axis (origin, tangent), whether it is a
    half model, pair counts, closed and stick extents [s_min, s_max] (None when empty), total
    normal and tangential force (sum lambda_n, sum lambda_t: each pair's along its own frame),
    the resultant ``force`` [Fx, Fy] on the contactor body (sum lambda_n n + lambda_t t; in
    axisymmetry only Fy, the axial one, is a resultant) and peak pressure.  The closed extent
    is interpolated in path time at the snapshot's t between the edge's crossings of its stage
    (:func:`slipstep.measures.contact_edges.crossing_times`), the same way at every snapshot."""
    prof = contact_profile(scene, snapshot)
    last, upcoming = (x[prof["pair"]] for x in crossing_times(scene, result, snapshot))
    f = snapshot_time(snapshot)
    lambda_n = np.asarray(snapshot["lambda_n"], dtype=float)[prof["pair"]]
    lambda_t = np.asarray(snapshot["lambda_t"], dtype=float)[prof["pair"]]
    n_c = len(scene.model["contact_names"])
    resultant, _ = snapshot_resultants(scene, snapshot, n_c)
    out = {}
    for i, name in enumerate(scene.model["contact_names"]):
        mine = prof["contact"] == i
        s, status = prof["s"][mine], prof["status"][mine]
        closed = closed_extent(s, status, last[mine], upcoming[mine], f)
        origin, tau = contact_axis(scene, i)
        out[name] = {
            "kind": scene.case.record.contact[i].kind,
            "origin": origin.tolist(),
            "tangent": tau.tolist(),
            "half_model": sides[i] != 0,
            "n_pairs": int(mine.sum()),
            "n_closed": int((status > 0).sum()),
            "n_stick": int((status == 1).sum()),
            "n_slip": int((status == 2).sum()),
            "closed_extent": closed,
            "stick_extent": None if closed is None else stick_extent(s, status, closed),
            "total_normal_force": float(lambda_n[mine].sum()),
            "total_tangential_force": float(lambda_t[mine].sum()),
            "force": resultant[i, :2].tolist(),
            "peak_pressure": float(prof["pressure"][mine].max()),
        }
    return out


def half_widths(contacts: dict[str, dict], sides: list[int]) -> dict:
    """``contact_half_width`` a and ``stick_half_width`` c (the far ends of the closed and stick
    extents, measured from the symmetry line; 0 when empty) when the scene has one contact and
    it is a symmetric half model; else nothing."""
    if len(sides) != 1 or sides[0] == 0:
        return {}
    side, (entry,) = sides[0], contacts.values()
    far = 1 if side > 0 else 0
    closed, stick = entry["closed_extent"], entry["stick_extent"]
    return {
        "contact_half_width": side * closed[far] if closed else 0.0,
        "stick_half_width": side * stick[far] if stick else 0.0,
    }


def circle_radii(widths: dict, axisymmetric: bool) -> dict:
    """The half-widths, and in axisymmetry (a contact circle, as in 3D) the same numbers under
    the keys of a circle in every dimension, ``contact_radius`` and ``stick_radius`` (the
    half-width keys kept as aliases for one release)."""
    if not (axisymmetric and widths):
        return widths
    return {
        **widths,
        "contact_radius": widths["contact_half_width"],
        "stick_radius": widths["stick_half_width"],
    }


def solid_contact_numbers(scene, result) -> dict:
    """The contact part of a 3D summary at the final snapshot: per contact its numbers, and for
    one contact its area, radii and resultants at the top level; totals over every contact."""
    last = result["snapshots"][-1]
    status = np.asarray(last["status"])
    totals = space_contact_totals(scene, last)
    contacts = totals["contacts"]
    top = next(iter(contacts.values())) if len(contacts) == 1 else {}
    return {
        "snapshot_load_fraction": float(last["load_fraction"]),
        "snapshot_t": snapshot_time(last),
        **{
            k: top[k]
            for k in ("contact_area", "contact_radius", "stick_area", "stick_radius", "force")
            if k in top
        },
        **totals,
        "n_open": int((status == 0).sum()),
        "n_stick": int((status == 1).sum()),
        "n_slip": int((status == 2).sum()),
        "contact_reached_last_candidate": reached_window_edge(scene, last),
    }


def space_contact_totals(scene, snap: dict) -> dict:
    """A 3D snapshot's contacts (:func:`contact_numbers_3d` each) and their totals: normal
    force, tangential resultant and its size, the peak and the largest nodal pressure."""
    contacts = {
        name: contact_numbers_3d(scene, snap, i)
        for i, name in enumerate(scene.model["contact_names"])
    }
    tangential = np.sum([c["tangential_force"] for c in contacts.values()], axis=0)
    return {
        "peak_pressure": max(c["peak_pressure"] for c in contacts.values()),
        "max_nodal_pressure": max(c["max_nodal_pressure"] for c in contacts.values()),
        "total_normal_force": float(sum(c["total_normal_force"] for c in contacts.values())),
        "tangential_force": tangential.tolist(),
        "total_tangential_force": float(np.linalg.norm(tangential)),
        "contacts": contacts,
    }


def _contact_numbers(scene, result) -> dict:
    """The contact part of the summary at the final snapshot (empty without pairs)."""
    snaps = result.get("snapshots", [])
    if not (snaps and len(scene.pair_xy)):
        return {}
    return scene.idealisation.contact_numbers(scene, result)


def section_contact_numbers(scene, result) -> dict:
    """:func:`_contact_numbers` of a 2D scene (with pairs and snapshots)."""
    last = result["snapshots"][-1]
    status = np.asarray(last["status"])
    sides = half_model_sides(scene)
    contacts = contact_summaries(scene, result, last, sides)
    return {
        "snapshot_load_fraction": float(last["load_fraction"]),
        "snapshot_t": snapshot_time(last),
        **circle_radii(half_widths(contacts, sides), is_axisymmetric(scene.case)),
        "peak_pressure": max(c["peak_pressure"] for c in contacts.values()),
        "total_normal_force": float(np.sum(last["lambda_n"])),
        "total_tangential_force": float(np.sum(last["lambda_t"])),
        "n_open": int((status == 0).sum()),
        "n_stick": int((status == 1).sum()),
        "n_slip": int((status == 2).sum()),
        "contact_reached_last_candidate": reached_last_candidate(scene, last),
        "contacts": contacts,
    }


def plastic_counts(snap: dict) -> dict:
    """``n_plastic_elements``: elements yielding at the snapshot (on the yield surface and
    loading, the engine's ``plastic`` flag); ``n_yielded_elements``: elements with plastic
    strain > 0 (the plastic zone, which stays after unloading).  Empty for an elastic run."""
    out = {}
    if "plastic" in snap:
        out["n_plastic_elements"] = int(np.count_nonzero(snap["plastic"]))
    if "plastic_strain" in snap:
        out["n_yielded_elements"] = int(np.count_nonzero(np.asarray(snap["plastic_strain"]) > 0))
    return out


STAGE_CONTACT_KEYS = (
    "closed_extent",
    "stick_extent",
    "n_closed",
    "n_stick",
    "n_slip",
    "total_normal_force",
    "total_tangential_force",
    "peak_pressure",
)


def section_stage_contact(scene, result, snap: dict) -> dict:
    """A 2D stage record's contact numbers: total forces, the peak pressure and each contact's
    :data:`STAGE_CONTACT_KEYS`."""
    sides = half_model_sides(scene)
    contacts = contact_summaries(scene, result, snap, sides)
    return {
        "total_normal_force": float(np.sum(snap["lambda_n"])),
        "total_tangential_force": float(np.sum(snap["lambda_t"])),
        "peak_pressure": max(c["peak_pressure"] for c in contacts.values()),
        "contacts": {name: {k: c[k] for k in STAGE_CONTACT_KEYS} for name, c in contacts.items()},
    }


def solid_stage_contact(scene, snap: dict) -> dict:
    """A 3D stage record's contact numbers: :func:`space_contact_totals`, the tangential
    resultant by its size only."""
    totals = space_contact_totals(scene, snap)
    del totals["tangential_force"]
    return totals


def _snapshot_numbers(scene, result, snap: dict) -> dict:
    """Contact forces, per-contact extents, plastic elements and support reactions at one
    snapshot (the parts that apply)."""
    out = {}
    if len(scene.pair_xy):
        out.update(scene.idealisation.stage_contact_numbers(scene, result, snap))
    out.update(plastic_counts(snap))
    out["reactions"] = {name: list(r) for name, r in reactions(scene, snap).items()}
    return out


def stage_records(scene, result, hist: dict | None = None) -> list[dict]:
    """One record per completed stage, at the snapshot ending it (:func:`stage_ends`): stage
    (1-based), name, t_end, n_events (rows of events.csv in the stage), then
    :func:`_snapshot_numbers`, and ``driving_forces`` (each driving load's force at the stage's
    end, the history's last row there)."""
    snaps = result.get("snapshots", [])
    names = stage_names(scene, result)
    _, ev_stage = event_times(result)
    hist = step_history(scene, result) if hist is None else hist
    forces = driving_forces_along(scene, hist)
    records = []
    for k, i in stage_ends(result, len(names)):
        t_end = snapshot_time(snaps[i])
        records.append(
            {
                "stage": k + 1,
                "name": names[k],
                "t_end": t_end,
                "n_events": int(np.count_nonzero(ev_stage == k)),
                **_snapshot_numbers(scene, result, snaps[i]),
            }
        )
        row = np.flatnonzero(np.abs(hist["t"] - t_end) <= 1e-12 * max(1.0, t_end))
        if len(row) and forces:
            records[-1]["driving_forces"] = {name: float(f[row[-1]]) for name, f in forces.items()}
    return records


def driving_forces_along(scene, hist: dict) -> dict[str, np.ndarray]:
    """Each driving load's force along the history (the whole's; :func:`slipstep.measures.resultants.
    drivers`)."""
    return {name: d["force"] for name, d in drivers(scene, hist).items()}


# --------------------------------------------------------------------------- first yield
def element_depth(scene, element: int) -> float:
    """Depth of an element's centroid below the initial contact surface of its body.

    The surface near the element is taken as the tangent line at the nearest candidate pair of a
    contact on the element's body: through the pair's target point (:func:`slipstep.measures.contact_edges.target_points`) with
    the pair's normal n, so for a ``rigid_line`` contact this is the distance from the line.
    Without contact on the body: the centroid's y (3D: z).
    """
    c = centroids(scene.nodes, scene.elements[[element]])[0]
    pairs = scene.model["pairs"]
    node_a, node_b = np.asarray(pairs["node_a"]), np.asarray(pairs["node_b"])
    body = scene.bodies[scene.element_body[element]]
    lo = scene.offsets[body]
    hi = lo + scene.meshes[body].n_nodes
    mine = ((node_a >= lo) & (node_a < hi)) | ((node_b >= lo) & (node_b < hi))
    if not mine.any():
        return float(c[-1])
    idx = np.flatnonzero(mine)
    k = idx[np.argmin(np.linalg.norm(scene.pair_xy[idx] - c, axis=1))]
    return float(abs((c - target_points(scene)[k]) @ np.asarray(pairs["normal"])[k]))


def first_yield(scene, result) -> dict:
    """The first ``yield`` event: load fraction, element, its centroid x and depth
    (:func:`element_depth`); every value None when nothing yielded."""
    kinds = list(result["events"]["kind"])
    if "yield" not in kinds:
        return {
            "first_yield_load_fraction": None,
            "first_yield_element": None,
            "first_yield_x": None,
            "first_yield_depth": None,
        }
    k = kinds.index("yield")
    e = int(result["events"]["entity"][k])
    return {
        "first_yield_load_fraction": float(result["events"]["load_fraction"][k]),
        "first_yield_element": e,
        "first_yield_x": float(centroids(scene.nodes, scene.elements[[e]])[0, 0]),
        "first_yield_depth": element_depth(scene, e),
    }


def johnson_first_yield(scene) -> float | None:
    """The load fraction of first yield (von Mises) of a frictionless Hertz contact: a line
    contact yields below the surface when p0 = 1.79 Sy (Johnson, Contact Mechanics §4.3/§6.2,
    nu = 0.3), p0 growing as sqrt(f); a sphere when p0 = Sy / m
    (:func:`slipstep.measures.references.sphere_axis_yield`, m = 0.62 at nu = 0.3), p0 growing as
    f^(1/3).  So f = (p0 at yield / p0_hertz)^(1/exponent)
    with p0_hertz at full load.  None if the body is elastic."""
    ref = scene.reference
    if not ref:
        return None
    material = scene.case.record.hertz_body.material
    sy = material.Sy
    if sy is None:
        return None
    if ref.get("contact") == "sphere":
        return (sy / sphere_axis_yield(material.nu)[0] / ref["p0_hertz"]) ** 3
    return (JOHNSON_LINE_YIELD * sy / ref["p0_hertz"]) ** 2


def _hertz_numbers(scene, summary: dict, f: float) -> dict:
    """The closed-form Hertz values at the reached factor f of the load (a and p0 ~ f^k,
    k = ``load_exponent``: 1/2 for a line contact, 1/3 for a sphere, whose approach delta goes
    as f^(2/3)) and the run's relative errors against them; Johnson's first yield when plastic
    (for a sphere also the depth of Huber's axis maximum at that load)."""
    ref = dict(scene.reference)
    f = max(f, 0.0)
    scale = math.sqrt(f) if ref["contact"] == "line" else f ** ref["load_exponent"]
    ref["a_hertz_at_final"] = ref["a_hertz"] * scale
    ref["p0_hertz_at_final"] = ref["p0_hertz"] * scale
    if "delta_hertz" in ref:
        ref["delta_hertz_at_final"] = ref["delta_hertz"] * scale**2
    width = summary.get("contact_half_width", summary.get("contact_radius"))  # 3D: the radius
    if width is not None and ref["a_hertz_at_final"] > 0:
        ref["a_rel_error"] = width / ref["a_hertz_at_final"] - 1.0
        ref["p0_rel_error"] = summary["peak_pressure"] / ref["p0_hertz_at_final"] - 1.0
    f_johnson = johnson_first_yield(scene)
    if f_johnson is not None:
        ref["f_yield_johnson"] = f_johnson
        f_fe = summary.get("first_yield_load_fraction")
        ref["first_yield_rel_error"] = None if f_fe is None else f_fe / f_johnson - 1.0
        if ref.get("contact") == "sphere":
            nu = scene.case.record.hertz_body.material.nu
            depth = sphere_axis_yield(nu)[1] * ref["a_hertz"] * f_johnson ** (1.0 / 3.0)
            ref["first_yield_depth_huber"] = depth
    return ref


def driver_numbers(scene, result, hist: dict | None = None) -> dict:
    """``driving_forces`` (by load name: the loads that drive the run, their force and
    displacement at the end and the largest force reached, :func:`slipstep.measures.resultants.
    driving_forces`), ``driving_force`` (the force of the load that moves in the last stage,
    else the first one's) and ``indentation`` (Oliver–Pharr, by load name, for an indenter that
    unloads: :func:`slipstep.measures.resultants.indentation`); empty without drivers."""
    hist = step_history(scene, result) if hist is None else hist
    forces = driving_forces(scene, hist)
    if not forces:
        return {}
    factor, stage = hist["factor"], hist["stage"]
    last = stage == stage.max() if len(stage) else np.zeros(0, bool)
    moving = [
        name
        for name in forces
        if last.any() and np.ptp(factor[last, list(hist["load_names"]).index(name)]) > 0
    ]
    main = (moving or list(forces))[0]
    out = {"driving_forces": forces, "driving_force": {"name": main, **forces[main]}}
    ind = indentation(scene, hist)
    if ind:
        out["indentation"] = ind
    return out


def summarize(scene, result, wall_time_s: float = float("nan")) -> dict:
    """The numbers of a run, for summary.json and the one-line report."""
    model = scene.model
    snaps = result.get("snapshots", [])
    f = final_load_fraction(result)
    stop = result["stop"]
    names = stage_names(scene, result)
    summary = {
        "case": scene.case.name,
        "units": scene.case.units,
        "n_events": int(len(result["events"]["step"])),
        "n_steps": int(len(result["steps"]["load_fraction"])),
        "final_load_fraction": f,
        "stop": {
            "kind": stop["kind"],
            "message": stop["message"],
            "load_fraction": float(stop["load_fraction"]),
            "t": final_time(result),
        },
        "final_t": final_time(result),
        "n_stages": len(names),
        "stage_names": names,
        "interrupted": stop["kind"] == "interrupted",
        "stop_reason": result.get("stop_reason"),
        "n_nodes": int(len(model["nodes"])),
        "n_elements": int(len(scene.elements)),
        "n_dofs": int(scene.n_dofs),
        "n_pairs": int(len(model["pairs"]["node_a"])),
        "frictionless": scene.case.record.frictionless,
        "n_factorizations": int(result.get("n_factorizations", 0)),
        "n_factor_builds": int(result.get("n_factor_builds", 0)),
        "n_solves": int(result.get("n_solves", 0)),
        "n_contact_substeps": int(result.get("n_contact_substeps", 0)),
        "n_retaken_windows": int(result.get("n_retaken_windows", 0)),
        "max_equilibrium_residual": float(result.get("max_equilibrium_residual", float("nan"))),
        "max_drift": float(result.get("max_drift", 0.0)),
        "wall_time_s": float(wall_time_s),
        "engine_timings_s": {k: float(v) for k, v in result.get("timings", {}).items()},
        "versions": versions(),
    }
    if snaps:
        stress = np.asarray(snaps[-1]["stress"], dtype=float)
        mises = scene.idealisation.von_mises(stress)
        summary["max_von_mises"] = float(mises.max()) if len(mises) else 0.0
    if is_elastoplastic(scene):
        summary.update(first_yield(scene, result))
        if snaps:
            summary.update(plastic_counts(snaps[-1]))
    summary.update(_contact_numbers(scene, result))
    if snaps and "reaction" in snaps[-1]:
        summary["reactions"] = {k: list(r) for k, r in reactions(scene, snaps[-1]).items()}
    hist = step_history(scene, result)
    summary.update(driver_numbers(scene, result, hist))
    summary["stages"] = stage_records(scene, result, hist)
    if scene.reference:
        # one stage: every factor is f; else the factor of the load pattern at the end
        load = f if len(names) == 1 else float(load_factor(scene, "load", summary["final_t"]))
        summary["hertz"] = _hertz_numbers(scene, summary, load)
    return summary


def quantity(summary: dict, value: float, kind: str) -> str:
    """``value`` to four digits with the case's unit of ``kind`` (length, force or stress, from
    ``[case] units`` given as "length, force, stress"); no unit when the case gives none."""
    unit = summary.get("units", {}).get(kind)
    return f"{value:.4g} {unit}" if unit else f"{value:.4g}"


def contact_text(summary: dict, named: bool = False) -> str:
    """The contact state in a few words: a and c of a half model, else each contact's closed
    and stick extents along s, in the case's length unit (``named``: a and c named); empty
    without contact.  A frictionless run has no stick zone: c is left out."""
    stick = not summary.get("frictionless", False)
    for a_key, c_key, what in (
        ("contact_radius", "stick_radius", "radius"),
        ("contact_half_width", "stick_half_width", "half-width"),
    ):
        if a_key in summary:
            a = quantity(summary, summary[a_key], "length")
            c = quantity(summary, summary[c_key], "length")
            if named:
                return f"a = {a} contact {what}" + (f", c = {c} stick {what}" if stick else "")
            return f"a = {a}" + (f", c = {c}" if stick else "")
    unit = summary.get("units", {}).get("length")
    unit = f" {unit}" if unit else ""
    parts = []
    for name, c in summary.get("contacts", {}).items():
        if "contact_radius" in c:  # 3D
            parts.append(
                f"{name}: contact radius {c['contact_radius']:.4g}{unit}"
                + (f", stick radius {c['stick_radius']:.4g}{unit}" if stick else "")
            )
            continue
        closed, stick = c["closed_extent"], c["stick_extent"]
        text = f"{name}: " + (
            f"closed s in [{closed[0]:.4g}, {closed[1]:.4g}]{unit}" if closed else "open"
        )
        if stick:
            text += f", stick [{stick[0]:.4g}, {stick[1]:.4g}]{unit}"
        parts.append(text)
    return "; ".join(parts)


def driver_text(summary: dict) -> list[str]:
    """The driving forces in a few words each, named by their load: ``pyramid: F = 43.66 N
    along its motion at 0.03 mm`` (with its largest when the run unloaded from it), then the
    Oliver–Pharr hardness and reduced modulus of an indenter that unloaded."""
    what = {
        "motion": "along its motion at {u}",
        "displacement": "reaction at {u} along it",
        "load": "resultant, its nodes {u} along it",
    }
    out = []
    for name, d in summary.get("driving_forces", {}).items():
        force = d["force"] if abs(d["force"]) > 1e-12 * abs(d["max_force"]) else 0.0
        u = quantity(summary, d["displacement"], "length")
        text = f"{name}: F = {quantity(summary, force, 'force')} " + what[d["kind"]].format(u=u)
        if d["max_force"] > d["force"] + 1e-3 * abs(d["max_force"]):  # it unloaded
            text += (
                f" (max {quantity(summary, d['max_force'], 'force')} at "
                f"{quantity(summary, d['displacement_at_max'], 'length')})"
            )
        out.append(text)
    for name, op in summary.get("indentation", {}).items():
        out.append(
            f"Oliver-Pharr ({name}): H = {quantity(summary, op['H'], 'stress')}, "
            f"E_r = {quantity(summary, op['E_r'], 'stress')}"
        )
    return out


def one_line(summary: dict) -> str:
    """The summary the CLI prints: each quantity named, in the case's units (:func:`quantity`)."""
    parts = [f"{summary['case']}: {summary['n_events']} events"]
    if summary.get("n_stages", 1) > 1:
        parts.append(f"t = {summary['final_t']:.4g} of {summary['n_stages']} stages")
    else:
        parts.append(f"f = {summary['final_load_fraction']:.4g} load fraction")
    if contact_text(summary):
        p0 = quantity(summary, summary["peak_pressure"], "stress")
        parts += [contact_text(summary, named=True), f"p0 = {p0} peak pressure"]
    if "hertz" in summary and "a_rel_error" in summary["hertz"]:
        h = summary["hertz"]
        parts.append(
            f"(Hertz a = {quantity(summary, h['a_hertz_at_final'], 'length')}, "
            f"p0 = {quantity(summary, h['p0_hertz_at_final'], 'stress')})"
        )
    parts += driver_text(summary)
    if summary.get("first_yield_load_fraction") is not None:
        now = summary.get("n_plastic_elements", 0)
        parts += [
            f"first yield at f = {summary['first_yield_load_fraction']:.4g}",
            f"{summary.get('n_yielded_elements', now)} elements yielded (plastic strain "
            f"> 0), {now} yielding now",
        ]
    parts += [f"{summary['n_dofs']} dofs", f"{summary['wall_time_s']:.2f} s"]
    if summary["stop"]["kind"] == "interrupted":
        parts.append("INTERRUPTED")
    return ", ".join(parts)
