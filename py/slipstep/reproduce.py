"""``slipstep reproduce --out DIR [--quick]``: the paper's Table 1 and Figs. 5-16, regenerated.

Abdalla, Ali-Eldin & Ghazy, §5: every scene is run through the sweep runner
(:mod:`slipstep.sweep`, local processes), each writing its full results (XDMF series, CSV,
per-run PNGs) under ``DIR/runs/<scene>``; Fig. 10 is the study ``studies/fig10_onset_of_yield.toml``
run by the same runner under ``DIR/fig10``.  Then the paper's figures are drawn with the
closed-form curves overlaid wherever one exists, and ``DIR/report.md`` gathers them with what
agrees, what does not, and why; ``DIR/reproduce.json`` holds every number and check.

Scenes
  * Hertz cylinder (§5.1): the built-in case (R = 125 mm, E = 70 GPa, nu = 0.3, P = 1000 N/mm,
    plane strain, quarter model); elastoplastic with Al-5%Mg Sy = 200 MPa and linear hardening
    H' = 700 MPa (the paper gives no hardening value: ours); mu = 0, 0.1, 0.35.
  * Block on a half-space (§5.2): ``cases/paper_block_elastic.toml`` (q = 1.2 MPa, mu = 0.2, plane
    strain) and ``cases/paper_block_plastic.toml`` (q = 36 MPa, plane stress, mu = 0 and 0.2).

Axisymmetric page (:mod:`slipstep.reproduce_axisymmetric`): ``DIR/axisymmetric.md``,
the Hertz sphere, first yield against Huber, the thick sphere against Lame and Hill, and the
elastic-plastic sphere on a rigid flat against Kogut & Etsion and Jackson & Green; linked
from report.md.

A rerun into the same DIR reuses the finished runs (the sweep runner resumes); delete DIR to
start afresh.  ``--quick`` uses coarse meshes (for the tests).
"""

from __future__ import annotations

import json
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from . import reproduce_axisymmetric, shipped, sweep
from .derived import centroids, contact_half_width, stick_half_width, von_mises
from .output import json_safe
from .references import (JOHNSON_LINE_YIELD, JOHNSON_LINE_YIELD_DEPTH, effective_modulus,
                         flat_punch_pressure, hertz_line, hertz_pressure)

# --------------------------------------------------------------------------- constants
SY, H_PLASTIC = 200.0, 700.0           # Al-5%Mg yield stress (paper) and our hardening modulus
PLASTIC = [f"material.Sy={SY:g}", f"material.H={H_PLASTIC:g}"]
MUS = (0.0, 0.1, 0.35)
R, E, NU, P = 125.0, 70000.0, 0.3, 1000.0
E_STAR = effective_modulus(E, NU)
A_HERTZ, P0_HERTZ = hertz_line(P, R, E, NU)                     # 1.4384 mm, 442.6 MPa
P0_JOHNSON = JOHNSON_LINE_YIELD * SY                            # 358 MPa (von Mises, nu = 0.3)
A_JOHNSON = 2.0 * R * P0_JOHNSON / E_STAR                       # Hertz a at p0 = 358: 1.164 mm
F_JOHNSON = (P0_JOHNSON / P0_HERTZ) ** 2                        # 0.654
DEPTH_JOHNSON = JOHNSON_LINE_YIELD_DEPTH                        # z / a of first yield
PAPER_TABLE1 = {  # analytical (paper), FEM (paper), error % (paper)
    "elastic_a": (1.438, 1.43, 0.58), "elastic_p0": (442.6, 451.0, 1.86),
    "yield_a": (1.036, 1.08, 4.04), "yield_p0": (358.0, 323.9, 9.5)}
BLOCK_B = 10.0                          # punch half-width in the block cases (mm)
KIND_COLOURS = {"close": "tab:blue", "separate": "tab:cyan", "stick_to_slip": "tab:red",
                "slip_to_stick": "tab:green", "yield": "tab:orange", "unload": "tab:purple",
                "frozen": "0.3", "frozen_element": "0.6"}


@dataclass(frozen=True)
class Settings:
    """Mesh sizes (mm). Full: the shipped default mesh for Table 1 and Fig. 10 (h = 0.03 at the
    contact), h = 0.1 for the full elastoplastic cylinder runs (one refactorization per yield
    event: 500-650 events, 2-4 s each), the case files' meshes for the blocks (their half-space
    is the structured grid of spacing h inside refine_box under the punch, graded outside)."""

    quick: bool
    h_table: float
    h_cyl: float
    h_fig10: float | None          # None: the study's own (the default mesh)
    h_block_elastic: float
    h_block_plastic: float
    h_check_elastic: float         # half-space doubling check, elastic case
    h_check_plastic: float         # half-space doubling check, elastoplastic mu = 0.2


FULL = Settings(False, 0.03, 0.1, None, 0.5, 1.0, 0.5, 2.0)
QUICK = Settings(True, 0.1, 0.15, 0.1, 1.0, 2.0, 1.0, 2.0)


def _path(kind: str, name: str) -> Path:
    """A shipped case or study (:mod:`slipstep.shipped`: works from an installed wheel)."""
    return shipped.path(name, kind)


def _task(cid: str, base, overrides, **options) -> dict:
    opts = dict(sweep.OUTPUT_KEYS)
    opts.update(options)
    return {"case_id": cid, "params": {"scene": cid}, "base": None if base is None else str(base),
            "overrides": list(overrides), "options": opts}


def _mu_id(mu: float) -> str:
    return f"{mu:g}"


def _block_mesh(h: float) -> list[str]:
    """The block cases at spacing h: the punch, and the half-space's structured grid inside its
    refine_box (the grading outside follows from h, h_max and growth)."""
    return [f"body.punch.mesh.h={h:g}", f"body.halfspace.mesh.h={h:g}"]


# the half-space's size doubled (10 b -> 20 b each way); its refine_box, spacing and grading law
# stay, so the mesh near the punch is the same and only the far field grows
DOUBLE = ["body.halfspace.mesh.width=200", "body.halfspace.mesh.height=200",
          "body.halfspace.mesh.y0=-200"]


def scene_tasks(s: Settings) -> list[dict]:
    """Every run of the reproduction but Fig. 10 (longest first, for the process pool)."""
    block_el, block_pl = _path("cases", "paper_block_elastic.toml"), _path(
        "cases", "paper_block_plastic.toml")
    snaps = "output.snapshots=[0.25, 0.5, 0.75, 1.0]"
    tasks = []
    for mu in (0.2, 0.0):
        tasks.append(_task(f"block_plastic_mu{_mu_id(mu)}", block_pl,
                           [*_block_mesh(s.h_block_plastic), f"contact.mu={mu}"], results=True,
                           fields=True))
    tasks.append(_task("block_elastic", block_el, _block_mesh(s.h_block_elastic), results=True))
    tasks.append(_task("check_block_elastic_2x", block_el, [*_block_mesh(s.h_check_elastic),
                                                             *DOUBLE, snaps]))
    if s.h_check_elastic != s.h_block_elastic:
        tasks.append(_task("check_block_elastic_1x", block_el,
                           [*_block_mesh(s.h_check_elastic), snaps]))
    for mu in MUS[::-1]:
        tasks.append(_task(f"cyl_plastic_mu{_mu_id(mu)}", None,
                           [*PLASTIC, f"mesh.h_contact={s.h_cyl:g}", f"contact.mu={mu}", snaps],
                           results=True, fields=True))
    tasks.append(_task("table1_elastic", None, [f"mesh.h_contact={s.h_table:g}", snaps],
                       results=True))
    tasks.append(_task("table1_yield", None, [*PLASTIC, f"mesh.h_contact={s.h_table:g}",
                                              "output.snapshots=[1.0]"],
                       results=True, fields=True, stop_at_first_yield=True))
    for mu in MUS:
        tasks.append(_task(f"cyl_elastic_mu{_mu_id(mu)}", None,
                           [f"mesh.h_contact={s.h_cyl:g}", f"contact.mu={mu}", snaps],
                           results=True))
    tasks.append(_task("check_block_plastic_2x", block_pl,
                       [*_block_mesh(s.h_check_plastic), "contact.mu=0.2", *DOUBLE]))
    if s.h_check_plastic != s.h_block_plastic:  # else block_plastic_mu0.2 is that run
        tasks.append(_task("check_block_plastic_1x", block_pl,
                           [*_block_mesh(s.h_check_plastic), "contact.mu=0.2"]))
    # the same half-space without hardening (H' = 0): where would it flow? (may fail to finish)
    tasks.append(_task("probe_block_perfectly_plastic", block_pl,
                       [*_block_mesh(s.h_check_plastic), "body.halfspace.material.H=0"],
                       fields=True))
    tasks.append(_task("block_plastic_elastic_reference", block_pl,
                       [*_block_mesh(s.h_block_plastic), "contact.mu=0.2",
                        "body.punch.material.Sy=1e12", "body.halfspace.material.Sy=1e12"],
                       results=False))
    return tasks


