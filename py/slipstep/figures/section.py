"""PNG figures of a run: the interface at the final snapshot, the growth of the contact
half-length with the load fraction (cf. Figs. 6-9 of the paper) and, for elastoplastic runs,
the von Mises map with the plastic zone outlined (cf. Fig. 5).  A load path (several stages,
prescribed displacements or motions) adds its force-displacement curves and the contact extent
against the path time t.  Axis labels carry the case's units (``[case] units``).

Notebook-safe: matplotlib's object API only (``matplotlib.figure.Figure``, saved with Agg by
``savefig``), no ``matplotlib.use``, no pyplot, so a notebook's backend and figures are left
alone.  Each ``*_figure(path, ...)`` writes a PNG and returns its path, or with ``path=None``
returns the Figure (:func:`figures`: all of a run's, for :class:`slipstep.output.result.Result`).

Cheap by design (figures must not dominate a run): fixed margins instead of a layout
engine, one render per file (no ``bbox_inches="tight"``), and the von Mises map draws only the
elements inside its zoom window.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..measures.contact_edges import (
    contact_growth,
    contact_profile,
    force_displacement,
    path_history,
)
from ..output.fields import centroids, coordinate_names, is_elastoplastic, von_mises
from .frame import STATUS_COLOURS, STATUS_LABELS, finish, given_axes, label, new_figure, title
from ..output.history import is_staged, snapshot_time, stage_names
from ..output.summary import contact_text


def chosen(scene, result) -> list[tuple[str, object]]:
    """(file stem, builder) of the figures that apply to a run, in writing order:
    ``contact_interface`` and, for one stage, ``contact_growth`` (when the case has contact
    pairs); for a load path (:func:`slipstep.output.history.is_staged`) ``force_displacement`` (when
    it has prescribed displacements or motions and reactions) and ``contact_extent`` (with
    contact pairs); ``load_depth`` and ``q_delta`` (:mod:`slipstep.figures.loads`: a motion or
    prescribed displacement into a contact, a load along one); ``von_mises`` (when a material
    has a yield stress)."""
    from .loads import chosen_load_figures

    out = []
    if not result.get("snapshots"):
        return out
    pairs = len(scene.pair_xy) > 0
    if pairs:
        out.append(("contact_interface", interface_figure))
        if len(stage_names(scene, result)) == 1:
            out.append(("contact_growth", growth_figure))
    if is_staged(scene, result):
        if force_displacement(scene, result):
            out.append(("force_displacement", force_displacement_figure))
        if pairs:
            out.append(("contact_extent", extent_figure))
    out += chosen_load_figures(scene, result)
    if is_elastoplastic(scene):
        out.append(("von_mises", von_mises_figure))
    return out


def write_figures(folder: Path, scene, result, summary: dict) -> list[Path]:
    """Write every figure of :func:`chosen` as ``folder/<stem>.png``; returns the paths."""
    return [
        draw(Path(folder) / f"{stem}.png", scene, result, summary)
        for stem, draw in chosen(scene, result)
    ]


def figures(scene, result, summary: dict) -> dict:
    """The figures of :func:`chosen` as matplotlib Figures, by stem (nothing is written)."""
    return {stem: draw(None, scene, result, summary) for stem, draw in chosen(scene, result)}


def interface_figure(path: Path | None, scene, result, summary: dict, *, ax=None):
    """Contact pressure, tangential stress and RTD along the interface (3 panels, or the three
    Axes ``ax``), points coloured by status; the Hertz pressure p0 sqrt(1 - x^2/a^2) overlaid
    when it applies."""
    snap = result["snapshots"][-1]
    prof = contact_profile(scene, snap)
    x, status = prof["x"], prof["status"]
    a = summary.get("contact_half_width")  # a half model: show the contact and as far again
    show = np.ones(len(x), bool)
    if a is not None:
        xmax = max(2.0 * a, x[status > 0].max() * 1.5 if (status > 0).any() else x.max())
        show = x <= xmax if xmax > 0 else show

    if ax is None:
        fig = new_figure(7, 8, left=0.14, bottom=0.07, top=0.94, hspace=0.08)
        axes = fig.subplots(3, 1, sharex=True)
    else:
        axes = given_axes(ax, 3, "interface")
        fig = axes[0].figure
    panels = [
        ("pressure", "contact pressure", "stress"),
        ("tangential_stress", "tangential stress\n(along t = (-n_y, n_x))", "stress"),
        ("rtd", "relative tangential\ndisplacement (RTD)", "length"),
    ]
    for ax, (key, text, kind) in zip(axes, panels):
        ax.plot(x[show], prof[key][show], "-", color="0.75", lw=1, zorder=1)
        for s, colour in STATUS_COLOURS.items():
            m = show & (status == s)
            if m.any():
                ax.plot(
                    x[m], prof[key][m], "o", ms=3, color=colour, label=STATUS_LABELS[s], zorder=2
                )
        ax.set_ylabel(label(text, scene, kind))
        ax.grid(alpha=0.3)
    hertz = summary.get("hertz")
    if hertz and hertz["a_hertz_at_final"] > 0:  # 0: the load unloaded to nothing
        ah, p0 = hertz["a_hertz_at_final"], hertz["p0_hertz_at_final"]
        xs = np.linspace(0.0, ah, 200)
        axes[0].plot(
            xs,
            p0 * np.sqrt(np.clip(1 - (xs / ah) ** 2, 0, None)),
            "k--",
            lw=1,
            label=f"Hertz (a = {ah:.4g}, p0 = {p0:.4g})",
        )
    if a:
        for ax in axes:
            ax.axvline(a, color="k", lw=0.7, ls=":")
    axes[0].legend(fontsize=8)
    axes[-1].set_xlabel(label(coordinate_names(scene)[0], scene, "length"))
    title(
        fig,
        axes,
        f"{scene.case.name}: interface at {_when(scene, result, snap)}   "
        f"({contact_text(summary)})",
        own=ax is None,
    )
    return finish(fig, path)


def growth_figure(path: Path | None, scene, result, summary: dict, *, ax=None):
    """Outermost closed node x against the load fraction (a step curve from the event history),
    with a_Hertz sqrt(f) when the case is the Hertz cylinder (cf. Fig. 9); on ``ax`` if given."""
    f, xs = contact_growth(scene, result)
    if ax is None:
        fig = new_figure(6, 4.5, left=0.14, bottom=0.12)
        ax = fig.subplots()
    else:
        (ax,) = given_axes(ax, 1, "growth")
        fig = ax.figure
    ax.step(f, xs, where="post", color="tab:blue", label="outermost closed node")
    hertz = summary.get("hertz")
    if hertz:
        ff = np.linspace(0.0, 1.0, 200)
        k = hertz.get("load_exponent", 0.5)  # a grows as f^k: 1/2 line contact, 1/3 sphere
        # plain text, no TeX: matplotlib's mathtext parser costs more than this whole figure
        ax.plot(
            ff,
            hertz["a_hertz"] * ff**k,
            "k--",
            lw=1,
            label="Hertz a √f" if k == 0.5 else "Hertz a f^(1/3)",
        )
    ax.set_xlabel("load fraction f")
    ax.set_ylabel(label("contact half-length", scene, "length"))
    ax.set_xlim(0, 1)
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend()
    ax.set_title(f"{scene.case.name}: growth of the contact", fontsize=10)
    return finish(fig, path)


def _when(scene, result, snap: dict) -> str:
    """``load fraction f`` for one stage, else ``t = ... (stage name)``."""
    names = stage_names(scene, result)
    if len(names) == 1:
        return f"load fraction {float(snap['load_fraction']):.4g}"
    return f"t = {snapshot_time(snap):.4g} ({names[int(snap.get('stage', 0))]})"


# --------------------------------------------------------------------------- load paths
def _stage_masks(t: np.ndarray, names: list[str]):
    """(k, name, points of stage k): t in [k, k + 1], both ends, so the branches join."""
    for k, name in enumerate(names):
        m = (t >= k - 1e-12) & (t <= k + 1 + 1e-12)
        if m.sum() > 1:
            yield k, name, m


def _stage_lines(ax, names: list[str], label: bool) -> None:
    """Dotted lines at the stage ends; with ``label`` each stage named above its span."""
    for k, name in enumerate(names):
        if k:
            ax.axvline(k, color="k", lw=0.7, ls=":")
        if label:
            ax.text(
                k + 0.5,
                1.0,
                name,
                transform=ax.get_xaxis_transform(),
                ha="center",
                va="bottom",
                fontsize=8,
            )
    ax.set_xlim(0, len(names))


def _steps(t: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A value held from each t to the next as explicit points (NaN = a gap)."""
    return np.repeat(t, 2)[1:], np.repeat(v, 2)[:-1]


