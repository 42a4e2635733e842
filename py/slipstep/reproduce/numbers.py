"""The numbers of the reproduction: Table 1 against Hertz and Johnson, the half-space size
check, the paper's claims as measured checks, the cylinder and block results, and the
load-settlement of the punch; all of them end in reproduce.json."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..measures.contact_edges import contact_half_width
from ..output.fields import centroids
from .. import sweep
from .scenes import (
    A_HERTZ,
    A_JOHNSON,
    BLOCK_B,
    F_JOHNSON,
    MUS,
    P0_HERTZ,
    P0_JOHNSON,
    PAPER_TABLE1,
    R,
    Run,
    Settings,
    mu_id,
)


def threshold_half_width(el: Run, yl: Run, f_y: float) -> float:
    """Contact half-width at the first yield load f_y.  The run that stops at its first yield
    event never predicts the next closure, so its own half-width is the outermost closed node.
    Up to f_y the elastoplastic run IS the elastic one (same mesh, mu = 0), so the closure
    fractions of the elastic run give the same interpolation the summary uses:
    a = x_c + (x_o - x_c) (f_y - f_c) / (f_o - f_c)."""
    if not np.allclose(el.x, yl.x):
        return yl.a
    status = yl.status()
    closure = el.data["closure_fraction"]
    # the next open node's closure in the elastic run = its predicted closure here
    predicted = np.where(status > 0, np.inf, closure)
    return contact_half_width(el.x, status, closure, predicted, f_y)


def table1(el: Run, yl: Run, h: float) -> dict:
    s = yl.summary
    p_y, f_y = float(s["peak_pressure"]), float(s["first_yield_load_fraction"])
    a_y = threshold_half_width(el, yl, f_y)
    depth = s["first_yield_depth"]
    return {
        "h_contact": h,
        "elastic_a": el.a,
        "elastic_a_err": el.a / A_HERTZ - 1,
        "elastic_p0": float(el.summary["peak_pressure"]),
        "elastic_p0_err": float(el.summary["peak_pressure"]) / P0_HERTZ - 1,
        "yield_f": f_y,
        "yield_f_err": f_y / F_JOHNSON - 1,
        "yield_a": a_y,
        "yield_a_err": a_y / A_JOHNSON - 1,
        "yield_a_err_paper": a_y / PAPER_TABLE1["yield_a"][0] - 1,
        "yield_p0": p_y,
        "yield_p0_err": p_y / P0_JOHNSON - 1,
        "yield_a_outermost_closed_node": yl.a,
        "yield_depth": float(depth),
        "yield_depth_over_a": float(depth) / a_y,
        "yield_x": float(s.get("first_yield_x", float("nan"))),
        "a_johnson": A_JOHNSON,
        "p0_johnson": P0_JOHNSON,
        "f_johnson": F_JOHNSON,
        "a_hertz": A_HERTZ,
        "p0_hertz": P0_HERTZ,
    }


def doubling(r1: Run, r2: Run) -> float:
    """Largest change of the interface pressure, node by node, relative to the peak."""
    p1, p2 = r1.profile("pressure"), r2.profile("pressure")
    assert np.allclose(r1.x, r2.x)
    return float(np.max(np.abs(p2 - p1)) / np.max(np.abs(p1)))


def surface_transition(rows: list[dict]) -> float | None:
    """Smallest mu of the Fig. 10 sweep whose first yield is at the surface (depth < a/4)."""
    return next((r["mu"] for r in rows if r["depth"] < 0.25 * r["a"]), None)


def checks(cyl_el: dict, cyl_pl: dict, fig10_rows: list[dict], blocks: dict) -> dict:
    """The paper's claims, measured.  ``required`` marks the ones the tests assert;
    the others are reported (some are mesh-sensitive or do not hold)."""
    out = {}

    def add(name, claim, value, ok, required=False):
        out[name] = {"claim": claim, "value": value, "pass": bool(ok), "required": required}

    _cylinder_checks(add, cyl_el, cyl_pl)
    _onset_checks(add, fig10_rows)
    _interface_checks(add, cyl_el, cyl_pl)
    _block_checks(add, blocks)
    return out


def _cylinder_checks(add, cyl_el: dict, cyl_pl: dict) -> None:
    """Figs. 6-9, the claims the tests assert: a longer, flatter plastic contact; the slip zone
    shrinking with mu."""
    a_el = {mu: cyl_el[mu].a for mu in MUS}
    a_pl = {mu: cyl_pl[mu].a for mu in MUS}
    add(
        "plastic_contact_longer",
        "cylinder: elastoplastic contact half-length > elastic at "
        "full load, each mu [elastic, plastic]",
        {f"{mu:g}": [a_el[mu], a_pl[mu]] for mu in MUS},
        all(a_pl[mu] > a_el[mu] for mu in MUS),
        True,
    )
    r_el = {mu: cyl_el[mu].pressure_ratio() for mu in MUS}
    r_pl = {mu: cyl_pl[mu].pressure_ratio() for mu in MUS}
    add(
        "plastic_pressure_flatter",
        "cylinder: peak / mean pressure smaller when plastic, each "
        "mu [elastic, plastic] (Hertz: 4/pi = 1.273)",
        {f"{mu:g}": [r_el[mu], r_pl[mu]] for mu in MUS},
        all(r_pl[mu] < r_el[mu] for mu in MUS),
        True,
    )
    for kind, runs in (("elastic", cyl_el), ("plastic", cyl_pl)):
        slip = [runs[mu].slip_length() for mu in MUS]
        add(
            f"slip_zone_shrinks_{kind}",
            f"cylinder, {kind}: slip zone a - c shrinks as mu "
            f"grows (mu = {', '.join(f'{m:g}' for m in MUS)})",
            slip,
            all(b < a for a, b in zip(slip, slip[1:])),
            True,
        )


def _onset_checks(add, fig10_rows: list[dict]) -> None:
    """Fig. 10: the onset of yield against mu."""
    f = [r["f"] for r in fig10_rows]
    mu_s = surface_transition(fig10_rows)
    tail = [r["f"] for r in fig10_rows if mu_s is not None and r["mu"] >= mu_s]
    add(
        "onset_falls",
        "Fig. 10: onset-of-yield load lower at mu = 0.5 than at mu = 0, and "
        "non-increasing from the mu where first yield moves to the surface",
        {"f(0)": f[0], "f(0.5)": f[-1], "surface from mu": mu_s, "f from there": tail},
        f[-1] < f[0]
        and mu_s is not None
        and all(b <= a * (1 + 1e-9) for a, b in zip(tail, tail[1:])),
        True,
    )
    head = [r["f"] for r in fig10_rows if mu_s is None or r["mu"] < mu_s]
    add(
        "onset_falls_everywhere",
        "Fig. 10 as drawn by the paper: onset non-increasing for every "
        "mu (here: also while yield starts below the surface)",
        head,
        all(b <= a * (1 + 1e-9) for a, b in zip(head, head[1:])),
    )


def _interface_checks(add, cyl_el: dict, cyl_pl: dict) -> None:
    """Figs. 5-8, reported: the finer patterns of pressure, length, RTD, tangential stress and
    plastic zone with mu."""
    a_pl = {mu: cyl_pl[mu].a for mu in MUS}
    a_el = {mu: cyl_el[mu].a for mu in MUS}
    p_centre = [float(cyl_el[mu].profile("pressure")[0]) for mu in MUS]
    add(
        "elastic_centre_pressure_rises",
        "Fig. 6: elastic central pressure increases slightly " "with mu",
        p_centre,
        all(b > a for a, b in zip(p_centre, p_centre[1:])),
    )
    pp = [float(cyl_pl[mu].profile("pressure")[0]) for mu in MUS]
    add(
        "plastic_centre_pressure_pattern",
        "Fig. 6: elastoplastic central pressure rises from "
        "mu = 0 to 0.1, then drops back towards the frictionless value at 0.35",
        pp,
        pp[1] > pp[0] and pp[2] < pp[1],
    )
    al = [a_pl[mu] for mu in MUS]
    add(
        "plastic_length_pattern",
        "Figs. 6/9: elastoplastic contact length decreases from "
        "mu = 0 to 0.1, then grows back towards the frictionless value at 0.35",
        al,
        al[1] < al[0] and al[2] > al[1],
    )
    rtd = {}
    for mu in MUS:
        inside = cyl_el[mu].x <= a_el[mu]
        rtd[f"{mu:g}"] = [
            float(np.abs(r.profile("rtd")[inside]).max()) for r in (cyl_el[mu], cyl_pl[mu])
        ]
    add(
        "plastic_rtd_smaller",
        "Fig. 7: RTD smaller when plastic (largest abs(RTD) inside the elastic "
        "contact) [elastic, plastic]",
        rtd,
        all(v[1] < v[0] for v in rtd.values()),
    )
    tau = {
        f"{mu:g}": [
            float(np.abs(r.profile("tangential_stress")).max()) for r in (cyl_el[mu], cyl_pl[mu])
        ]
        for mu in MUS
        if mu > 0
    }
    add(
        "plastic_tangential_smaller",
        "Fig. 8: tangential stress smaller when plastic (peak) " "[elastic, plastic]",
        tau,
        all(v[1] < v[0] for v in tau.values()),
    )
    zones = []
    for mu in MUS:
        d = cyl_pl[mu].data
        zones.append(_area(d["nodes"], d["triangles"], d["plastic_strain"] > 0))
    add(
        "plastic_zone_grows",
        "Fig. 5: plastic zone area (mm^2) grows with mu",
        zones,
        all(b > a for a, b in zip(zones, zones[1:])),
    )


def _block_checks(add, blocks: dict) -> None:
    """Figs. 14-16: the elastoplastic block's pressure, slip and tangential stress."""
    bp = blocks["plastic"]
    pc = [float(bp[mu].profile("pressure")[0]) for mu in (0.0, 0.2)]
    add(
        "block_centre_pressure_mu",
        "Fig. 14: block, central pressure for mu = 0.2 slightly " "larger than for mu = 0",
        pc,
        pc[1] > pc[0],
    )
    run = bp[0.2]
    levels = snapshot_levels(run)
    slips = [run.slip_length(run.snapshot_index(f), a=BLOCK_B) for f in levels]
    add(
        "block_slip_zone_shrinks_with_load",
        "Fig. 15: block mu = 0.2, slip zone (mm) " "decreases as the load increases",
        {f"{f:g}": s for f, s in zip(levels, slips)},
        slips[-1] < slips[0] and all(b <= a + 1e-9 for a, b in zip(slips, slips[1:])),
    )
    peak = [
        float(np.abs(run.profile("tangential_stress", run.snapshot_index(f))).max()) for f in levels
    ]
    add(
        "block_tangential_stress_grows",
        "Fig. 16: block mu = 0.2, peak tangential stress "
        "(MPa) larger at full load than at the lowest level shown",
        {f"{f:g}": t for f, t in zip(levels, peak)},
        peak[-1] > peak[0],
    )
    rtd_b, tau_b = run.profile("rtd"), run.profile("tangential_stress")
    slipping = run.status() == 2
    add(
        "block_tangential_opposes_rtd",
        "Figs. 15/16: tangential stress opposes the RTD in the "
        "slip zone (number of slipping pairs)",
        int(slipping.sum()),
        bool(np.all(rtd_b[slipping] * tau_b[slipping] <= 0)),
    )


