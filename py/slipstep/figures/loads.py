"""The load-displacement figures of a run from its history of increments (2D and 3D alike;
:mod:`slipstep.measures.resultants`):

- ``load_depth.png``: per load that drives the run into a contact (an obstacle's motion, a
  prescribed displacement), its force against its displacement at every increment from t = 0,
  one colour per stage, so loading and unloading show; where an indenter unloads, the
  Oliver–Pharr analysis on it: the power-law fit of the upper unloading part, the contact
  stiffness S at the deepest point, and the numbers h_c, A, H, E_r (:mod:`slipstep.measures.indentation`);
- ``q_delta.png``: per load along the contact (a tangential force or motion after a press,
  Cattaneo–Mindlin), its force Q against its displacement δ (the work-conjugate displacement of
  a force: P·u / |P|), with the friction limit μP of the contact it shears (P its normal
  force at the shear's start).

Forces are the whole model's (a 3D part mirrored across its symmetry planes), displacements the
driver's along its direction.  On the notebook-safe helpers of :mod:`slipstep.figures`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .frame import finish, given_axes, label, new_figure, title
from ..output.history import stage_names
from ..measures.resultants import contact_normal, drivers, indentation, step_history, whole


def depth_drivers(scene, hist: dict) -> dict:
    """The drivers of ``load_depth``: motions and prescribed displacements into a contact."""
    return {
        k: d
        for k, d in drivers(scene, hist).items()
        if d["kind"] in ("motion", "displacement") and not d["tangential"]
    }


def shear_drivers(scene, hist: dict) -> dict:
    """The drivers of ``q_delta``: loads, motions or displacements along a contact."""
    return {k: d for k, d in drivers(scene, hist).items() if d["tangential"]}


def _panels(n: int, ax, what: str):
    if ax is not None:
        axes = given_axes(ax, n, what)
        return axes[0].figure, axes, False
    fig = new_figure(
        5.2 * n, 4.4, left=0.15 / n, right=1 - 0.03 / n, bottom=0.12, top=0.87, wspace=0.32
    )
    return fig, list(np.atleast_1d(fig.subplots(1, n))), True


def _by_stage(ax, x, y, stage, names) -> None:
    """The curve, one colour per stage (each stage's branch joined to the previous point)."""
    for k, name in enumerate(names):
        idx = np.flatnonzero(stage == k)
        idx = np.concatenate([[idx[0] - 1], idx]) if len(idx) and idx[0] > 0 else idx
        if len(idx) < 2:
            continue
        ax.plot(x[idx], y[idx], "-", lw=1.3, color=f"C{k % 10}", label=name)
    from matplotlib.ticker import MaxNLocator

    ax.xaxis.set_major_locator(MaxNLocator(5))


def load_depth_figure(path: Path | None, scene, result, summary: dict | None = None, *, ax=None):
    """Force against depth per driver into a contact (module doc), with the Oliver–Pharr
    analysis where an indenter unloads; on the caller's Axes ``ax`` (one per driver) if
    given."""
    hist = step_history(scene, result)
    curves = depth_drivers(scene, hist)
    ops = indentation(scene, hist)
    names = stage_names(scene, result)
    fig, axes, own = _panels(len(curves), ax, "load-depth")
    for ax, (name, d) in zip(axes, curves.items()):
        h, P = d["displacement"], d["force"]
        _by_stage(ax, h, P, d["stage"], names)
        op = ops.get(name)
        if op is not None:
            _oliver_pharr(ax, op, scene)
            _unloading_inset(ax, h, P, d["stage"], names, op)
        what = "depth" if d["kind"] == "motion" else "prescribed displacement"
        ax.set_xlabel(label(f"{name}: {what} h", scene, "length"))
        ax.set_ylabel(label("force P" + (" (whole model)" if d["planes"] else ""), scene, "force"))
        ax.set_xlim(left=min(0.0, float(np.nanmin(h))))
        ax.set_ylim(bottom=min(0.0, float(np.nanmin(P))))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper left")
    title(fig, axes, f"{scene.case.name}: load against depth", own)
    return finish(fig, path)


def _unloading_inset(ax, h, P, stage, names, op: dict) -> None:
    """A stiff unloading (a plastic indent: h_f near h_max) is a near-vertical line at the
    panel's scale: an inset shows it, its fit and the tangent S, over [h_f, h_max]."""
    h_max, h_f = op["h_max"], op["h_f"]
    if not 0 < h_max - h_f < 0.3 * h_max:
        return
    inset = ax.inset_axes([0.1, 0.3, 0.34, 0.34])
    _by_stage(inset, h, P, stage, names)
    lo = h_f - 0.15 * (h_max - h_f)
    hs = np.linspace(h_f, h_max, 60)
    inset.plot(hs, op["alpha"] * (hs - h_f) ** op["m"], "k--", lw=0.8)
    inset.plot([h_max - op["P_max"] / op["S"], h_max], [0.0, op["P_max"]], ":", color="0.3", lw=0.8)
    inset.set_xlim(lo, h_max + 0.05 * (h_max - h_f))
    inset.set_ylim(0, 1.05 * op["P_max"])
    inset.tick_params(labelsize=6)
    inset.set_title("unloading", fontsize=7, y=1.0)
    inset.grid(alpha=0.3)


def _oliver_pharr(ax, op: dict, scene) -> None:
    """The fit of the upper unloading part, the tangent S at h_max, and the numbers."""
    h_max, P_max, h_f = op["h_max"], op["P_max"], op["h_f"]
    hs = np.linspace(max(h_f, h_max - 1.5 * (h_max - h_f)), h_max, 100)
    ax.plot(
        hs,
        op["alpha"] * np.clip(hs - h_f, 0, None) ** op["m"],
        "k--",
        lw=0.9,
        label=f"fit P = α (h − h_f)^m, m = {op['m']:.3g}",
    )
    h0 = h_max - P_max / op["S"]
    ax.plot([h0, h_max], [0.0, P_max], ":", color="0.3", lw=0.9, label="S = dP/dh at h_max")
    ax.plot([op["h_c"]], [0.0], "v", color="k", ms=5, label="h_c")
    units = scene.case.units

    def q(v, kind):
        return f"{v:.4g} {units[kind]}" if units else f"{v:.4g}"

    text = (
        f"Oliver–Pharr ({op['indenter']}, ε = {op['epsilon']}, β = {op['beta']})\n"
        f"S = {op['S']:.4g}, h_c = {q(op['h_c'], 'length')}\n"
        f"A(h_c) = {op['A']:.4g}, H = {q(op['H'], 'stress')}\n"
        f"E_r = {q(op['E_r'], 'stress')}"
    )
    ax.text(
        0.98,
        0.03,
        text,
        transform=ax.transAxes,
        ha="right",
        va="bottom",
        fontsize=7.5,
        bbox={"facecolor": "white", "alpha": 0.85, "edgecolor": "0.7"},
    )


def q_delta_figure(path: Path | None, scene, result, summary: dict | None = None, *, ax=None):
    """Tangential force Q against its displacement δ per driver along a contact (module doc),
    from the start of the stage it begins in, with the friction limit μP of the contact it
    shears; on the caller's Axes ``ax`` (one per driver) if given."""
    hist = step_history(scene, result)
    curves = shear_drivers(scene, hist)
    names = stage_names(scene, result)
    fig, axes, own = _panels(len(curves), ax, "Q-delta")
    for ax, (name, d) in zip(axes, curves.items()):
        Q, delta, stage = d["force"], d["displacement"], d["stage"]
        moving = np.flatnonzero(np.abs(np.diff(Q)) > 0)
        start = int(moving[0]) if len(moving) else 0
        dq, dd = Q[start:] - Q[start], delta[start:] - delta[start]
        _by_stage(ax, dd, Q[start:], stage[start:], names)
        first = np.flatnonzero(np.abs(dd) > 0)
        if len(first):  # the first increment's stiffness: where Q would go without slip
            k0 = dq[first[0]] / dd[first[0]]
            ax.plot(
                [0.0, float(np.nanmax(dd))],
                [Q[start], Q[start] + k0 * float(np.nanmax(dd))],
                ":",
                color="0.4",
                lw=0.9,
                label="first increment's stiffness",
            )
        limit = _friction_limit(scene, hist, d, start)
        if limit is not None:
            ax.axhline(limit, color="k", ls="--", lw=0.9, label=f"μP = {limit:.4g}")
        ax.set_xlabel(label(f"{name}: tangential displacement δ", scene, "length"))
        ax.set_ylabel(
            label("tangential force Q" + (" (whole model)" if d["planes"] else ""), scene, "force")
        )
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="lower right")
    title(fig, axes, f"{scene.case.name}: tangential force against displacement (Mindlin)", own)
    return finish(fig, path)


