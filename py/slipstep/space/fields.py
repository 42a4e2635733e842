"""The stress field of a 3D result (docs/engine_api.md: ``stress`` (M, 6) in Voigt order
sigma_xx, sigma_yy, sigma_zz, sigma_yz, sigma_xz, sigma_xy): von Mises, the full tensor for
ParaView, and nodal averages (numpy only).  The 3D counterpart of :mod:`slipstep.fields`."""

from __future__ import annotations

import numpy as np

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
    around each node (the lumped L2 projection, as :func:`slipstep.fields.nodal_stress` in 2D:
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