def zone_at_surface(run: Run) -> bool | None:
    """Does the yielded zone of a cylinder run touch the contact (an element with a node on
    the arc inside the contact half-width)?"""
    d = run.data
    if "plastic_strain" not in d:
        return None
    nodes, tri = d["nodes"], d["triangles"]
    x, y = nodes[:, 0], nodes[:, 1]
    on_arc = (np.abs(y - (R - np.sqrt(np.clip(R**2 - x**2, 0, None)))) < 1e-6) & (x <= run.a)
    yielded = d["plastic_strain"] > 0
    return bool(on_arc[tri[yielded]].any())


def snapshot_levels(run: Run) -> list[float]:
    """The snapshot load fractions Figs. 15-16 show: 0.4, 0.5, ... 1.0 (those the run has)."""
    fs = run.data["snap_load_fraction"]
    return [float(f) for f in fs if f >= 0.4 - 1e-9 and abs(10 * f - round(10 * f)) < 1e-9]


def _area(nodes, tri, mask) -> float:
    t = nodes[tri[mask]]
    return float(
        0.5
        * np.abs(
            (t[:, 1, 0] - t[:, 0, 0]) * (t[:, 2, 1] - t[:, 0, 1])
            - (t[:, 2, 0] - t[:, 0, 0]) * (t[:, 1, 1] - t[:, 0, 1])
        ).sum()
    )


