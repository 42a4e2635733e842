"""The thick-walled cylinder's exact von Mises answer at any Poisson ratio: a fine 1D radial
model, the reference Hill's closed form (:mod:`slipstep.measures.references`) approximates.

Hill's closed form takes sigma_z as the mean of sigma_r and sigma_theta in the plastic zone,
which is exact only for an incompressible material (nu = 1/2).  With nu < 1/2 von Mises in
plane strain has no closed form (Hill, ch. V, integrates it numerically); here it is the
axisymmetric plane-strain problem in r alone, solved to convergence:

    equilibrium (virtual work per radian):  int (sigma_r d(eps_r) + sigma_theta d(eps_theta)) r dr
                                            = p a du(a)
    strains:  eps_r = du/dr,  eps_theta = u/r,  eps_z = 0
    material: isotropic elastic, von Mises perfectly plastic, backward-Euler radial return
              (sigma_r, sigma_theta, sigma_z tracked) with its consistent tangent

Linear elements graded towards the bore, two Gauss points each, Newton in every one of
``n_steps`` equal pressure steps.  The elastic-plastic radius c follows from u(b): the
elastic zone c <= r <= b carries Lame's stresses, so u(b) fixes them, and c is where they
reach the yield surface (:meth:`_Model.plastic_radius`).

numpy only (a tridiagonal solve): independent of the engine, its mesh and its integrator.

    >>> from slipstep.fenicsx import radial
    >>> ref = radial.solve(a=10, b=20, E=2e5, nu=0.3, Sy=250, pressures=[150, 175])
    >>> ref.c            # mm; Hill's closed form: 13.27 and 14.42   # doctest: +SKIP
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: Elements and pressure steps of the default model (0.2 s): c within 2e-5 mm and u(b) within
#: 3e-6 of the model with 16x the elements and 4x the steps, at the shipped case's pressures.
N_ELEMENTS, N_STEPS = 400, 100
#: Newton stops when the residual is below this × p_max a (the round-off floor of the r-weighted
#: system is ~1e-9 of it) or after MAX_NEWTON iterations (then an error).
NEWTON_TOL, MAX_NEWTON = 1e-8, 50
_GAUSS = np.array([-1.0, 1.0]) / math.sqrt(3.0)


@dataclass
class RadialSolution:
    """At each requested pressure: the plastic radius c (a while elastic) and u at r = a, b."""

    pressures: np.ndarray
    c: np.ndarray
    u_bore: np.ndarray
    u_outer: np.ndarray

    def __repr__(self) -> str:
        rows = ", ".join(f"p {p:g}: c {c:.4f}" for p, c in zip(self.pressures, self.c))
        return f"RadialSolution({rows})"


def solve(
    a: float,
    b: float,
    E: float,
    nu: float,
    Sy: float,
    pressures,
    n_elements: int = N_ELEMENTS,
    n_steps: int = N_STEPS,
) -> RadialSolution:
    """Load monotonically to max(pressures) in ``n_steps`` equal steps (each requested
    pressure is hit exactly: the steps are refined to pass through them)."""
    pressures = np.sort(np.asarray(pressures, dtype=float))
    model = _Model(a, b, E, nu, Sy, n_elements)
    steps = np.linspace(0.0, pressures[-1], n_steps + 1)[1:]
    near = np.abs(steps[:, None] - pressures[None, :]).min(axis=1) <= 1e-9 * pressures[-1]
    path = [(p, False) for p in steps[~near]] + [(p, True) for p in pressures]
    out = {k: [] for k in ("c", "u_bore", "u_outer")}
    for p, requested in sorted(path):
        model.step_to(p, NEWTON_TOL * pressures[-1] * a)
        if requested:
            out["c"].append(model.plastic_radius())
            out["u_bore"].append(model.u[0])
            out["u_outer"].append(model.u[-1])
    return RadialSolution(pressures, *(np.array(out[k]) for k in ("c", "u_bore", "u_outer")))


class _Model:
    """The 1D model's state: nodal u, Gauss-point stresses (r, theta, z) and plastic flags."""

    def __init__(self, a, b, E, nu, Sy, n):
        self.a, self.r_outer, self.E, self.nu, self.Sy = a, b, E, nu, Sy
        self.G, self.K = E / (2 * (1 + nu)), E / (3 * (1 - 2 * nu))
        r = a + (b - a) * np.linspace(0.0, 1.0, n + 1) ** 2  # graded: fine at the bore
        length = np.diff(r)
        xi = (_GAUSS[None, :] + 1) / 2
        self.r = r[:-1, None] + length[:, None] * xi  # Gauss radii (n, 2)
        self.w = length[:, None] / 2 * self.r  # r dr weights
        self.B = np.zeros((n, 2, 3, 2))  # eps (r, theta, z) per node
        self.B[..., 0, 0], self.B[..., 0, 1] = -1 / length[:, None], 1 / length[:, None]
        self.B[..., 1, 0], self.B[..., 1, 1] = (1 - xi) / self.r, xi / self.r
        self.u = np.zeros(n + 1)
        self.stress = np.zeros((n, 2, 3))
        self.plastic = np.zeros((n, 2), dtype=bool)

    def step_to(self, p: float, tol: float) -> None:
        du = np.zeros_like(self.u)
        f = np.zeros_like(self.u)
        f[0] = p * self.a
        for _ in range(MAX_NEWTON):
            strain = np.einsum("egij,ej->egi", self.B, _pairs(du))
            stress, tangent, plastic = self._return_map(strain)
            residual = f - _scatter(np.einsum("egij,egi,eg->ej", self.B, stress, self.w), len(f))
            if np.abs(residual).max() <= tol:
                self.u += du
                self.stress, self.plastic = stress, plastic
                return
            k = np.einsum("egia,egij,egjb,eg->eab", self.B, tangent, self.B, self.w)
            du += _tridiagonal_solve(k, residual)
        raise RuntimeError(f"the radial model did not converge at p = {p:g}")

    def _return_map(self, strain):
        """Radial return from the last converged stress over a strain increment, and the
        consistent tangent K 1x1 + 2G theta (I - 1x1/3) - 2G theta n x n (plastic points)."""
        one, eye = np.ones(3), np.eye(3)
        dev = eye - np.outer(one, one) / 3
        trial = self.stress + self.K * strain.sum(-1, keepdims=True) + 2 * self.G * (strain @ dev)
        mean = trial.mean(-1, keepdims=True)
        s = trial - mean
        q = np.sqrt(1.5 * (s**2).sum(-1))
        plastic = q > self.Sy
        theta = np.where(plastic, self.Sy / np.maximum(q, 1e-300), 1.0)
        n = s / np.maximum(np.sqrt((s**2).sum(-1)), 1e-300)[..., None]
        tangent = (
            self.K * np.outer(one, one)
            + 2 * self.G * theta[..., None, None] * dev
            - (2 * self.G * theta * plastic)[..., None, None] * n[..., :, None] * n[..., None, :]
        )
        return mean + s * theta[..., None], tangent, plastic

    def plastic_radius(self) -> float:
        """c from the elastic zone c <= r <= b, which carries Lame's stresses with
        sigma_r(b) = 0 and sigma_z = nu (sigma_r + sigma_theta) (no plastic strain there):
            sigma_r, sigma_theta = B (1/b^2 -+ 1/r^2),  u(b) = 2 (1 + nu)(1 - nu) B / (E b),
        so B follows from u(b), and the front is where von Mises reaches Sy:
            3 B^2 / c^4 + (1 - 2 nu)^2 B^2 / b^4 = Sy^2.
        (u(b) converges much faster than any front read from the Gauss points.)"""
        if not self.plastic.any():
            return self.a
        b, nu = self.r_outer, self.nu
        B = self.E * self.u[-1] * b / (2 * (1 + nu) * (1 - nu))
        return float((3 * B * B / (self.Sy**2 - ((1 - 2 * nu) * B / b**2) ** 2)) ** 0.25)


def _pairs(u: np.ndarray) -> np.ndarray:
    """Nodal values per element (n, 2)."""
    return np.stack([u[:-1], u[1:]], axis=1)


def _scatter(fe: np.ndarray, n: int) -> np.ndarray:
    f = np.zeros(n)
    f[:-1] += fe[:, 0]
    f[1:] += fe[:, 1]
    return f


def _tridiagonal_solve(ke: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """Solve the assembled tridiagonal system of 2-node element matrices (Thomas algorithm;
    the matrix is SPD, no pivoting needed)."""
    n = rhs.size
    diag = np.zeros(n)
    diag[:-1] += ke[:, 0, 0]
    diag[1:] += ke[:, 1, 1]
    off = ke[:, 0, 1].tolist()
    d, y = diag.tolist(), rhs.tolist()
    for i in range(1, n):
        m = off[i - 1] / d[i - 1]
        d[i] -= m * off[i - 1]
        y[i] -= m * y[i - 1]
    x = [0.0] * n
    x[-1] = y[-1] / d[-1]
    for i in range(n - 2, -1, -1):
        x[i] = (y[i] - off[i] * x[i + 1]) / d[i]
    return np.array(x)
