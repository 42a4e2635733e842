"""The numpy return mapping used by the dolfinx elastoplastic solver (no dolfinx needed)."""

from __future__ import annotations

import numpy as np
import pytest

from slipstep.fenicsx import plasticity as pl

E, NU, SY = 200000.0, 0.3, 250.0


def _state(rng, M, scale=150.0, plane="strain"):
    sig = rng.normal(size=(M, 4)) * scale
    if plane == "stress":
        sig[:, 2] = 0.0
    return sig, np.abs(rng.normal(size=M)) * 1e-3


@pytest.mark.parametrize("plane", ["strain", "stress"])
def test_elastic_steps_use_the_elastic_stiffness(plane):
    rng = np.random.default_rng(0)
    deps = rng.normal(size=(5, 3)) * 1e-5
    sig, alpha, C3, plastic, _ = pl.integrate(
        np.zeros((5, 4)), np.zeros(5), deps, E, NU, np.inf, 0.0, plane
    )
    D = pl.in_plane_d(np.full(5, E), np.full(5, NU), plane)
    assert not plastic.any()
    assert np.allclose(C3, D, rtol=1e-12, atol=0)
    assert np.allclose(sig[:, [0, 1, 3]], np.einsum("mij,mj->mi", D, deps), rtol=1e-12)
    if plane == "strain":
        assert np.allclose(sig[:, 2], NU * (sig[:, 0] + sig[:, 1]), rtol=1e-12)
    else:
        assert np.all(sig[:, 2] == 0.0)


@pytest.mark.parametrize("plane", ["strain", "stress"])
@pytest.mark.parametrize("H", [0.0, 8000.0])
def test_return_lands_on_the_hardened_surface(plane, H):
    rng = np.random.default_rng(1)
    M = 40
    deps = rng.normal(size=(M, 3)) * 4e-3  # far beyond yield
    sig, alpha, _, plastic, _ = pl.integrate(
        np.zeros((M, 4)), np.zeros(M), deps, E, NU, SY, H, plane
    )
    assert plastic.all()
    assert np.allclose(pl.von_mises(sig), SY + H * alpha, rtol=1e-10)
    if plane == "stress":
        assert np.abs(sig[:, 2]).max() == 0.0


@pytest.mark.parametrize("plane", ["strain", "stress"])
@pytest.mark.parametrize("H", [0.0, 8000.0])
def test_consistent_tangent_matches_finite_differences(plane, H):
    """d sigma_inplane / d eps_inplane of the whole update (including the sigma_z = 0
    iteration in plane stress) against central differences."""
    rng = np.random.default_rng(2)
    M = 12
    sig_n = np.zeros((M, 4))
    alpha_n = np.zeros(M)
    # first a plastic step from zero, then test the tangent of a second plastic step
    first = rng.normal(size=(M, 3)) * 2e-3
    sig_n, alpha_n, *_ = pl.integrate(sig_n, alpha_n, first, E, NU, SY, H, plane)
    deps = 0.5 * first + rng.normal(size=(M, 3)) * 2e-4  # keep loading, turn the path a bit
    _, _, C3, plastic, _ = pl.integrate(sig_n, alpha_n, deps, E, NU, SY, H, plane)
    assert plastic.sum() >= M - 2  # a mostly volumetric first step may stay elastic
    h = 1e-8
    fd = np.zeros((M, 3, 3))
    for j in range(3):
        dp, dm = deps.copy(), deps.copy()
        dp[:, j] += h
        dm[:, j] -= h
        sp = pl.integrate(sig_n, alpha_n, dp, E, NU, SY, H, plane)[0][:, [0, 1, 3]]
        sm = pl.integrate(sig_n, alpha_n, dm, E, NU, SY, H, plane)[0][:, [0, 1, 3]]
        fd[:, :, j] = (sp - sm) / (2 * h)
    scale = np.abs(C3).max()
    assert np.abs(fd - C3).max() < 1e-5 * scale


def test_plane_stress_uniaxial_hardening_curve():
    """Uniaxial stress in plane stress (eps_y chosen so sigma_y = 0 by an outer Newton):
    sigma = Sy + H' eps_p with eps = sigma/E + eps_p."""
    H = 10000.0
    sig, alpha = np.zeros((1, 4)), np.zeros(1)
    eps_total = 0.0
    eps_y = 0.0
    for _ in range(40):
        dex = 1e-4
        dey = -NU * dex
        for _ in range(30):  # find dey with sigma_y = 0
            s, a, C3, _, _ = pl.integrate(
                sig, alpha, np.array([[dex, dey, 0.0]]), E, NU, SY, H, "stress"
            )
            if abs(s[0, 1]) < 1e-10:
                break
            dey -= s[0, 1] / C3[0, 1, 1]
        sig, alpha = s, a
        eps_total += dex
        eps_y += dey
    sx = sig[0, 0]
    assert abs(sx - (SY + H * alpha[0])) < 1e-8 * SY
    assert abs(eps_total - (sx / E + alpha[0])) < 1e-10
