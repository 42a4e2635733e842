"""A steel roller of finite length on a steel block (cases/roller_on_block_3d.toml, the eighth of
the roller on the quarter of the block, as shipped: roller spacing HR = 0.04 mm along its
contact line) against Hertz's line contact (Johnson, Contact Mechanics §4.3) and the end effect
of a square-ended roller (§5.8):

    b = sqrt(4 P' R / (pi E*)),  E* = E / (2 (1 - nu^2)),  P' = P / L.

Tolerances:
- equilibrium: the contact's normal resultant (the full contact, mirrored across x = 0 and
  y = 0) equals the applied traction times the cut's meshed area, to the engine's tolerance;
- the strip's half-width at the middle of the roller (the outermost closed node within 0.3 mm
  of y = 0) within one contactor spacing HR of b: the true edge lies between a closed and an
  open node; the line load carried at the middle is P' less what the ends draw, which only
  narrows the strip there (b goes as sqrt(P'));
- the end effect: the largest nodal pressure of the contact lies within a spacing of the
  roller's end and exceeds every pressure within 0.3 mm of the middle (at a square end the
  continuum pressure is unbounded; a mesh shows it as its largest value).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import CASES, needs_gmsh
from physics import EQUILIBRIUM_TOL

import slipstep

R, L, E, NU, HR = 10.0, 4.0, 210000.0, 0.3, 0.04
E_STAR = E / (2 * (1 - NU**2))


@pytest.fixture(scope="module")
def pressed():
    pytest.importorskip("gmsh")
    return slipstep.run(CASES / "roller_on_block_3d.toml", progress=False)


def applied_force(result) -> float:
    """The traction on the roller's cut times its meshed area, times 4 (the eighth)."""
    bc = next(b for b in result.case.data["bc"] if b["name"] == "press")
    x = result.scene.nodes[result.scene.global_boundary("roller", "top")]
    area = 0.5 * np.linalg.norm(np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]), axis=1).sum()
    return -4.0 * area * bc["traction"][2]


@needs_gmsh
def test_the_contact_carries_the_applied_force(pressed):
    assert pressed.completed
    total = pressed.summary["contacts"]["line"]["total_normal_force"]
    assert math.isclose(total, applied_force(pressed), rel_tol=EQUILIBRIUM_TOL)


@needs_gmsh
def test_the_strip_at_the_middle_is_hertz_s(pressed):
    b = math.sqrt(4 * applied_force(pressed) / L * R / (math.pi * E_STAR))
    prof = pressed.profile()
    middle = (prof["status"] > 0) & (prof["y"] <= 0.3)
    assert abs(prof["x"][middle].max() - b) <= HR, (prof["x"][middle].max(), b)


@needs_gmsh
def test_the_pressure_rises_at_the_roller_s_end(pressed):
    prof = pressed.profile()
    peak = int(np.argmax(prof["pressure"]))
    assert prof["y"][peak] >= L / 2 - HR, prof["y"][peak]
    assert prof["pressure"][peak] > prof["pressure"][prof["y"] <= 0.3].max()