def fig10_study(s: Settings) -> sweep.Study:
    extra = [] if s.h_fig10 is None else [f"mesh.h_contact={s.h_fig10:g}"]
    return sweep.load_study(_path("studies", "fig10_onset_of_yield.toml"), extra_set=extra)


# --------------------------------------------------------------------------- run data
class Run:
    """One finished run: its summary and arrays (result.npz)."""

    def __init__(self, folder: Path, cid: str):
        self.cid = cid
        self.folder = folder / cid
        self.summary = sweep.load_summary(folder, cid)
        self.data = sweep.load_arrays(folder, cid)

    @property
    def x(self):
        return self.data["profile_x"]

    def profile(self, key: str, k: int = -1) -> np.ndarray:
        """A contact quantity at snapshot k; tangential quantities turned to +x (the engine's
        tangent for a normal (0, 1) is -x)."""
        v = self.data[f"profile_{key}"][k]
        return -v if key in ("tangential_stress", "rtd") else v

    def snapshot_index(self, f: float) -> int:
        return int(np.argmin(np.abs(self.data["snap_load_fraction"] - f)))

    def status(self, k: int = -1) -> np.ndarray:
        return self.data["profile_status"][k].astype(int)

    @property
    def a(self) -> float:
        return float(self.summary["contact_half_width"])

    def pressure_ratio(self) -> float:
        """Peak over mean pressure, mean = (normal force of the modelled part) / a."""
        return float(self.summary["peak_pressure"] / (self.summary["total_normal_force"] / self.a))

    def slip_length(self, k: int = -1, a: float | None = None) -> float:
        a = self.a if a is None else a
        return a - stick_half_width(self.x, self.status(k), a)


# --------------------------------------------------------------------------- figures
def _plt():
    """pyplot's figure calls on matplotlib's object API (:class:`slipstep.figures.Plots`): no
    backend switch, no global figure state, so the figures are notebook-safe."""
    from .figures import Plots

    return Plots()


