"""The stress field of a result: stress names per plane (axisymmetric scenes, x = r, y = z: the
columns are sigma_r, sigma_z, sigma_theta (hoop), tau_rz), von Mises, the full tensor, nodal
averages, element centroids, polar components, and the plastic state (numpy only)."""

from __future__ import annotations

import numpy as np

from .space.fields import von_mises_3d


#: Names of the four stress columns, per plane (the engine's x, y, z, xy; z out of plane, the
#: hoop direction theta of a ring).
STRESS_NAMES = {
    "strain": ("sigma_x", "sigma_y", "sigma_z", "tau_xy"),
    "stress": ("sigma_x", "sigma_y", "sigma_z", "tau_xy"),
    "axisymmetric": ("sigma_r", "sigma_z", "sigma_theta", "tau_rz"),
}


def coordinate_names(scene) -> tuple[str, ...]:
    """("r", "z") for an axisymmetric scene, ("x", "y", "z") in 3D, else ("x", "y")."""
    if scene.model.get("dimension", 2) == 3:
        return ("x", "y", "z")
    return ("r", "z") if scene.model["plane"] == "axisymmetric" else ("x", "y")


def stress_names(scene) -> tuple[str, str, str, str]:
    """The names of the four stress columns of ``scene`` (:data:`STRESS_NAMES`)."""
    return STRESS_NAMES[scene.model["plane"]]


def von_mises(stress: np.ndarray) -> np.ndarray:
    """Equivalent stress of (M, 4) rows sigma_x, sigma_y, sigma_z, tau_xy."""
    sx, sy, sz, txy = stress.T
    return np.sqrt(0.5 * ((sx - sy) ** 2 + (sy - sz) ** 2 + (sz - sx) ** 2) + 3.0 * txy**2)


def stress_tensor(stress: np.ndarray) -> np.ndarray:
    """(K, 9) the full symmetric stress tensor of (K, 4) rows sigma_x, sigma_y, sigma_z,
    tau_xy, row by row (xx, xy, xz, yx, yy, yz, zx, zy, zz: ParaView's 9-component order; the
    same read by columns).  z is the out-of-plane direction: zz is sigma_z of plane strain (0 in
    plane stress), the hoop stress sigma_theta in axisymmetry (x = r, y = z); xz = yz = 0."""
    sx, sy, sz, txy = np.asarray(stress, dtype=float).reshape(-1, 4).T
    zero = np.zeros_like(sx)
    return np.stack([sx, txy, zero, txy, sy, zero, zero, zero, sz], axis=1)


def nodal_stress(scene, stress: np.ndarray) -> np.ndarray:
    """(N, 4) stresses at the nodes (columns as ``stress``) recovered from the constant element
    stresses by area-weighted averaging over the elements around each node: the lumped L2
    projection of the piecewise-constant field onto continuous linear functions,
    sum_e A_e sigma_e / sum_e A_e (in axisymmetry the section's areas).  Chosen over patch
    recovery (SPR) because it is what codes that print nodal stresses do for linear triangles
    (average the elements' values at the node), is exact for a uniform stress, and is defined
    alike at boundary and corner nodes, where SPR patches degenerate; it is first order in h
    (tests/output/test_nodal_stress.py).  Bodies share no nodes, so nothing is averaged across an
    interface."""
    stress = np.asarray(stress, dtype=float).reshape(-1, 4)
    n, p = len(scene.nodes), scene.nodes[scene.triangles]
    area = np.repeat(0.5 * np.abs(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])), 3)
    corner = scene.triangles.ravel()  # element e's nodes at rows 3e, 3e + 1, 3e + 2
    weight = np.bincount(corner, area, minlength=n)
    total = np.stack(
        [np.bincount(corner, area * np.repeat(column, 3), minlength=n) for column in stress.T],
        axis=1,
    )
    return total / np.where(weight > 0, weight, 1.0)[:, None]


def centroids(nodes: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """(M, 2) centroids of the triangles (rows of node ids into ``nodes``)."""
    return np.asarray(nodes)[np.asarray(triangles)].mean(axis=1)


def polar(nodes: np.ndarray, u: np.ndarray, stress: np.ndarray, triangles: np.ndarray):
    """Radial displacement at the nodes, and (r, sigma_r, sigma_theta) at element centroids,
    from Cartesian results centred at the origin."""
    r_n = np.linalg.norm(nodes, axis=1)
    ur = np.einsum("ij,ij->i", u, nodes) / np.where(r_n > 0, r_n, 1.0)
    xc = centroids(nodes, triangles)
    rc = np.linalg.norm(xc, axis=1)
    c, s = xc[:, 0] / rc, xc[:, 1] / rc
    sx, sy, txy = stress[:, 0], stress[:, 1], stress[:, 3]
    sr = c * c * sx + s * s * sy + 2 * c * s * txy
    st = s * s * sx + c * c * sy - 2 * c * s * txy
    return ur, rc, sr, st


def is_elastoplastic(scene) -> bool:
    """True when some material has a yield stress (the run can have plasticity events)."""
    return any(m.get("Sy") is not None for m in scene.model["materials"])


def yield_drift(scene, snap) -> np.ndarray:
    """Per element |sigma_e - sigma_y(eps_p)| / sigma_y(eps_p) for plastic elements, 0 elsewhere:
    how far the stored stress sits off the hardening yield surface (the engine's drift measure)."""
    mats = scene.model["materials"]
    index = np.asarray(scene.model["element_material"])
    sy = np.array([m.get("Sy") or np.inf for m in mats], dtype=float)[index]
    hp = np.array([m.get("H") or 0.0 for m in mats], dtype=float)[index]
    current = sy + hp * np.asarray(snap["plastic_strain"], dtype=float)
    stress = np.asarray(snap["stress"], dtype=float)
    se = (
        von_mises_3d(stress)
        if scene.model.get("dimension", 2) == 3
        else von_mises(stress.reshape(-1, 4))
    )
    plastic = (np.asarray(snap["plastic"]) > 0) & np.isfinite(current)  # elastic bodies: Sy = inf
    drift = np.zeros(len(se))
    drift[plastic] = np.abs(se[plastic] - current[plastic]) / current[plastic]
    return drift
