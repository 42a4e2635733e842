"""Hill's closed form: thick-walled cylinder under internal pressure, plane strain, elastic -
perfectly plastic, von Mises (Hill, The Mathematical Theory of Plasticity, 1950, ch. V).

Bore a, outer radius b, internal pressure p, k = Sy / sqrt(3).  Hill takes sigma_z as the mean
of sigma_r and sigma_theta in the plastic zone (exact for nu = 1/2), so that the yield
condition reads sigma_theta - sigma_r = 2k there:

    elastic-plastic radius c:  p = k [2 ln(c/a) + 1 - c^2/b^2]          (a <= c <= b)
    plastic zone  a <= r <= c: sigma_r = -p + 2k ln(r/a),  sigma_theta = sigma_r + 2k
    elastic zone  c <= r <= b: sigma_r = -k c^2/b^2 (b^2/r^2 - 1),
                               sigma_theta = k c^2/b^2 (b^2/r^2 + 1)
    displacement in the elastic zone (exact for any nu given those stresses):
        u(r) = (1 + nu) k c^2 / (E b^2) [(1 - 2 nu) r + b^2 / r]

Below first yield (p <= k (1 - a^2/b^2)) it is Lame's solution.  With nu < 1/2 the Mises
first-yield pressure is slightly lower (sigma_z = 2 nu A in the elastic solution):
:func:`first_yield_pressure` gives the exact value.
"""

from __future__ import annotations

import math

import numpy as np

from ..derived import centroids


def first_yield_pressure(a: float, b: float, Sy: float, nu: float) -> float:
    """Exact von Mises first yield at the bore (Lame stresses, sigma_z = 2 nu A)."""
    beta = b * b / (a * a)
    # A = p a^2/(b^2 - a^2);  sigma_e(a) = A sqrt(3 beta^2 + (1 - 2 nu)^2)
    return Sy * (b * b - a * a) / (a * a) / math.sqrt(3 * beta ** 2 + (1 - 2 * nu) ** 2)


def plastic_radius(p: float, a: float, b: float, Sy: float) -> float:
    """c with p = k [2 ln(c/a) + 1 - c^2/b^2]; a if p is below Hill's first yield pressure."""
    k = Sy / math.sqrt(3.0)
    if p <= k * (1 - a * a / (b * b)):
        return a
    if p >= 2 * k * math.log(b / a):
        raise ValueError(f"p = {p:g} reaches the limit pressure 2k ln(b/a) = "
                         f"{2 * k * math.log(b / a):g}")
    lo, hi = a, b
    for _ in range(200):  # bisection: the right side increases with c
        c = 0.5 * (lo + hi)
        if k * (2 * math.log(c / a) + 1 - c * c / (b * b)) < p:
            lo = c
        else:
            hi = c
    return 0.5 * (lo + hi)


def stresses(r, p: float, a: float, b: float, Sy: float):
    """(sigma_r, sigma_theta) at radii r."""
    r = np.asarray(r, dtype=float)
    k = Sy / math.sqrt(3.0)
    c = plastic_radius(p, a, b, Sy)
    if c == a:  # Lame
        A = p * a * a / (b * b - a * a)
        return A * (1 - b * b / r ** 2), A * (1 + b * b / r ** 2)
    s = k * c * c / (b * b)
    sr = np.where(r < c, -p + 2 * k * np.log(r / a), -s * (b * b / r ** 2 - 1))
    st = np.where(r < c, sr + 2 * k, s * (b * b / r ** 2 + 1))
    return sr, st


def radial_displacement(r, p: float, a: float, b: float, E: float, nu: float, Sy: float):
    """u(r) in the elastic zone c <= r <= b (Lame below first yield)."""
    r = np.asarray(r, dtype=float)
    c = plastic_radius(p, a, b, Sy)
    if c == a:
        A = p * a * a / (b * b - a * a)
        return (1 + nu) * A / E * ((1 - 2 * nu) * r + b * b / r)
    k = Sy / math.sqrt(3.0)
    return (1 + nu) * k * c * c / (E * b * b) * ((1 - 2 * nu) * r + b * b / r)


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