def block_numbers(blocks: dict, reference: Run) -> dict:
    el = blocks["elastic"]
    out = {
        "elastic": {
            "p_centre": float(el.profile("pressure")[0]),
            "p_edge": float(
                el.profile("pressure")[-1]
                if el.x[-1] <= BLOCK_B + 1e-9
                else el.profile("pressure")[el.x <= BLOCK_B + 1e-9][-1]
            ),
            "stick_half_width": float(el.summary["stick_half_width"]),
            "n_events": int(el.summary["n_events"]),
            "max_event_f": float(np.max(el.data["events_load_fraction"], initial=0.0)),
            "n_nodes": int(el.summary["n_nodes"]),
            "n_elements": int(el.summary["n_elements"]),
        }
    }
    for mu, r in blocks["plastic"].items():
        d = r.data
        eb = d["element_body"]
        yielded = d["plastic_strain"] > 0
        cent = centroids(d["nodes"], d["triangles"])
        lower = yielded & (eb == 1)
        out[f"plastic_mu{mu:g}"] = {
            "p_centre": float(r.profile("pressure")[0]),
            "p_peak": float(r.summary["peak_pressure"]),
            "stick_half_width": float(r.summary["stick_half_width"]),
            "first_yield_f": r.summary.get("first_yield_load_fraction"),
            "yielded_punch": int((yielded & (eb == 0)).sum()),
            "yielded_halfspace": int(lower.sum()),
            "plastic_zone_depth": float(-cent[lower, 1].min()) if lower.any() else 0.0,
            "plastic_zone_width": float(cent[lower, 0].max()) if lower.any() else 0.0,
            "max_plastic_strain": float(d["plastic_strain"].max()),
            "max_drift": float(r.summary.get("max_drift", 0.0)),
            "n_events": int(r.summary["n_events"]),
            "slip_by_level": {
                f"{f:g}": r.slip_length(r.snapshot_index(f), a=BLOCK_B) for f in snapshot_levels(r)
            },
        }
    out["elastic_reference_q36_mu0.2"] = {
        "p_centre": float(reference.profile("pressure")[0]),
        "p_peak": float(reference.summary["peak_pressure"]),
    }
    return out


