"""Closed-form references: every formula the package and its tests compare results with, each
with its source.  numpy only (``goodman_stick_ratio`` imports scipy when called).

Hertz (Johnson, Contact Mechanics, 1985)
    ``hertz_line`` the cylinder on a rigid flat (§4.3), ``hertz_sphere`` the sphere (§4.2, §3.4),
    ``hertz_pressure`` their elliptical pressure profile, ``effective_modulus`` E*.
Johnson's first yield of a line contact (§4.3, §6.2)
    ``JOHNSON_LINE_YIELD``, ``JOHNSON_LINE_YIELD_DEPTH``.
Huber's axis field below a Hertz sphere (Johnson eq. 3.45)
    ``sphere_axis_stresses``, ``sphere_axis_yield``, ``sphere_axis_compression``.
The rigid flat punch on a half-plane (Johnson ch. 2; Sadowsky 1928)
    ``flat_punch_pressure``.
Lamé and Hill (Hill, The Mathematical Theory of Plasticity, 1950, ch. V)
    the thick-walled cylinder in plane strain ``thick_cylinder_*``; the thick-walled sphere
    ``thick_sphere_*``.
Cattaneo–Mindlin and Mindlin–Deresiewicz (Johnson §7.1–7.3)
    ``cattaneo_traction``, ``line_contact_dissipation``.
Spence's stick zone (Spence 1968, 1975; Goodman 1962)
    ``dundurs_beta``, ``goodman_stick_ratio``, ``spence_stick_ratio`` (the exact coupled
    problem has no closed form: solved by collocation).
Elastic-plastic sphere on a rigid flat (Kogut & Etsion 2002; Jackson & Green 2005)
    ``kogut_etsion_critical``, ``kogut_etsion``, ``jackson_green_critical``,
    ``jackson_green``.

Numerical references that are models of their own: :mod:`slipstep.fenicsx.radial` (the thick
cylinder's exact von Mises answer at any Poisson ratio, which Hill's closed form idealises).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


# --------------------------------------------------------------------------- Hertz
def effective_modulus(E: float, nu: float, plane: str = "strain") -> float:
    """E* of an elastic body on a rigid one: E/(1 − ν²) in plane strain and for a sphere
    (``"axisymmetric"``), E in plane stress."""
    return E if plane == "stress" else E / (1.0 - nu**2)


def hertz_line(
    P: float, R: float, E: float, nu: float, plane: str = "strain"
) -> tuple[float, float]:
    """Contact half-width a and peak pressure p0 of an elastic cylinder (radius R, line load P
    per unit thickness on the full cylinder) on a rigid flat (Johnson §4.3):
    a = √(4PR/(πE*)), p0 = 2P/(πa); a and p0 grow as P^(1/2)."""
    e_star = effective_modulus(E, nu, plane)
    a = math.sqrt(4.0 * P * R / (math.pi * e_star))
    return a, 2.0 * P / (math.pi * a)


def hertz_sphere(P: float, R: float, E: float, nu: float) -> tuple[float, float, float]:
    """Contact radius a, peak pressure p0 and approach δ of an elastic sphere (radius R, total
    force P) on a rigid flat (Johnson §4.2, §3.4): a³ = 3PR/(4E*), p0 = 3P/(2πa²), δ = a²/R,
    E* = E/(1 − ν²); a and p0 grow as P^(1/3), δ as P^(2/3)."""
    e_star = effective_modulus(E, nu)
    a = (3.0 * P * R / (4.0 * e_star)) ** (1.0 / 3.0)
    return a, 3.0 * P / (2.0 * math.pi * a**2), a**2 / R


def hertz_pressure(x, a: float, p0: float) -> np.ndarray:
    """The Hertz pressure p0 √(1 − x²/a²) at distances x from the centre, 0 outside |x| < a."""
    return p0 * np.sqrt(np.clip(1.0 - (np.asarray(x, dtype=float) / a) ** 2, 0.0, None))


#: First yield (von Mises, ν = 0.3) of a frictionless Hertz line contact: p0 = 1.79 Sy, at the
#: depth 0.70 a below the centre (Johnson §4.3, §6.2).
JOHNSON_LINE_YIELD = 1.79
JOHNSON_LINE_YIELD_DEPTH = 0.70


# --------------------------------------------------------------------------- Huber
def sphere_axis_stresses(zeta, nu: float) -> tuple[np.ndarray, np.ndarray]:
    """Huber's stresses on the axis below a Hertz sphere contact (Johnson eq. 3.45), over p0,
    at depths ζ = z/a > 0: σr = σθ = −(1 + ν)(1 − ζ arctan(1/ζ)) + 1/(2(1 + ζ²)),
    σz = −1/(1 + ζ²) (τrz = 0 on the axis)."""
    zeta = np.asarray(zeta, dtype=float)
    sigma_r = -(1.0 + nu) * (1.0 - zeta * np.arctan(1.0 / zeta)) + 0.5 / (1.0 + zeta**2)
    return sigma_r, -1.0 / (1.0 + zeta**2)


def sphere_axis_yield(nu: float) -> tuple[float, float]:
    """(m, z/a): the largest (σr − σz)/p0 along the axis below a Hertz sphere contact and its
    depth.  On the axis σr = σθ and τrz = 0, so the von Mises stress is |σz − σr|
    (:func:`sphere_axis_stresses`); first yield at p0 = Sy/m.  Maximised on a grid of step
    1e-4 a over (0, 2a] (the maximum, 0.62 at 0.48a for ν = 0.3, is smooth: the grid costs
    ~1e-8 relative)."""
    zeta = np.linspace(0.0, 2.0, 20001)[1:]
    sigma_r, sigma_z = sphere_axis_stresses(zeta, nu)
    difference = sigma_r - sigma_z
    k = int(np.argmax(difference))
    return float(difference[k]), float(zeta[k])


def sphere_axis_compression(zeta, nu: float) -> np.ndarray:
    """The shortening, over p0 a/E, of the axis of the half-space from depth ζ = z/a down to
    infinity under the Hertz pressure: −∫_ζ^∞ (σz − 2ν σr) dζ'/p0 from
    :func:`sphere_axis_stresses`, integrated in closed form,
    (1 + ν) [arccot ζ − 2ν (π/4 − G(ζ))], G(ζ) = ζ/2 − (ζ²/2) arccot ζ + (1/2) arctan ζ.
    At ζ = 0 it is the approach of distant points, (1 − ν²) π/2 = δ E/(p0 a)."""
    zeta = np.asarray(zeta, dtype=float)
    arccot = np.arctan2(1.0, zeta)
    g = 0.5 * zeta - 0.5 * zeta**2 * arccot + 0.5 * np.arctan(zeta)
    return (1.0 + nu) * (arccot - 2.0 * nu * (0.25 * math.pi - g))


# --------------------------------------------------------------------------- flat punch
def flat_punch_pressure(x, b: float, P: float) -> np.ndarray:
    """Pressure under a rigid flat punch of half-width b pressed by P (per unit thickness) into
    an elastic half-plane, frictionless (Johnson ch. 2; Sadowsky 1928): P/(π √(b² − x²)),
    singular at the edges |x| = b."""
    x = np.asarray(x, dtype=float)
    return P / (np.pi * np.sqrt(b**2 - x**2))


# --------------------------------------------------------------------------- thick cylinder
# Hill ch. V: bore a, outer radius b, internal pressure p, plane strain, elastic - perfectly
# plastic with k = Sy/√3.  Hill takes σz as the mean of σr and σθ in the plastic zone (exact
# for ν = 1/2), so the yield condition reads σθ − σr = 2k there:
#     elastic-plastic radius c:  p = k [2 ln(c/a) + 1 − c²/b²]          (a <= c <= b)
#     plastic zone  a <= r <= c: σr = −p + 2k ln(r/a),  σθ = σr + 2k
#     elastic zone  c <= r <= b: σr = −k c²/b² (b²/r² − 1),  σθ = k c²/b² (b²/r² + 1)
#     displacement in the elastic zone (exact for any ν given those stresses):
#         u(r) = (1 + ν) k c² / (E b²) [(1 − 2ν) r + b²/r]
# Below first yield (p <= k (1 − a²/b²)) it is Lamé's solution.
def thick_cylinder_pressure(c, a: float, b: float, k: float):
    """Hill: the internal pressure at which the plastic zone reaches radius c,
    k [2 ln(c/a) + 1 − c²/b²]."""
    c = np.asarray(c, dtype=float)
    return k * (2.0 * np.log(c / a) + 1.0 - c**2 / b**2)


def thick_cylinder_radius(p, a: float, b: float, k: float):
    """Inverse of :func:`thick_cylinder_pressure` (increasing on [a, b]: dp/dc =
    2k (1/c − c/b²) > 0): c(p), a while elastic (p <= k (1 − a²/b²)); a pressure at or beyond
    the limit 2k ln(b/a) is a ValueError."""
    limit = 2.0 * k * math.log(b / a)
    if np.any(np.asarray(p) >= limit):
        raise ValueError(f"p = {np.max(p):g} reaches the limit pressure 2k ln(b/a) = {limit:g}")
    c = _increasing_inverse(lambda c: thick_cylinder_pressure(c, a, b, k), p, a, b)
    return np.where(np.asarray(p) <= k * (1.0 - a * a / (b * b)), a, c)[()]


def thick_cylinder_first_yield(a: float, b: float, Sy: float, nu: float) -> float:
    """The exact von Mises first-yield pressure at the bore (Lamé's stresses, σz = 2νA with
    A = p a²/(b² − a²): σe(a) = A √(3 β² + (1 − 2ν)²), β = b²/a²); slightly below Hill's
    k (1 − a²/b²) for ν < 1/2."""
    beta = b * b / (a * a)
    return Sy * (b * b - a * a) / (a * a) / math.sqrt(3 * beta**2 + (1 - 2 * nu) ** 2)


def thick_cylinder_stresses(r, p: float, a: float, b: float, Sy: float):
    """(σr, σθ) at radii r (Hill; Lamé below first yield)."""
    r = np.asarray(r, dtype=float)
    k = Sy / math.sqrt(3.0)
    c = thick_cylinder_radius(p, a, b, k)
    if c == a:  # Lamé
        A = p * a * a / (b * b - a * a)
        return A * (1 - b * b / r**2), A * (1 + b * b / r**2)
    s = k * c * c / (b * b)
    sr = np.where(r < c, -p + 2 * k * np.log(r / a), -s * (b * b / r**2 - 1))
    st = np.where(r < c, sr + 2 * k, s * (b * b / r**2 + 1))
    return sr, st


def thick_cylinder_displacement(r, p: float, a: float, b: float, E: float, nu: float, Sy: float):
    """u(r) in the elastic zone c <= r <= b (Hill; Lamé below first yield)."""
    r = np.asarray(r, dtype=float)
    k = Sy / math.sqrt(3.0)
    c = thick_cylinder_radius(p, a, b, k)
    if c == a:
        A = p * a * a / (b * b - a * a)
        return (1 + nu) * A / E * ((1 - 2 * nu) * r + b * b / r)
    return (1 + nu) * k * c * c / (E * b * b) * ((1 - 2 * nu) * r + b * b / r)


def _increasing_inverse(increasing, value, lo: float, hi: float):
    """x in [lo, hi] with increasing(x) = value (lo where value <= increasing(lo)), by
    bisection: 100 halvings, to round-off; ``value`` may be an array."""
    value = np.asarray(value, dtype=float)
    lo, hi = np.full(value.shape, float(lo)), np.full(value.shape, float(hi))
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        below = increasing(mid) < value
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    x = 0.5 * (lo + hi)
    return float(x) if x.ndim == 0 else x


# --------------------------------------------------------------------------- thick sphere
def thick_sphere_lame(rho, p: float, a: float, b: float) -> tuple[np.ndarray, np.ndarray]:
    """Lamé's elastic sphere a <= ρ <= b under internal pressure p: (σ_R, σ_t) at the spherical
    radius ρ, σ_R = −p (b³/ρ³ − 1)/(b³/a³ − 1), σ_t = σθ = σφ = p (b³/(2ρ³) + 1)/(b³/a³ − 1)."""
    rho = np.asarray(rho, dtype=float)
    k = b**3 / a**3 - 1.0
    return -p * (b**3 / rho**3 - 1.0) / k, p * (0.5 * b**3 / rho**3 + 1.0) / k


def thick_sphere_displacement(rho, p: float, a: float, b: float, E: float, nu: float) -> np.ndarray:
    """Lamé's radial displacement: p a³/(E (b³ − a³)) [(1 − 2ν) ρ + (1 + ν) b³/(2ρ²)]."""
    rho = np.asarray(rho, dtype=float)
    return p * a**3 / (E * (b**3 - a**3)) * ((1 - 2 * nu) * rho + (1 + nu) * b**3 / (2 * rho**2))


