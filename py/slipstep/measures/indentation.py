"""Indentation analysis of a load-depth curve (numpy only): the Oliver–Pharr method on the
unloading branch (W. C. Oliver, G. M. Pharr, J. Mater. Res. 7 (1992) 1564; 19 (2004) 3).

From the curve P(h) (the indenter's force on the body along its motion, the whole indenter's,
against its depth):

- the unloading branch: from the deepest point (h_max, P_max) on, while h decreases;
- its upper part, P >= ``UPPER_FRACTION`` P_max, fitted by the power law P = α (h − h_f)^m
  (least squares on log P for each h_f, h_f chosen to minimise the relative misfit);
- the contact stiffness S = dP/dh at h_max = α m (h_max − h_f)^(m−1);
- the contact depth h_c = h_max − ε P_max / S, ε = 0.72 for a pyramid (Berkovich, Vickers:
  the cone's 2(π − 2)/π), 0.75 for a paraboloid (a sphere);
- the projected contact area A(h_c) of the ideal indenter: 24.504 h_c² for a Vickers
  (4 tan² 68°), 24.494 h_c² for a Berkovich (3√3 tan² 65.27°), π (2 R h_c − h_c²) for a
  sphere of radius R;
- the hardness H = P_max / A and the reduced modulus E_r = √π S / (2 β √A), β = 1.012 for a
  Vickers, 1.034 for a Berkovich (King 1987), 1 for a sphere (axisymmetric).  A rigid indenter
  gives E_r = E / (1 − ν²) of the body.
"""

from __future__ import annotations

import math

import numpy as np

#: The unloading points fitted: P >= UPPER_FRACTION P_max (the upper half of the branch).
UPPER_FRACTION = 0.5
#: ε of h_c = h_max − ε P_max / S.
EPSILON = {"vickers": 0.72, "berkovich": 0.72, "sphere": 0.75}
#: β of E_r = √π S / (2 β √A).
BETA = {"vickers": 1.012, "berkovich": 1.034, "sphere": 1.0}
#: Face angle from the axis of the ideal pyramids (slipstep.contact.indenters.FACE_ANGLE).
AREA_COEFFICIENT = {
    "vickers": 4.0 * math.tan(math.radians(68.0)) ** 2,
    "berkovich": 3.0 * math.sqrt(3.0) * math.tan(math.radians(65.27)) ** 2,
}


def projected_area(indenter: str, h_c: float, radius: float | None = None) -> float:
    """A(h_c) of the ideal indenter (module doc)."""
    if indenter == "sphere":
        if radius is None:
            raise ValueError("projected_area: a sphere needs its radius")
        return math.pi * (2.0 * radius * h_c - h_c * h_c)
    return AREA_COEFFICIENT[indenter] * h_c * h_c


def unloading_branch(h, P) -> np.ndarray:
    """Indices of the unloading branch: the deepest point (the first of the largest h), then
    every following point while h does not increase."""
    h = np.asarray(h, dtype=float)
    top = int(np.argmax(h))
    end = top + 1
    while end < len(h) and h[end] <= h[end - 1]:
        end += 1
    return np.arange(top, end)


def power_law_fit(h, P) -> tuple[float, float, float]:
    """(α, h_f, m) of P = α (h − h_f)^m through the points (h, P > 0): for each trial h_f in
    [−max |h|, min h), α and m by least squares on log P; h_f minimising the relative misfit
    Σ (α (h − h_f)^m / P − 1)², from a scan refined by golden sections."""
    h, P = np.asarray(h, dtype=float), np.asarray(P, dtype=float)
    keep = P > 0
    h, P = h[keep], P[keep]
    if len(h) < 3:
        raise ValueError(f"power_law_fit: {len(h)} points with P > 0; it needs 3")
    span = float(h.max() - h.min())
    if span <= 0:
        raise ValueError("power_law_fit: the points have one depth")

    def fit(hf: float):
        x, y = np.log(h - hf), np.log(P)
        m, log_a = np.polyfit(x, y, 1)
        misfit = float(np.sum((np.exp(log_a + m * x) / P - 1.0) ** 2))
        return misfit, float(np.exp(log_a)), float(m)

    scale = max(span, float(np.abs(h).max()))
    top = float(h.min()) - 1e-9 * scale  # h_f from just below the shallowest point
    # down to h_f = -h_max: a residual depth is >= 0 (a little below for a fit's noise), and
    # further down the misfit of a few points flattens while m runs away
    grid = top - (top + scale) * np.geomspace(1e-7, 1.0, 240)
    misfits = [fit(x)[0] for x in grid]
    k = int(np.argmin(misfits))
    a, b = grid[min(k + 1, len(grid) - 1)], grid[max(k - 1, 0)]
    a, b = min(a, b), max(a, b)
    golden = (math.sqrt(5.0) - 1.0) / 2.0
    for _ in range(100):
        c, d = b - golden * (b - a), a + golden * (b - a)
        if fit(c)[0] <= fit(d)[0]:
            b = d
        else:
            a = c
    hf = 0.5 * (a + b)
    _, alpha, m = fit(hf)
    return alpha, hf, m


def oliver_pharr(
    h,
    P,
    indenter: str,
    radius: float | None = None,
    epsilon: float | None = None,
    beta: float | None = None,
    upper: float = UPPER_FRACTION,
) -> dict:
    """The Oliver–Pharr numbers of a load-depth curve with an unloading branch (module doc):
    ``h_max``, ``P_max``, the fit (``alpha``, ``h_f``, ``m``, ``n_fit`` points), ``S``,
    ``h_c``, ``A``, ``H``, ``E_r``, and the ``epsilon`` and ``beta`` used.  ValueError when the
    curve does not unload through 3 points of its upper part."""
    h, P = np.asarray(h, dtype=float), np.asarray(P, dtype=float)
    branch = unloading_branch(h, P)
    h_max, P_max = float(h[branch[0]]), float(P[branch[0]])
    if len(branch) < 3 or P_max <= 0:
        raise ValueError("oliver_pharr: the curve has no unloading branch after its deepest point")
    fitted = branch[P[branch] >= (1.0 - upper) * P_max]
    alpha, h_f, m = power_law_fit(h[fitted], P[fitted])
    S = alpha * m * (h_max - h_f) ** (m - 1.0)
    eps = EPSILON[indenter] if epsilon is None else epsilon
    b = BETA[indenter] if beta is None else beta
    h_c = h_max - eps * P_max / S
    A = projected_area(indenter, h_c, radius)
    return {
        "indenter": indenter,
        "h_max": h_max,
        "P_max": P_max,
        "alpha": alpha,
        "h_f": h_f,
        "m": m,
        "n_fit": int(len(fitted)),
        "upper_fraction": upper,
        "S": S,
        "epsilon": eps,
        "beta": b,
        "h_c": h_c,
        "A": A,
        "H": P_max / A,
        "E_r": math.sqrt(math.pi) * S / (2.0 * b * math.sqrt(A)),
    }