def settlement(run: Run) -> dict:
    """Load-settlement of a block run (top centre of the punch, from the snapshots): the
    settlement at full load and the tangent stiffness of the last snapshot interval relative
    to the initial (elastic) one."""
    d = run.data
    nodes, u, f = d["nodes"], d["snap_u"], d["snap_load_fraction"]
    top = np.flatnonzero((np.abs(nodes[:, 0]) < 1e-9))
    top = top[np.argmax(nodes[top, 1])]
    v = -u[:, top, 1]
    k0 = f[0] / v[0]
    k = np.diff(f) / np.diff(v) / k0  # incremental stiffness / elastic, per interval
    soft = np.flatnonzero(k < 0.1)
    return {
        "settlement": float(v[-1]),
        "load_fraction": float(f[-1]),
        "tangent_stiffness_ratio": float(k[-1]),
        "flow_from_load_fraction": float(f[soft[0]]) if len(soft) else None,
        "curve": [[float(a), float(b)] for a, b in zip(f, v)],
    }


def scene_groups(run: dict) -> dict:
    """The runs by role: the cylinders by mu (``cyl_el``, ``cyl_pl``), the blocks (elastic, and
    plastic by mu), and the 1x runs the half-space doubling compares with."""
    return {
        "cyl_el": {mu: run[f"cyl_elastic_mu{mu_id(mu)}"] for mu in MUS},
        "cyl_pl": {mu: run[f"cyl_plastic_mu{mu_id(mu)}"] for mu in MUS},
        "blocks": {
            "elastic": run["block_elastic"],
            "plastic": {mu: run[f"block_plastic_mu{mu_id(mu)}"] for mu in (0.0, 0.2)},
        },
        "el_1x": run.get("check_block_elastic_1x", run["block_elastic"]),
        "pl_1x": run.get("check_block_plastic_1x", run[f"block_plastic_mu{mu_id(0.2)}"]),
    }


def onset_rows(study: sweep.Study, folder: Path) -> list[dict]:
    """Fig. 10: per case of the study, mu and the first yield (load fraction, depth, x) with
    the contact half-width then."""
    rows = []
    for t in study.tasks():
        sm = sweep.load_summary(folder, t["case_id"])
        rows.append(
            {
                "mu": t["params"]["contact.mu"],
                "f": sm["first_yield_load_fraction"],
                "depth": sm["first_yield_depth"],
                "x": sm["first_yield_x"],
                "a": sm["contact_half_width"],
            }
        )
    return rows