def thick_sphere_pressure(c, a: float, b: float, Y: float):
    """Hill (ch. V): internal pressure at which the plastic zone of a thick sphere (von Mises =
    Tresca here: σθ = σφ) reaches radius c: 2Y ln(c/a) + (2Y/3)(1 − c³/b³).  At c = a it is the
    elastic limit p_e = (2Y/3)(1 − a³/b³), at c = b the limit 2Y ln(b/a)."""
    c = np.asarray(c, dtype=float)
    return 2.0 * Y * np.log(c / a) + 2.0 * Y / 3.0 * (1.0 - c**3 / b**3)


def thick_sphere_radius(p, a: float, b: float, Y: float):
    """Inverse of :func:`thick_sphere_pressure` on [a, b] (increasing: dp/dc =
    2Y (1/c − c²/b³) > 0); ``p`` may be an array."""
    return _increasing_inverse(lambda c: thick_sphere_pressure(c, a, b, Y), p, a, b)


def thick_sphere_plastic_radius(p: float, a: float, b: float, Y: float) -> float:
    """Hill's plastic radius c at the pressure p: a while the sphere is elastic (p <= p_e)."""
    return float(thick_sphere_radius(p, a, b, Y)) if p > thick_sphere_pressure(a, a, b, Y) else a


def thick_sphere_stresses(rho, p: float, a: float, b: float, Y: float):
    """(σ_R, σ_t) at spherical radii ρ (Hill, ch. V; Lamé below the elastic limit): in the
    plastic zone a <= ρ <= c, σ_R = −p + 2Y ln(ρ/a) and σ_t = σ_R + Y; outside it Lamé's
    shell c <= ρ <= b under the pressure p_c = (2Y/3)(1 − c³/b³) that yields it at c."""
    rho = np.asarray(rho, dtype=float)
    c = thick_sphere_plastic_radius(p, a, b, Y)
    if c == a:
        return thick_sphere_lame(rho, p, a, b)
    er, et = thick_sphere_lame(rho, float(thick_sphere_pressure(c, c, b, Y)), c, b)
    plastic_r = -p + 2.0 * Y * np.log(rho / a)
    return np.where(rho < c, plastic_r, er), np.where(rho < c, plastic_r + Y, et)


