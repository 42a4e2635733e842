"""PNG figures of a 3D run: the contact area seen along its normal, each candidate node coloured
by its status (stick, slip, open) with the circles of the equivalent contact and stick radii,
and the pressure along a line through the contact (with Hertz's when the scene has it).  The
3D counterpart of :mod:`slipstep.figures`, on its notebook-safe figure helpers."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..figures import STATUS_COLOURS, STATUS_LABELS, finish, label, new_figure
from ..references import hertz_pressure
from .contact_geometry import contactor_face
from .contact_measures import contact_frame, contact_profile_3d, pressure_centre, pressure_line


def chosen(scene, result) -> list[tuple[str, object]]:
    """(file stem, builder) of the figures that apply: both, when the scene has contact pairs
    and the run snapshots."""
    if not (result.get("snapshots") and len(scene.pair_xy)):
        return []
    return [("contact_area", contact_area_figure), ("contact_pressure_line", pressure_figure)]


def write_figures_3d(folder: Path, scene, result, summary: dict) -> list[Path]:
    """Write every figure of :func:`chosen` as ``folder/<stem>.png``; returns the paths."""
    return [draw(Path(folder) / f"{stem}.png", scene, result, summary)
            for stem, draw in chosen(scene, result)]


def figures_3d(scene, result, summary: dict) -> dict:
    """The figures of :func:`chosen` as matplotlib Figures, by stem (nothing is written)."""
    return {stem: draw(None, scene, result, summary) for stem, draw in chosen(scene, result)}


def _panels(scene, width: float = 5.0):
    """A figure with one panel per contact."""
    n = len(scene.model["contact_names"])
    fig = new_figure(width * n, 4.8, left=0.12 / n, right=1 - 0.04 / n, wspace=0.3)
    return fig, list(np.atleast_1d(fig.subplots(1, n)))


def contact_area_figure(path: Path | None, scene, result, summary: dict):
    """Per contact at the final snapshot: its contactor face near the candidates seen along the
    contact's mean normal (axes e1, e2 of its frame through its centre of pressure), each
    candidate node a dot coloured by status, and dashed circles of the full contact's
    equivalent radii (``contact_radius``, ``stick_radius``) about that centre."""
    snap = result["snapshots"][-1]
    prof = contact_profile_3d(scene, snap)
    fig, axes = _panels(scene)
    for i, (ax, name) in enumerate(zip(axes, scene.model["contact_names"])):
        mine = prof["contact"] == i
        _, e1, e2 = contact_frame(scene, i)
        plane = (scene.nodes - pressure_centre(scene, prof, i)) @ np.stack([e1, e2]).T
        face = scene.global_boundary(*contactor_face(scene.case.data["contact"][i]))
        face = face[np.isin(face, prof["node_a"][mine]).all(axis=1)]
        if len(face):
            ax.triplot(plane[:, 0], plane[:, 1], face, color="0.85", lw=0.5)
        xy = plane[prof["node_a"][mine]]
        for status, colour in STATUS_COLOURS.items():
            here = prof["status"][mine] == status
            ax.plot(xy[here, 0], xy[here, 1], "o", ms=3, color=colour,
                    label=f"{STATUS_LABELS[status]} ({int(here.sum())})")
        numbers = summary.get("contacts", {}).get(name, {})
        circle = np.linspace(0, 2 * np.pi, 181)
        for key, style in (("contact_radius", "k--"), ("stick_radius", "b:")):
            radius = numbers.get(key, 0.0)
            if radius > 0:
                ax.plot(radius * np.cos(circle), radius * np.sin(circle), style, lw=0.8,
                        label=f"{key.replace('_', ' ')} {radius:.4g}")
        ax.set_aspect("equal")
        ax.set_xlim(xy[:, 0].min() - 1e-12, xy[:, 0].max() + 1e-12)
        ax.set_ylim(xy[:, 1].min() - 1e-12, xy[:, 1].max() + 1e-12)
        ax.set_xlabel(label(f"along {_axis_text(e1)}", scene, "length"))
        ax.set_ylabel(label(f"along {_axis_text(e2)}", scene, "length"))
        ax.set_title(f"{name}: contact seen along its normal", fontsize=9)
        ax.legend(fontsize=7, loc="upper right")
    return finish(fig, path)


def pressure_figure(path: Path | None, scene, result, summary: dict):
    """Per contact at the final snapshot: the pressure along the line through its centre of
    pressure in the direction e1 (:func:`slipstep.space.contact_measures.pressure_line`), and
    Hertz's p0 sqrt(1 - s^2/a^2) at the reached load when the scene has the sphere's
    reference."""
    snap = result["snapshots"][-1]
    fig, axes = _panels(scene)
    ref = summary.get("hertz", {})
    for i, (ax, name) in enumerate(zip(axes, scene.model["contact_names"])):
        line = pressure_line(scene, snap, i)
        ax.plot(line["s"], line["pressure"], "-", color="tab:blue", label="slipstep")
        if ref.get("a_hertz_at_final"):
            s = np.linspace(line["s"].min(), line["s"].max(), 400)
            ax.plot(s, hertz_pressure(s, ref["a_hertz_at_final"], ref["p0_hertz_at_final"]),
                    "k--", lw=0.8, label="Hertz")
        ax.set_xlabel(label(f"distance along {_axis_text(line['direction'])}", scene, "length"))
        ax.set_ylabel(label("contact pressure", scene, "stress"))
        ax.set_title(f"{name}: pressure along a line through the contact", fontsize=9)
        ax.legend(fontsize=7)
    return finish(fig, path)


def _axis_text(v: np.ndarray) -> str:
    """A direction as text: the axis it is (x, y, z, -x, ...), else its components."""
    for k, name in enumerate("xyz"):
        for sign, text in ((1.0, name), (-1.0, f"-{name}")):
            if np.allclose(v, sign * np.eye(3)[k], atol=1e-9):
                return text
    return "(" + ", ".join(f"{c:.3g}" for c in v) + ")"
