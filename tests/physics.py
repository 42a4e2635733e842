"""Independent physics checks on result arrays (not the engine's own residuals).

``equilibrium_residual(model, snapshot)`` recomputes equilibrium of a snapshot from its arrays
alone: the internal force Σ_e t A_e B_eᵀ σ_e of the constant-strain triangles (B from the
nodes), minus the applied load at the snapshot's load fraction, minus the contact forces
λ_n n + λ_t t on node a (and the opposite on node b; t = (−n_y, n_x), docs/engine_api.md),
over the DOFs that are not supported.  It does not call the engine.
"""

from __future__ import annotations

import numpy as np


def internal_force(nodes: np.ndarray, triangles: np.ndarray, stress: np.ndarray,
                   thickness: float) -> np.ndarray:
    """Σ_e t A_e B_eᵀ (σx, σy, τxy)_e over all DOFs (2 per node)."""
    x, y = nodes[triangles, 0], nodes[triangles, 1]            # (M, 3)
    area2 = (x[:, 1] - x[:, 0]) * (y[:, 2] - y[:, 0]) - (x[:, 2] - x[:, 0]) * (y[:, 1] - y[:, 0])
    b = np.stack([y[:, 1] - y[:, 2], y[:, 2] - y[:, 0], y[:, 0] - y[:, 1]], axis=1)  # A2 ∂N/∂x
    c = np.stack([x[:, 2] - x[:, 1], x[:, 0] - x[:, 2], x[:, 1] - x[:, 0]], axis=1)  # A2 ∂N/∂y
    sx, sy, txy = stress[:, 0:1], stress[:, 1:2], stress[:, 3:4]
    # t A Bᵀσ with A = area2/2 and B's entries ∂N/∂x = b/area2: t/2 (b σx + c τxy, c σy + b τxy)
    fx = 0.5 * thickness * (b * sx + c * txy)
    fy = 0.5 * thickness * (c * sy + b * txy)
    f = np.zeros(2 * len(nodes))
    np.add.at(f, 2 * triangles, fx)
    np.add.at(f, 2 * triangles + 1, fy)
    return f


def contact_force(n_nodes: int, pairs: dict, lambda_n: np.ndarray,
                  lambda_t: np.ndarray) -> np.ndarray:
    """The contact forces on the bodies over all DOFs."""
    normal = np.asarray(pairs["normal"], dtype=float)
    tangent = np.stack([-normal[:, 1], normal[:, 0]], axis=1)
    force = lambda_n[:, None] * normal + lambda_t[:, None] * tangent
    f = np.zeros(2 * n_nodes)
    a, b = np.asarray(pairs["node_a"]), np.asarray(pairs["node_b"])
    for comp in (0, 1):
        np.add.at(f, 2 * a + comp, force[:, comp])
        np.add.at(f, 2 * b[b >= 0] + comp, -force[b >= 0, comp])
    return f


def equilibrium_residual(model: dict, snapshot: dict) -> float:
    """|internal − load − contact| over the unsupported DOFs, relative to |load| there
    (absolute for a scene without load)."""
    nodes = np.asarray(model["nodes"], dtype=float)
    r = (internal_force(nodes, np.asarray(model["triangles"]), np.asarray(snapshot["stress"]),
                        model["thickness"])
         - snapshot["load_fraction"] * np.asarray(model["load"], dtype=float)
         - contact_force(len(nodes), model["pairs"], np.asarray(snapshot["lambda_n"]),
                         np.asarray(snapshot["lambda_t"])))
    free = np.ones(len(r), bool)
    free[np.asarray(model["fixed_dofs"], dtype=np.int64)] = False
    scale = np.linalg.norm(np.asarray(model["load"], dtype=float)[free])
    return float(np.linalg.norm(r[free]) / (scale if scale > 0 else 1.0))