def thick_sphere_outer_displacement(
    p: float, a: float, b: float, E: float, nu: float, Y: float
) -> float:
    """The radial displacement of the outer surface ρ = b (Hill; Lamé below the elastic
    limit): Lamé's of the elastic shell c <= ρ <= b under p_c (:func:`thick_sphere_stresses`)."""
    c = thick_sphere_plastic_radius(p, a, b, Y)
    p_c = p if c == a else float(thick_sphere_pressure(c, c, b, Y))
    return float(thick_sphere_displacement(b, p_c, c, b, E, nu))


# --------------------------------------------------------------------------- Cattaneo-Mindlin
def cattaneo_traction(x, a: float, c: float, p0: float, mu: float) -> np.ndarray:
    """Cattaneo–Mindlin shear of a Hertz line contact (Johnson §7.1, the cylinder; half-width
    a, peak pressure p0, stick zone |x| < c, c/a = √(1 − Q/(μP))):
    q = μ p0 [√(1 − x²/a²) − (c/a) √(1 − x²/c²)] in the stick zone, μ p(x) in the slip zones,
    0 outside the contact."""
    x = np.asarray(x, dtype=float)
    full = mu * p0 * np.sqrt(np.clip(1.0 - (x / a) ** 2, 0.0, None))
    stick = mu * p0 * (c / a) * np.sqrt(np.clip(1.0 - (x / c) ** 2, 0.0, None))
    return full - np.where(np.abs(x) < c, stick, 0.0)


