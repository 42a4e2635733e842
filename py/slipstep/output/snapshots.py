"""Which snapshots a run keeps, and how large its results.h5 grows.

``[output] snapshots``: ``"events"`` keeps the state after every event, a list keeps the
given path times, and ``"auto"`` (the default) is sized for the scene.  In 2D it is
``"events"``: the plane meshes are small and the event history is what the figures draw.  In
space one full-field time step of a 25k-DOF scene is ~8 MB and a frictional run has hundreds of
events, so ``"auto"`` keeps the stage ends and evenly spaced path times between them, as many
per stage (at most :data:`AUTO_PER_STAGE`) as keep results.h5 within :data:`AUTO_BYTES`; the
events themselves stay in events.csv either way.

The size of a time step is that of the arrays the XDMF writer
(:func:`slipstep.output.writers.xdmf_step`, :func:`~slipstep.output.writers.xdmf_step_3d`, and the record
:func:`~slipstep.output.writers.snapshot_record` beside them) writes for a
snapshot of zeros of the engine's shapes: the same code that writes them, so the prediction
follows the writer.
"""

from __future__ import annotations

import numpy as np

from ..validation.terms import terms_of

#: The budget of results.h5 under ``snapshots = "auto"`` in 3D (bytes).
AUTO_BYTES = 100e6
#: At most this many evenly spaced snapshots per stage under ``"auto"`` in 3D (the stage end
#: one of them).
AUTO_PER_STAGE = 10


def _zero_snapshot(scene) -> dict:
    """A snapshot of zeros with the engine's shapes (docs/engine_api.md)."""
    n, m, p, d = len(scene.nodes), len(scene.elements), len(scene.pair_xy), scene.dimension
    stress = scene.idealisation.stress_width
    return {
        "u": np.zeros(n * d),
        "reaction": np.zeros(n * d),
        "stress": np.zeros(m * stress),
        "plastic_strain": np.zeros(m),
        "plastic": np.zeros(m, dtype=np.int8),
        "lambda_n": np.zeros(p),
        "lambda_t": np.zeros(p * (d - 1)),
        "status": np.zeros(p, dtype=np.int8),
        "gap": np.zeros(p),
        "rtd": np.zeros(p * (d - 1)),
        "t": 1.0,
        "stage": 0,
        "load_fraction": 1.0,
    }


def step_bytes(scene) -> int:
    """The bytes of one time step of results.h5 (its point and cell data)."""
    from .writers import snapshot_record

    zero = _zero_snapshot(scene)
    point_data, cell_data = scene.idealisation.xdmf_step(scene, zero)
    return int(
        sum(np.asarray(v).nbytes for v in point_data.values())
        + sum(np.asarray(block).nbytes for v in cell_data.values() for block in v)
        + sum(v.nbytes for v in snapshot_record(zero).values())
    )


def mesh_bytes(scene) -> int:
    """The bytes of the mesh results.h5 holds once: points (3 coordinates) and cells."""
    return int(len(scene.nodes) * 3 * 8 + scene.elements.size * 8)


def auto_times(n_stages: int, bytes_per_step: float) -> list[float]:
    """The path times of ``"auto"`` in 3D: per stage k the times k - 1 + i/n, i = 1..n, with n
    the most (up to :data:`AUTO_PER_STAGE`, at least 1: the stage end) whose steps fit in
    :data:`AUTO_BYTES`."""
    fit = int(AUTO_BYTES // max(bytes_per_step * n_stages, 1.0))
    per_stage = min(AUTO_PER_STAGE, max(1, fit))
    return [round(k + i / per_stage, 12) for k in range(n_stages) for i in range(1, per_stage + 1)]


def requested(case, bytes_per_step: float | None = None):
    """What the run asks the engine for: ``"events"`` or a list of path times (the stage ends
    are added by :func:`slipstep.options.solver_options`).  ``"auto"`` in 3D needs the size of a
    step (:func:`step_bytes`)."""
    snaps = case.record.output.snapshots
    if snaps != "auto":
        return snaps
    if terms_of(case.dimension).auto_snapshots == "events":
        return "events"
    return auto_times(case.path.n_stages, bytes_per_step)


def predicted_text(scene) -> str:
    """``slipstep check``'s line on the results: results.h5's size for the snapshots asked for
    (per snapshot for ``"events"``, whose count the run decides)."""
    per_step, mesh = step_bytes(scene), mesh_bytes(scene)
    snaps = requested(scene.case, per_step)
    mb = 1e-6
    if snaps == "events":
        return (
            f"results.h5: {mesh * mb:.1f} MB of mesh and {per_step * mb:.1f} MB per "
            f"snapshot, one after every event (output.snapshots = \"events\"; a list of "
            f"path times bounds it)"
        )
    times = sorted(set(snaps) | {float(k) for k in range(1, scene.case.path.n_stages + 1)})
    total = mesh + len(times) * per_step
    return (
        f"results.h5: ~{total * mb:.1f} MB ({len(times)} snapshots of "
        f"{per_step * mb:.1f} MB at t = {_listed(times)})"
    )


def _listed(times: list[float], most: int = 6) -> str:
    shown = [f"{t:.4g}" for t in times]
    if len(shown) > most:
        shown = shown[: most // 2] + ["..."] + shown[-(most // 2) :]
    return ", ".join(shown)
