"""PNG figures of a 3D run: the contact area seen along its normal, each candidate node coloured
by its status (stick, slip, open; "closed" for a frictionless contact) with the circles of the
equivalent contact and stick radii when the contact is round; the pressure along a line
through the contact (with Hertz's when the scene has it); and for elastoplastic runs the
plastic zone on the section through the contact's centre.  The 3D counterpart of
:mod:`slipstep.figures`, on its notebook-safe figure helpers; each draws on the caller's axes
when given (``ax``: one Axes per panel)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..output.fields import is_elastoplastic
from .frame import STATUS_COLOURS, STATUS_LABELS, finish, given_axes, label, new_figure
from ..measures.references import hertz_pressure
from ..measures.contact_faces import (
    contact_frame,
    contact_numbers_3d,
    contact_profile_3d,
    mirrored_points,
    pressure_centre,
    pressure_line,
)
from ..output.fields import von_mises_3d


def chosen(scene, result) -> list[tuple[str, object]]:
    """(file stem, builder) of the figures that apply: the contact area and the pressure line
    when the scene has contact pairs and the run snapshots, ``load_depth`` and ``q_delta``
    (:mod:`slipstep.figures.loads`: a motion or prescribed displacement into a contact, a load
    along one), the plastic zone when it can yield."""
    from .loads import chosen_load_figures

    if not result.get("snapshots"):
        return []
    out = []
    if len(scene.pair_xy):
        out += [("contact_area", contact_area_figure), ("contact_pressure_line", pressure_figure)]
        out += chosen_load_figures(scene, result)
    if is_elastoplastic(scene):
        out.append(("plastic_zone", plastic_zone_figure))
    return out


def write_figures_3d(folder: Path, scene, result, summary: dict) -> list[Path]:
    """Write every figure of :func:`chosen` as ``folder/<stem>.png``; returns the paths."""
    return [
        draw(Path(folder) / f"{stem}.png", scene, result, summary)
        for stem, draw in chosen(scene, result)
    ]


def figures_3d(scene, result, summary: dict) -> dict:
    """The figures of :func:`chosen` as matplotlib Figures, by stem (nothing is written)."""
    return {stem: draw(None, scene, result, summary) for stem, draw in chosen(scene, result)}


def _panels(n: int, ax, what: str, width: float = 5.0):
    """(figure, n Axes): the caller's ``ax`` (n of them), else a figure of n panels with room
    for the tick labels and the y label of each."""
    if ax is not None:
        axes = given_axes(ax, n, what)
        return axes[0].figure, axes
    fig = new_figure(width * n, 4.8, left=0.16 / n, right=1 - 0.04 / n, bottom=0.12, wspace=0.45)
    return fig, list(np.atleast_1d(fig.subplots(1, n)))


def view_axes(scene, index: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(n, e1, e2) of [[contact]] ``index``: its frame (:func:`contact_frame`) with e2 turned,
    if need be, to point along its own largest component's positive axis, so that the view
    reads in the positive directions of the axes it is seen along (x to the right, y up for a
    contact seen along z, from either side)."""
    n, e1, e2 = contact_frame(scene, index)
    return n, e1, (-e2 if e2[np.argmax(np.abs(e2))] < 0 else e2)


def is_round(points: np.ndarray, radius: float, spacing: float) -> bool:
    """Whether a zone of closed points (K, 2) about its centre (0, 0) and of equivalent radius
    ``radius`` (its area's) is a disc: no point farther than the radius and half a spacing (the
    zone's area reaches about half a spacing past its outermost nodes).  A zone that lies in
    the disc of its own area is that disc; a square reaches 1.25 times its equivalent radius
    at its corners, a strip its half length."""
    if len(points) == 0:
        return False
    return float(np.hypot(points[:, 0], points[:, 1]).max()) <= radius + 0.5 * spacing


