"""One run's result as an object for scripts and notebooks (:func:`slipstep.run` returns it).

A :class:`Result` holds the scene, the engine's result dict (``raw``, docs/engine_api.md) and
the summary; it gives numpy views of them and writes the usual files (``write``, through
:mod:`slipstep.output.results`).  Every derived quantity comes from :mod:`slipstep.output.fields`,
:mod:`slipstep.output.history` and :mod:`slipstep.measures.contact_edges`, and the XDMF content from :func:`slipstep.output.writers.xdmf_step`, the places the files take them from.

    >>> r = slipstep.run("hertz_cylinder", overrides=["contact.mu=0.2"])
    >>> r.summary["peak_pressure"], r.times, r.events[:3]
    >>> r.fields(1.0)["u"], r.profile(1.0)["pressure"], r.to_meshio(1.0)
"""

from __future__ import annotations

import html
from collections import Counter
from pathlib import Path

import numpy as np

from ..measures.contact_edges import contact_profile
from .fields import is_elastoplastic, nodal_stress, yield_drift
from ..measures.contact_faces import contact_profile_3d
from .fields import nodal_stress_3d
from .snapshot import Snapshot
from .history import ELEMENT_EVENTS, event_positions, event_times, same_time, snapshot_time
from ..errors import InputError
from .summary import one_line

#: The columns of :attr:`Result.events` (3D: z after y).
EVENT_DTYPE = [
    ("step", "i8"),
    ("t", "f8"),
    ("stage", "i8"),
    ("load_fraction", "f8"),
    ("kind", "U14"),
    ("entity", "i8"),
    ("entity_kind", "U7"),
    ("x", "f8"),
    ("y", "f8"),
]


