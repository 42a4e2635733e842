"""One snapshot of the engine's result read in the scene's shapes (:class:`Snapshot`): what the
fields of :meth:`slipstep.Result.fields` and the files are made of.  Which snapshots a run keeps
is :mod:`slipstep.output.snapshots`."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .history import snapshot_time


@dataclass(frozen=True, kw_only=True)
class Snapshot:
    """One snapshot of the engine's result (docs/engine_api.md) in the scene's shapes: the path
    time ``t``, ``stage`` (0-based) and ``load_fraction`` (within it); ``u`` and ``reaction``
    (N, dim), ``stress`` (M, the idealisation's stress_width), ``plastic_strain`` and
    ``plastic`` (M,); per pair ``lambda_n``, ``status`` (P,) and ``lambda_t`` ((P,) in 2D,
    (P, 2) in 3D in each pair's (t1, t2)).  A key the snapshot lacks is None (a result read
    back keeps ``reaction`` and the plastic fields only when it wrote them)."""

    t: float
    stage: int
    load_fraction: float
    u: np.ndarray
    reaction: np.ndarray | None
    stress: np.ndarray
    plastic_strain: np.ndarray | None
    plastic: np.ndarray | None
    lambda_n: np.ndarray
    lambda_t: np.ndarray
    status: np.ndarray

    @classmethod
    def of(cls, scene, snap: dict) -> Snapshot:
        """The view of the engine's snapshot dict ``snap`` of ``scene``."""
        d = scene.dimension

        def array(key, dtype=float):
            return np.asarray(snap[key], dtype=dtype)

        def optional(key, dtype=float):
            return array(key, dtype) if key in snap else None

        reaction, lambda_t = optional("reaction"), array("lambda_t")
        return cls(
            t=snapshot_time(snap),
            stage=int(snap.get("stage", 0)),
            load_fraction=float(snap["load_fraction"]),
            u=array("u").reshape(-1, d),
            reaction=None if reaction is None else reaction.reshape(-1, d),
            stress=array("stress").reshape(-1, scene.idealisation.stress_width),
            plastic_strain=optional("plastic_strain"),
            plastic=optional("plastic", None),
            lambda_n=array("lambda_n"),
            lambda_t=lambda_t.reshape(-1, 2) if d == 3 else lambda_t,
            status=array("status", None),
        )
