"""Small-strain von Mises plasticity with linear isotropic hardening, per element (numpy).

The integration point of a CST is its one cell: every function here works on arrays of M
elements at once.  Components follow the engine (docs/engine_api.md): stresses
(sigma_x, sigma_y, sigma_z, tau_xy), strains (eps_x, eps_y, eps_z, gamma_xy) with the
engineering shear gamma = 2 eps_xy.

Backward-Euler radial return (Simo & Hughes 1998, Box 3.2; de Souza Neto et al. 2008,
§7.3.2) with the consistent (algorithmic) tangent

    C = K 1(x)1 + 2G theta I_dev - 2G theta_bar n(x)n,
    theta = 1 - 3G dgamma / q_trial,  theta_bar = 1/(1 + H/3G) - (1 - theta),

n = s_trial / |s_trial|, yield function q - (Sy + H alpha), alpha = equivalent plastic strain.

Plane strain: d eps_z = 0 and sigma_z follows.  Plane stress: d eps_z is found per element
by a local Newton iteration on sigma_z = 0 (dsigma_z/deps_z = C_zz), and the in-plane
tangent is the static condensation C_ab - C_az C_zb / C_zz.  Axisymmetric: z is the hoop
direction theta and its strain u_r / r is one of the section's four strains
(:class:`.forms.RingSection`), so the full 3D return applies as it is: four components in, the
4 x 4 tangent out.  In space (``plane = "space"``, a 3D scene's tetrahedra) the same return on
the six Voigt components of docs/engine_api.md (x, y, z, yz, xz, xy; engineering shears):
six in, the 6 x 6 tangent out.
"""

from __future__ import annotations

import numpy as np

VOIGT_ONE = np.array([1.0, 1.0, 1.0, 0.0])
IN_PLANE = [0, 1, 3]  # x, y, xy rows/columns of the 4x4 (x, y, z, xy) matrices
ALL = [0, 1, 2, 3]  # the ring's r, z, theta, rz: every row and column
SPACE = [0, 1, 2, 3, 4, 5]  # in 3D: x, y, z, yz, xz, xy


def section_columns(plane: str) -> list[int]:
    """The (x, y, z, xy) components the section's strain carries (its stress conjugates); in
    space all six."""
    return SPACE if plane == "space" else ALL if plane == "axisymmetric" else IN_PLANE


def stress_size(plane: str) -> int:
    """The number of stress components a stress state keeps: 4 in 2D, 6 in space."""
    return 6 if plane == "space" else 4


def lame(E, nu):
    """(K, G, lambda) of arrays E, nu."""
    E, nu = np.asarray(E, float), np.asarray(nu, float)
    G = E / (2.0 * (1.0 + nu))
    lam = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    return lam + 2.0 * G / 3.0, G, lam


def elastic_d4(E, nu, size: int = 4) -> np.ndarray:
    """(M, 4, 4) isotropic elasticity over (x, y, z, xy), engineering shear; ``size`` 6: over
    the Voigt (x, y, z, yz, xz, xy) of space."""
    K, G, lam = lame(E, nu)
    M = np.broadcast(E, nu).size
    D = np.zeros((M, size, size))
    for i in range(3):
        for j in range(3):
            D[:, i, j] = lam
        D[:, i, i] += 2.0 * G
    for k in range(3, size):
        D[:, k, k] = G
    return D


def in_plane_d(E, nu, plane: str) -> np.ndarray:
    """(M, 3, 3) in-plane elastic stiffness (x, y, xy) for plane strain or plane stress."""
    return condense(elastic_d4(E, nu), plane)


def section_d(E, nu, plane: str) -> np.ndarray:
    """(M, n, n) elastic stiffness over the section's strain (:func:`section_columns`)."""
    if plane == "space":
        return elastic_d4(E, nu, 6)
    return elastic_d4(E, nu) if plane == "axisymmetric" else in_plane_d(E, nu, plane)


def condense(C4: np.ndarray, plane: str) -> np.ndarray:
    """The in-plane 3x3 block (plane strain) or its static condensation on sigma_z = 0."""
    C3 = C4[:, IN_PLANE][:, :, IN_PLANE]
    if plane == "strain":
        return C3.copy()
    az = C4[:, IN_PLANE, 2]
    za = C4[:, 2, IN_PLANE]
    return C3 - az[:, :, None] * za[:, None, :] / C4[:, 2, 2][:, None, None]


def von_mises(s4: np.ndarray) -> np.ndarray:
    """Equivalent stress of (M, 4) rows (x, y, z, xy) or (M, 6) Voigt rows of space."""
    s4 = np.asarray(s4)
    normal, shear = s4[:, :3].T, s4[:, 3:]
    sx, sy, sz = normal
    return np.sqrt(
        0.5 * ((sx - sy) ** 2 + (sy - sz) ** 2 + (sz - sx) ** 2) + 3.0 * (shear**2).sum(axis=1)
    )


