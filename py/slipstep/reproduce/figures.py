"""The paper's figures redrawn from the runs, with the closed-form curves overlaid wherever one
exists (Table 1 as a figure, Figs. 5-16, and the timeline of every event)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..output.fields import von_mises
from ..measures.references import flat_punch_pressure, hertz_pressure
from .numbers import scene_groups, snapshot_levels
from .scenes import (
    A_HERTZ,
    A_JOHNSON,
    BLOCK_B,
    DEPTH_JOHNSON,
    F_JOHNSON,
    H_PLASTIC,
    MUS,
    P0_HERTZ,
    P0_JOHNSON,
    PAPER_TABLE1,
    SY,
    Run,
)


KIND_COLOURS = {
    "close": "tab:blue",
    "separate": "tab:cyan",
    "stick_to_slip": "tab:red",
    "slip_to_stick": "tab:green",
    "yield": "tab:orange",
    "unload": "tab:purple",
    "frozen": "0.3",
    "frozen_element": "0.6",
    "slip_turn": "tab:olive",
}


def _plt():
    """pyplot's figure calls on matplotlib's object API (:class:`slipstep.figures.frame.Plots`): no
    backend switch, no global figure state, so the figures are notebook-safe."""
    from ..figures.frame import Plots

    return Plots()


def fig_table1(path: Path, el: Run, yl: Run, t1: dict) -> Path:
    """Table 1 as a figure: the two pressure profiles against Hertz, and the table."""
    plt = _plt()
    fig = plt.figure(figsize=(11, 7.5), constrained_layout=True)
    gs = fig.add_gridspec(2, 2, height_ratios=[1.25, 1])
    for col, (run, a_ref, p_ref, title) in enumerate(
        (
            (el, A_HERTZ, P0_HERTZ, "elastic, full load (P = 1000 N/mm)"),
            (
                yl,
                A_JOHNSON,
                P0_JOHNSON,
                f"elastoplastic, threshold of plasticity (f = {t1['yield_f']:.4f})",
            ),
        )
    ):
        ax = fig.add_subplot(gs[0, col])
        x, p = run.x, run.profile("pressure")
        m = x <= 2.0 * a_ref
        ax.plot(x[m], p[m], "o-", ms=3, lw=1, label="slipstep (nodal λn / L)")
        xs = np.linspace(0, a_ref, 300)
        ax.plot(
            xs,
            hertz_pressure(xs, a_ref, p_ref),
            "k--",
            lw=1,
            label=f"Hertz: a = {a_ref:.4g} mm, p0 = {p_ref:.4g} MPa",
        )
        if col == 1:
            ax.axvline(
                PAPER_TABLE1["yield_a"][0],
                color="tab:red",
                ls=":",
                lw=1,
                label="paper's 'analytical' a = 1.036 mm",
            )
        a_run = run.a if col == 0 else t1["yield_a"]
        ax.axvline(a_run, color="tab:blue", ls=":", lw=1, label=f"slipstep a = {a_run:.4g} mm")
        ax.set_xlabel("x (mm)")
        ax.set_ylabel("contact pressure (MPa)")
        ax.set_title(title, fontsize=10)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    ax = fig.add_subplot(gs[1, :])
    ax.axis("off")
    rows = [
        [
            "Elastic",
            "a (mm)",
            f"{A_HERTZ:.4f}",
            f"{t1['elastic_a']:.4f}",
            f"{100 * t1['elastic_a_err']:+.2f}",
            "1.43",
            "0.58",
        ],
        [
            "",
            "p0 (MPa)",
            f"{P0_HERTZ:.1f}",
            f"{t1['elastic_p0']:.1f}",
            f"{100 * t1['elastic_p0_err']:+.2f}",
            "451",
            "1.86",
        ],
        [
            "Elastoplastic,",
            "a (mm)",
            f"{A_JOHNSON:.4f} (paper: 1.036)",
            f"{t1['yield_a']:.4f}",
            f"{100 * t1['yield_a_err']:+.2f} ({100 * t1['yield_a_err_paper']:+.1f} vs 1.036)",
            "1.08",
            "4.04",
        ],
        [
            "threshold",
            "p0 (MPa)",
            f"{P0_JOHNSON:.1f}",
            f"{t1['yield_p0']:.1f}",
            f"{100 * t1['yield_p0_err']:+.2f}",
            "323.9",
            "9.5",
        ],
        [
            "",
            "load fraction",
            f"{F_JOHNSON:.4f}",
            f"{t1['yield_f']:.4f}",
            f"{100 * t1['yield_f_err']:+.2f}",
            "-",
            "-",
        ],
        [
            "",
            "depth / a",
            f"{DEPTH_JOHNSON:.2f}",
            f"{t1['yield_depth_over_a']:.3f}",
            f"{100 * (t1['yield_depth_over_a'] / DEPTH_JOHNSON - 1):+.1f}",
            "-",
            "-",
        ],
    ]
    labels = [
        "solution",
        "parameter",
        "closed form",
        "slipstep",
        "error %",
        "paper FEM",
        "paper error %",
    ]
    table = ax.table(cellText=rows, colLabels=labels, loc="center", cellLoc="center")
    table.auto_set_font_size(False)
    table.set_fontsize(9)
    table.scale(1, 1.5)
    ax.set_title(
        f"Table 1 (h_contact = {t1['h_contact']:g} mm; Sy = {SY:g} MPa, "
        f"H' = {H_PLASTIC:g} MPa; Johnson: p0 = 1.79 Sy at depth 0.70 a, "
        f"Hertz a = 2R p0 / E* at that p0)",
        fontsize=10,
    )
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def fig05(path: Path, runs: dict) -> Path:
    """Von Mises maps at full load with the plastic zone outlined, mu = 0, 0.1, 0.35."""
    from matplotlib.collections import LineCollection

    from ..figures.section import zone_boundary

    plt = _plt()
    fig, axes = plt.subplots(1, len(MUS), figsize=(5 * len(MUS), 4.6), constrained_layout=True)
    vms = {mu: von_mises(runs[mu].data["stress"]) for mu in MUS}
    a = max(runs[mu].a for mu in MUS)
    window = (0.0, 2.5 * a), (0.0, 2.0 * a)
    art = None
    for ax, mu in zip(axes, MUS):
        d = runs[mu].data
        nodes, tri = d["nodes"], d["triangles"]
        art = ax.tripcolor(
            nodes[:, 0],
            nodes[:, 1],
            tri,
            facecolors=vms[mu],
            cmap="viridis",
            vmin=0.0,
            vmax=max(SY * 1.15, max(v.max() for v in vms.values())),
        )
        plastic = d["plastic"].astype(bool)
        yielded = d["plastic_strain"] > 0
        if yielded.any():
            segs = nodes[zone_boundary(tri, yielded)]
            ax.add_collection(
                LineCollection(
                    segs,
                    colors="tab:red",
                    linewidths=1.1,
                    label="plastic zone (plastic strain > 0)",
                )
            )
        ax.axvline(runs[mu].a, color="w", ls=":", lw=1)
        ax.set_xlim(*window[0])
        ax.set_ylim(*window[1])
        ax.set_aspect("equal")
        ax.set_xlabel("x (mm)")
        ax.set_title(
            f"μ = {mu:g}: {int(yielded.sum())} elements yielded "
            f"({int(plastic.sum())} plastic now)",
            fontsize=10,
        )
        ax.legend(fontsize=7, loc="upper right")
    axes[0].set_ylabel("height above the flat (mm)")
    fig.colorbar(art, ax=axes, label="von Mises stress (MPa)", shrink=0.9)
    fig.suptitle(
        f"Fig. 5: von Mises stress at full load, elastoplastic cylinder (Sy = {SY:g} "
        f"MPa, H' = {H_PLASTIC:g} MPa); dotted: contact half-width",
        fontsize=11,
    )
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def fig_interface(
    path: Path, elastic: dict, plastic: dict, key: str, ylabel: str, title: str
) -> Path:
    """Figs. 6-8: one panel per mu, elastic (solid) vs elastoplastic (dashed) at full load."""
    plt = _plt()
    fig, axes = plt.subplots(1, len(MUS), figsize=(15, 4.4), sharey=True, constrained_layout=True)
    for ax, mu in zip(axes, MUS):
        xmax = 1.35 * max(elastic[mu].a, plastic[mu].a)
        for run, style, label, colour in (
            (elastic[mu], "-", "elastic", "tab:blue"),
            (plastic[mu], "--", "elastoplastic", "tab:orange"),
        ):
            x, v = run.x, run.profile(key)
            m = x <= xmax
            ax.plot(
                x[m],
                v[m],
                style,
                marker="o",
                ms=2.5,
                lw=1.2,
                color=colour,
                label=f"{label} (a = {run.a:.3f})",
            )
            if key == "tangential_stress" and mu > 0:
                sign = 1.0 if v.sum() >= 0 else -1.0
                ax.plot(
                    x[m],
                    sign * mu * run.profile("pressure")[m],
                    ":",
                    lw=1,
                    color=colour,
                    label=f"{'' if sign > 0 else '−'}μ p, {label} (Coulomb limit)",
                )
        xs = np.linspace(0, A_HERTZ, 300)
        if key == "pressure":
            ax.plot(
                xs,
                hertz_pressure(xs, A_HERTZ, P0_HERTZ),
                "k:",
                lw=1,
                label="Hertz (elastic, μ = 0)",
            )
        ax.axhline(0, color="0.5", lw=0.5)
        ax.set_title(f"μ = {mu:g}", fontsize=10)
        ax.set_xlabel("x (mm)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    axes[0].set_ylabel(ylabel)
    fig.suptitle(title, fontsize=11)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def fig09(path: Path, elastic: dict, plastic: dict) -> Path:
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7.5, 5.5), constrained_layout=True)
    colours = dict(zip(MUS, ("tab:blue", "tab:orange", "tab:green")))
    for mu in MUS:
        for run, style, label in (
            (elastic[mu], "-", "elastic"),
            (plastic[mu], "--", "elastoplastic"),
        ):
            d = run.data
            ax.step(
                d["growth_load_fraction"],
                d["growth_x"],
                where="post",
                ls=style,
                color=colours[mu],
                lw=1.3,
                label=f"{label}, μ = {mu:g}",
            )
    f = np.linspace(0, 1, 300)
    ax.plot(f, A_HERTZ * np.sqrt(f), "k:", lw=1.2, label=r"Hertz $a\sqrt{f}$ (elastic, μ = 0)")
    ax.set_xlabel("load fraction f")
    ax.set_ylabel("half contact length (mm): outermost closed node")
    ax.set_xlim(0, 1)
    ax.set_ylim(0, None)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, ncol=2)
    ax.set_title("Fig. 9: growth of the half contact length (from the event history)", fontsize=10)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def fig10(path: Path, rows: list[dict]) -> Path:
    plt = _plt()
    mu = np.array([r["mu"] for r in rows])
    f = np.array([r["f"] for r in rows])
    surface = np.array([r["depth"] < 0.25 * r["a"] for r in rows])
    fig, ax = plt.subplots(figsize=(7, 5), constrained_layout=True)
    ax.plot(mu, 100 * f, "-", color="0.6", lw=1)
    ax.plot(
        mu[~surface],
        100 * f[~surface],
        "o",
        color="tab:blue",
        label="first yield below the surface",
    )
    ax.plot(
        mu[surface],
        100 * f[surface],
        "s",
        color="tab:red",
        label="first yield at the surface (centre, stick zone)",
    )
    ax.plot(
        [0],
        [100 * F_JOHNSON],
        "k*",
        ms=12,
        label=f"Johnson, μ = 0: p0 = 1.79 Sy → {100 * F_JOHNSON:.1f} %",
    )
    ax.axhline(100 * F_JOHNSON, color="k", ls=":", lw=0.8)
    ax.set_xlabel("friction coefficient μ")
    ax.set_ylabel("load at the onset of yield (% of P = 1000 N/mm)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("Fig. 10: load at the onset of yield vs μ (sweep runner)", fontsize=10)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def fig12_13(paths: tuple[Path, Path], run: Run, q: float) -> tuple[Path, Path]:
    plt = _plt()
    x = run.x
    b = BLOCK_B
    xs = np.linspace(0, b * 0.999, 400)
    rigid = flat_punch_pressure(xs, b, 2.0 * b * q)
    fig, ax = plt.subplots(figsize=(7.5, 5), constrained_layout=True)
    st = run.status()
    ax.plot(x, run.profile("pressure"), "o-", ms=3, label="contact pressure")
    ax.plot(
        x, run.profile("tangential_stress"), "s-", ms=3, label="tangential stress on the punch (+x)"
    )
    ax.plot(
        x,
        -0.2 * run.profile("pressure"),
        ":",
        color="tab:orange",
        lw=1,
        label="−μ p (Coulomb limit)",
    )
    ax.plot(
        xs,
        rigid,
        "k--",
        lw=0.8,
        label="rigid flat punch on a half-plane, 2bq/(π√(b²-x²)) (reference shape)",
    )
    ax.axhline(q, color="0.5", lw=0.8, ls="-.", label=f"applied q = {q:g} MPa")
    c = b - run.slip_length(a=b)
    ax.axvspan(c, b, color="tab:red", alpha=0.08, label=f"slip zone (c = {c:.2f} mm)")
    ax.set_ylim(-0.5 * q, 4 * q)
    ax.set_xlabel("x (mm); punch half-width b = 10 mm")
    ax.set_ylabel("stress (MPa)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(
        "Fig. 12: elastic block on a half-space, contact stresses (q = 1.2 MPa, μ = 0.2, "
        "plane strain)",
        fontsize=10,
    )
    fig.savefig(paths[0], dpi=120)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(7.5, 4.5), constrained_layout=True)
    rtd = run.profile("rtd")
    ax.plot(x, 1e6 * rtd, "o-", ms=3)
    for s, col, lab in ((1, "tab:blue", "stick"), (2, "tab:red", "slip")):
        m = st == s
        ax.plot(x[m], 1e6 * rtd[m], "o", ms=4, color=col, label=lab)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("RTD, punch relative to half-space, +x (nm)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("Fig. 13: elastic block, relative tangential displacement", fontsize=10)
    fig.savefig(paths[1], dpi=120)
    plt.close(fig)
    return paths


def fig14(path: Path, runs: dict, reference: Run, q: float) -> Path:
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7.5, 5), constrained_layout=True)
    for mu, style in ((0.0, "o-"), (0.2, "s--")):
        r = runs[mu]
        ax.plot(r.x, r.profile("pressure"), style, ms=3.5, label=f"elastoplastic, μ = {mu:g}")
    ax.plot(
        reference.x,
        reference.profile("pressure"),
        ":",
        color="0.4",
        marker=".",
        label="elastic (same scene, yield switched off), μ = 0.2",
    )
    ax.axhline(q, color="0.5", lw=0.8, ls="-.", label=f"applied q = {q:g} MPa")
    ax.set_xlabel("x (mm); punch half-width b = 10 mm")
    ax.set_ylabel("contact pressure (MPa)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(
        "Fig. 14: elastoplastic block, contact pressure at q = 36 MPa (plane stress)", fontsize=10
    )
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def fig15_16(paths: tuple[Path, Path], run: Run, levels) -> tuple[Path, Path]:
    plt = _plt()
    cmap = plt.get_cmap("viridis")
    for path, key, label, title in (
        (
            paths[0],
            "rtd",
            "RTD, punch relative to half-space, +x (μm)",
            "Fig. 15: RTD along the interface with increasing load",
        ),
        (
            paths[1],
            "tangential_stress",
            "tangential stress on the punch, +x (MPa)",
            "Fig. 16: tangential stress along the interface with increasing load",
        ),
    ):
        fig, ax = plt.subplots(figsize=(7.5, 5), constrained_layout=True)
        for i, f in enumerate(levels):
            k = run.snapshot_index(f)
            v = run.profile(key, k) * (1e3 if key == "rtd" else 1.0)
            c = BLOCK_B - run.slip_length(k, a=BLOCK_B)
            ax.plot(
                run.x,
                v,
                "o-",
                ms=2.5,
                color=cmap(i / max(1, len(levels) - 1)),
                label=f"q = {36 * run.data['snap_load_fraction'][k]:.1f} MPa "
                f"(f = {run.data['snap_load_fraction'][k]:.2g}), stick up to {c:.1f}",
            )
            if key == "tangential_stress":
                ax.plot(
                    run.x,
                    -0.2 * run.profile("pressure", k),
                    ":",
                    lw=0.8,
                    color=cmap(i / max(1, len(levels) - 1)),
                )
        ax.axhline(0, color="0.5", lw=0.5)
        ax.set_xlabel("x (mm)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
        ax.set_title(
            title + " (μ = 0.2; dotted: −μ p)"
            if key == "tangential_stress"
            else title + " (μ = 0.2)",
            fontsize=10,
        )
        fig.savefig(path, dpi=120)
        plt.close(fig)
    return paths


def fig_timeline(path: Path, runs: list[tuple[str, Run]]) -> Path:
    plt = _plt()
    fig, axes = plt.subplots(
        1,
        2,
        figsize=(15, 0.45 * len(runs) + 2.5),
        gridspec_kw={"width_ratios": [2.2, 1]},
        constrained_layout=True,
    )
    ax = axes[0]
    kinds_seen = {}
    for i, (label, run) in enumerate(runs):
        d = run.data
        kinds = d["events_kind"]
        for j, kind in enumerate(KIND_COLOURS):
            m = kinds == kind
            if m.any():
                h = ax.plot(
                    d["events_load_fraction"][m],
                    np.full(m.sum(), i + 0.1 * (j - 3)),
                    "|",
                    ms=7,
                    color=KIND_COLOURS[kind],
                )
                kinds_seen[kind] = h[0]
    ax.set_yticks(range(len(runs)))
    ax.set_yticklabels(
        [f"{label} ({len(run.data['events_kind'])})" for label, run in runs], fontsize=8
    )
    ax.set_xlim(-0.02, 1.0)
    ax.set_xlabel("load fraction of the event")
    ax.invert_yaxis()
    ax.grid(alpha=0.3, axis="x")
    ax.legend(
        list(kinds_seen.values()),
        list(kinds_seen),
        fontsize=8,
        loc="lower left",
        bbox_to_anchor=(0.0, 1.0),
        ncol=len(kinds_seen),
        frameon=False,
    )
    ax.set_title(
        "every event of every scene, by kind (number of events in brackets)", fontsize=10, pad=22
    )
    label, run = next((lr for lr in runs if lr[0] == "cylinder, plastic, μ = 0.35"), runs[0])
    ax = axes[1]
    d = run.data
    for kind, colour in KIND_COLOURS.items():
        m = d["events_kind"] == kind
        if m.any():
            f = np.sort(d["events_load_fraction"][m])
            ax.step(
                np.r_[f, 1],
                np.r_[np.arange(1, len(f) + 1), len(f)],
                where="post",
                color=colour,
                label=f"{kind} ({m.sum()})",
            )
    ax.set_xlim(0, 1)
    ax.set_xlabel("load fraction")
    ax.set_ylabel("cumulative number of events")
    ax.set_yscale("log")
    ax.set_ylim(0.8, None)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(f"{label}: the sequence of events", fontsize=10)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def draw(out: Path, run: dict, numbers: dict) -> tuple[dict, list]:
    """Every figure of report.md into ``out``: their paths by key, and the runs of the event
    timeline (label, run)."""
    g = scene_groups(run)
    cyl_el, cyl_pl, blocks = g["cyl_el"], g["cyl_pl"], g["blocks"]
    figs = {}
    figs["table1"] = fig_table1(
        out / "table1.png", run["table1_elastic"], run["table1_yield"], numbers["table1"]
    )
    figs["fig05"] = fig05(out / "fig05_von_mises.png", cyl_pl)
    figs["fig06"] = fig_interface(
        out / "fig06_pressure.png",
        cyl_el,
        cyl_pl,
        "pressure",
        "contact pressure (MPa)",
        "Fig. 6: contact pressure at full " "load, elastic vs elastoplastic",
    )
    figs["fig07"] = fig_interface(
        out / "fig07_rtd.png",
        cyl_el,
        cyl_pl,
        "rtd",
        "RTD along +x (mm)",
        "Fig. 7: relative tangential displacement " "at full load",
    )
    figs["fig08"] = fig_interface(
        out / "fig08_tangential.png",
        cyl_el,
        cyl_pl,
        "tangential_stress",
        "tangential stress on the cylinder, +x " "(MPa)",
        "Fig. 8: tangential stress at full load",
    )
    figs["fig09"] = fig09(out / "fig09_contact_growth.png", cyl_el, cyl_pl)
    figs["fig10"] = fig10(out / "fig10_onset_of_yield.png", numbers["fig10"])
    figs["fig12"], figs["fig13"] = fig12_13(
        (out / "fig12_block_elastic_stresses.png", out / "fig13_block_elastic_rtd.png"),
        blocks["elastic"],
        1.2,
    )
    figs["fig14"] = fig14(
        out / "fig14_block_plastic_pressure.png",
        blocks["plastic"],
        run["block_plastic_elastic_reference"],
        36.0,
    )
    figs["fig15"], figs["fig16"] = fig15_16(
        (out / "fig15_block_plastic_rtd.png", out / "fig16_block_plastic_tangential.png"),
        blocks["plastic"][0.2],
        snapshot_levels(blocks["plastic"][0.2]),
    )
    timeline = [
        ("Table 1, elastic", run["table1_elastic"]),
        ("Table 1, to first yield", run["table1_yield"]),
    ]
    timeline += [(f"cylinder, elastic, μ = {mu:g}", cyl_el[mu]) for mu in MUS]
    timeline += [(f"cylinder, plastic, μ = {mu:g}", cyl_pl[mu]) for mu in MUS]
    timeline += [("block, elastic, μ = 0.2", blocks["elastic"])]
    timeline += [(f"block, plastic, μ = {mu:g}", blocks["plastic"][mu]) for mu in (0.0, 0.2)]
    figs["timeline"] = fig_timeline(out / "events_timeline.png", timeline)
    return figs, timeline