def _spacing(points: np.ndarray) -> float:
    """The median distance from a point to its nearest neighbour."""
    if len(points) < 2:
        return 0.0
    d = np.linalg.norm(points[:, None] - points[None], axis=2)
    np.fill_diagonal(d, np.inf)
    return float(np.median(d.min(axis=1)))


def shown_snapshot(scene, result) -> dict:
    """The snapshot the contact figures show: the final one, or when nothing is closed there
    (an indenter drawn back) the one of the largest total normal force."""
    snaps = result["snapshots"]
    if (np.asarray(snaps[-1]["status"]) > 0).any():
        return snaps[-1]
    return max(snaps, key=lambda s: float(np.sum(s["lambda_n"])))


def _at(snap: dict) -> str:
    return f" (t = {float(snap.get('t', snap['load_fraction'])):.4g})"


def contact_area_figure(path: Path | None, scene, result, summary: dict, *, ax=None):
    """Per contact at :func:`shown_snapshot`: its contactor face near the candidates seen along
    the contact's mean normal (axes e1, e2 of :func:`view_axes` through its centre of pressure),
    each candidate node a dot coloured by status, zoomed to the closed nodes (to the candidates
    when none is closed); dashed circles of the full contact's equivalent radii
    (``contact_radius``, ``stick_radius``) when the contact is round (:func:`is_round`, on the
    contact mirrored across its symmetry planes)."""
    snap = shown_snapshot(scene, result)
    prof = contact_profile_3d(scene, snap)
    fig, axes = _panels(len(scene.engine_model.contact_names), ax, "contact area")
    for i, (ax_i, name) in enumerate(zip(axes, scene.engine_model.contact_names)):
        mine = prof["contact"] == i
        frictionless = scene.case.record.contact[i].mu == 0.0
        _, e1, e2 = view_axes(scene, i)
        centre = pressure_centre(scene, prof, i)
        plane = (scene.nodes - centre) @ np.stack([e1, e2]).T
        face = scene.global_boundary(*scene.case.record.contact[i].contactor)
        face = face[np.isin(face, prof["node_a"][mine]).all(axis=1)]
        if len(face):
            ax_i.triplot(plane[:, 0], plane[:, 1], face, color="0.85", lw=0.5)
        xy, status = plane[prof["node_a"][mine]], prof["status"][mine]
        for s, colour in STATUS_COLOURS.items():
            here = status == s
            text = "closed" if frictionless and s == 2 else STATUS_LABELS[s]
            if here.any() or not (frictionless and s == 1):
                ax_i.plot(
                    xy[here, 0],
                    xy[here, 1],
                    "o",
                    ms=3,
                    color=colour,
                    label=f"{text} ({int(here.sum())})",
                )
        numbers = (
            summary.get("contacts", {}).get(name, {})
            if snap is result["snapshots"][-1]
            else contact_numbers_3d(scene, snap, i)
        )
        _radii(ax_i, scene, prof, i, numbers, centre, frictionless)
        shown = xy[status > 0] if (status > 0).any() else xy
        pad = 0.25 * float(np.ptp(shown, axis=0).max()) + _spacing(xy)
        ax_i.set_aspect("equal")
        ax_i.set_xlim(shown[:, 0].min() - pad, shown[:, 0].max() + pad)
        ax_i.set_ylim(shown[:, 1].min() - pad, shown[:, 1].max() + pad)
        ax_i.set_xlabel(label(f"along {_axis_text(e1)}", scene, "length"))
        ax_i.set_ylabel(label(f"along {_axis_text(e2)}", scene, "length"))
        ax_i.set_title(f"{name}: contact seen along its normal{_at(snap)}", fontsize=9)
        ax_i.legend(fontsize=7, loc="upper right")
    return finish(fig, path)