# The energy a Hertz line contact of two equal bodies (β = 0: shear and pressure uncoupled)
# dissipates per cycle of tangential load ±Q*, the planar analogue of Mindlin–Deresiewicz
# (Johnson §7.3 for the sphere), derived here.  One half-plane under a surface shear q has
# ∂u_x/∂x = −(K/π) PV∫ q(s)/(x − s) ds, K = 2(1 − ν²)/E (Johnson eq. 2.25; plane strain); an
# elliptical shear of total F over half-width b moves its centre by (K F/π)(ln(d/b) + C)
# against a point at distance d ≫ b.  Cattaneo's q is such a shear μP over a minus one of
# μP (c/a)² over c, and the stick zone moves rigidly, so the relative displacement of the two
# bodies there (2K, two equal bodies) is linear in Q (the d and C terms: elastic) plus
#     δ(Q) = (2K μP/(2π)) (1 − r) ln(1 − r),   r = Q/(μP),   ((c/a)² = 1 − r),
# convex in Q.  Unloading follows Masing (Mindlin & Deresiewicz's superposition:
# δ_unload(Q) = δ(Q*) − 2 δ((Q* − Q)/2)), so the loop's area is
#     W = 4 ∫_0^{Q*} [δ(Q*) − δ(u) − δ(Q* − u)] du
#       = (4 K (μP)²/π) [(1 − r*) ln(1 − r*) + r* − r*²/2],   r* = Q*/(μP),
# linear terms cancelling; for small r* W ≈ 2 K Q*³/(3π μP), cubic as for the sphere.
def line_contact_dissipation(P: float, Q_star: float, mu: float, E: float, nu: float) -> float:
    """W per cycle ±Q* (per unit thickness) of a line contact of two equal elastic bodies
    pressed by P (plane strain), from the derivation above."""
    K, F = 2.0 * (1.0 - nu**2) / E, mu * P
    r = Q_star / F
    return 4.0 * K * F**2 / math.pi * ((1.0 - r) * math.log1p(-r) + r - 0.5 * r * r)