def collect(
    s: Settings, run: dict, probe_failed: dict, fig10_rows: list[dict], runs_dir: Path
) -> dict:
    """Every number of the reproduction but the events, timings, figures and the axisymmetric
    page (:func:`slipstep.reproduce.reproduce` adds those)."""
    g = scene_groups(run)
    numbers = {
        "quick": s.quick,
        "settings": s.__dict__,
        "table1": table1(run["table1_elastic"], run["table1_yield"], s.h_table),
        "paper_table1": PAPER_TABLE1,
        "half_space_doubling": half_space_doubling(s, run, g),
        "fig10": fig10_rows,
        "checks": checks(g["cyl_el"], g["cyl_pl"], fig10_rows, g["blocks"]),
        "cylinder": cylinder_numbers(g["cyl_el"], g["cyl_pl"]),
        "blocks": block_numbers(g["blocks"], run["block_plastic_elastic_reference"]),
    }
    for mu in (0.0, 0.2):
        numbers["blocks"][f"plastic_mu{mu:g}"]["load_settlement"] = settlement(
            g["blocks"]["plastic"][mu]
        )
    probe = run.get("probe_block_perfectly_plastic")
    numbers["blocks"]["perfectly_plastic_halfspace"] = (
        {
            "h": s.h_check_plastic,
            **settlement(probe),
            "yielded_halfspace": int(
                ((probe.data["plastic_strain"] > 0) & (probe.data["element_body"] == 1)).sum()
            ),
        }
        if probe is not None
        else {"error": probe_failed.get("probe_block_perfectly_plastic")}
    )
    numbers["warnings"] = [
        f"{cid}: per-run figures not written ({r.summary['figures_error']})"
        for cid, r in run.items()
        if r.summary.get("figures_error")
    ]
    numbers["warnings"] += [f"{cid}: did not finish ({msg})" for cid, msg in probe_failed.items()]
    numbers["per_run_von_mises"] = all(
        (runs_dir / f"cyl_plastic_mu{mu_id(mu)}" / "von_mises.png").exists() for mu in MUS
    )
    numbers["runs"] = {
        cid: {
            "n_events": int(r.summary["n_events"]),
            "n_nodes": int(r.summary["n_nodes"]),
            "wall_time_s": float(r.summary["wall_time_s"]),
        }
        for cid, r in run.items()
    }
    return numbers


def half_space_doubling(s: Settings, run: dict, g: dict) -> dict:
    """The half-space doubled against the case's size: the largest change of the interface
    pressure, of the centre pressure, and the stick half-widths (elastic; plastic mu = 0.2)."""
    out = {}
    for key, r1, r2, h in (
        ("elastic", g["el_1x"], run["check_block_elastic_2x"], s.h_check_elastic),
        ("plastic_mu0.2", g["pl_1x"], run["check_block_plastic_2x"], s.h_check_plastic),
    ):
        out[key] = {
            "h": h,
            "max_pressure_change": doubling(r1, r2),
            "centre_pressure_change": float(
                r2.profile("pressure")[0] / r1.profile("pressure")[0] - 1
            ),
            "stick_half_width": [
                float(r1.summary["stick_half_width"]),
                float(r2.summary["stick_half_width"]),
            ],
        }
    return out


def cylinder_numbers(cyl_el: dict, cyl_pl: dict) -> dict:
    """Per cylinder run (elastic and plastic, each mu): contact size, pressures, slip, events,
    yield."""
    return {
        f"{kind}_mu{mu:g}": {
            "a": r.a,
            "c": float(r.summary["stick_half_width"]),
            "p0": float(r.summary["peak_pressure"]),
            "p_centre": float(r.profile("pressure")[0]),
            "peak_over_mean": r.pressure_ratio(),
            "slip_length": r.slip_length(),
            "n_events": int(r.summary["n_events"]),
            "n_plastic": r.summary.get("n_plastic_elements"),
            "yielded": int((r.data["plastic_strain"] > 0).sum())
            if "plastic_strain" in r.data
            else None,
            "first_yield_f": r.summary.get("first_yield_load_fraction"),
            "zone_at_surface": zone_at_surface(r),
            "wall_time_s": float(r.summary["wall_time_s"]),
        }
        for kind, group in (("elastic", cyl_el), ("plastic", cyl_pl))
        for mu, r in group.items()
    }
