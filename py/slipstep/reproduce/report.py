"""report.md of ``slipstep reproduce``: the numbers (those of reproduce.json) put into the
template ``report.md`` beside this module.  The template holds the prose; :func:`values` gives
its fields, and picks here every phrase whose wording depends on a result (whether a claim
holds, which regime Fig. 10 shows, whether the probe collapsed)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .scenes import (
    A_HERTZ,
    A_JOHNSON,
    DEPTH_JOHNSON,
    F_JOHNSON,
    H_PLASTIC,
    MUS,
    P0_HERTZ,
    P0_JOHNSON,
    SY,
)

TEMPLATE = Path(__file__).with_name("report.md")


def write_report(path: Path, n: dict) -> Path:
    """Fill the template with the numbers ``n`` and write it to ``path``."""
    path.write_text(TEMPLATE.read_text(encoding="utf-8").format_map(values(n)))
    return path


def values(n: dict) -> dict:
    """The template's fields: the numbers' own tables (``t`` Table 1, ``s`` settings, ``dbl``,
    ``bl``, ``runs``), the reference values, and the phrases and rows made from them."""
    t, ch, s = n["table1"], n["checks"], n["settings"]
    f10 = n["fig10"]
    mu_s = ch["onset_falls"]["value"]["surface from mu"]
    return {
        "t": t,
        "s": s,
        "dbl": n["half_space_doubling"],
        "bl": n["blocks"],
        "runs": n["runs"],
        "A_HERTZ": A_HERTZ,
        "P0_HERTZ": P0_HERTZ,
        "A_JOHNSON": A_JOHNSON,
        "P0_JOHNSON": P0_JOHNSON,
        "F_JOHNSON": F_JOHNSON,
        "F_JOHNSON_PC": 100 * F_JOHNSON,
        "SY": SY,
        "H_PLASTIC": H_PLASTIC,
        "ok": {name: _holds(c) for name, c in ch.items()},
        "pc": {k: _pc(v) for k, v in t.items() if isinstance(v, float)},
        "quick_flag": " --quick" if n["quick"] else "",
        "quick_note": (
            " **Quick mode: coarse meshes, for the tests; the numbers are not the "
            "converged ones.**"
            if n["quick"]
            else ""
        ),
        "n_runs": len(n["runs"]),
        "n_fig10": len(f10),
        "solver_sum": n["wall_time_s"]["solver_sum"],
        "fig10_h": s["h_fig10"] if s["h_fig10"] is not None else s["h_table"],
        "depth_err": _pc(t["yield_depth_over_a"] / DEPTH_JOHNSON - 1),
        "a_err_abs": 100 * abs(t["elastic_a_err"]),
        "p0_err_abs": 100 * abs(t["elastic_p0_err"]),
        "paper_fem_err": _pc(1.08 / A_JOHNSON - 1),
        **_cylinder_values(n),
        **_fig10_values(f10, ch, mu_s),
        **_block_values(n),
        "timeline_counts": _kind_counts(n["events"]["cylinder, plastic, μ = 0.35"]),
        "check_rows": "\n".join(
            f"| {c['claim']} | {_fmt_value(c['value'])} | "
            f"{'yes' if c['pass'] else '**no**'} | "
            f"{'yes' if c['required'] else ''} |"
            for c in ch.values()
        ),
        "axisymmetric": _axisymmetric_text(n["axisymmetric"]),
        "warnings": (
            "\n\n## Warnings\n\n" + "\n".join(f"- {w}" for w in n["warnings"])
            if n["warnings"]
            else ""
        ),
        "run_rows": "\n".join(
            f"| {cid} | {r['n_nodes']} | {r['n_events']} | " f"{r['wall_time_s']:.2f} |"
            for cid, r in n["runs"].items()
        ),
    }


def _cylinder_values(n: dict) -> dict:
    """Figs. 5-9: the plastic zones, the per-mu table and the elastoplastic patterns."""
    cyl, ch = n["cylinder"], n["checks"]

    def cy(kind, mu, key):
        return cyl[f"{kind}_mu{mu:g}"][key]

    rows = []
    for mu in MUS:
        e, p = cyl[f"elastic_mu{mu:g}"], cyl[f"plastic_mu{mu:g}"]
        rows.append(
            f"| {mu:g} | {e['a']:.4f} | {p['a']:.4f} | {e['p_centre']:.1f} | "
            f"{p['p_centre']:.1f} | {e['peak_over_mean']:.3f} | "
            f"{p['peak_over_mean']:.3f} | {e['slip_length']:.3f} | "
            f"{p['slip_length']:.3f} |"
        )
    return {
        "zones": ", ".join(f"{z:.3f}" for z in ch["plastic_zone_grows"]["value"]),
        "mus": ", ".join(f"{m:g}" for m in MUS),
        "zone_reach": ", ".join(
            f"μ = {mu:g}: the zone "
            f"{_reach(cy('plastic', mu, 'zone_at_surface'))} the contact "
            f"surface"
            for mu in MUS
        ),
        "per_run_maps": (
            " Per-run maps (with the first yield element marked) are "
            "`runs/cyl_plastic_mu*/von_mises.png`."
            if n["per_run_von_mises"]
            else ""
        ),
        "cylinder_rows": "\n".join(rows),
        "centre_pattern": _join(ch["plastic_centre_pressure_pattern"]["value"], ".1f"),
        "length_pattern": _join(ch["plastic_length_pattern"]["value"], ".4f"),
        "fy_plastic": ", ".join(f"{cy('plastic', mu, 'first_yield_f'):.3f}" for mu in MUS),
    }


def _fig10_values(f10: list[dict], ch: dict, mu_s) -> dict:
    """Fig. 10: the table's rows and the two regimes of the onset."""
    below = (
        "does not fall: it rises by "
        f"{100 * (max(ch['onset_falls_everywhere']['value']) / f10[0]['f'] - 1):.1f} % "
        if not ch["onset_falls_everywhere"]["pass"]
        else "falls only slightly "
    )
    return {
        "fig10_mu_row": "| μ | " + " | ".join(f"{r['mu']:g}" for r in f10) + " |",
        "fig10_rule": "|---|" + "---|" * len(f10),
        "fig10_onset_row": "| onset (% of P) | "
        + " | ".join(f"{100 * r['f']:.2f}" for r in f10)
        + " |",
        "fig10_depth_row": "| depth of first yield / a | "
        + " | ".join(f"{r['depth'] / r['a']:.2f}" for r in f10)
        + " |",
        "onset_first": 100 * f10[0]["f"],
        "onset_last": 100 * f10[-1]["f"],
        "mu_surface": f"{mu_s if mu_s is not None else '–'}",
        "onset_below": below,
    }