def fig_table1(path: Path, el: Run, yl: Run, t1: dict) -> Path:
    """Table 1 as a figure: the two pressure profiles against Hertz, and the table."""
    plt = _plt()
    fig = plt.figure(figsize=(11, 7.5), constrained_layout=True)
    gs = fig.add_gridspec(2, 2, height_ratios=[1.25, 1])
    for col, (run, a_ref, p_ref, title) in enumerate((
            (el, A_HERTZ, P0_HERTZ, "elastic, full load (P = 1000 N/mm)"),
            (yl, A_JOHNSON, P0_JOHNSON,
             f"elastoplastic, threshold of plasticity (f = {t1['yield_f']:.4f})"))):
        ax = fig.add_subplot(gs[0, col])
        x, p = run.x, run.profile("pressure")
        m = x <= 2.0 * a_ref
        ax.plot(x[m], p[m], "o-", ms=3, lw=1, label="slipstep (nodal λn / L)")
        xs = np.linspace(0, a_ref, 300)
        ax.plot(xs, hertz_pressure(xs, a_ref, p_ref), "k--", lw=1,
                label=f"Hertz: a = {a_ref:.4g} mm, p0 = {p_ref:.4g} MPa")
        if col == 1:
            ax.axvline(PAPER_TABLE1["yield_a"][0], color="tab:red", ls=":", lw=1,
                       label="paper's 'analytical' a = 1.036 mm")
        a_run = run.a if col == 0 else t1["yield_a"]
        ax.axvline(a_run, color="tab:blue", ls=":", lw=1, label=f"slipstep a = {a_run:.4g} mm")
        ax.set_xlabel("x (mm)")
        ax.set_ylabel("contact pressure (MPa)")
        ax.set_title(title, fontsize=10)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    ax = fig.add_subplot(gs[1, :])
    ax.axis("off")
    rows = [["Elastic", "a (mm)", f"{A_HERTZ:.4f}", f"{t1['elastic_a']:.4f}",
             f"{100 * t1['elastic_a_err']:+.2f}", "1.43", "0.58"],
            ["", "p0 (MPa)", f"{P0_HERTZ:.1f}", f"{t1['elastic_p0']:.1f}",
             f"{100 * t1['elastic_p0_err']:+.2f}", "451", "1.86"],
            ["Elastoplastic,", "a (mm)", f"{A_JOHNSON:.4f} (paper: 1.036)", f"{t1['yield_a']:.4f}",
             f"{100 * t1['yield_a_err']:+.2f} ({100 * t1['yield_a_err_paper']:+.1f} vs 1.036)",
             "1.08", "4.04"],
            ["threshold", "p0 (MPa)", f"{P0_JOHNSON:.1f}", f"{t1['yield_p0']:.1f}",
             f"{100 * t1['yield_p0_err']:+.2f}", "323.9", "9.5"],
            ["", "load fraction", f"{F_JOHNSON:.4f}", f"{t1['yield_f']:.4f}",
             f"{100 * t1['yield_f_err']:+.2f}", "-", "-"],
            ["", "depth / a", f"{DEPTH_JOHNSON:.2f}", f"{t1['yield_depth_over_a']:.3f}",
             f"{100 * (t1['yield_depth_over_a'] / DEPTH_JOHNSON - 1):+.1f}", "-", "-"]]
    labels = ["solution", "parameter", "closed form", "slipstep", "error %", "paper FEM",
              "paper error %"]
    table = ax.table(cellText=rows, colLabels=labels, loc="center", cellLoc="center")
    table.auto_set_font_size(False)
    table.set_fontsize(9)
    table.scale(1, 1.5)
    ax.set_title(f"Table 1 (h_contact = {t1['h_contact']:g} mm; Sy = {SY:g} MPa, "
                 f"H' = {H_PLASTIC:g} MPa; Johnson: p0 = 1.79 Sy at depth 0.70 a, "
                 f"Hertz a = 2R p0 / E* at that p0)", fontsize=10)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def fig05(path: Path, runs: dict) -> Path:
    """Von Mises maps at full load with the plastic zone outlined, mu = 0, 0.1, 0.35."""
    from matplotlib.collections import LineCollection

    from .figures import zone_boundary
    plt = _plt()
    fig, axes = plt.subplots(1, len(MUS), figsize=(5 * len(MUS), 4.6), constrained_layout=True)
    vms = {mu: von_mises(runs[mu].data["stress"]) for mu in MUS}
    a = max(runs[mu].a for mu in MUS)
    window = (0.0, 2.5 * a), (0.0, 2.0 * a)
    art = None
    for ax, mu in zip(axes, MUS):
        d = runs[mu].data
        nodes, tri = d["nodes"], d["triangles"]
        art = ax.tripcolor(nodes[:, 0], nodes[:, 1], tri, facecolors=vms[mu], cmap="viridis",
                           vmin=0.0, vmax=max(SY * 1.15, max(v.max() for v in vms.values())))
        plastic = d["plastic"].astype(bool)
        yielded = d["plastic_strain"] > 0
        if yielded.any():
            segs = nodes[zone_boundary(tri, yielded)]
            ax.add_collection(LineCollection(segs, colors="tab:red", linewidths=1.1,
                                             label="plastic zone (plastic strain > 0)"))
        ax.axvline(runs[mu].a, color="w", ls=":", lw=1)
        ax.set_xlim(*window[0])
        ax.set_ylim(*window[1])
        ax.set_aspect("equal")
        ax.set_xlabel("x (mm)")
        ax.set_title(f"μ = {mu:g}: {int(yielded.sum())} elements yielded "
                     f"({int(plastic.sum())} plastic now)", fontsize=10)
        ax.legend(fontsize=7, loc="upper right")
    axes[0].set_ylabel("height above the flat (mm)")
    fig.colorbar(art, ax=axes, label="von Mises stress (MPa)", shrink=0.9)
    fig.suptitle(f"Fig. 5: von Mises stress at full load, elastoplastic cylinder (Sy = {SY:g} "
                 f"MPa, H' = {H_PLASTIC:g} MPa); dotted: contact half-width", fontsize=11)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def fig_interface(path: Path, elastic: dict, plastic: dict, key: str, ylabel: str,
                  title: str) -> Path:
    """Figs. 6-8: one panel per mu, elastic (solid) vs elastoplastic (dashed) at full load."""
    plt = _plt()
    fig, axes = plt.subplots(1, len(MUS), figsize=(15, 4.4), sharey=True,
                             constrained_layout=True)
    for ax, mu in zip(axes, MUS):
        xmax = 1.35 * max(elastic[mu].a, plastic[mu].a)
        for run, style, label, colour in ((elastic[mu], "-", "elastic", "tab:blue"),
                                          (plastic[mu], "--", "elastoplastic", "tab:orange")):
            x, v = run.x, run.profile(key)
            m = x <= xmax
            ax.plot(x[m], v[m], style, marker="o", ms=2.5, lw=1.2, color=colour,
                    label=f"{label} (a = {run.a:.3f})")
            if key == "tangential_stress" and mu > 0:
                sign = 1.0 if v.sum() >= 0 else -1.0
                ax.plot(x[m], sign * mu * run.profile("pressure")[m], ":", lw=1, color=colour,
                        label=f"{'' if sign > 0 else '−'}μ p, {label} (Coulomb limit)")
        xs = np.linspace(0, A_HERTZ, 300)
        if key == "pressure":
            ax.plot(xs, hertz_pressure(xs, A_HERTZ, P0_HERTZ), "k:", lw=1, label="Hertz (elastic, μ = 0)")
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
        for run, style, label in ((elastic[mu], "-", "elastic"), (plastic[mu], "--", "elastoplastic")):
            d = run.data
            ax.step(d["growth_load_fraction"], d["growth_x"], where="post", ls=style,
                    color=colours[mu], lw=1.3, label=f"{label}, μ = {mu:g}")
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
    ax.plot(mu[~surface], 100 * f[~surface], "o", color="tab:blue",
            label="first yield below the surface")
    ax.plot(mu[surface], 100 * f[surface], "s", color="tab:red",
            label="first yield at the surface (centre, stick zone)")
    ax.plot([0], [100 * F_JOHNSON], "k*", ms=12,
            label=f"Johnson, μ = 0: p0 = 1.79 Sy → {100 * F_JOHNSON:.1f} %")
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
    ax.plot(x, run.profile("tangential_stress"), "s-", ms=3,
            label="tangential stress on the punch (+x)")
    ax.plot(x, -0.2 * run.profile("pressure"), ":", color="tab:orange", lw=1,
            label="−μ p (Coulomb limit)")
    ax.plot(xs, rigid, "k--", lw=0.8,
            label="rigid flat punch on a half-plane, 2bq/(π√(b²-x²)) (reference shape)")
    ax.axhline(q, color="0.5", lw=0.8, ls="-.", label=f"applied q = {q:g} MPa")
    c = b - run.slip_length(a=b)
    ax.axvspan(c, b, color="tab:red", alpha=0.08, label=f"slip zone (c = {c:.2f} mm)")
    ax.set_ylim(-0.5 * q, 4 * q)
    ax.set_xlabel("x (mm); punch half-width b = 10 mm")
    ax.set_ylabel("stress (MPa)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("Fig. 12: elastic block on a half-space, contact stresses (q = 1.2 MPa, μ = 0.2, "
                 "plane strain)", fontsize=10)
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
    ax.plot(reference.x, reference.profile("pressure"), ":", color="0.4", marker=".",
            label="elastic (same scene, yield switched off), μ = 0.2")
    ax.axhline(q, color="0.5", lw=0.8, ls="-.", label=f"applied q = {q:g} MPa")
    ax.set_xlabel("x (mm); punch half-width b = 10 mm")
    ax.set_ylabel("contact pressure (MPa)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("Fig. 14: elastoplastic block, contact pressure at q = 36 MPa (plane stress)",
                 fontsize=10)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def fig15_16(paths: tuple[Path, Path], run: Run, levels) -> tuple[Path, Path]:
    plt = _plt()
    cmap = plt.get_cmap("viridis")
    for path, key, label, title in (
            (paths[0], "rtd", "RTD, punch relative to half-space, +x (μm)",
             "Fig. 15: RTD along the interface with increasing load"),
            (paths[1], "tangential_stress", "tangential stress on the punch, +x (MPa)",
             "Fig. 16: tangential stress along the interface with increasing load")):
        fig, ax = plt.subplots(figsize=(7.5, 5), constrained_layout=True)
        for i, f in enumerate(levels):
            k = run.snapshot_index(f)
            v = run.profile(key, k) * (1e3 if key == "rtd" else 1.0)
            c = BLOCK_B - run.slip_length(k, a=BLOCK_B)
            ax.plot(run.x, v, "o-", ms=2.5, color=cmap(i / max(1, len(levels) - 1)),
                    label=f"q = {36 * run.data['snap_load_fraction'][k]:.1f} MPa "
                          f"(f = {run.data['snap_load_fraction'][k]:.2g}), stick up to {c:.1f}")
            if key == "tangential_stress":
                ax.plot(run.x, -0.2 * run.profile("pressure", k), ":", lw=0.8,
                        color=cmap(i / max(1, len(levels) - 1)))
        ax.axhline(0, color="0.5", lw=0.5)
        ax.set_xlabel("x (mm)")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
        ax.set_title(title + " (μ = 0.2; dotted: −μ p)" if key == "tangential_stress"
                     else title + " (μ = 0.2)", fontsize=10)
        fig.savefig(path, dpi=120)
        plt.close(fig)
    return paths


def fig_timeline(path: Path, runs: list[tuple[str, Run]]) -> Path:
    plt = _plt()
    fig, axes = plt.subplots(1, 2, figsize=(15, 0.45 * len(runs) + 2.5),
                             gridspec_kw={"width_ratios": [2.2, 1]}, constrained_layout=True)
    ax = axes[0]
    kinds_seen = {}
    for i, (label, run) in enumerate(runs):
        d = run.data
        kinds = d["events_kind"]
        for j, kind in enumerate(KIND_COLOURS):
            m = kinds == kind
            if m.any():
                h = ax.plot(d["events_load_fraction"][m], np.full(m.sum(), i + 0.1 * (j - 3)), "|",
                            ms=7, color=KIND_COLOURS[kind])
                kinds_seen[kind] = h[0]
    ax.set_yticks(range(len(runs)))
    ax.set_yticklabels([f"{label} ({len(run.data['events_kind'])})" for label, run in runs],
                       fontsize=8)
    ax.set_xlim(-0.02, 1.0)
    ax.set_xlabel("load fraction of the event")
    ax.invert_yaxis()
    ax.grid(alpha=0.3, axis="x")
    ax.legend(list(kinds_seen.values()), list(kinds_seen), fontsize=8, loc="lower left",
              bbox_to_anchor=(0.0, 1.0), ncol=len(kinds_seen), frameon=False)
    ax.set_title("every event of every scene, by kind (number of events in brackets)",
                 fontsize=10, pad=22)
    label, run = next((lr for lr in runs if lr[0] == "cylinder, plastic, μ = 0.35"), runs[0])
    ax = axes[1]
    d = run.data
    for kind, colour in KIND_COLOURS.items():
        m = d["events_kind"] == kind
        if m.any():
            f = np.sort(d["events_load_fraction"][m])
            ax.step(np.r_[f, 1], np.r_[np.arange(1, len(f) + 1), len(f)], where="post",
                    color=colour, label=f"{kind} ({m.sum()})")
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


# --------------------------------------------------------------------------- the numbers
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
    return {"h_contact": h,
            "elastic_a": el.a, "elastic_a_err": el.a / A_HERTZ - 1,
            "elastic_p0": float(el.summary["peak_pressure"]),
            "elastic_p0_err": float(el.summary["peak_pressure"]) / P0_HERTZ - 1,
            "yield_f": f_y, "yield_f_err": f_y / F_JOHNSON - 1,
            "yield_a": a_y, "yield_a_err": a_y / A_JOHNSON - 1,
            "yield_a_err_paper": a_y / PAPER_TABLE1["yield_a"][0] - 1,
            "yield_p0": p_y, "yield_p0_err": p_y / P0_JOHNSON - 1,
            "yield_a_outermost_closed_node": yl.a,
            "yield_depth": float(depth), "yield_depth_over_a": float(depth) / a_y,
            "yield_x": float(s.get("first_yield_x", float("nan"))),
            "a_johnson": A_JOHNSON, "p0_johnson": P0_JOHNSON, "f_johnson": F_JOHNSON,
            "a_hertz": A_HERTZ, "p0_hertz": P0_HERTZ}


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

    a_el = {mu: cyl_el[mu].a for mu in MUS}
    a_pl = {mu: cyl_pl[mu].a for mu in MUS}
    add("plastic_contact_longer", "cylinder: elastoplastic contact half-length > elastic at "
        "full load, each mu [elastic, plastic]", {f"{mu:g}": [a_el[mu], a_pl[mu]] for mu in MUS},
        all(a_pl[mu] > a_el[mu] for mu in MUS), True)
    r_el = {mu: cyl_el[mu].pressure_ratio() for mu in MUS}
    r_pl = {mu: cyl_pl[mu].pressure_ratio() for mu in MUS}
    add("plastic_pressure_flatter", "cylinder: peak / mean pressure smaller when plastic, each "
        "mu [elastic, plastic] (Hertz: 4/pi = 1.273)",
        {f"{mu:g}": [r_el[mu], r_pl[mu]] for mu in MUS},
        all(r_pl[mu] < r_el[mu] for mu in MUS), True)
    for kind, runs in (("elastic", cyl_el), ("plastic", cyl_pl)):
        slip = [runs[mu].slip_length() for mu in MUS]
        add(f"slip_zone_shrinks_{kind}", f"cylinder, {kind}: slip zone a - c shrinks as mu "
            f"grows (mu = {', '.join(f'{m:g}' for m in MUS)})", slip,
            all(b < a for a, b in zip(slip, slip[1:])), True)
    f = [r["f"] for r in fig10_rows]
    mu_s = surface_transition(fig10_rows)
    tail = [r["f"] for r in fig10_rows if mu_s is not None and r["mu"] >= mu_s]
    add("onset_falls", "Fig. 10: onset-of-yield load lower at mu = 0.5 than at mu = 0, and "
        "non-increasing from the mu where first yield moves to the surface", {
            "f(0)": f[0], "f(0.5)": f[-1], "surface from mu": mu_s, "f from there": tail},
        f[-1] < f[0] and mu_s is not None
        and all(b <= a * (1 + 1e-9) for a, b in zip(tail, tail[1:])), True)
    head = [r["f"] for r in fig10_rows if mu_s is None or r["mu"] < mu_s]
    add("onset_falls_everywhere", "Fig. 10 as drawn by the paper: onset non-increasing for every "
        "mu (here: also while yield starts below the surface)", head,
        all(b <= a * (1 + 1e-9) for a, b in zip(head, head[1:])))
    p_centre = [float(cyl_el[mu].profile("pressure")[0]) for mu in MUS]
    add("elastic_centre_pressure_rises", "Fig. 6: elastic central pressure increases slightly "
        "with mu", p_centre, all(b > a for a, b in zip(p_centre, p_centre[1:])))
    pp = [float(cyl_pl[mu].profile("pressure")[0]) for mu in MUS]
    add("plastic_centre_pressure_pattern", "Fig. 6: elastoplastic central pressure rises from "
        "mu = 0 to 0.1, then drops back towards the frictionless value at 0.35", pp,
        pp[1] > pp[0] and pp[2] < pp[1])
    al = [a_pl[mu] for mu in MUS]
    add("plastic_length_pattern", "Figs. 6/9: elastoplastic contact length decreases from "
        "mu = 0 to 0.1, then grows back towards the frictionless value at 0.35", al,
        al[1] < al[0] and al[2] > al[1])
    rtd = {}
    for mu in MUS:
        inside = cyl_el[mu].x <= a_el[mu]
        rtd[f"{mu:g}"] = [float(np.abs(r.profile("rtd")[inside]).max()) for r in
                          (cyl_el[mu], cyl_pl[mu])]
    add("plastic_rtd_smaller", "Fig. 7: RTD smaller when plastic (largest abs(RTD) inside the elastic "
        "contact) [elastic, plastic]", rtd, all(v[1] < v[0] for v in rtd.values()))
    tau = {f"{mu:g}": [float(np.abs(r.profile("tangential_stress")).max()) for r in
                       (cyl_el[mu], cyl_pl[mu])] for mu in MUS if mu > 0}
    add("plastic_tangential_smaller", "Fig. 8: tangential stress smaller when plastic (peak) "
        "[elastic, plastic]", tau, all(v[1] < v[0] for v in tau.values()))
    zones = []
    for mu in MUS:
        d = cyl_pl[mu].data
        zones.append(_area(d["nodes"], d["triangles"], d["plastic_strain"] > 0))
    add("plastic_zone_grows", "Fig. 5: plastic zone area (mm^2) grows with mu", zones,
        all(b > a for a, b in zip(zones, zones[1:])))
    bp = blocks["plastic"]
    pc = [float(bp[mu].profile("pressure")[0]) for mu in (0.0, 0.2)]
    add("block_centre_pressure_mu", "Fig. 14: block, central pressure for mu = 0.2 slightly "
        "larger than for mu = 0", pc, pc[1] > pc[0])
    run = bp[0.2]
    levels = _levels(run)
    slips = [run.slip_length(run.snapshot_index(f), a=BLOCK_B) for f in levels]
    add("block_slip_zone_shrinks_with_load", "Fig. 15: block mu = 0.2, slip zone (mm) "
        "decreases as the load increases", {f"{f:g}": s for f, s in zip(levels, slips)},
        slips[-1] < slips[0] and all(b <= a + 1e-9 for a, b in zip(slips, slips[1:])))
    peak = [float(np.abs(run.profile("tangential_stress", run.snapshot_index(f))).max())
            for f in levels]
    add("block_tangential_stress_grows", "Fig. 16: block mu = 0.2, peak tangential stress "
        "(MPa) larger at full load than at the lowest level shown",
        {f"{f:g}": t for f, t in zip(levels, peak)}, peak[-1] > peak[0])
    rtd_b, tau_b = run.profile("rtd"), run.profile("tangential_stress")
    slipping = run.status() == 2
    add("block_tangential_opposes_rtd", "Figs. 15/16: tangential stress opposes the RTD in the "
        "slip zone (number of slipping pairs)", int(slipping.sum()),
        bool(np.all(rtd_b[slipping] * tau_b[slipping] <= 0)))
    return out


def zone_at_surface(run: Run) -> bool | None:
    """Does the yielded zone of a cylinder run touch the contact (an element with a node on
    the arc inside the contact half-width)?"""
    d = run.data
    if "plastic_strain" not in d:
        return None
    nodes, tri = d["nodes"], d["triangles"]
    x, y = nodes[:, 0], nodes[:, 1]
    on_arc = (np.abs(y - (R - np.sqrt(np.clip(R ** 2 - x ** 2, 0, None)))) < 1e-6) & (x <= run.a)
    yielded = d["plastic_strain"] > 0
    return bool(on_arc[tri[yielded]].any())


def _levels(run: Run) -> list[float]:
    fs = run.data["snap_load_fraction"]
    return [float(f) for f in fs if f >= 0.4 - 1e-9 and abs(10 * f - round(10 * f)) < 1e-9]


def _area(nodes, tri, mask) -> float:
    t = nodes[tri[mask]]
    return float(0.5 * np.abs((t[:, 1, 0] - t[:, 0, 0]) * (t[:, 2, 1] - t[:, 0, 1])
                              - (t[:, 2, 0] - t[:, 0, 0]) * (t[:, 1, 1] - t[:, 0, 1])).sum())


# --------------------------------------------------------------------------- the whole thing
def reproduce(out: str | Path, quick: bool = False, workers: int | None = None,
              log=print) -> dict:
    """Run every scene, draw every figure, write report.md and reproduce.json; returns the
    numbers (also in reproduce.json)."""
    start = time.perf_counter()
    s = QUICK if quick else FULL
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    runs_dir, fig10_dir = out / "runs", out / "fig10"
    tasks = scene_tasks(s)
    rep = sweep.run_tasks(tasks, runs_dir, workers=workers, log=log, name="reproduce")
    _raise_failures(rep)
    probe_failed = {cid: msg for cid, msg in rep.failed.items() if cid.startswith("probe_")}
    study = fig10_study(s)
    rep10 = sweep.run_sweep(study, fig10_dir, workers=workers, log=log)
    _raise_failures(rep10)
    t_runs = time.perf_counter() - start

    run = {t["case_id"]: Run(runs_dir, t["case_id"]) for t in tasks
           if t["case_id"] not in probe_failed}
    cyl_el = {mu: run[f"cyl_elastic_mu{_mu_id(mu)}"] for mu in MUS}
    cyl_pl = {mu: run[f"cyl_plastic_mu{_mu_id(mu)}"] for mu in MUS}
    blocks = {"elastic": run["block_elastic"],
              "plastic": {mu: run[f"block_plastic_mu{_mu_id(mu)}"] for mu in (0.0, 0.2)}}
    el_1x = run.get("check_block_elastic_1x", run["block_elastic"])
    pl_1x = run.get("check_block_plastic_1x", run[f"block_plastic_mu{_mu_id(0.2)}"])
    numbers = {"quick": quick, "settings": s.__dict__,
               "table1": table1(run["table1_elastic"], run["table1_yield"], s.h_table),
               "paper_table1": PAPER_TABLE1}
    numbers["half_space_doubling"] = {}
    for key, r1, r2, h in (("elastic", el_1x, run["check_block_elastic_2x"], s.h_check_elastic),
                           ("plastic_mu0.2", pl_1x,
                            run["check_block_plastic_2x"], s.h_check_plastic)):
        numbers["half_space_doubling"][key] = {
            "h": h, "max_pressure_change": doubling(r1, r2),
            "centre_pressure_change": float(r2.profile("pressure")[0] / r1.profile("pressure")[0]
                                            - 1),
            "stick_half_width": [float(r1.summary["stick_half_width"]),
                                 float(r2.summary["stick_half_width"])]}
    fig10_rows = []
    for t in study.tasks():
        sm = sweep.load_summary(fig10_dir, t["case_id"])
        depth = sm["first_yield_depth"]
        fig10_rows.append({"mu": t["params"]["contact.mu"],
                           "f": sm["first_yield_load_fraction"], "depth": depth,
                           "x": sm["first_yield_x"], "a": sm["contact_half_width"]})
    numbers["fig10"] = fig10_rows
    numbers["checks"] = checks(cyl_el, cyl_pl, fig10_rows, blocks)
    numbers["cylinder"] = {
        f"{kind}_mu{mu:g}": {"a": r.a, "c": float(r.summary["stick_half_width"]),
                             "p0": float(r.summary["peak_pressure"]),
                             "p_centre": float(r.profile("pressure")[0]),
                             "peak_over_mean": r.pressure_ratio(),
                             "slip_length": r.slip_length(),
                             "n_events": int(r.summary["n_events"]),
                             "n_plastic": r.summary.get("n_plastic_elements"),
                             "yielded": int((r.data["plastic_strain"] > 0).sum())
                             if "plastic_strain" in r.data else None,
                             "first_yield_f": r.summary.get("first_yield_load_fraction"),
                             "zone_at_surface": zone_at_surface(r),
                             "wall_time_s": float(r.summary["wall_time_s"])}
        for kind, group in (("elastic", cyl_el), ("plastic", cyl_pl)) for mu, r in group.items()}
    numbers["blocks"] = _block_numbers(blocks, run["block_plastic_elastic_reference"])
    for mu in (0.0, 0.2):
        numbers["blocks"][f"plastic_mu{mu:g}"]["load_settlement"] = settlement(
            blocks["plastic"][mu])
    probe = run.get("probe_block_perfectly_plastic")
    numbers["blocks"]["perfectly_plastic_halfspace"] = (
        {"h": s.h_check_plastic, **settlement(probe),
         "yielded_halfspace": int(((probe.data["plastic_strain"] > 0)
                                   & (probe.data["element_body"] == 1)).sum())}
        if probe is not None else {"error": probe_failed.get("probe_block_perfectly_plastic")})
    numbers["warnings"] = [f"{cid}: per-run figures not written ({r.summary['figures_error']})"
                           for cid, r in run.items() if r.summary.get("figures_error")]
    numbers["warnings"] += [f"{cid}: did not finish ({msg})" for cid, msg in probe_failed.items()]
    numbers["per_run_von_mises"] = all((runs_dir / f"cyl_plastic_mu{_mu_id(mu)}" /
                                        "von_mises.png").exists() for mu in MUS)
    numbers["runs"] = {cid: {"n_events": int(r.summary["n_events"]),
                             "n_nodes": int(r.summary["n_nodes"]),
                             "wall_time_s": float(r.summary["wall_time_s"])}
                       for cid, r in run.items()}

    figs = {}
    figs["table1"] = fig_table1(out / "table1.png", run["table1_elastic"], run["table1_yield"],
                                numbers["table1"])
    figs["fig05"] = fig05(out / "fig05_von_mises.png", cyl_pl)
    figs["fig06"] = fig_interface(out / "fig06_pressure.png", cyl_el, cyl_pl, "pressure",
                                  "contact pressure (MPa)", "Fig. 6: contact pressure at full "
                                  "load, elastic vs elastoplastic")
    figs["fig07"] = fig_interface(out / "fig07_rtd.png", cyl_el, cyl_pl, "rtd",
                                  "RTD along +x (mm)", "Fig. 7: relative tangential displacement "
                                  "at full load")
    figs["fig08"] = fig_interface(out / "fig08_tangential.png", cyl_el, cyl_pl,
                                  "tangential_stress", "tangential stress on the cylinder, +x "
                                  "(MPa)", "Fig. 8: tangential stress at full load")
    figs["fig09"] = fig09(out / "fig09_contact_growth.png", cyl_el, cyl_pl)
    figs["fig10"] = fig10(out / "fig10_onset_of_yield.png", fig10_rows)
    figs["fig12"], figs["fig13"] = fig12_13((out / "fig12_block_elastic_stresses.png",
                                             out / "fig13_block_elastic_rtd.png"),
                                            blocks["elastic"], 1.2)
    figs["fig14"] = fig14(out / "fig14_block_plastic_pressure.png", blocks["plastic"],
                          run["block_plastic_elastic_reference"], 36.0)
    figs["fig15"], figs["fig16"] = fig15_16((out / "fig15_block_plastic_rtd.png",
                                             out / "fig16_block_plastic_tangential.png"),
                                            blocks["plastic"][0.2], _levels(blocks["plastic"][0.2]))
    timeline = [("Table 1, elastic", run["table1_elastic"]),
                ("Table 1, to first yield", run["table1_yield"])]
    timeline += [(f"cylinder, elastic, μ = {mu:g}", cyl_el[mu]) for mu in MUS]
    timeline += [(f"cylinder, plastic, μ = {mu:g}", cyl_pl[mu]) for mu in MUS]
    timeline += [("block, elastic, μ = 0.2", blocks["elastic"])]
    timeline += [(f"block, plastic, μ = {mu:g}", blocks["plastic"][mu]) for mu in (0.0, 0.2)]
    figs["timeline"] = fig_timeline(out / "events_timeline.png", timeline)
    numbers["events"] = {label: {k: int(v) for k, v in zip(*np.unique(r.data["events_kind"],
                                                                       return_counts=True))}
                         for label, r in timeline}

    numbers["wall_time_s"] = {
        "runs": t_runs, "total": time.perf_counter() - start,
        "solver_sum": float(sum(r["wall_time_s"] for r in numbers["runs"].values()) + sum(
            sweep.load_summary(fig10_dir, t["case_id"])["wall_time_s"] for t in study.tasks()))}
    numbers["figures"] = {k: p.name for k, p in figs.items()}
    numbers["axisymmetric"] = reproduce_axisymmetric.page(out, quick, workers, log)
    write_report(out / "report.md", numbers)
    numbers["wall_time_s"]["total"] = time.perf_counter() - start
    with open(out / ".reproduce.json.partial", "w") as fh:
        json.dump(json_safe(numbers), fh, indent=2)
        fh.write("\n")
    (out / ".reproduce.json.partial").replace(out / "reproduce.json")
    if log:
        log(f"reproduce: {len(figs)} figures, report.md in {out} "
            f"({numbers['wall_time_s']['total']:.1f} s)")
    return numbers


def _block_numbers(blocks: dict, reference: Run) -> dict:
    el = blocks["elastic"]
    out = {"elastic": {"p_centre": float(el.profile("pressure")[0]),
                       "p_edge": float(el.profile("pressure")[-1] if el.x[-1] <= BLOCK_B + 1e-9
                                       else el.profile("pressure")[el.x <= BLOCK_B + 1e-9][-1]),
                       "stick_half_width": float(el.summary["stick_half_width"]),
                       "n_events": int(el.summary["n_events"]),
                       "max_event_f": float(np.max(el.data["events_load_fraction"], initial=0.0)),
                       "n_nodes": int(el.summary["n_nodes"]),
                       "n_elements": int(el.summary["n_elements"])}}
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
            "slip_by_level": {f"{f:g}": r.slip_length(r.snapshot_index(f), a=BLOCK_B)
                              for f in _levels(r)}}
    out["elastic_reference_q36_mu0.2"] = {"p_centre": float(reference.profile("pressure")[0]),
                                          "p_peak": float(reference.summary["peak_pressure"])}
    return out


