"""The paper's §5.2 block scenes on a refined half-space (issue 14): the same interface results
as on the structured half-space, with more than ten times fewer nodes.

The shipped cases (``cases/paper_block_*.toml``) keep the half-space's structured grid (h 0.5
elastic, h 1 plastic) only inside ``refine_box = [0, -15, 15, 0]``, 1.5 b x 1.5 b under the
punch (it holds the plastic scene's plastic zone, ~11 mm wide and ~13 mm deep), and let gmsh
coarsen the rest as h + 0.15 d up to 10 mm. The reference is the structured 100 x 100 mm
half-space the cases stood on before: the override ``refine_box`` = the whole block gives it
back, bit for bit (asserted). Compared node by node along the interface (the punch's nodes,
unchanged), relative to the peak of each quantity over the interface.

Tolerance: 1 % of the peak for pressure, tangential stress and RTD, both as rms and at every
node: the issue's requirement ("reproduce today's interface results within 1 %"), read at
every node, not a measured value. Measured (gmsh 4.15): elastic rms 0.004 / 0.046 / 0.15 %,
largest 0.014 / 0.20 / 0.29 %; plastic μ = 0 pressure / RTD rms 0.001 / 0.094 %, largest 0.004
/ 0.16 %; plastic μ = 0.2 rms 0.003 / 0.078 / 0.098 %, largest 0.008 / 0.24 / 0.26 %. Inside
the box the two meshes are the same, so what differs is the stiffness of the far field, which
the RTD (a half-plane's tangential surface displacement does not decay) feels most. The
structured reference itself is not converged: its plastic run is 5.5 / 12.3 / 11.8 % rms off a
run at h 0.5 (see the case file); the 1 % is about reproducing it, not about accuracy.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import CASES, needs_gmsh

from slipstep.mesh import triangle_generators as generators
from slipstep import prepare, solve
from slipstep.measures.contact_edges import contact_profile

pytestmark = needs_gmsh

#: the override giving back the structured half-space: a refine_box covering the whole block
STRUCTURED = ["body.halfspace.mesh.refine_box=[0.0, -100.0, 100.0, 0.0]"]
QUANTITIES = ("pressure", "tangential_stress", "rtd")


def run(case: str, sets: list[str]):
    scene = prepare(CASES / case, ["output.figures=false", *sets])
    return scene, contact_profile(scene, solve(scene)["snapshots"][-1])


def compare(case: str, h: float, common=()) -> tuple[float, dict]:
    """Node ratio (structured / refined) and, per quantity, the rms and largest difference
    at the interface nodes relative to the structured run's peak."""
    s0, a = run(case, [*common, *STRUCTURED])
    s1, b = run(case, list(common))
    n = round(100.0 / h)
    ref = generators.block(100.0, 100.0, n, n, 0.0, -100.0)
    assert np.array_equal(s0.meshes["halfspace"].nodes, ref.nodes)
    assert np.array_equal(s0.meshes["halfspace"].triangles, ref.triangles)
    assert np.array_equal(a["x"], b["x"]), "the punch's interface nodes must be the same"
    diff = {}
    for k in QUANTITIES:
        peak = np.abs(a[k]).max()
        if peak == 0:  # frictionless: no tangential stress in either run
            assert np.abs(b[k]).max() == 0, k
            continue
        d = np.abs(b[k] - a[k]) / peak
        diff[k] = (float(np.sqrt(np.mean(d**2))), float(d.max()))
    return len(s0.nodes) / len(s1.nodes), diff


def test_elastic_block_on_a_refined_half_space():
    """Plane strain, q = 1.2 MPa, μ = 0.2, h = 0.5: 40 842 nodes structured, 2 142 refined
    (19.1x fewer, measured)."""
    ratio, diff = compare("paper_block_elastic.toml", 0.5)
    assert ratio >= 10
    assert set(diff) == set(QUANTITIES)
    assert all(rms <= 0.01 and largest <= 0.01 for rms, largest in diff.values()), diff


@pytest.mark.parametrize("mu", [0.0, 0.2])
def test_plastic_block_on_a_refined_half_space(mu):
    """Plane stress, q = 36 MPa, both bodies yielding, h = 1: 10 322 nodes structured, 808
    refined (12.8x fewer, measured); at μ = 0 there is no tangential stress to compare."""
    ratio, diff = compare("paper_block_plastic.toml", 1.0, [f"contact.mu={mu}"])
    assert ratio >= 10
    assert set(diff) == set(QUANTITIES) - ({"tangential_stress"} if mu == 0 else set())
    assert all(rms <= 0.01 and largest <= 0.01 for rms, largest in diff.values()), diff