def _radii(ax, scene, prof: dict, index: int, numbers: dict, centre, frictionless: bool):
    """The circles of the contact's (and, with friction, the stick zone's) equivalent radius
    about the centre, each when its zone is round."""
    _, e1, e2 = view_axes(scene, index)
    mine = prof["contact"] == index
    circle = np.linspace(0, 2 * np.pi, 181)
    zones = (
        ("contact_radius", "k--", prof["status"] > 0),
        ("stick_radius", "b:", prof["status"] == 1),
    )
    for key, style, zone in zones[: 1 if frictionless else 2]:
        radius = numbers.get(key, 0.0)
        x, _ = mirrored_points(scene, index, prof["x"][mine & zone], np.zeros((mine & zone).sum()))
        plane = (x - centre) @ np.stack([e1, e2]).T
        if radius > 0 and is_round(plane, radius, _spacing(plane)):
            ax.plot(
                radius * np.cos(circle),
                radius * np.sin(circle),
                style,
                lw=0.8,
                label=f"{key.replace('_', ' ')} {radius:.4g}",
            )


def pressure_figure(path: Path | None, scene, result, summary: dict, *, ax=None):
    """Per contact at :func:`shown_snapshot`: the pressure along the line through its centre of
    pressure in the direction e1 (:func:`slipstep.measures.contact_faces.pressure_line`), and
    Hertz's p0 sqrt(1 - s^2/a^2) at the reached load when the scene has the sphere's
    reference."""
    snap = shown_snapshot(scene, result)
    fig, axes = _panels(len(scene.engine_model.contact_names), ax, "pressure line")
    ref = summary.get("hertz", {}) if snap is result["snapshots"][-1] else {}
    for i, (ax_i, name) in enumerate(zip(axes, scene.engine_model.contact_names)):
        line = pressure_line(scene, snap, i)
        ax_i.plot(line["s"], line["pressure"], "-", color="tab:blue", label="slipstep")
        if ref.get("a_hertz_at_final"):
            s = np.linspace(line["s"].min(), line["s"].max(), 400)
            ax_i.plot(
                s,
                hertz_pressure(s, ref["a_hertz_at_final"], ref["p0_hertz_at_final"]),
                "k--",
                lw=0.8,
                label="Hertz",
            )
        ax_i.set_xlabel(label(f"distance along {_axis_text(line['direction'])}", scene, "length"))
        ax_i.set_ylabel(label("contact pressure", scene, "stress"))
        ax_i.set_title(f"{name}: pressure along a line through the contact{_at(snap)}", fontsize=9)
        ax_i.legend(fontsize=7)
    return finish(fig, path)


def plastic_zone_figure(path: Path | None, scene, result, summary: dict, *, ax=None):
    """The final snapshot on the section through the first contact's centre of pressure that
    holds its normal and e1 (:func:`view_axes`; through the body's centre without contact):
    the von Mises stress and the equivalent plastic strain of every tetrahedron the plane cuts
    (two panels, or the two Axes ``ax``), zoomed to the yielded elements there (to the
    contact without them)."""
    from matplotlib.collections import PolyCollection

    snap = result["snapshots"][-1]
    centre, e1, up = _section_plane(scene, snap)
    cells, polygons = section(scene.nodes, scene.tetrahedra, centre, e1, up)
    stress = np.asarray(snap["stress"], dtype=float).reshape(-1, 6)
    strain = np.asarray(snap.get("plastic_strain", np.zeros(len(stress))), dtype=float)
    fig, axes = _panels(2, ax, "plastic zone", width=5.5)
    values = (
        (von_mises_3d(stress), "von Mises stress", "viridis", "stress"),
        (strain, "equivalent plastic strain", "magma", None),
    )
    for ax_i, (value, text, cmap, kind) in zip(axes, values):
        art = PolyCollection(
            polygons, array=value[cells], cmap=cmap, edgecolors="face", linewidths=0.2
        )
        ax_i.add_collection(art)
        fig.colorbar(art, ax=ax_i, label=label(text, scene, kind) if kind else text, shrink=0.85)
        ax_i.set_aspect("equal")
        ax_i.set_xlabel(label(f"along {_axis_text(e1)}", scene, "length"))
        ax_i.set_ylabel(label(f"along {_axis_text(up)}", scene, "length"))
        ax_i.set_title(f"{text} on the section through the contact", fontsize=9)
    _zoom(axes, polygons, strain[cells] > 0)
    return finish(fig, path)