class Result:
    """The result of one run (see the module docstring)."""

    def __init__(self, scene, raw: dict, summary: dict, out: Path | None = None):
        self.scene, self.raw, self.summary = scene, raw, summary
        self.out = None if out is None else Path(out)

    # ------------------------------------------------------------------ what the run was
    @property
    def case(self):
        return self.scene.case

    @property
    def stop(self) -> dict:
        """How the run ended: ``kind`` (completed, interrupted, limit_load, ...), ``t``."""
        return self.raw["stop"]

    @property
    def completed(self) -> bool:
        return self.stop["kind"] == "completed"

    @property
    def nodes(self) -> np.ndarray:
        """(N, 2) node coordinates (undeformed; 3D: (N, 3))."""
        return self.scene.nodes

    @property
    def elements(self) -> np.ndarray:
        """(M, 3) node ids of the triangles, or in 3D (M, 4) of the tetrahedra."""
        return self.scene.elements

    @property
    def triangles(self) -> np.ndarray:
        """(M, 3) node ids of the elements (counter-clockwise); a 3D result has
        :attr:`tetrahedra`."""
        return self._elements_as(
            "triangle", "a 3D result has tetrahedra, not triangles: r.tetrahedra"
        )

    @property
    def tetrahedra(self) -> np.ndarray:
        """(M, 4) node ids of the elements of a 3D result."""
        return self._elements_as("tetra", "a 2D result has triangles, not tetrahedra: r.triangles")

    def _elements_as(self, cell_type: str, otherwise: str) -> np.ndarray:
        """The elements when they are of ``cell_type``, else an AttributeError: ``otherwise``."""
        if self.scene.idealisation.cell_type != cell_type:
            raise AttributeError(f"{otherwise} (r.elements in either dimension)")
        return self.elements

    # ------------------------------------------------------------------ history
    @property
    def times(self) -> np.ndarray:
        """Path time t of every snapshot, in order (= load fraction for one stage)."""
        return np.array([snapshot_time(s) for s in self.raw.get("snapshots", [])])

    @property
    def history(self) -> dict:
        """The resultants at t = 0 and after every increment, the arrays of history.csv
        (:func:`slipstep.measures.resultants.step_history`): ``t``, ``stage``, ``contact_force`` (R, C,
        3), ``contact_moment``, ``reaction`` (R, G, 3, per ``support_names``), ``factor``,
        ``applied``, ``load_work``, ``motion``, ``prescribed``; the driving loads' curves are
        :func:`slipstep.measures.resultants.drivers` of it."""
        from ..measures.resultants import step_history

        return step_history(self.scene, self.raw)

    @property
    def events(self) -> np.ndarray:
        """One row per event (and entity), a numpy structured array with the columns of
        events.csv: step, t (path time), stage (1-based), load_fraction (within its stage),
        kind, entity (pair or element index), entity_kind, x, y (3D: x, y, z; node a of the
        pair, the element's centroid).  ``r.events["t"][r.events["kind"] == "yield"]``, or
        ``pandas.DataFrame(r.events)``."""
        ev = self.raw["events"]
        dtype = EVENT_DTYPE + [(c, "f8") for c in "xyz"[2 : self.scene.dimension]]
        out = np.zeros(len(ev["step"]), dtype=dtype)
        t, stage = event_times(self.raw)
        out["step"], out["t"], out["stage"] = ev["step"], t, stage + 1
        for key in ("load_fraction", "kind", "entity"):
            out[key] = ev[key]
        out["entity_kind"] = np.where(np.isin(out["kind"], ELEMENT_EVENTS), "element", "pair")
        xy = event_positions(self.scene, self.raw)
        for k, name in enumerate("xyz"[: xy.shape[1]]):
            out[name] = xy[:, k]
        return out

    # ------------------------------------------------------------------ one snapshot
    def snapshot(self, t: float | None = None, stage: int | None = None) -> dict:
        """The engine's snapshot at path time ``t`` (None: the last one).  Of several at the
        same t the last, the state after every event there; ``stage`` (1-based) picks among
        them by stage: at a stage end t = k, ``stage=k`` is the end of stage k, the default
        the start of stage k + 1 after its zero-length switches (elements that unload, say)."""
        snaps = self.raw.get("snapshots", [])
        if not snaps:
            raise InputError(
                f"{self.case.name}: the run has no snapshots (it stopped before "
                f"the first increment)"
            )
        times = self.times
        pick = np.ones(len(snaps), bool)
        if stage is not None:
            pick = np.array([int(s.get("stage", 0)) + 1 == stage for s in snaps])
        if t is not None:
            pick &= same_time(times, t)
        if not pick.any():
            where = f"t = {t:g}" if t is not None else "the end"
            where += f" in stage {stage}" if stage is not None else ""
            raise InputError(
                f"{self.case.name}: no snapshot at {where}; snapshots are at t = "
                f"{_listed(times)}: ask for more with output.snapshots"
            )
        return snaps[np.flatnonzero(pick)[-1]]

    def fields(self, t: float | None = None, stage: int | None = None) -> dict:
        """numpy arrays at snapshot time ``t`` (None: the last; ``stage`` as for
        :meth:`snapshot`): ``u`` (N, 2), ``reaction``
        (N, 2; supports and prescribed displacements), ``stress`` (M, 4: sigma_x, sigma_y,
        sigma_z, tau_xy), ``von_mises`` (M,), ``nodal_stress`` (N, 4: the same columns at the
        nodes, recovered by :func:`slipstep.output.fields.nodal_stress`) and ``nodal_von_mises``
        (N,), for elastoplastic cases ``plastic_strain``,
        ``plastic`` (bool) and ``yield_drift`` (M,); per candidate pair in the engine's order
        (P,): ``lambda_n``, ``lambda_t`` (nodal contact forces), ``status`` (0 open, 1 stick,
        2 slip), ``pressure``, ``tangential_stress``, ``gap``, ``rtd`` (as in
        contact_profile.csv); ``t``, ``stage`` (1-based) and ``load_fraction`` (within it).
        A 3D scene (docs/engine_api.md): ``u``, ``reaction`` (N, 3), ``stress`` (M, 6: Voigt
        sigma_xx, sigma_yy, sigma_zz, tau_yz, tau_xz, tau_xy), ``nodal_stress`` (N, 6),
        ``lambda_t`` and ``rtd`` (P, 2) in each pair's (t1, t2), ``tangential_stress`` (P, 3)
        in x, y, z."""
        return self.scene.idealisation.fields(self.scene, self.snapshot(t, stage))

    def profile(self, t: float | None = None, stage: int | None = None) -> dict:
        """The contact profile at snapshot time ``t`` (None: the last), as in
        contact_profile.csv: per candidate pair sorted by x, arrays x, y, s, contact, pressure,
        tangential_stress, rtd, status, gap, pair, node_a (:func:`slipstep.
        contact_measures.contact_profile`; 3D: :func:`slipstep.measures.contact_faces.
        contact_profile_3d`, sorted by x, y, z, with node a's coordinates as the columns x, y,
        z as in contact_profile.csv, and together as ``position`` (P, 3))."""
        return self.scene.idealisation.profile(self.scene, self.snapshot(t, stage))

    def to_meshio(self, t: float | None = None, stage: int | None = None):
        """A ``meshio.Mesh`` at snapshot time ``t`` (None: the last): points with z = 0 (3D, so
        every meshio format takes them, ``.vtu`` too), triangles, and the point and cell data
        results.xdmf holds for that time step (vectors padded to 3 components, stresses also
        as 9-component tensors, as ParaView wants them)."""
        import meshio

        idealisation = self.scene.idealisation
        point_data, cell_data = idealisation.xdmf_step(self.scene, self.snapshot(t, stage))
        n, d = self.nodes.shape
        points = np.column_stack([self.nodes, np.zeros((n, 3 - d))])
        return meshio.Mesh(
            points,
            [(idealisation.cell_type, self.elements)],
            point_data=point_data,
            cell_data=cell_data,
        )

    # ------------------------------------------------------------------ files and figures
    def figures(self) -> dict:
        """The run's figures as matplotlib Figures by name (contact_interface, von_mises, ...);
        built with the object API, so a notebook's pyplot state is untouched."""
        return self.scene.idealisation.figures(self.scene, self.raw, self.summary)

    def figure(self, name: str, ax=None):
        """One of :meth:`figures` by name, drawn on the caller's ``ax`` when given (an Axes, or
        a sequence of Axes for the figures of several panels: contact_interface 3,
        contact_extent 2, force_displacement one per prescribed load; in 3D contact_area and
        contact_pressure_line one per contact, plastic_zone two); returns its Figure."""
        builders = dict(self.scene.idealisation.chosen_figures(self.scene, self.raw))
        if name not in builders:
            raise ValueError(f"figure {name!r}: this run has {', '.join(builders) or 'none'}")
        return builders[name](None, self.scene, self.raw, self.summary, ax=ax)

    def write(
        self, out: str | Path, figures: bool | None = None, xdmf: bool | None = None
    ) -> list[Path]:
        """Write the run's files into ``out`` (all or nothing, :func:`slipstep.output.results.
        write_results`); ``figures`` and ``xdmf`` default to the case's ``[output]``."""
        from .results import write_results

        written = write_results(out, self.scene, self.raw, self.summary, figures, xdmf)
        self.out = Path(out)
        return written

    # ------------------------------------------------------------------ display
    def __repr__(self) -> str:
        where = f", files in {self.out}" if self.out else ""
        return f"<slipstep.Result {one_line(self.summary)}; {self._snapshot_text()}{where}>"

    def _snapshot_text(self) -> str:
        times = self.times
        return f"{len(times)} snapshots" + (f" at t = {_listed(times)}" if len(times) else "")

    def _repr_html_(self) -> str:
        rows = [(k, v) for k, v in self._overview() if v]
        body = "".join(
            f"<tr><th style='text-align:left'>{html.escape(k)}</th>"
            f"<td style='text-align:left'>{html.escape(str(v))}</td></tr>"
            for k, v in rows
        )
        return (
            f"<b>slipstep.Result</b> <code>{html.escape(self.case.name)}</code>"
            f"<table>{body}</table>"
        )

    def _overview(self) -> list[tuple[str, str]]:
        """(label, text) rows of the HTML view."""
        s, m = self.summary, self.scene.engine_model
        stop = self.stop["kind"] + (
            f" ({self.stop['message']})" if self.stop.get("message") else ""
        )
        kinds = Counter(self.raw["events"]["kind"])
        return [
            (
                "stopped",
                f"{stop} at t = {float(self.stop.get('t', 0.0)):.4g} of "
                f"{s.get('n_stages', 1)} stage(s)",
            ),
            (
                "mesh",
                f"{len(m.nodes)} nodes, {len(self.elements)} elements, "
                f"{self.scene.n_dofs} DOFs, {len(m.pairs)} contact pairs",
            ),
            ("events", f"{s['n_events']}: " + ", ".join(f"{n} {k}" for k, n in kinds.items())),
            ("summary", one_line(s)),
            ("snapshots", self._snapshot_text()),
            ("files", str(self.out) if self.out else ""),
            (
                "methods",
                "fields(t), profile(t), to_meshio(t), events, history, figures(), " "write(out)",
            ),
        ]


