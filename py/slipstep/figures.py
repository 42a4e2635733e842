"""PNG figures of a run (matplotlib, Agg backend): the interface at the final snapshot and the
growth of the contact half-length with the load fraction (cf. Figs. 6-9 of the paper)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .output import contact_growth, contact_profile

STATUS_COLOURS = {0: "0.6", 1: "tab:blue", 2: "tab:red"}
STATUS_LABELS = {0: "open", 1: "stick", 2: "slip"}


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def write_figures(folder: Path, scene, result, summary: dict) -> list[Path]:
    """``contact_interface.png`` and ``contact_growth.png`` (when the case has contact pairs)."""
    folder = Path(folder)
    paths = []
    if result.get("snapshots") and len(scene.pair_xy):
        paths.append(interface_figure(folder / "contact_interface.png", scene, result, summary))
        paths.append(growth_figure(folder / "contact_growth.png", scene, result, summary))
    return paths


def interface_figure(path: Path, scene, result, summary: dict) -> Path:
    """Contact pressure, tangential stress and RTD along the interface (3 panels), points
    coloured by status; the Hertz pressure p0 sqrt(1 - x^2/a^2) overlaid when it applies."""
    plt = _pyplot()
    snap = result["snapshots"][-1]
    prof = contact_profile(scene, snap)
    x, status = prof["x"], prof["status"]
    a = summary.get("contact_half_width", 0.0)
    xmax = max(2.0 * a, x[status > 0].max() * 1.5 if (status > 0).any() else x.max())
    show = x <= xmax if xmax > 0 else np.ones(len(x), bool)

    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(7, 8), constrained_layout=True)
    panels = [("pressure", "contact pressure"),
              ("tangential_stress", "tangential stress\n(along t = (-n_y, n_x))"),
              ("rtd", "relative tangential\ndisplacement (RTD)")]
    for ax, (key, label) in zip(axes, panels):
        ax.plot(x[show], prof[key][show], "-", color="0.75", lw=1, zorder=1)
        for s, colour in STATUS_COLOURS.items():
            m = show & (status == s)
            if m.any():
                ax.plot(x[m], prof[key][m], "o", ms=3, color=colour, label=STATUS_LABELS[s],
                        zorder=2)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    hertz = summary.get("hertz")
    if hertz:
        ah, p0 = hertz["a_hertz_at_final"], hertz["p0_hertz_at_final"]
        xs = np.linspace(0.0, ah, 200)
        axes[0].plot(xs, p0 * np.sqrt(np.clip(1 - (xs / ah) ** 2, 0, None)), "k--", lw=1,
                     label=f"Hertz (a = {ah:.4g}, p0 = {p0:.4g})")
    if a > 0:
        for ax in axes:
            ax.axvline(a, color="k", lw=0.7, ls=":")
    axes[0].legend(fontsize=8)
    axes[-1].set_xlabel("x")
    fig.suptitle(f"{scene.case.name}: interface at load fraction "
                 f"{float(snap['load_fraction']):.4g}   (a = {a:.4g}, "
                 f"c = {summary.get('stick_half_width', 0.0):.4g})", fontsize=10)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def growth_figure(path: Path, scene, result, summary: dict) -> Path:
    """Outermost closed node x against the load fraction (a step curve from the event history),
    with a_Hertz sqrt(f) when the case is the Hertz cylinder (cf. Fig. 9)."""
    plt = _pyplot()
    f, xs = contact_growth(scene, result)
    fig, ax = plt.subplots(figsize=(6, 4.5), constrained_layout=True)
    ax.step(f, xs, where="post", color="tab:blue", label="outermost closed node")
    hertz = summary.get("hertz")
    if hertz:
        ff = np.linspace(0.0, 1.0, 200)
        ax.plot(ff, hertz["a_hertz"] * np.sqrt(ff), "k--", lw=1, label=r"Hertz $a\sqrt{f}$")
    ax.set_xlabel("load fraction f")
    ax.set_ylabel("contact half-length")
    ax.set_xlim(0, 1)
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend()
    ax.set_title(f"{scene.case.name}: growth of the contact", fontsize=10)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