def _section_plane(scene, snap: dict):
    """(a point, e1, up) of the section: the first contact's centre of pressure, its e1 and its
    normal turned to point along its largest component's positive axis; the nodes' centre and
    x, z without contact."""
    if not len(scene.pair_xy):
        return scene.nodes.mean(axis=0), np.eye(3)[0], np.eye(3)[2]
    n, e1, _ = view_axes(scene, 0)
    up = -n if n[np.argmax(np.abs(n))] < 0 else n
    return pressure_centre(scene, contact_profile_3d(scene, snap), 0), e1, up


def section(nodes: np.ndarray, tets: np.ndarray, point, e1, up):
    """The tetrahedra the plane through ``point`` spanned by e1 and up cuts, and each cut as a
    polygon (3 or 4 corners, in order) in the plane's coordinates (along e1, along up); a
    tetrahedron with a face in the plane gives that face."""
    normal = np.cross(e1, up)
    d = (nodes - point) @ normal
    size = float(np.ptp(nodes, axis=0).max())
    d = np.where(np.abs(d) <= 1e-12 * size, 0.0, d)
    ds = d[tets]
    cut = np.flatnonzero(
        (ds.min(axis=1) <= 0) & (ds.max(axis=1) >= 0) & (np.count_nonzero(ds == 0, axis=1) != 4)
    )
    edges = ((0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3))
    cells, polygons = [], []
    for e in cut:
        corner, dist = nodes[tets[e]], ds[e]
        found = [corner[k] for k in range(4) if dist[k] == 0]
        found += [
            corner[i] + dist[i] / (dist[i] - dist[j]) * (corner[j] - corner[i])
            for i, j in edges
            if dist[i] * dist[j] < 0
        ]
        if len(found) < 3:
            continue  # the plane touches an edge or a corner only
        flat = (np.array(found) - point) @ np.stack([e1, up]).T
        middle = flat.mean(axis=0)
        order = np.argsort(np.arctan2(*(flat - middle).T[::-1]))
        cells.append(e)
        polygons.append(flat[order])
    return np.asarray(cells, dtype=np.int64), polygons


def _zoom(axes, polygons, yielded: np.ndarray) -> None:
    """The axes' limits: around the yielded cells' polygons, grown by half their extent; the
    polygons near the section's point (a tenth of the section) without yielding."""
    corners = [p for p, y in zip(polygons, yielded) if y] or [
        p for p in polygons if np.abs(p).max() <= 0.1 * max(np.abs(q).max() for q in polygons)
    ]
    box, whole = np.vstack(corners or polygons), np.vstack(polygons)
    pad = 0.5 * float(np.ptp(box, axis=0).max())
    low = np.maximum(box.min(axis=0) - pad, whole.min(axis=0))  # not beyond the section
    high = np.minimum(box.max(axis=0) + pad, whole.max(axis=0))
    for ax in axes:
        ax.set_xlim(low[0], high[0])
        ax.set_ylim(low[1], high[1])


def _axis_text(v: np.ndarray) -> str:
    """A direction as text: the axis it is (x, y, z, -x, ...) to within 2 degrees (the mean
    normal of a discrete contact leans by a fraction of a degree), else its components."""
    for k, name in enumerate("xyz"):
        for sign, text in ((1.0, name), (-1.0, f"-{name}")):
            if sign * v[k] >= math.cos(math.radians(2.0)):
                return text
    return "(" + ", ".join(f"{c:.3g}" for c in v) + ")"