def _block_values(n: dict) -> dict:
    """Figs. 12-16: the elastic block's events, the plastic block's tangential stress and slip
    by level, and whether its half-space would collapse without hardening."""
    bl, ch = n["blocks"], n["checks"]
    el = bl["elastic"]
    events = (
        f"All {el['n_events']} events of the run (stick→slip) happen at the first "
        "instant (load fraction 0): elastic and proportional, the solution then only "
        "scales with q."
        if el["max_event_f"] < 1e-9
        else f"Its {el['n_events']} events (stick→slip) end at load fraction "
        f"{el['max_event_f']:.3g}."
    )
    tau = ch["block_tangential_stress_grows"]["value"]
    fs, vs = list(tau), list(tau.values())
    k = int(np.argmax(vs))
    tau_story = (
        f"it grows from {vs[0]:.2f} MPa at f = {fs[0]} to {vs[k]:.2f} MPa at f = {fs[k]}"
        + (
            f" and then falls to {vs[-1]:.2f} MPa at full load, once the corner pressure "
            "is capped by plasticity"
            if k < len(vs) - 1
            else ""
        )
        + f" (larger at full load than at f = {fs[0]}: "
        f"{_holds(ch['block_tangential_stress_grows'])})"
    )
    b0, b2 = bl["plastic_mu0"], bl["plastic_mu0.2"]
    return {
        "elastic_events": events,
        "tau_story": tau_story,
        "b0": b0,
        "b2": b2,
        "ref": bl["elastic_reference_q36_mu0.2"],
        "strain_over_yield": b0["max_plastic_strain"] / (25.0 / 70000.0),
        "slip_levels": ", ".join(f"{v:.1f} mm at f = {f}" for f, v in b2["slip_by_level"].items()),
        "collapse": _collapse_sentence(bl),
        "dbl_elastic_change": 100 * n["half_space_doubling"]["elastic"]["max_pressure_change"],
        "dbl_plastic_change": 100
        * n["half_space_doubling"]["plastic_mu0.2"]["max_pressure_change"],
        "max_drift": 100 * max(b0["max_drift"], b2["max_drift"]),
    }