# --------------------------------------------------------------------------- Spence
#
# The problem (2D, half-plane theory, Johnson's Contact Mechanics ch. 2 and 5): an elastic
# half-plane (compliance A = 2(1−ν²)/E per unit load, Dundurs' β) indented by a rigid profile,
# contact |x| < a, pressure p, shear q.  Surface displacements (z into the body):
#     u_z(x) = −(A/π) ∫ p(s) ln|x − s| ds + (βA/2) ∫ q(s) sgn(x − s) ds
#     u_x(x) = −(A/π) ∫ q(s) ln|x − s| ds − (βA/2) ∫ p(s) sgn(x − s) ds
# (the sgn terms: a normal line load pulls surface points towards it, Johnson ch. 2, line
# loading of a half-space; the sign of the other is fixed by reciprocity).  Under monotonic
# loading of a Hertz profile the solution is self-similar (Spence 1968, Proc. R. Soc. A 305,
# 55-80; 1975, J. Elasticity 5, 297-319): the stick zone |x| < c grows with a at a fixed ratio
# c/a, and the rates ṗ = ∂p/∂a, q̇ = ∂q/∂a at fixed x solve a flat-punch problem (∂/∂a of the
# profile term x/R vanishes): u̇_z = const on |x| < a, u̇_x = 0 in the stick zone,
# q̇ = μ ṗ sgn(x) in the slip zones c < |x| < a (friction on the body points outwards: the
# body's surface moves inwards).  c/a is the one for which q̇ stays bounded at ±c; it depends
# on μ and β only.
#
# Goodman's approximation drops β q from u_z (ṗ is then the flat-punch 1/√(a²−x²)); with
# q̇ = μ sgn(x) ṗ + q*, q* supported on the stick zone, the stick condition is a finite Hilbert
# transform equation for q* on (−c, c) whose solution is bounded at both ends only if its
# right-hand side g has ∫ g/√(c²−x²) dx = 0 (a = 1, k = √(1−x²)):
#     g = −β/k + (μ/(πk)) ln((1−k)/(1+k)),   ∫_0^c dx/(k√(c²−x²)) = K(c),
#     ∫_0^c ln((1+k)/(1−k)) dx/(k√(c²−x²)) = π K'(c)   (checked numerically to 1e-10),
# so that
#     β/μ = K'(c/a) / K(c/a)          (K complete elliptic integral of the 1st kind, modulus c/a).
# Its limits: c/a → 0 as μ/β → 0, c/a ≈ 4 exp(−πβ/(2μ)); c/a → 1 only as μ/β → ∞,
# √(1 − (c/a)²) ≈ 4 exp(−πμ/(2β)); self-dual: c(β/μ)² + c(μ/β)² = 1, c = 1/√2 at μ = β.
# The exact (coupled) problem is a vector Riemann-Hilbert problem without an elementary closed
# form; ``spence_stick_ratio`` solves it by collocation (piecewise-constant tractions, the
# kernels above integrated exactly over each panel, the stick zone found by bisection on its
# number of panels), and with ``coupled=False`` reproduces the closed form (a check of the
# solver, tests/physics/test_spence.py).
def dundurs_beta(nu: float, plane: str = "strain") -> float:
    """Dundurs' β of an elastic body (ν) against a rigid one: (1 − 2ν)/(2(1 − ν)) in plane
    strain; plane stress is plane strain with ν/(1 + ν), giving (1 − ν)/2."""
    if plane == "stress":
        nu = nu / (1.0 + nu)
    return (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu))


