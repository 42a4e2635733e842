"""Independent checks of 3D results from their arrays alone (the 3D counterpart of
tests/physics.py; nothing here calls the engine or slipstep's own measures).

Equilibrium
    ``internal_force_3d``: Σ_e V_e B_eᵀ σ_e of linear tetrahedra (constant strain, B from the
    nodes, σ in the contract's Voigt order σxx, σyy, σzz, σyz, σxz, σxy, engineering shears).
    ``contact_force_3d``: the contact forces of a snapshot on every DOF: pair k puts
    λ_n n + λ_t1 t1 + λ_t2 t2 on node a (the opposite on node b), or, for a weighted
    (node-to-surface) row, that vector times each weight on the weight's node
    (docs/engine_api.md, "3D models").
    ``equilibrium_residual_3d``: |f_int − load(t) − contact| over the DOFs not held, measured as
    tests/physics.py's ``equilibrium_residual`` measures it in 2D (its path load and held DOFs).

Geometry
    ``tet_centroids``, ``angle_deg`` (between directions in the plane), ``second_moments``
    (centroid and principal axes of a set of weighted points in the plane).
"""

from __future__ import annotations

import numpy as np
from physics import applied_load, held_dofs


def tet_centroids(nodes: np.ndarray, tets: np.ndarray) -> np.ndarray:
    return np.asarray(nodes, dtype=float)[np.asarray(tets)].mean(axis=1)


def internal_force_3d(nodes: np.ndarray, tets: np.ndarray, stress: np.ndarray) -> np.ndarray:
    """Σ_e V_e B_eᵀ σ_e over all 3N DOFs.  For a tetrahedron the gradients of its shape
    functions are the rows of inv([x1-x0, x2-x0, x3-x0]) (for nodes 1..3) and minus their sum
    (node 0); the nodal force of node k is V (σ ∇N_k) with σ the symmetric tensor."""
    x = np.asarray(nodes, dtype=float)[np.asarray(tets)]            # (M, 4, 3)
    J = np.transpose(x[:, 1:] - x[:, :1], (0, 2, 1))                # columns x_k - x0
    volume = np.abs(np.linalg.det(J)) / 6.0
    grad = np.linalg.inv(J)                                         # rows: grad N_1..N_3
    grad = np.concatenate([-grad.sum(axis=1, keepdims=True), grad], axis=1)  # (M, 4, 3)
    s = np.asarray(stress, dtype=float).reshape(-1, 6)
    sigma = np.empty((len(s), 3, 3))
    sigma[:, 0, 0], sigma[:, 1, 1], sigma[:, 2, 2] = s[:, 0], s[:, 1], s[:, 2]
    sigma[:, 1, 2] = sigma[:, 2, 1] = s[:, 3]
    sigma[:, 0, 2] = sigma[:, 2, 0] = s[:, 4]
    sigma[:, 0, 1] = sigma[:, 1, 0] = s[:, 5]
    f = volume[:, None, None] * np.einsum("mij,mkj->mki", sigma, grad)  # (M, 4, 3)
    dofs = 3 * np.asarray(tets)[:, :, None] + np.arange(3)
    return np.bincount(dofs.ravel(), weights=f.ravel(), minlength=3 * len(nodes))


def contact_force_3d(model: dict, snapshot: dict) -> np.ndarray:
    """The contact forces of ``snapshot`` on all 3N DOFs (module docstring)."""
    pairs = model["pairs"]
    n_dof = 3 * len(model["nodes"])
    lam_n = np.asarray(snapshot["lambda_n"], dtype=float)
    lam_t = np.asarray(snapshot["lambda_t"], dtype=float).reshape(-1, 2)
    tangent = np.asarray(pairs["tangent"], dtype=float)
    vector = lam_n[:, None] * np.asarray(pairs["normal"], dtype=float) \
        + np.einsum("pt,ptd->pd", lam_t, tangent)                   # (P, 3) on node a
    f = np.zeros(n_dof)
    ptr = pairs.get("weight_ptr")
    for k, (a, b) in enumerate(zip(pairs["node_a"], pairs["node_b"])):
        if ptr is not None and ptr[k + 1] > ptr[k]:
            rows = slice(ptr[k], ptr[k + 1])
            for node, w in zip(pairs["weight_node"][rows], pairs["weight_value"][rows]):
                f[3 * node:3 * node + 3] += w * vector[k]
            continue
        f[3 * a:3 * a + 3] += vector[k]
        if b >= 0:
            f[3 * b:3 * b + 3] -= vector[k]
    return f


def equilibrium_residual_3d(model: dict, snapshot: dict) -> float:
    """|f_int − load(t) − contact| over the DOFs not held, relative to the largest |load| along
    the path, or to the supports' forces when the path prescribes displacements or motions: the
    measure of tests/physics.py's ``equilibrium_residual`` (its path load and held DOFs), with
    the forces of tetrahedra and of pairs in space."""
    t = float(snapshot.get("t", snapshot["load_fraction"]))
    internal = internal_force_3d(model["nodes"], model["tetrahedra"], snapshot["stress"])
    r = internal - applied_load(model, t) - contact_force_3d(model, snapshot)
    free = np.ones(len(r), bool)
    free[held_dofs(model)] = False
    n_stages = max(1, len(model.get("stages", [])))
    scale = max(np.linalg.norm(applied_load(model, k)[free]) for k in range(1, n_stages + 1))
    if "patterns" in model:
        scale = max(scale, float(np.linalg.norm(internal[~free])))
    return float(np.linalg.norm(r[free]) / (scale if scale > 0 else 1.0))


def angle_deg(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Angles in degrees between the rows of u and the direction v (both in the plane)."""
    u = np.asarray(u, dtype=float)
    v = np.asarray(v, dtype=float) / np.linalg.norm(v)
    cos = (u @ v) / np.linalg.norm(u, axis=1)
    return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def second_moments(points: np.ndarray, weights: np.ndarray):
    """(centroid (2,), principal values (2,) descending, principal axes (2, 2) as rows) of
    points in the plane weighted by ``weights`` (areas)."""
    w = np.asarray(weights, dtype=float)
    p = np.asarray(points, dtype=float)[:, :2]
    c = (w[:, None] * p).sum(axis=0) / w.sum()
    d = p - c
    cov = np.einsum("p,pi,pj->ij", w, d, d) / w.sum()
    values, axes = np.linalg.eigh(cov)
    return c, values[::-1], axes[:, ::-1].T
