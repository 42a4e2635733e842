"""The stress field of a result: stress names per plane (axisymmetric scenes, x = r, y = z: the
columns are sigma_r, sigma_z, sigma_theta (hoop), tau_rz), von Mises, the full tensor, nodal
averages, element centroids, polar components, and the plastic state (numpy only).

A 3D result (docs/engine_api.md: ``stress`` (M, 6) in Voigt order sigma_xx, sigma_yy,
sigma_zz, sigma_yz, sigma_xz, sigma_xy) has the ``_3d`` functions: von Mises, the full tensor
for ParaView, nodal averages and spherical components."""

from __future__ import annotations

import numpy as np


#: Names of the four stress columns, per plane (the engine's x, y, z, xy; z out of plane, the
#: hoop direction theta of a ring).
STRESS_NAMES = {
    "strain": ("sigma_x", "sigma_y", "sigma_z", "tau_xy"),
    "stress": ("sigma_x", "sigma_y", "sigma_z", "tau_xy"),
    "axisymmetric": ("sigma_r", "sigma_z", "sigma_theta", "tau_rz"),
}


def coordinate_names(scene) -> tuple[str, ...]:
    """("r", "z") for an axisymmetric scene, ("x", "y", "z") in 3D, else ("x", "y"): the first
    of its idealisation's component names."""
    return tuple(scene.idealisation.component_names[: scene.dimension])


def stress_names(scene) -> tuple[str, str, str, str]:
    """The names of the four stress columns of ``scene`` (:data:`STRESS_NAMES`)."""
    return STRESS_NAMES[scene.engine_model.plane]


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
    return any(m.Sy is not None for m in scene.engine_model.materials)


def yield_drift(scene, snap) -> np.ndarray:
    """Per element |sigma_e - sigma_y(eps_p)| / sigma_y(eps_p) for plastic elements, 0 elsewhere:
    how far the stored stress sits off the hardening yield surface (the engine's drift measure)."""
    model = scene.engine_model
    index = np.asarray(model.element_material)
    sy = np.array([m.Sy or np.inf for m in model.materials], dtype=float)[index]
    hp = np.array([m.H or 0.0 for m in model.materials], dtype=float)[index]
    current = sy + hp * np.asarray(snap["plastic_strain"], dtype=float)
    se = scene.idealisation.von_mises(np.asarray(snap["stress"], dtype=float))
    plastic = (np.asarray(snap["plastic"]) > 0) & np.isfinite(current)  # elastic bodies: Sy = inf
    drift = np.zeros(len(se))
    drift[plastic] = np.abs(se[plastic] - current[plastic]) / current[plastic]
    return drift


#: The six stress columns of a 3D result, in the engine's (Voigt) order.
STRESS_NAMES_3D = ("sigma_xx", "sigma_yy", "sigma_zz", "tau_yz", "tau_xz", "tau_xy")


def von_mises_3d(stress: np.ndarray) -> np.ndarray:
    """Equivalent stress of (M, 6) Voigt rows: sqrt(((sxx - syy)^2 + (syy - szz)^2 +
    (szz - sxx)^2) / 2 + 3 (syz^2 + sxz^2 + sxy^2))."""
    sxx, syy, szz, syz, sxz, sxy = np.asarray(stress, dtype=float).reshape(-1, 6).T
    return np.sqrt(
        0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2)
        + 3.0 * (syz**2 + sxz**2 + sxy**2)
    )


def stress_tensor_3d(stress: np.ndarray) -> np.ndarray:
    """(K, 9) the symmetric tensor of (K, 6) Voigt rows, row by row (xx, xy, xz, yx, yy, yz,
    zx, zy, zz: ParaView's 9-component order, unambiguous where 6-component layouts differ
    between readers)."""
    sxx, syy, szz, syz, sxz, sxy = np.asarray(stress, dtype=float).reshape(-1, 6).T
    return np.stack([sxx, sxy, sxz, sxy, syy, syz, sxz, syz, szz], axis=1)


def spherical(nodes: np.ndarray, u: np.ndarray, stress: np.ndarray, tetrahedra: np.ndarray):
    """Radial displacement at the nodes, and (rho, sigma_R, sigma_t) at element centroids, of
    a spherically symmetric state centred at the origin: sigma_R = e_R . sigma e_R and the
    mean tangential stress sigma_t = (tr sigma - sigma_R) / 2."""
    rho_n = np.linalg.norm(nodes, axis=1)
    ur = np.einsum("ij,ij->i", u, nodes) / np.where(rho_n > 0, rho_n, 1.0)
    xc = np.asarray(nodes)[np.asarray(tetrahedra)].mean(axis=1)
    rho = np.linalg.norm(xc, axis=1)
    e = xc / rho[:, None]
    sigma = stress_tensor_3d(stress).reshape(-1, 3, 3)
    sr = np.einsum("ei,eij,ej->e", e, sigma, e)
    return ur, rho, sr, 0.5 * (np.trace(sigma, axis1=1, axis2=2) - sr)


def tetrahedron_volumes(nodes: np.ndarray, tetrahedra: np.ndarray) -> np.ndarray:
    """|det[x1 - x0, x2 - x0, x3 - x0]| / 6 of each tetrahedron."""
    p = np.asarray(nodes)[np.asarray(tetrahedra)]
    return np.abs(np.linalg.det(p[:, 1:] - p[:, :1])) / 6.0


def nodal_stress_3d(nodes: np.ndarray, tetrahedra: np.ndarray, stress: np.ndarray) -> np.ndarray:
    """(N, 6) nodal stresses: the volume-weighted average of the constant element stresses
    around each node (the lumped L2 projection, as :func:`slipstep.output.fields.nodal_stress` in 2D:
    exact for a uniform stress, first order in h)."""
    stress = np.asarray(stress, dtype=float).reshape(-1, 6)
    weight = np.repeat(tetrahedron_volumes(nodes, tetrahedra), 4)
    corner = np.asarray(tetrahedra).ravel()
    total = np.stack(
        [
            np.bincount(corner, weight * np.repeat(column, 4), minlength=len(nodes))
            for column in stress.T
        ],
        axis=1,
    )
    volume = np.bincount(corner, weight, minlength=len(nodes))
    return total / np.where(volume > 0, volume, 1.0)[:, None]