def _elliptic_ratio(k: float) -> float:
    """K'(k)/K(k) for the modulus k in (0, 1), accurate near both ends."""
    from scipy.special import ellipkm1

    kp2 = (1.0 - k) * (1.0 + k)  # k'² without cancellation
    return float(ellipkm1(k * k) / ellipkm1(kp2))  # K(m = 1 − k²) / K(m = k²)


def goodman_stick_ratio(beta_over_mu: float) -> float:
    """c/a from β/μ = K'(c/a)/K(c/a) (Goodman's approximation), by bisection (brentq)."""
    from scipy.optimize import brentq

    if beta_over_mu <= 0:
        return 1.0
    return float(
        brentq(
            lambda k: _elliptic_ratio(k) - beta_over_mu, 1e-300, 1.0 - 1e-16, xtol=1e-15, rtol=1e-14
        )
    )


def _panel_log(x, s1, s2):
    """−(1/π) ∫_{s1}^{s2} ln|x − s| ds."""

    def F(t):
        at = np.abs(t)
        return np.where(at > 0, t * np.log(np.where(at > 0, at, 1.0)) - t, 0.0)

    return -(F(x - s1) - F(x - s2)) / math.pi


def _panel_sign(x, s1, s2):
    """(1/2) ∫_{s1}^{s2} sgn(x − s) ds."""
    return 0.5 * (np.abs(x - s1) - np.abs(x - s2))


