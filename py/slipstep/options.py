"""The engine's ``options`` from a case's [solver] and [output] tables."""

from __future__ import annotations

import numpy as np

from .case import Case


def solver_options(case: Case) -> dict:
    """The engine's ``options``: snapshots at every event or at given path times, every stage
    end added (``"fractions"`` as always for a case without [[stage]], displacement and
    motion, ``"times"`` otherwise)."""
    snaps = case.data["output"]["snapshots"]
    solver = case.data["solver"]
    options = {"tie_tol": float(solver["tie_tol"]), "group_tol": float(solver["group_tol"]),
               "max_events": int(solver["max_events"]),
               "equilibrium_tol": float(solver["equilibrium_tol"]),
               "drift_control": bool(solver["drift_control"]),
               "max_stress_step": float(solver["max_stress_step"]),
               "tangent_turn": float(solver["tangent_turn"]),
               "stop_at_first_yield": bool(solver["stop_at_first_yield"])}
    if snaps == "events":
        options["output"] = "events"
    else:
        path = case.path
        times = sorted(set(snaps) | {float(k) for k in range(1, path.n_stages + 1)})
        options["output"] = "times" if path.new else "fractions"
        options[options["output"]] = np.asarray(times, dtype=np.float64)
    return options