def _axisymmetric_text(ax: dict) -> str:
    """A pointer to axisymmetric.md with its headline numbers."""
    h, t, sf = ax["hertz"], ax["thick"], ax["sphere_flat"]["meshes"][-1]
    return (
        "Not in the paper: the axisymmetric ring element, on its own page "
        "[axisymmetric.md](axisymmetric.md). Hertz sphere: a "
        + _pc(h["a_err"])
        + ", p0 "
        + _pc(h["p0_err"])
        + "; first yield "
        + _pc(h["yield_f_err"])
        + " from Huber's; thick sphere: first yield "
        + _pc(t["p_first_yield_err"])
        + ", plastic radius within "
        + f"{t['c_max_err']:.3f} mm of Hill's, limit "
        + _pc(t["limit_err"])
        + f"; sphere on a rigid flat to 50 ω_c ({sf['label']}, "
        f"{sf['n_nodes']} nodes): force {100 * sf['KE']['P_range'][0]:+.1f} … "
        f"{100 * sf['KE']['P_range'][1]:+.1f} % from Kogut & Etsion, "
        f"{100 * sf['JG']['P_range'][0]:+.1f} … {100 * sf['JG']['P_range'][1]:+.1f} % from "
        "Jackson & Green."
    )


def _collapse_sentence(bl: dict) -> str:
    b0 = bl["plastic_mu0"]["load_settlement"]
    pp = bl["perfectly_plastic_halfspace"]
    text = (
        f"The load-settlement curve of the punch keeps a finite slope: at full load its "
        f"tangent stiffness is {100 * b0['tangent_stiffness_ratio']:.0f} % of the elastic "
        f"one (settlement {1000 * b0['settlement']:.1f} µm, μ = 0). That is owed to the "
        f"hardening of the half-space: "
    )
    if "error" in pp:
        return text + (
            f"the same scene with a perfectly plastic half-space (H' = 0) did not "
            f"finish ({pp['error']})."
        )
    if pp["flow_from_load_fraction"] is None:
        return text + (
            "with a perfectly plastic half-space (H' = 0) the tangent stiffness "
            f"at full load is {100 * pp['tangent_stiffness_ratio']:.1f} % of the "
            "elastic one."
        )
    f = pp["flow_from_load_fraction"]
    return text + (
        f"with a perfectly plastic half-space (H' = 0, h = {pp['h']:g} mm) the "
        f"stiffness falls below 10 % of the elastic one beyond f = {f:g} "
        f"(q = {36 * f:.1f} MPa = {36 * f / 25.0:.2f} Sy of the half-space) and the "
        f"settlement at full load is {pp['settlement'] / b0['settlement']:.0f}× "
        "larger: a non-hardening half-space would flow before q = 36 MPa (plane "
        "stress leaves little room between first yield, σe ≈ p, and flow). With "
        "H' = 2000 MPa the scene is substantially plastic without collapsing."
    )


def _holds(check: dict) -> str:
    return "holds" if check["pass"] else "does **not** hold"


def _pc(x: float) -> str:
    return f"{100 * x:+.2f} %"


def _join(values, fmt: str) -> str:
    return ", ".join(format(v, fmt) for v in values)


def _reach(flag) -> str:
    return "reaches" if flag else "does not reach"


def _kind_counts(counts: dict) -> str:
    return ", ".join(f"{v} {k}" for k, v in counts.items())


def _fmt_value(v) -> str:
    if isinstance(v, dict):
        return ", ".join(f"{k}: {_fmt_value(x)}" for k, x in v.items())
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_fmt_value(x) for x in v) + "]"
    if isinstance(v, float):
        return f"{v:.4g}"
    return str(v)