def _raise_failures(rep) -> None:
    if rep.interrupted:
        raise KeyboardInterrupt
    failed = {cid: msg for cid, msg in rep.failed.items() if not cid.startswith("probe_")}
    if failed:
        cid, msg = next(iter(failed.items()))
        raise RuntimeError(f"run {cid} failed: {msg}")


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
    k = np.diff(f) / np.diff(v) / k0          # incremental stiffness / elastic, per interval
    soft = np.flatnonzero(k < 0.1)
    return {"settlement": float(v[-1]), "load_fraction": float(f[-1]),
            "tangent_stiffness_ratio": float(k[-1]),
            "flow_from_load_fraction": float(f[soft[0]]) if len(soft) else None,
            "curve": [[float(a), float(b)] for a, b in zip(f, v)]}


# --------------------------------------------------------------------------- report.md
def _pc(x: float) -> str:
    return f"{100 * x:+.2f} %"


def write_report(path: Path, n: dict) -> Path:
    t = n["table1"]
    ch = n["checks"]
    cyl = n["cylinder"]
    bl = n["blocks"]
    dbl = n["half_space_doubling"]
    s = n["settings"]
    fig10_h = s["h_fig10"] if s["h_fig10"] is not None else s["h_table"]

    def ok(name):
        return "holds" if ch[name]["pass"] else "does **not** hold"

    def cy(kind, mu, key):
        return cyl[f"{kind}_mu{mu:g}"][key]

    fy_plastic = ", ".join(f"{cy('plastic', mu, 'first_yield_f'):.3f}" for mu in MUS)

    lines = [
        "# slipstep: reproduction of Abdalla, Ali-Eldin & Ghazy, §5",
        "",
        f"Generated by `slipstep reproduce{' --quick' if n['quick'] else ''}`: "
        f"{len(n['runs'])} scene runs and {len(n['fig10'])} sweep cases, "
        f"{n['wall_time_s']['solver_sum']:.0f} s of solver time in all (see the table at the "
        "end; runs found finished in the output folder are reused). Every run's full results (XDMF "
        "series for ParaView, events.csv, contact_profile.csv, summary.json, per-run PNGs) are "
        "in `runs/<scene>/`, the Fig. 10 sweep in `fig10/` (with `summaries.csv`); every number "
        "below is in `reproduce.json`."
        + (" **Quick mode: coarse meshes, for the tests; the numbers are not the converged "
           "ones.**" if n["quick"] else ""),
        "",
        "Scenes: the Hertz cylinder of §5.1 (R = 125 mm, E = 70 GPa, ν = 0.3, P = 1000 N/mm, "
        f"plane strain, quarter model), elastoplastic with **Sy = {SY:g} MPa and linear "
        f"hardening H' = {H_PLASTIC:g} MPa** (the paper gives no hardening value; ours); the "
        "blocks of §5.2 from `cases/paper_block_elastic.toml` and "
        "`cases/paper_block_plastic.toml` (the paper gives neither dimensions nor materials; "
        "ours and the reasons are in the case files: punch half-width b = 10 mm, lower block "
        "10 b × 10 b). "
        f"Meshes: h_contact = {s['h_table']:g} mm for Table 1, {fig10_h:g} mm for Fig. 10, "
        f"{s['h_cyl']:g} mm for Figs. 5-9 (elastoplastic runs cost one refactorization per "
        f"yield event); block spacing {s['h_block_elastic']:g} mm (elastic) and "
        f"{s['h_block_plastic']:g} mm (elastoplastic): the punch structured, the half-space "
        "structured at that spacing inside a box under the punch that holds the plastic zone "
        "and graded outside (`refine_box`, see the case files), "
        f"{n['runs']['block_elastic']['n_nodes']:,} and "
        f"{n['runs']['block_plastic_mu0']['n_nodes']:,} nodes in all. Inside the box the "
        "mesh is the structured block's own, and at the case files' spacing the interface "
        "pressure, tangential stress and RTD are those of the structured 10 b × 10 b "
        "half-space within 1 % of their peaks, node by node, with more than 10× fewer nodes "
        "(`tests/physics/test_paper_blocks_graded.py`).",
        "",
        "## Table 1",
        "",
        "![Table 1](table1.png)",
        "",
        "| solution | parameter | closed form | slipstep | error | paper FEM | paper error |",
        "|---|---|---|---|---|---|---|",
        f"| elastic, full load | a (mm) | {A_HERTZ:.4f} (Hertz) | {t['elastic_a']:.4f} | "
        f"{_pc(t['elastic_a_err'])} | 1.43 | 0.58 % |",
        f"| | p0 (MPa) | {P0_HERTZ:.1f} (Hertz) | {t['elastic_p0']:.1f} | "
        f"{_pc(t['elastic_p0_err'])} | 451 | 1.86 % |",
        f"| elastoplastic, threshold of plasticity | a (mm) | {A_JOHNSON:.4f} (Hertz at p0 = "
        f"358) / 1.036 (paper's) | {t['yield_a']:.4f} | {_pc(t['yield_a_err'])} / "
        f"{_pc(t['yield_a_err_paper'])} | 1.08 | 4.04 % |",
        f"| | p0 (MPa) | {P0_JOHNSON:.1f} (Johnson: 1.79 Sy) | {t['yield_p0']:.1f} | "
        f"{_pc(t['yield_p0_err'])} | 323.9 | 9.5 % |",
        f"| | load fraction | {F_JOHNSON:.4f} = (358/442.6)² | {t['yield_f']:.4f} | "
        f"{_pc(t['yield_f_err'])} | – | – |",
        f"| | depth of first yield / a | 0.70 (Johnson) | {t['yield_depth_over_a']:.3f} | "
        f"{_pc(t['yield_depth_over_a'] / DEPTH_JOHNSON - 1)} | – | – |",
        "",
        f"**What agrees.** At full elastic load the contact half-width (interpolated in load "
        f"between the last closed and the first open node, from the event history) and the peak "
        f"nodal pressure are within {100 * abs(t['elastic_a_err']):.2f} % and "
        f"{100 * abs(t['elastic_p0_err']):.2f} % of Hertz (the paper: 0.58 % and 1.86 %). The "
        f"first yield event comes at load fraction {t['yield_f']:.4f}, where Johnson's "
        f"p0 = 1.79 Sy puts it at {F_JOHNSON:.4f} ({_pc(t['yield_f_err'])}), in the element "
        f"whose centroid is {t['yield_depth']:.3f} mm deep, {t['yield_depth_over_a']:.2f} a "
        f"(Johnson: 0.70 a); the peak pressure at that instant is {t['yield_p0']:.1f} MPa "
        f"({_pc(t['yield_p0_err'])} from 358 MPa). The paper's 323.9 MPa (−9.5 %) is the "
        "largest error of its Table 1; slipstep does not share it, because the event-driven "
        "loop stops exactly at the yield event (the load at which the table is read is exact "
        "to round-off, not to a load step), so what remains is the mesh.",
        "",
        "**What does not, and why.** The paper's 'analytical' half-width at the threshold, "
        f"a = 1.036 mm, is not Hertz's for its own numbers: Hertz gives a = 2R p0/E* = "
        f"{A_JOHNSON:.4f} mm at p0 = 358 MPa (equivalently 1.4384 mm × √{F_JOHNSON:.4f}). "
        f"Ours, {t['yield_a']:.4f} mm, is {_pc(t['yield_a_err'])} from Hertz's value and "
        f"{_pc(t['yield_a_err_paper'])} from the paper's 1.036; the paper's own FEM value "
        f"1.08 mm is {_pc(1.08 / A_JOHNSON - 1)} from Hertz's. (The half-width at the threshold is "
        "interpolated with the closure loads of the elastic run, identical up to first yield; "
        f"the outermost closed node is at {t['yield_a_outermost_closed_node']:.4f} mm.) Our "
        "residual errors are discretisation: the half-width is read between nodes, the peak "
        "pressure is a lumped "
        "nodal value λn/(L t), and yield is detected at element centroids (constant-strain "
        "triangles).",
        "",
        "## Fig. 5: von Mises stress and the plastic zone",
        "",
        "![Fig. 5](fig05_von_mises.png)",
        "",
        f"The plastic zone (elements with plastic strain) covers "
        f"{', '.join(f'{z:.3f}' for z in ch['plastic_zone_grows']['value'])} mm² at full load "
        f"for μ = {', '.join(f'{m:g}' for m in MUS)}: the paper's 'the increase in friction "
        f"coefficient increases the plastic zone' {ok('plastic_zone_grows')}. "
        + ", ".join(f"μ = {mu:g}: the zone {_reach(cy('plastic', mu, 'zone_at_surface'))} the "
                    "contact surface" for mu in MUS)
        + " (paper, Fig. 5-c: at μ = 0.35 it reaches the surface). Without friction the zone "
        "grows from Johnson's subsurface point (0.70 a under the centre); friction adds surface "
        "shear and stick, which push it towards the surface."
        + (" Per-run maps (with the first yield element marked) are "
           "`runs/cyl_plastic_mu*/von_mises.png`." if n["per_run_von_mises"] else ""),
        "",
        "## Figs. 6-8: the interface, elastic vs elastoplastic",
        "",
        "![Fig. 6](fig06_pressure.png)",
        "",
        "![Fig. 7](fig07_rtd.png)",
        "",
        "![Fig. 8](fig08_tangential.png)",
        "",
        "| μ | a elastic | a plastic | p(0) elastic | p(0) plastic | peak/mean elastic | "
        "peak/mean plastic | slip a−c elastic | slip a−c plastic |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for mu in MUS:
        e, p = cyl[f"elastic_mu{mu:g}"], cyl[f"plastic_mu{mu:g}"]
        lines.append(f"| {mu:g} | {e['a']:.4f} | {p['a']:.4f} | {e['p_centre']:.1f} | "
                     f"{p['p_centre']:.1f} | {e['peak_over_mean']:.3f} | "
                     f"{p['peak_over_mean']:.3f} | {e['slip_length']:.3f} | "
                     f"{p['slip_length']:.3f} |")
    lines += [
        "",
        f"What agrees with the paper: the elastoplastic contact is longer than the elastic one "
        f"at the same load ({ok('plastic_contact_longer')} for every μ) and its pressure is "
        f"flatter (peak/mean pressure smaller: {ok('plastic_pressure_flatter')}; Hertz: "
        f"4/π = 1.273); the slip zone shrinks, the stick zone grows, as μ grows (elastic: "
        f"{ok('slip_zone_shrinks_elastic')}, elastoplastic: {ok('slip_zone_shrinks_plastic')}); "
        f"the elastic central pressure rises slightly with μ "
        f"({ok('elastic_centre_pressure_rises')}); the RTD is smaller when plastic "
        f"({ok('plastic_rtd_smaller')}) and so is the tangential stress "
        f"({ok('plastic_tangential_smaller')}), the paper's explanation being the lower "
        "stiffness of the plastic surface layer. The tangential stress never exceeds the "
        "Coulomb limit μ p (dotted). Finer points of the paper's text: 'for μ = 0.1 the "
        "central contact pressure increases slightly and the contact length decreases; for "
        "μ = 0.35 the central pressure drops to nearly the value of frictionless' and the "
        f"length comes back: the pressure pattern {ok('plastic_centre_pressure_pattern')} "
        f"(plastic p(0) = {_join(ch['plastic_centre_pressure_pattern']['value'], '.1f')} MPa), "
        f"the length pattern {ok('plastic_length_pattern')} "
        f"(a = {_join(ch['plastic_length_pattern']['value'], '.4f')} mm); "
        "these differences are below one element size for the length and a few per cent for "
        "the pressure, so they depend on the mesh and on our hardening modulus (the paper's is "
        "unknown), unlike the ones above.",
        "",
        "## Fig. 9: growth of the contact",
        "",
        "![Fig. 9](fig09_contact_growth.png)",
        "",
        "The curves are the event history itself: each step is a `close` event at the load "
        "fraction where it happened, no load stepping is involved. The elastic frictionless "
        "curve touches Hertz's a√f at every node. Friction delays each closure slightly (the "
        "stick zone restrains the surface), as in the paper ('the fraction of applied load "
        "increases for the same contact length'). The elastoplastic curves leave the elastic "
        "ones after the first yield (f = "
        f"{fy_plastic} "
        "for μ = 0, 0.1, 0.35) and close the outer nodes at lower loads: the plastic contact "
        "grows faster.",
        "",
        "## Fig. 10: load at the onset of yield vs μ",
        "",
        "![Fig. 10](fig10_onset_of_yield.png)",
        "",
        "| μ | " + " | ".join(f"{r['mu']:g}" for r in n["fig10"]) + " |",
        "|---|" + "---|" * len(n["fig10"]),
        "| onset (% of P) | " + " | ".join(f"{100 * r['f']:.2f}" for r in n["fig10"]) + " |",
        "| depth of first yield / a | " + " | ".join(
            f"{r['depth'] / r['a']:.2f}" for r in n["fig10"]) + " |",
        "",
    ]
    mu_s = ch["onset_falls"]["value"]["surface from mu"]
    f10 = n["fig10"]
    lines += [
        f"Made by the sweep runner (`slipstep sweep studies/fig10_onset_of_yield.toml`: "
        f"{len(f10)} cases, each stopped right after its first yield event). At μ = 0 the onset "
        f"is {100 * f10[0]['f']:.2f} % of P, Johnson's value {100 * F_JOHNSON:.2f} %. "
        f"The paper's claim, the onset falls as μ grows, {ok('onset_falls')} overall "
        f"({100 * f10[0]['f']:.1f} % at μ = 0, {100 * f10[-1]['f']:.1f} % at μ = 0.5), but the "
        "curve has two regimes the paper does not show. While first yield is below the surface "
        f"(μ < {mu_s if mu_s is not None else '–'}) the onset "
        + ("does not fall: it rises by "
           f"{100 * (max(ch['onset_falls_everywhere']['value']) / f10[0]['f'] - 1):.1f} % "
           if not ch["onset_falls_everywhere"]["pass"] else "falls only slightly ")
        + "(the partial-slip traction of a cylinder pressed on a rigid flat is small and barely "
        "changes the subsurface stresses). From "
        f"μ = {mu_s if mu_s is not None else '–'} on, yield starts instead at the surface under "
        "the centre, inside the stick zone: stick holds the surface strain ε_x at zero, so there "
        "σx = σz = ν/(1−ν) σy and σe = (1−2ν)/(1−ν) p = 0.571 p, instead of (1−2ν) p = 0.4 p "
        "without friction, while the central pressure also rises with μ; from there the onset "
        "falls monotonically. The μ at which the mechanism switches depends on the mesh "
        "(measured: 0.15 on the default mesh h = 0.03 mm, 0.25 at h = 0.1 mm): the centroid of the "
        "first surface element lies deeper on a coarser mesh. The paper's explanation, 'the "
        "increase in the stress that results from the friction', fits the surface regime.",
        "",
        "## Figs. 12-13: elastic block on a half-space (q = 1.2 MPa, μ = 0.2, plane strain)",
        "",
        "![Fig. 12](fig12_block_elastic_stresses.png)",
        "",
        "![Fig. 13](fig13_block_elastic_rtd.png)",
        "",
        f"Half-space size: doubling the lower block (10 b × 10 b → 20 b × 20 b, the same mesh "
        f"under the punch and the same grading) "
        f"changes the interface pressure by at most "
        f"{100 * dbl['elastic']['max_pressure_change']:.2f} % of its peak, node by node "
        f"(elastic, h = {dbl['elastic']['h']:g} mm), and by "
        f"{100 * dbl['plastic_mu0.2']['max_pressure_change']:.2f} % in the elastoplastic "
        f"μ = 0.2 case (h = {dbl['plastic_mu0.2']['h']:g} mm): the lower block stands for the "
        "half-space to better than 1 %. The end of the stick zone is more sensitive: it moves "
        f"from {dbl['elastic']['stick_half_width'][0]:.2f} to "
        f"{dbl['elastic']['stick_half_width'][1]:.2f} mm (elastic; "
        f"{dbl['plastic_mu0.2']['stick_half_width'][0]:.2f} → "
        f"{dbl['plastic_mu0.2']['stick_half_width'][1]:.2f} mm elastoplastic), because in plane "
        "elasticity the tangential surface displacement of a loaded half-plane does not decay "
        "with distance, so the far boundaries of any finite model shift the slip "
        "(the stick-zone end is also read at node spacing). "
        f"The pressure is nearly uniform under the middle of the punch (p(0) = "
        f"{bl['elastic']['p_centre']:.3f} MPa for q = 1.2 MPa) and rises steeply towards its "
        f"corner ({bl['elastic']['p_edge']:.2f} MPa at the corner node, a mesh-dependent value "
        "of a singular field), the 'stationary contact' of the paper: every pair starts closed "
        "and stays closed. The punch expands laterally more than the half-space surface, so it "
        "slips outwards near its edge, and friction on it points inwards (−x), bounded by μ p "
        f"in the slip zone; it sticks up to x = {bl['elastic']['stick_half_width']:.2f} mm of "
        f"b = 10 mm. "
        + (f"All {bl['elastic']['n_events']} events of the run (stick→slip) happen at the first "
           "instant (load fraction 0): elastic and proportional, the solution then only scales "
           "with q." if bl["elastic"]["max_event_f"] < 1e-9 else
           f"Its {bl['elastic']['n_events']} events (stick→slip) end at load fraction "
           f"{bl['elastic']['max_event_f']:.3g}.")
        + " There is no closed form for this geometry; "
        "the dashed curve is the rigid flat punch on a half-plane, shown only for the shape of "
        "the edge singularity. The paper's comparison with Qin & Wang (its ref. 14) cannot be "
        "redone, their dimensions and materials being unknown.",
        "",
        "## Figs. 14-16: elastoplastic block (q = 36 MPa, plane stress, μ = 0 and 0.2)",
        "",
        "![Fig. 14](fig14_block_plastic_pressure.png)",
        "",
        "![Fig. 15](fig15_block_plastic_rtd.png)",
        "",
        "![Fig. 16](fig16_block_plastic_tangential.png)",
        "",
    ]
    b0, b2 = bl["plastic_mu0"], bl["plastic_mu0.2"]
    ref = bl["elastic_reference_q36_mu0.2"]
    tau = ch["block_tangential_stress_grows"]["value"]
    fs, vs = list(tau), list(tau.values())
    k = int(np.argmax(vs))
    tau_story = (f"it grows from {vs[0]:.2f} MPa at f = {fs[0]} to {vs[k]:.2f} MPa at f = {fs[k]}"
                 + (f" and then falls to {vs[-1]:.2f} MPa at full load, once the corner pressure "
                    "is capped by plasticity" if k < len(vs) - 1 else "")
                 + f" (larger at full load than at f = {fs[0]}: "
                 f"{ok('block_tangential_stress_grows')})")
    slip_levels = ", ".join(f"{v:.1f} mm at f = {k}" for k, v in b2["slip_by_level"].items())
    lines += [
        f"Substantially plastic, and kept from collapse by hardening: first yield at f = {b0['first_yield_f']:.3f} "
        f"(μ = 0) and {b2['first_yield_f']:.3f} (μ = 0.2); at full load {b0['yielded_halfspace']} "
        f"/ {b2['yielded_halfspace']} elements of the half-space and {b0['yielded_punch']} / "
        f"{b2['yielded_punch']} of the punch (at its corner) have yielded; the half-space's "
        f"plastic zone is {b0['plastic_zone_depth']:.1f} mm deep and "
        f"{b0['plastic_zone_width']:.1f} mm wide (b = 10 mm), peak equivalent plastic strain "
        f"{b0['max_plastic_strain']:.4f} (~{b0['max_plastic_strain'] / (25.0 / 70000.0):.0f}× "
        "the yield strain of the half-space). " + _collapse_sentence(bl) + " "
        "As in the paper's Fig. 14, the pressure is nearly flat and rises towards the end of "
        f"the contact; plasticity cuts the corner peak from {ref['p_peak']:.1f} MPa (the same "
        f"scene with yield switched off) to {b2['p_peak']:.1f} MPa. 'Central contact pressure "
        f"for μ = 0.2 slightly larger than that of μ = 0' {ok('block_centre_pressure_mu')} "
        f"({b2['p_centre']:.2f} vs {b0['p_centre']:.2f} MPa). Fig. 15, 'as the load increases, "
        f"the slip zone decreases' (Zhu): {ok('block_slip_zone_shrinks_with_load')} "
        f"({slip_levels}). Elastic loading is proportional (the slip zone of the elastic block "
        "is fixed from the first instant), so this is a plastic effect: the yielding surface "
        "layer of the half-space flows outwards with the punch. Fig. 16, 'both the tangential "
        f"stress and the stick zone increase': the peak tangential stress, at the corner where it "
        f"equals μ p: {tau_story}; inside the growing stick zone the tangential stress also "
        "falls again at the highest loads, for the same reason as above. The tangential "
        "stress opposes the RTD wherever "
        f"the punch slips ({ok('block_tangential_opposes_rtd')}). These runs use the paper's own "
        "increment (`[solver] drift_control = false`: max drift "
        f"{100 * max(b0['max_drift'], b2['max_drift']):.2f} % of Sy) because the engine's "
        "drift-controlled variant stops the μ = 0.2 run on the tolerance of its Coulomb check "
        "(see the case file).",
        "",
        "## The sequence of events",
        "",
        "![event timeline](events_timeline.png)",
        "",
        "The paper's key claim is that the adaptive increment captures every change of state, "
        "in order. Each tick is one event at the load fraction where it happened (left); the "
        "right panel counts them for the μ = 0.35 elastoplastic cylinder "
        f"({_kind_counts(n['events']['cylinder, plastic, μ = 0.35'])}): contact closures "
        "spread over the whole load, each followed by stick/slip changes at the edge of the "
        "stick zone; yield events start at the onset of plasticity and then dominate, with a "
        "few elements unloading elastically as the plastic zone reshapes.",
        "",
        "## Checks",
        "",
        "`required`: asserted by `tests/studies/test_reproduce.py`; the others are "
        "reported only.",
        "",
        "| claim | measured | holds | required |",
        "|---|---|---|---|",
    ]
    for c in ch.values():
        lines.append(f"| {c['claim']} | {_fmt_value(c['value'])} | "
                     f"{'yes' if c['pass'] else '**no**'} | {'yes' if c['required'] else ''} |")
    lines += _axisymmetric_lines(n["axisymmetric"])
    if n["warnings"]:
        lines += ["", "## Warnings", ""] + [f"- {w}" for w in n["warnings"]]
    lines += ["", "## Run times", "", "| run | nodes | events | s |", "|---|---|---|---|"]
    for cid, r in n["runs"].items():
        lines.append(f"| {cid} | {r['n_nodes']} | {r['n_events']} | {r['wall_time_s']:.2f} |")
    lines.append("")
    path.write_text("\n".join(lines))
    return path


def _axisymmetric_lines(ax: dict) -> list[str]:
    """A pointer to axisymmetric.md with its headline numbers."""
    h, t, sf = ax["hertz"], ax["thick"], ax["sphere_flat"]["meshes"][-1]
    return ["", "## Axisymmetric analysis", "",
            "Not in the paper: the axisymmetric ring element, on its own page "
            "[axisymmetric.md](axisymmetric.md). Hertz sphere: a " + _pc(h["a_err"])
            + ", p0 " + _pc(h["p0_err"]) + "; first yield " + _pc(h["yield_f_err"])
            + " from Huber's; thick sphere: first yield " + _pc(t["p_first_yield_err"])
            + ", plastic radius within " + f"{t['c_max_err']:.3f} mm of Hill's, limit "
            + _pc(t["limit_err"]) + f"; sphere on a rigid flat to 50 ω_c ({sf['label']}, "
            f"{sf['n_nodes']} nodes): force {100 * sf['KE']['P_range'][0]:+.1f} … "
            f"{100 * sf['KE']['P_range'][1]:+.1f} % from Kogut & Etsion, "
            f"{100 * sf['JG']['P_range'][0]:+.1f} … {100 * sf['JG']['P_range'][1]:+.1f} % from "
            "Jackson & Green."]


def _join(values, fmt: str) -> str:
    return ", ".join(format(v, fmt) for v in values)


def _reach(flag) -> str:
    return "reaches" if flag else "does not reach"


def _collapse_sentence(bl: dict) -> str:
    b0 = bl["plastic_mu0"]["load_settlement"]
    pp = bl["perfectly_plastic_halfspace"]
    text = (f"The load-settlement curve of the punch keeps a finite slope: at full load its "
            f"tangent stiffness is {100 * b0['tangent_stiffness_ratio']:.0f} % of the elastic "
            f"one (settlement {1000 * b0['settlement']:.1f} µm, μ = 0). That is owed to the "
            f"hardening of the half-space: ")
    if "error" in pp:
        return text + (f"the same scene with a perfectly plastic half-space (H' = 0) did not "
                       f"finish ({pp['error']}).")
    if pp["flow_from_load_fraction"] is None:
        return text + ("with a perfectly plastic half-space (H' = 0) the tangent stiffness "
                       f"at full load is {100 * pp['tangent_stiffness_ratio']:.1f} % of the "
                       "elastic one.")
    f = pp["flow_from_load_fraction"]
    return text + (f"with a perfectly plastic half-space (H' = 0, h = {pp['h']:g} mm) the "
                   f"stiffness falls below 10 % of the elastic one beyond f = {f:g} "
                   f"(q = {36 * f:.1f} MPa = {36 * f / 25.0:.2f} Sy of the half-space) and the "
                   f"settlement at full load is {pp['settlement'] / b0['settlement']:.0f}× "
                   "larger: a non-hardening half-space would flow before q = 36 MPa (plane "
                   "stress leaves little room between first yield, σe ≈ p, and flow). With "
                   "H' = 2000 MPa the scene is substantially plastic without collapsing.")


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


def main(args) -> int:
    try:
        reproduce(args.out, quick=args.quick, workers=args.workers,
                  log=lambda m: print(m, flush=True))
    except FileNotFoundError as exc:
        print(f"slipstep: error: {exc}", file=sys.stderr)
        return 2
    except RuntimeError as exc:
        print(f"slipstep: error: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"slipstep: reproduce interrupted; rerun the same command to resume "
              f"(finished runs in {args.out} are kept)", file=sys.stderr)
        return 130
    return 0