def force_displacement_figure(
    path: Path | None, scene, result, summary: dict | None = None, *, ax=None
):
    """One panel per prescribed displacement or motion (:func:`slipstep.
    contact_measures.force_displacement`; or one Axes of ``ax`` each): force against displacement from t = 0,
    one colour per stage, so the loading and unloading branches (and any hysteresis) show."""
    curves = force_displacement(scene, result)
    names = stage_names(scene, result)
    own = ax is None
    if own:
        fig = new_figure(
            5 * len(curves), 4.2, left=0.16 / len(curves), bottom=0.13, top=0.88, wspace=0.3
        )
        panels = list(fig.subplots(1, len(curves), squeeze=False)[0])
    else:
        panels = given_axes(ax, len(curves), "force-displacement")
        fig = panels[0].figure
    for ax, (load, c) in zip(panels, curves.items()):
        for k, name, m in _stage_masks(c["t"], names):
            ax.plot(
                c["displacement"][m],
                c["force"][m],
                "-o",
                ms=2.5,
                lw=1.2,
                color=f"C{k % 10}",
                label=name,
            )
        kind = "motion" if c["what"] != "support reaction" else "prescribed displacement"
        ax.set_xlabel(label(f"{load}: {kind}", scene, "length"))
        ax.set_ylabel(label(c["what"], scene, "force"))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    title(fig, panels, f"{scene.case.name}: force against displacement along the load path", own)
    return finish(fig, path)


