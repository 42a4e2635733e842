"""The published elastic-plastic sphere-on-rigid-flat fits: force P and contact area A against
the interference omega (the flat's approach to the base of the hemisphere), frictionless, the
sphere elastic-perfectly plastic (von Mises), in units of their values at first yield.

Kogut & Etsion (2002), "Elastic-plastic contact analysis of a sphere and a rigid flat",
J. Appl. Mech. 69: 657-662 (finite elements, a deformable sphere pressed by a rigid flat):

    omega_c = (pi K H / (2 E*))^2 R,   K = 0.454 + 0.41 nu,   H = 2.8 Y        (first yield)
    P_c = (2/3) pi K H R omega_c  (= Hertz's (4/3) E* R^(1/2) omega_c^(3/2)),  A_c = pi R omega_c
    w = omega/omega_c < 1 (Hertz):  P/P_c = w^(3/2),          A/A_c = w
    1 <= w <= 6:                    P/P_c = 1.03 w^1.425,     A/A_c = 0.93 w^1.136
    6 <= w <= 110:                  P/P_c = 1.40 w^1.263,     A/A_c = 0.94 w^1.146

Jackson & Green (2005), "A finite element study of elasto-plastic hemispherical contact
against a rigid flat", J. Tribol. 127: 343-354 (elastic-perfectly plastic hemisphere):

    omega_c = (pi C Y / (2 E*))^2 R,   C = 1.295 exp(0.736 nu)
    P_c = (4/3) (R/E*)^2 (C pi Y / 2)^3,   A_c = pi R omega_c
    w < 1.9 (Hertz):  P/P_c = w^(3/2),   A/A_c = w
    w >= 1.9:         A/A_c = w (w/1.9)^B,   B = 0.14 exp(23 Y/E*)
                      P/P_c = exp(-w^(5/12)/4) w^(3/2)
                              + (4 H_G / (C Y)) (1 - exp(-w^(5/9)/25)) w
                      H_G / Y = 2.84 (1 - exp(-0.82 (a/R)^(-0.7))),  a = sqrt(A/pi)
                      (the hardness-geometry limit: the mean pressure of the fully plastic
                      contact falls below 2.84 Y as the contact radius grows against R)

E* = E/(1 - nu^2) for a deformable sphere on a rigid flat; Y the yield strength.  The formulas
carry over from the papers (checked against their openings in the public record and against
independent public implementations of both models); the code here is the project's own.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: Largest w = omega/omega_c of Kogut & Etsion's elastic-plastic fits (fully plastic beyond).
KE_MAX = 110.0
#: Jackson & Green's switch from Hertz to their elastic-plastic fits.
JG_SWITCH = 1.9


@dataclass(frozen=True)
class Critical:
    """The first-yield values a fit is normalised by."""

    interference: float   # omega_c
    force: float          # P_c
    area: float           # A_c


def kogut_etsion_critical(R: float, E_star: float, Y: float, nu: float) -> Critical:
    KH = (0.454 + 0.41 * nu) * 2.8 * Y
    w_c = (math.pi * KH / (2.0 * E_star)) ** 2 * R
    return Critical(w_c, 2.0 / 3.0 * math.pi * KH * R * w_c, math.pi * R * w_c)


def kogut_etsion(w) -> tuple[np.ndarray, np.ndarray]:
    """(P/P_c, A/A_c) at w = omega/omega_c (0 <= w <= 110)."""
    w = np.asarray(w, dtype=float)
    if np.any(w > KE_MAX) or np.any(w < 0):
        raise ValueError(f"Kogut & Etsion's fits cover 0 <= omega/omega_c <= {KE_MAX:g}")
    P = np.where(w < 1, w ** 1.5, np.where(w <= 6, 1.03 * w ** 1.425, 1.40 * w ** 1.263))
    A = np.where(w < 1, w, np.where(w <= 6, 0.93 * w ** 1.136, 0.94 * w ** 1.146))
    return P, A


def jackson_green_critical(R: float, E_star: float, Y: float, nu: float) -> Critical:
    C = 1.295 * math.exp(0.736 * nu)
    w_c = (math.pi * C * Y / (2.0 * E_star)) ** 2 * R
    P_c = 4.0 / 3.0 * (R / E_star) ** 2 * (C * math.pi * Y / 2.0) ** 3
    return Critical(w_c, P_c, math.pi * R * w_c)


def jackson_green(w, R: float, E_star: float, Y: float, nu: float):
    """(P/P_c, A/A_c) at w = omega/omega_c (w >= 0)."""
    w = np.asarray(w, dtype=float)
    C = 1.295 * math.exp(0.736 * nu)
    B = 0.14 * math.exp(23.0 * Y / E_star)
    plastic = w >= JG_SWITCH
    A = np.where(plastic, w * (w / JG_SWITCH) ** B, w)
    a = np.sqrt(A * jackson_green_critical(R, E_star, Y, nu).area / math.pi)
    hardness = 2.84 * Y * (1.0 - np.exp(-0.82 * np.maximum(a / R, 1e-300) ** -0.7))
    P_plastic = (np.exp(-0.25 * w ** (5.0 / 12.0)) * w ** 1.5
                 + 4.0 * hardness / (C * Y) * (1.0 - np.exp(-w ** (5.0 / 9.0) / 25.0)) * w)
    return np.where(plastic, P_plastic, w ** 1.5), A
