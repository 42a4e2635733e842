"""The paper's §5.2 block scenes on a graded half-space (issue 14): the same interface results
with an order of magnitude fewer nodes.

The structured half-space (100 x 100 mm, h everywhere) is replaced by the graded block: h at the
interface (h_contact, with uniform_edges so the punch's structured nodes still match and the
contact stays node_to_node), growing away from the punch corner (10, 0) up to 10 mm. Compared
node by node along the interface, relative to the peak of each quantity.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import CASES, needs_gmsh

from slipstep import prepare, solve
from slipstep.derived import contact_profile

pytestmark = needs_gmsh


def graded(h, zone, growth):
    """--set overrides turning the case's structured half-space into the graded one."""
    return ["body.halfspace.mesh.h=0", f"body.halfspace.mesh.h_contact={h}",
            f"body.halfspace.mesh.contact_zone={zone}", "body.halfspace.mesh.h_max=10",
            f"body.halfspace.mesh.growth={growth}", "body.halfspace.mesh.focus=[10.0, 0.0]",
            "body.halfspace.mesh.uniform_edges=true"]


def compare(case, sets, common=()):
    runs = []
    for extra in ([], sets):
        scene = prepare(CASES / case, ["output.figures=false", *common, *extra])
        runs.append((len(scene.nodes), contact_profile(scene, solve(scene)["snapshots"][-1])))
    (n0, a), (n1, b) = runs
    assert np.array_equal(a["x"], b["x"]), "the punch's interface nodes must be the same"
    rms = {k: float(np.sqrt(np.mean((b[k] - a[k]) ** 2)) / np.abs(a[k]).max())
           for k in ("pressure", "tangential_stress", "rtd") if np.abs(a[k]).max() > 0}
    return n0 / n1, rms


def test_elastic_block_on_a_graded_half_space():
    """Plane strain, q = 1.2 MPa, μ = 0.2, h = 0.5: at least 10x fewer nodes (measured 12.8x)
    and pressure, tangential stress and RTD within 1 % rms of the structured run (measured
    0.65 %, 0.70 %, 0.50 %; the largest single differences, 2 %, sit at the node next to the
    singular punch corner, where the structured mesh is itself 25 % off a mesh twice as fine)."""
    ratio, rms = compare("paper_block_elastic.toml", graded(0.5, 15, 0.1))
    assert ratio >= 10
    assert max(rms.values()) <= 0.01, rms


@pytest.mark.parametrize("mu", [0.0, 0.2])
def test_plastic_block_pressure_on_a_graded_half_space(mu):
    """Plane stress, q = 36 MPa, both bodies yielding, h = 1: at least 10x fewer nodes
    (measured 12.1x) and the interface pressure within 1 % rms (measured 0.30 % at μ = 0.2,
    0.51 % at μ = 0). The tangential quantities are not asserted: at μ = 0.2 the tangential
    stress differs by 5 % rms, a mesh dependence of the plastic half-space that the structured
    reference shares (it is 12 % off a mesh twice as fine; see the issue-14 note)."""
    ratio, rms = compare("paper_block_plastic.toml", graded(1.0, 10, 0.12), [f"contact.mu={mu}"])
    assert ratio >= 10
    assert rms["pressure"] <= 0.01, rms