def extent_figure(path: Path | None, scene, result, summary: dict | None = None, *, ax=None):
    """Per contact against the path time t: the closed extent [s_min, s_max] of its closed
    pairs (top) and its total normal force (solid) and tangential force (dashed, bottom; or
    the two Axes ``ax``); dotted lines at the stage ends."""
    h = path_history(scene, result)
    names = stage_names(scene, result)
    if ax is None:
        fig = new_figure(7, 6, left=0.12, bottom=0.09, top=0.9, hspace=0.1)
        top, bottom = fig.subplots(2, 1, sharex=True)
    else:
        top, bottom = given_axes(ax, 2, "extent")
        fig = top.figure
    for c, contact in enumerate(scene.engine_model.contact_names):
        colour = f"C{c % 10}"
        (x, lo), (_, hi) = (_steps(h["t"], h["extent"][:, c, j]) for j in (0, 1))
        top.fill_between(x, lo, hi, color=colour, alpha=0.3, label=contact)
        for edge in (lo, hi):
            top.plot(x, edge, color=colour, lw=1)
        bottom.plot(h["t"], h["normal_force"][:, c], "-", color=colour, label=f"{contact}: normal")
        bottom.plot(
            h["t"], h["tangential_force"][:, c], "--", color=colour, label=f"{contact}: tangential"
        )
    top.set_ylabel(label("closed extent along s", scene, "length"))
    bottom.set_ylabel(label("contact force", scene, "force"))
    bottom.set_xlabel("path time t")
    for ax in (top, bottom):
        _stage_lines(ax, names, ax is top)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    title(fig, [top], f"{scene.case.name}: contact along the load path", ax is None, y=0.985)
    return finish(fig, path)


# --------------------------------------------------------------------------- plasticity
def zone_boundary(triangles: np.ndarray, inside: np.ndarray) -> np.ndarray:
    """The sides shared by an element of the set ``inside`` (bool per element) and one outside
    it: (K, 2) node pairs, the outline of the set within the body."""
    sides = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    owner = np.tile(np.arange(len(triangles)), 3)
    key = np.sort(sides, axis=1)
    order = np.lexsort((key[:, 1], key[:, 0]))
    key, owner = key[order], owner[order]
    # an interior side appears twice, consecutively after sorting
    twin = np.flatnonzero((key[1:] == key[:-1]).all(axis=1))
    differ = inside[owner[twin]] != inside[owner[twin + 1]]
    return key[twin[differ]]