def spence_stick_ratio(mu: float, beta: float, panels: int = 1000, coupled: bool = True) -> float:
    """c/a of the self-similar frictional Hertz line contact (the flat-punch rate problem
    above), by collocation with ``panels`` equal panels on 0 < x < a = 1 (p even, q odd).
    The stick zone is located to one panel: the result is the panel edge between the last stick
    and the first slip panel (resolution 1/panels of a)."""
    e = np.linspace(0.0, 1.0, panels + 1)
    x = 0.5 * (e[1:] + e[:-1])[:, None]
    s1, s2 = e[None, :-1], e[None, 1:]
    log_p = _panel_log(x, s1, s2) + _panel_log(x, -s2, -s1)  # even density on both halves
    log_q = _panel_log(x, s1, s2) - _panel_log(x, -s2, -s1)  # odd density
    sgn_p = _panel_sign(x, s1, s2) + _panel_sign(x, -s2, -s1)
    sgn_q = _panel_sign(x, s1, s2) - _panel_sign(x, -s2, -s1)
    kernels = {
        "uz_p": log_p,
        "uz_q": beta * sgn_q if coupled else 0.0 * sgn_q,
        "ux_p": -beta * sgn_p,
        "ux_q": log_q,
        "length": np.diff(e),
    }

    # Bisection on the number k of stick panels: too many and q̇ exceeds the cone outwards at
    # the stick edge (the square-root singularity of an oversized stick zone), too few and q̇
    # turns inwards there while the slip next to it runs against its friction.
    lo, hi = 0, panels  # invariant: k <= lo is too small (or 0), k >= hi too large (or n)
    while hi - lo > 1:
        mid = (lo + hi) // 2
        over, against = _stick_slip_rates(kernels, mu, mid)
        if over and against:
            raise RuntimeError(f"spence_stick_ratio: no consistent stick zone near {mid}/{panels}")
        if over:
            hi = mid
        elif against:
            lo = mid
        else:
            lo = hi = mid
    if any(_stick_slip_rates(kernels, mu, lo)):
        raise RuntimeError("spence_stick_ratio: the stick/slip set is not consistent")
    return float(e[lo])


def _stick_slip_rates(kernels: dict, mu: float, k: int) -> tuple[bool, bool]:
    """Solve the rate problem with the first k panels sticking and the others slipping
    (q = μ p: friction on the body outwards); returns (a stick panel beyond the cone
    outwards, a slip panel slipping against its friction)."""
    uz_p, uz_q, ux_p, ux_q = (kernels[n] for n in ("uz_p", "uz_q", "ux_p", "ux_q"))
    n = len(uz_p)
    stick = np.arange(n) < k
    M = np.zeros((2 * n + 1, 2 * n + 1))
    rhs = np.zeros(2 * n + 1)
    M[:n, :n], M[:n, n : 2 * n], M[:n, 2 * n] = uz_p, uz_q, -1.0  # u_z = rigid approach
    M[n : 2 * n, :n] = np.where(stick[:, None], ux_p, 0.0)  # stick: u_x = 0
    M[n : 2 * n, n : 2 * n] = np.where(stick[:, None], ux_q, 0.0)
    slip = np.flatnonzero(~stick)  # slip: q = μ p
    M[n + slip, n + slip] = 1.0
    M[n + slip, slip] = -mu
    M[2 * n, :n] = 2.0 * kernels["length"]  # total load 1
    rhs[2 * n] = 1.0
    sol = np.linalg.solve(M, rhs)
    p, q = sol[:n], sol[n : 2 * n]
    ux = ux_p @ p + ux_q @ q
    return bool(np.any(q[stick] > mu * p[stick])), bool(np.any(ux[~stick] > 0))


# --------------------------------------------------------------------------- sphere on a flat
# The published elastic-plastic sphere-on-rigid-flat fits: force P and contact area A against
# the interference ω (the flat's approach to the base of the hemisphere), frictionless, the
# sphere elastic-perfectly plastic (von Mises), in units of their values at first yield; E* =
# E/(1 − ν²) for a deformable sphere on a rigid flat, Y the yield strength.  The formulas carry
# over from the papers (checked against their openings in the public record and against
# independent public implementations of both models); the code here is the project's own.
#
# Kogut & Etsion (2002), "Elastic-plastic contact analysis of a sphere and a rigid flat",
# J. Appl. Mech. 69: 657-662 (finite elements, a deformable sphere pressed by a rigid flat):
#     ω_c = (π K H / (2 E*))² R,   K = 0.454 + 0.41 ν,   H = 2.8 Y        (first yield)
#     P_c = (2/3) π K H R ω_c  (= Hertz's (4/3) E* R^(1/2) ω_c^(3/2)),  A_c = π R ω_c
#     w = ω/ω_c < 1 (Hertz):  P/P_c = w^(3/2),          A/A_c = w
#     1 <= w <= 6:            P/P_c = 1.03 w^1.425,     A/A_c = 0.93 w^1.136
#     6 <= w <= 110:          P/P_c = 1.40 w^1.263,     A/A_c = 0.94 w^1.146
#
# Jackson & Green (2005), "A finite element study of elasto-plastic hemispherical contact
# against a rigid flat", J. Tribol. 127: 343-354 (elastic-perfectly plastic hemisphere):
#     ω_c = (π C Y / (2 E*))² R,   C = 1.295 exp(0.736 ν)
#     P_c = (4/3) (R/E*)² (C π Y / 2)³,   A_c = π R ω_c
#     w < 1.9 (Hertz):  P/P_c = w^(3/2),   A/A_c = w
#     w >= 1.9:         A/A_c = w (w/1.9)^B,   B = 0.14 exp(23 Y/E*)
#                       P/P_c = exp(−w^(5/12)/4) w^(3/2) + (4 H_G / (C Y)) (1 − exp(−w^(5/9)/25)) w
#                       H_G / Y = 2.84 (1 − exp(−0.82 (a/R)^(−0.7))),  a = √(A/π)
#                       (the hardness-geometry limit: the mean pressure of the fully plastic
#                       contact falls below 2.84 Y as the contact radius grows against R)