def radial_return(sig_n, alpha_n, deps4, E, nu, Sy, H):
    """3D radial return for full strain increments ``deps4`` (M, 4): (x, y, z, xy); or (M, 6),
    the Voigt components of space.

    Returns (sigma (M, n), alpha (M,), C4 (M, n, n) consistent tangent, plastic (M,) bool).
    Elements with Sy = inf stay elastic.
    """
    size = np.shape(deps4)[1]
    one = np.concatenate([VOIGT_ONE[:3], np.zeros(size - 3)])  # the trace's components
    K, G, _ = lame(E, nu)
    D = elastic_d4(E, nu, size)
    trial = sig_n + np.einsum("mij,mj->mi", D, deps4)
    p = trial[:, :3].mean(axis=1)
    s = trial - p[:, None] * one
    norm_s = np.sqrt(s[:, 0] ** 2 + s[:, 1] ** 2 + s[:, 2] ** 2 + 2.0 * (s[:, 3:] ** 2).sum(axis=1))
    q = np.sqrt(1.5) * norm_s
    f = q - (Sy + H * alpha_n)
    plastic = f > 1e-12 * Sy
    sig = trial.copy()
    alpha = np.array(alpha_n, dtype=float, copy=True)
    C = D.copy()
    if plastic.any():
        i = np.flatnonzero(plastic)
        Gi, Hi, qi = G[i], H[i], q[i]
        dgamma = f[i] / (3.0 * Gi + Hi)
        theta = 1.0 - 3.0 * Gi * dgamma / qi
        sig[i] = p[i, None] * one + theta[:, None] * s[i]
        alpha[i] += dgamma
        theta_bar = 1.0 / (1.0 + Hi / (3.0 * Gi)) - (1.0 - theta)
        n = s[i] / norm_s[i, None]
        # deviatoric identity in Voigt form (stress <- engineering strain)
        Idev = np.diag([1.0, 1.0, 1.0] + [0.5] * (size - 3)) - np.outer(one, one) / 3.0
        C[i] = (
            K[i, None, None] * np.outer(one, one)
            + 2.0 * Gi[:, None, None] * theta[:, None, None] * Idev
            - 2.0 * Gi[:, None, None] * theta_bar[:, None, None] * n[:, :, None] * n[:, None, :]
        )
    return sig, alpha, C, plastic


def integrate(
    sig_n, alpha_n, deps3, E, nu, Sy, H, plane: str, tol: float = 1e-13, max_iter: int = 30
):
    """Stress update for the section's strain increments: in-plane ``deps3`` (M, 3) =
    (dex, dey, dgxy), or (M, 4) = (der, dez, detheta, dgrz) in axisymmetry, or the six Voigt
    components (M, 6) in space (``plane = "space"``).

    Returns (sigma (M, 4) (space: (M, 6)), alpha (M,), C (M, n, n) consistent tangent over the
    section's strain (in-plane 3 x 3, the ring's 4 x 4, 6 x 6 in space), plastic (M,) bool,
    deps_z (M,)).
    """
    M = len(deps3)
    E = np.broadcast_to(np.asarray(E, float), (M,))
    nu = np.broadcast_to(np.asarray(nu, float), (M,))
    Sy = np.broadcast_to(np.asarray(Sy, float), (M,))
    H = np.broadcast_to(np.asarray(H, float), (M,))
    if plane in ("axisymmetric", "space"):  # the section's strain is all of it
        sig, alpha, C4, plastic = radial_return(
            sig_n, alpha_n, np.asarray(deps3, float), E, nu, Sy, H
        )
        return sig, alpha, C4, plastic, np.asarray(deps3, float)[:, 2]
    deps4 = np.zeros((M, 4))
    deps4[:, IN_PLANE] = deps3
    if plane == "strain":
        sig, alpha, C4, plastic = radial_return(sig_n, alpha_n, deps4, E, nu, Sy, H)
        return sig, alpha, condense(C4, "strain"), plastic, deps4[:, 2]
    # plane stress: find deps_z with sigma_z = 0 (start from the elastic guess)
    K, G, lam = lame(E, nu)
    deps4[:, 2] = -(sig_n[:, 2] + lam * (deps3[:, 0] + deps3[:, 1])) / (lam + 2.0 * G)
    scale = np.maximum(np.where(np.isfinite(Sy), Sy, 0.0), np.abs(sig_n).max(axis=1)) + 1e-300
    for _ in range(max_iter):
        sig, alpha, C4, plastic = radial_return(sig_n, alpha_n, deps4, E, nu, Sy, H)
        r = sig[:, 2]
        if np.all(np.abs(r) <= tol * np.maximum(scale, np.abs(sig).max(axis=1))):
            break
        deps4[:, 2] -= r / C4[:, 2, 2]
    else:
        raise RuntimeError("plane-stress return mapping: sigma_z = 0 not reached")
    sig[:, 2] = 0.0
    return sig, alpha, condense(C4, "stress"), plastic, deps4[:, 2]
