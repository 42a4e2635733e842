"""Sharp indentation of an elastoplastic block, loaded and unloaded: cases/vickers_indentation_3d.toml
(the quarter) and cases/berkovich_indentation_3d.toml (the half), run as shipped (h = 0.02 mm
at the tip), against what a sharp indenter does whatever the mesh (Johnson, Contact Mechanics
§6.2-6.3; Tabor 1951):

- equilibrium: every snapshot's stresses balance the contact forces and the supports, to the
  engine's tolerance (1e-9, tests/physics.py);
- Kick's law: a self-similar indenter on a material without a length scale takes P = C h^2:
  the exponent n of a least-squares fit of log P against log h over the snapshots from 0.3 to
  1 of the depth is 2.  The discrete contact there is 1 to 4 spacings across (its edge moves
  by a spacing, a share of P of 2h/a, in steps the fit averages), so n is asserted within 0.5
  of 2: above a sphere's 1.5 and a flat punch's 1 (measured on these meshes: 1.83 Vickers,
  1.56 Berkovich; the Vickers at h = 0.01: 1.89);
- the contact's shape is the pyramid's section, oriented as cases/README.md states: the
  Vickers' square has its corners on the diagonals (sqrt(2) farther than the middles of its
  sides on the axes), so the farthest closed node lies between 22.5 and 67.5 degrees from x
  (a square turned by 45 degrees would put it within h/s ~ 15 degrees of an axis); the
  Berkovich's triangle has its vertex on +y at twice its inradius, so the closed nodes reach
  farther along +y than along -y (the other way round for the pyramid turned over: a ratio of
  1/2, and each reach moves by one spacing h: (2r - h)/(r + h) = 1.3 > 1 > (r + h)/(2r - h));
- the block yields: the mean pressure P/A lies between 2 Sy and a fifth of the elastic block's
  E* tan(beta)/2 = 110 Sy (Tabor's fully plastic value is ~3 Sy; linear tetrahedra lock under
  plastic, isochoric, flow and give more, and the nodal contact area is short of the edge);
- unloaded, the pyramid leaves the block: no pair closed, no contact force (to 1e-9 of the
  largest), and a plastic dent: the tip node stays below half the depth reached (an elastic
  block would return to 0; a metal with E/Sy = 500 recovers ~10 % of the depth).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import CASES, needs_gmsh
from physics import EQUILIBRIUM_TOL, equilibrium_residual

import slipstep

DEPTH, SY, E, NU = 0.03, 400.0, 200000.0, 0.3
H = 0.02  # the shipped meshes' spacing at the tip


SHIPPED = {"vickers": "vickers_indentation_3d.toml", "berkovich": "berkovich_indentation_3d.toml"}


@pytest.fixture(scope="module", params=list(SHIPPED))
def indented(request):
    pytest.importorskip("gmsh")
    result = slipstep.run(CASES / SHIPPED[request.param], progress=False)
    mirror = 4.0 if request.param == "vickers" else 2.0  # the quarter, the half
    return request.param, result, mirror


def force(result, mirror: float, t: float, stage: int) -> float:
    return mirror * float(np.sum(result.snapshot(t, stage=stage)["lambda_n"]))


@needs_gmsh
def test_every_snapshot_is_in_equilibrium(indented):
    _, result, _ = indented
    assert result.completed
    for snap in result.raw["snapshots"]:
        assert equilibrium_residual(result.scene.model, snap) <= EQUILIBRIUM_TOL


@needs_gmsh
def test_the_force_goes_as_the_depth_squared(indented):
    _, result, mirror = indented
    depths = np.unique([t for t in result.times if 0.3 - 1e-9 <= t <= 1.0 + 1e-9])
    forces = [force(result, mirror, t, 1) for t in depths]
    exponent = np.polyfit(np.log(depths), np.log(forces), 1)[0]
    assert abs(exponent - 2.0) <= 0.5, exponent


@needs_gmsh
def test_the_contact_is_the_pyramid_s_section_as_oriented(indented):
    kind, result, _ = indented
    prof = result.profile(1.0, stage=1)
    closed = prof["status"] > 0
    x, y = prof["x"][closed], prof["y"][closed]
    if kind == "vickers":
        far = np.argmax(np.hypot(x, y))
        angle = math.degrees(math.atan2(y[far], x[far]))
        assert 22.5 <= angle <= 67.5, angle
    else:
        assert y.max() > -y.min() > 0, (y.max(), y.min())


@needs_gmsh
def test_the_block_yields_under_the_pyramid(indented):
    _, result, mirror = indented
    numbers = result.summary["stages"][0]["contacts"]["pyramid"]
    mean = force(result, mirror, 1.0, 1) / numbers["contact_area"]
    elastic = E / (1 - NU**2) * math.tan(math.radians(22.0)) / 2
    assert 2 * SY <= mean <= elastic / 5, (mean / SY, elastic / SY)
    assert result.summary["n_yielded_elements"] > 0


@needs_gmsh
def test_drawn_back_the_pyramid_leaves_a_dent(indented):
    _, result, mirror = indented
    end = result.fields(2.0)
    assert (end["status"] == 0).all()
    assert abs(force(result, mirror, 2.0, 2)) <= 1e-9 * force(result, mirror, 1.0, 1)
    tip = int(np.argmin(np.linalg.norm(result.nodes, axis=1)))
    assert end["u"][tip, 2] < -0.5 * DEPTH, end["u"][tip]