#: Largest w = ω/ω_c of Kogut & Etsion's elastic-plastic fits (fully plastic beyond).
KE_MAX = 110.0
#: Jackson & Green's switch from Hertz to their elastic-plastic fits.
JG_SWITCH = 1.9


@dataclass(frozen=True)
class Critical:
    """The first-yield values a fit is normalised by."""

    interference: float  # ω_c
    force: float  # P_c
    area: float  # A_c


def kogut_etsion_critical(R: float, E_star: float, Y: float, nu: float) -> Critical:
    KH = (0.454 + 0.41 * nu) * 2.8 * Y
    w_c = (math.pi * KH / (2.0 * E_star)) ** 2 * R
    return Critical(w_c, 2.0 / 3.0 * math.pi * KH * R * w_c, math.pi * R * w_c)


def kogut_etsion(w) -> tuple[np.ndarray, np.ndarray]:
    """(P/P_c, A/A_c) at w = ω/ω_c (0 <= w <= 110)."""
    w = np.asarray(w, dtype=float)
    if np.any(w > KE_MAX) or np.any(w < 0):
        raise ValueError(f"Kogut & Etsion's fits cover 0 <= omega/omega_c <= {KE_MAX:g}")
    P = np.where(w < 1, w**1.5, np.where(w <= 6, 1.03 * w**1.425, 1.40 * w**1.263))
    A = np.where(w < 1, w, np.where(w <= 6, 0.93 * w**1.136, 0.94 * w**1.146))
    return P, A


def jackson_green_critical(R: float, E_star: float, Y: float, nu: float) -> Critical:
    C = 1.295 * math.exp(0.736 * nu)
    w_c = (math.pi * C * Y / (2.0 * E_star)) ** 2 * R
    P_c = 4.0 / 3.0 * (R / E_star) ** 2 * (C * math.pi * Y / 2.0) ** 3
    return Critical(w_c, P_c, math.pi * R * w_c)


def jackson_green(w, R: float, E_star: float, Y: float, nu: float):
    """(P/P_c, A/A_c) at w = ω/ω_c (w >= 0)."""
    w = np.asarray(w, dtype=float)
    C = 1.295 * math.exp(0.736 * nu)
    B = 0.14 * math.exp(23.0 * Y / E_star)
    plastic = w >= JG_SWITCH
    A = np.where(plastic, w * (w / JG_SWITCH) ** B, w)
    a = np.sqrt(A * jackson_green_critical(R, E_star, Y, nu).area / math.pi)
    hardness = 2.84 * Y * (1.0 - np.exp(-0.82 * np.maximum(a / R, 1e-300) ** -0.7))
    P_plastic = (
        np.exp(-0.25 * w ** (5.0 / 12.0)) * w**1.5
        + 4.0 * hardness / (C * Y) * (1.0 - np.exp(-(w ** (5.0 / 9.0)) / 25.0)) * w
    )
    return np.where(plastic, P_plastic, w**1.5), A