def _listed(times: np.ndarray, most: int = 6) -> str:
    """``0.1, 0.2, ..., 1`` (at most ``most`` values shown)."""
    shown = [f"{x:.4g}" for x in times]
    if len(shown) > most:
        shown = shown[: most // 2] + ["..."] + shown[-(most // 2) :]
    return ", ".join(shown)


def section_fields(scene, snap: dict) -> dict:
    """:meth:`Result.fields` of a snapshot of a 2D scene."""
    out = snapshot_fields(scene, snap, lambda stress: nodal_stress(scene, stress))
    prof = contact_profile(scene, snap)
    for key in ("pressure", "tangential_stress", "gap", "rtd"):
        out[key] = np.empty(len(prof["pair"]))
        out[key][prof["pair"]] = prof[key]
    return out


def solid_fields(scene, snap: dict) -> dict:
    """:meth:`Result.fields` of a snapshot of a 3D scene."""
    out = snapshot_fields(
        scene, snap, lambda stress: nodal_stress_3d(scene.nodes, scene.tetrahedra, stress)
    )
    prof = contact_profile_3d(scene, snap)
    for key, target in (
        ("pressure", "pressure"),
        ("tangential_stress", "tangential_stress"),
        ("gap", "gap"),
        ("slip", "rtd"),
    ):
        out[target] = np.empty_like(prof[key])
        out[target][prof["pair"]] = prof[key]
    return out


def snapshot_fields(scene, snap: dict, nodal_of) -> dict:
    """The fields of :meth:`Result.fields` alike in every dimension (all but the contact
    profile's) of the engine's snapshot ``snap``, with ``nodal_of(stress)`` the stresses at the
    nodes."""
    s, von_mises = Snapshot.of(scene, snap), scene.idealisation.von_mises
    nodal = nodal_of(s.stress)
    out = {
        "t": s.t,
        "stage": s.stage + 1,
        "load_fraction": s.load_fraction,
        "u": s.u,
        "stress": s.stress,
        "von_mises": von_mises(s.stress),
        "nodal_stress": nodal,
        "nodal_von_mises": von_mises(nodal),
    }
    if s.reaction is not None:
        out["reaction"] = s.reaction
    if is_elastoplastic(scene):
        out["plastic_strain"] = s.plastic_strain
        out["plastic"] = s.plastic.astype(bool)
        out["yield_drift"] = yield_drift(scene, snap)
    out["lambda_n"] = s.lambda_n
    out["lambda_t"] = s.lambda_t
    out["status"] = s.status.astype(np.int64)
    return out


def solid_profile(scene, snap: dict) -> dict:
    """:meth:`Result.profile` of a snapshot of a 3D scene: node a's coordinates as the columns
    x, y, z and together as ``position`` (P, 3)."""
    prof = contact_profile_3d(scene, snap)
    position = prof.pop("x")
    return {
        "x": position[:, 0],
        "y": position[:, 1],
        "z": position[:, 2],
        "position": position,
        **prof,
    }