def zoom_window(scene, summary: dict):
    """(x limits, y limits) of the contact region, or None for the whole body.

    For a ``rigid_line`` contact with a horizontal line and a known contact half-width a (the
    run's, else Hertz's): x in [-3a, 3a] (the scenes are symmetric about x = 0; clipped to the
    body) and depth 0..2.5a from the line into the body, the region of Fig. 5.
    """
    contacts = [c for c in scene.case.record.contact if c.kind == "rigid_line"]
    if not contacts:
        return None
    c = contacts[0]
    n = np.asarray(c.normal) / np.linalg.norm(c.normal)
    a = summary.get("contact_half_width") or scene.reference.get("a_hertz") or 0.0
    if a <= 0.0 or abs(n[1]) < 1.0 - 1e-9:
        return None
    x_lo, x_hi = scene.nodes[:, 0].min(), scene.nodes[:, 0].max()
    y_line = c.point[1]
    ys = sorted((y_line, y_line + np.sign(n[1]) * 2.5 * a))
    return (max(-3.0 * a, x_lo), min(3.0 * a, x_hi)), tuple(ys)


def von_mises_figure(path: Path | None, scene, result, summary: dict, *, ax=None, cax=None):
    """Von Mises stress of the final snapshot (element values) with the plastic zone outlined:
    solid = elements plastic now (on the yield surface and loading), dashed = elements with
    plastic strain that have unloaded (drawn only when that set differs); x = first yield.
    Zoomed to the contact region for a rigid-line contact (:func:`zoom_window`), and only the
    elements with a node in that window are drawn (a large mesh costs no more than its
    window). On ``ax`` if given, its colour bar beside it (or in ``cax``)."""
    from matplotlib.collections import LineCollection

    snap = result["snapshots"][-1]
    vm = von_mises(np.asarray(snap["stress"], dtype=float).reshape(-1, 4))
    window = zoom_window(scene, summary)
    centres = centroids(scene.nodes, scene.triangles)
    drawn = np.ones(len(vm), bool)
    if window is not None:
        drawn = _in_window(scene.nodes, scene.triangles, window)
        if not drawn.any():
            drawn[:] = True
            window = None
    if ax is None:
        fig = new_figure(7, 6, left=0.1, right=0.8, bottom=0.1, top=0.93)
        ax = fig.subplots()
        cax = fig.add_axes([0.84, 0.1, 0.025, 0.83])
    else:
        (ax,) = given_axes(ax, 1, "von Mises")
        fig = ax.figure
    art = ax.tripcolor(
        scene.nodes[:, 0],
        scene.nodes[:, 1],
        scene.triangles[drawn],
        facecolors=vm[drawn],
        cmap="viridis",
    )
    fig.colorbar(
        art,
        ax=None if cax is not None else ax,
        cax=cax,
        label=label("von Mises stress", scene, "stress"),
    )
    plastic = np.asarray(snap.get("plastic", np.zeros(len(vm))), dtype=bool)
    yielded = np.asarray(snap.get("plastic_strain", np.zeros(len(vm)))) > 0.0
    handles = []
    for zone, style, text in (
        (plastic, "-", f"plastic ({int(plastic.sum())} elements)"),
        (yielded, "--", f"yielded, now elastic " f"({int((yielded & ~plastic).sum())})"),
    ):
        if style == "--" and np.array_equal(zone, plastic):
            continue
        segs = scene.nodes[zone_boundary(scene.triangles, zone)]
        lines = LineCollection(segs, colors="tab:red", linewidths=1.2, linestyles=style, label=text)
        ax.add_collection(lines)
        handles.append(lines)
    e = summary.get("first_yield_element")
    if e is not None:
        handles += ax.plot(*centres[e], "*", color="white", mec="black", ms=11, label="first yield")
    if window is not None:
        ax.set_xlim(*window[0])
        ax.set_ylim(*window[1])
    ax.set_aspect("equal")
    ax.set_xlabel(label(coordinate_names(scene)[0], scene, "length"))
    ax.set_ylabel(label(coordinate_names(scene)[1], scene, "length"))
    if handles:
        ax.legend(handles=handles, fontsize=8, loc="best")
    ax.set_title(
        f"{scene.case.name}: von Mises stress at {_when(scene, result, snap)}", fontsize=10
    )
    return finish(fig, path)


def _in_window(nodes: np.ndarray, triangles: np.ndarray, window) -> np.ndarray:
    """Elements with a node inside the (x limits, y limits) window, or crossing it (an element
    larger than the window: its bounding box overlaps it)."""
    (x0, x1), (y0, y1) = window
    xy = nodes[triangles]  # (M, 3, 2)
    lo, hi = xy.min(axis=1), xy.max(axis=1)
    return (lo[:, 0] <= x1) & (hi[:, 0] >= x0) & (lo[:, 1] <= y1) & (hi[:, 1] >= y0)