def _friction_limit(scene, hist: dict, d: dict, row: int) -> float | None:
    """μ P of the one frictional contact a tangential driver shears, P its normal force (the
    whole's, along its mean normal) at ``row``; None unless exactly one contact touches it."""
    a = np.asarray(scene.engine_model.pairs.node_a, dtype=np.int64)
    ids = (
        np.concatenate([np.arange(scene.meshes[x].n_nodes) + scene.offsets[x] for x in d["bodies"]])
        if d["bodies"]
        else np.zeros(0, np.int64)
    )
    b = np.asarray(scene.engine_model.pairs.node_b, dtype=np.int64)
    touching = np.unique(np.asarray(scene.pair_contact)[np.isin(a, ids) | np.isin(b, ids)])
    if d["kind"] == "motion":
        touching = np.array([d["contact"]])
    if len(touching) != 1:
        return None
    c = int(touching[0])
    mu = float(scene.case.record.contact[c].mu)
    if mu <= 0:
        return None
    from ..measures.resultants import contact_planes

    n = contact_normal(scene, c)
    P = abs(float(whole(hist["contact_force"][row, c], contact_planes(scene, c)) @ n))
    return mu * P


def chosen_load_figures(scene, result) -> list[tuple[str, object]]:
    """(file stem, builder) of ``load_depth`` and ``q_delta`` when the run has their drivers."""
    if not len(scene.pair_xy):
        return []
    hist = step_history(scene, result)
    out = []
    if depth_drivers(scene, hist):
        out.append(("load_depth", load_depth_figure))
    if shear_drivers(scene, hist):
        out.append(("q_delta", q_delta_figure))
    return out
