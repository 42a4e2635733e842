"""The engine's ``options`` from a case's [solver] and [output] tables."""

from __future__ import annotations

import numpy as np

from .case import Case
from .schema import SOLVER_KEYS
from .output.snapshots import requested


def solver_options(case: Case, snapshots=None) -> dict:
    """The engine's ``options``: the [solver] table as it is (its keys are the engine's,
    :data:`slipstep.schema.SOLVER_KEYS`), and snapshots at every event or at given path times,
    every stage end added (``"fractions"`` as always for a case without [[stage]], displacement and
    motion, ``"times"`` otherwise).  ``snapshots``: ``"events"`` or the times, as
    :func:`slipstep.output.snapshots.requested` resolves the case's ``[output] snapshots``
    (None: that of a 2D case, where ``"auto"`` is ``"events"``)."""
    snaps = requested(case) if snapshots is None else snapshots
    solver = case.record.solver
    options = {key: getattr(solver, key) for key in SOLVER_KEYS}  # the engine's keys, as given
    if snaps == "events":
        options["output"] = "events"
    else:
        path = case.path
        times = sorted(set(snaps) | {float(k) for k in range(1, path.n_stages + 1)})
        options["output"] = "times" if path.new else "fractions"
        options[options["output"]] = np.asarray(times, dtype=np.float64)
    return options
