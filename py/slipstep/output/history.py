"""The path of a result: path time t of snapshots and events (stage k runs over t in [k-1, k]),
the stages, the load factors along the path, where each event happened, and the support
reactions of a snapshot (numpy only)."""

from __future__ import annotations

import numpy as np

from .fields import centroids


#: Event kinds whose entity is an element (the others are contact pairs).
ELEMENT_EVENTS = ("yield", "unload", "frozen_element")


def final_load_fraction(result) -> float:
    """The load fraction the run reached (end of its last increment; within its stage)."""
    steps = result.get("steps", {}).get("load_fraction", [])
    if len(steps):
        return float(steps[-1])
    snaps = result.get("snapshots", [])
    return float(snaps[-1]["load_fraction"]) if snaps else 0.0


#: Two snapshot times closer than this (relative to the path length, at least 1) are one time.
TIME_TOL = 1e-9
#: The same for the XDMF time series: ParaView's XDMF reader drops a time step within ~1e-8
#: (relative) of its neighbour, at single precision (measured: steps 1.4e-8 apart vanished, 1e-6
#: apart stayed), so a series keeps one state per time resolvable in single precision.
SERIES_TIME_TOL = 1e-6


# Results without stages (engines before load paths) have no ``t``/``stage``: one stage, t = f.
def snapshot_time(snap: dict) -> float:
    """Path time t of a snapshot (its load fraction in a result without stages)."""
    return float(snap.get("t", snap["load_fraction"]))


def same_time(times, t: float) -> np.ndarray:
    """(n,) True where ``times`` equal ``t`` within :data:`TIME_TOL`."""
    times = np.asarray(times, dtype=float)
    return np.abs(times - float(t)) <= TIME_TOL * max(1.0, float(times.max(initial=0.0)))


def distinct_time_snapshots(result) -> list[int]:
    """The index of the last snapshot at each distinct path time, in order.  Several snapshots
    share a t when events happen together (a stage end and the zero-length switches after it,
    several events at one load): the last is the state after all of them.  A time series
    keeps one state per time (ParaView shows a repeated time as an empty frame, and drops one
    closer to its neighbour than single precision resolves: :data:`SERIES_TIME_TOL`);
    events.csv keeps every event."""
    times = np.array([snapshot_time(s) for s in result.get("snapshots", [])])
    if len(times) == 0:
        return []
    last = np.append(np.diff(times) > SERIES_TIME_TOL * max(1.0, float(times.max())), True)
    return np.flatnonzero(last).tolist()


def event_times(result) -> tuple[np.ndarray, np.ndarray]:
    """(t, stage) of every events row, stage 0-based."""
    ev = result["events"]
    t = np.asarray(ev.get("t", ev["load_fraction"]), dtype=float)
    stage = np.asarray(ev.get("stage", np.zeros(len(t))), dtype=np.int64)
    return t, stage


def event_positions(scene, result) -> np.ndarray:
    """(n, 2) where each events row happened (3D: (n, 3)): node a of its pair, or the centroid
    of its element for the element events (:data:`ELEMENT_EVENTS`)."""
    ev = result["events"]
    kinds = np.asarray(ev["kind"], dtype=str)
    entity = np.asarray(ev["entity"], dtype=np.int64)
    out = np.zeros((len(entity), scene.nodes.shape[1]))
    on_element = np.isin(kinds, ELEMENT_EVENTS)
    if on_element.any():
        out[on_element] = centroids(scene.nodes, scene.elements[entity[on_element]])
    out[~on_element] = scene.pair_xy[entity[~on_element]]
    return out


def final_time(result) -> float:
    """The path time the run reached (``stop.t``, else the end of its last increment)."""
    if "t" in result.get("stop", {}):
        return float(result["stop"]["t"])
    steps = result.get("steps", {})
    if len(steps.get("t", [])):
        return float(steps["t"][-1])
    return final_load_fraction(result)


def stage_names(scene, result) -> list[str]:
    """The name of every stage of the load path (``stage 1`` for a run without stages)."""
    names = result.get("stage_names") or getattr(scene, "stage_names", None)
    n = int(result.get("n_stages", getattr(scene, "n_stages", len(names or [1]))))
    return list(names) if names and len(names) == n else [f"stage {k + 1}" for k in range(n)]


def stage_ends(result, n_stages: int) -> list[tuple[int, int]]:
    """(stage k 0-based, snapshot index) for every completed stage: the last snapshot of stage
    k at load fraction 1, else (a snapshot at t = k + 1 labelled as the next stage's start) the
    last one at t = k + 1 (each within 1e-12).  So the record of a stage is its own end state,
    before the zero-length switches that start the next (elements that unload, say)."""
    out = []
    snaps = result.get("snapshots", [])
    for k in range(n_stages):
        own = [
            i
            for i, s in enumerate(snaps)
            if int(s.get("stage", 0)) == k and abs(float(s["load_fraction"]) - 1.0) <= 1e-12
        ]
        at_t = [i for i, s in enumerate(snaps) if abs(snapshot_time(s) - (k + 1)) <= 1e-12]
        if own or at_t:
            out.append((k, (own or at_t)[-1]))
    return out


def is_staged(scene, result) -> bool:
    """True for a load path with several stages, prescribed displacements or motions."""
    return (
        len(stage_names(scene, result)) > 1
        or bool(getattr(scene, "prescribed", {}))
        or bool(getattr(scene, "motions", {}))
    )


def load_factor(scene, name: str, t):
    """Factor of load pattern ``name`` at path time(s) t: ``scene.factors`` (rows at
    t = 0, 1, ..., n_stages) interpolated linearly; t itself without stages."""
    names = getattr(scene, "load_names", None)
    factors = getattr(scene, "factors", None)
    if factors is None or not names or name not in names:
        return np.asarray(t, dtype=float)
    column = np.asarray(factors, dtype=float)[:, list(names).index(name)]
    return np.interp(t, np.arange(len(column)), column)


def reactions(scene, snapshot: dict) -> dict[str, tuple[float, ...]]:
    """Per [[bc]] name (``scene.support_dofs``): the summed support reaction (Rx, Ry) (3D:
    (Rx, Ry, Rz)) its DOFs exert on the body at ``snapshot``, a DOF held by several [[bc]] in
    the first (:func:`slipstep.loads.supports.support_groups`, as the engine's per-increment
    reactions); empty without ``reaction`` in the snapshot."""
    from ..loads.supports import support_groups

    if "reaction" not in snapshot:
        return {}
    r = np.asarray(snapshot["reaction"], dtype=float).reshape(-1)
    out = {}
    for name, dofs in support_groups(scene).items():
        d = scene.nodes.shape[1]
        dofs = np.unique(np.asarray(dofs, dtype=np.int64))
        out[name] = tuple(float(r[dofs[dofs % d == c]].sum()) for c in range(d))
    return out
