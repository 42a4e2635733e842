"""Independently meshed deformable bodies (node-to-segment, mortar-style rows): Hertz for a
cylinder on a block (same and dissimilar materials, a refinement series) and two_blocks on
matching and non-matching meshes (Cattaneo–Mindlin partial slip: test_cattaneo_mindlin.py).

Hertz line contact of two elastic bodies (Johnson, Contact Mechanics §4.3), plane strain:
1/E* = (1 − ν1²)/E1 + (1 − ν2²)/E2, a = √(4PR/(πE*)), p0 = 2P/(πa). Same material:
E* = E/(2(1 − ν²)).
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from conftest import CASES, needs_gmsh
from physics import EQUILIBRIUM_TOL, worst_equilibrium

from slipstep import parse_case, prepare, build_scene, solve
from slipstep.measures.contact_edges import contact_profile
from slipstep.output.summary import summarize

pytestmark = needs_gmsh

R, P, NU = 125.0, 1000.0, 0.3


def hertz(E1, E2):
    e_star = 1.0 / ((1 - NU**2) / E1 + (1 - NU**2) / E2)
    a = math.sqrt(4 * P * R / (math.pi * e_star))
    return a, 2 * P / (math.pi * a)


def cylinder_on_block(h, E_roller=70000.0):
    sets = [
        f"body.roller.mesh.h_contact={h}",
        f"body.block.mesh.h_contact={h}",
        f"body.roller.material.E={E_roller}",
        "output.figures=false",
    ]
    scene = prepare(CASES / "cylinder_on_block.toml", sets)
    result = solve(scene)
    return scene, result, summarize(scene, result)


@pytest.fixture(scope="module")
def series():
    return {h: cylinder_on_block(h) for h in (0.1, 0.05, 0.025)}


def test_cylinder_on_block_matches_two_body_hertz(series):
    """h = 0.05 mm (a/h = 41): the contact half-width (the closure-interpolated edge) within
    one element of Hertz's a, the peak pressure (node a's force over its tributary length)
    within h/a: the pressure field is sampled at nodes h apart and converges at first order
    (below). Equilibrium recomputed from the arrays."""
    scene, result, summary = series[0.05]
    a, p0 = hertz(70000.0, 70000.0)
    assert abs(summary["contact_half_width"] - a) <= 0.05
    assert abs(summary["peak_pressure"] / p0 - 1) <= 0.05 / a
    worst, _, _ = worst_equilibrium(scene.model, result["snapshots"])
    assert worst <= EQUILIBRIUM_TOL


def test_refinement_converges_to_hertz(series):
    """h = 0.1, 0.05, 0.025: both errors fall at every halving, and the peak pressure's
    observed order is at least 0.7 (first order expected from nodal sampling; measured ~1).
    The finite block (40 × 40 against a = 2 mm) leaves a floor far below these errors."""
    a, p0 = hertz(70000.0, 70000.0)
    err_a = [abs(series[h][2]["contact_half_width"] / a - 1) for h in (0.1, 0.05, 0.025)]
    err_p = [abs(series[h][2]["peak_pressure"] / p0 - 1) for h in (0.1, 0.05, 0.025)]
    assert err_a[0] > err_a[1] > err_a[2] and err_p[0] > err_p[1] > err_p[2]
    assert math.log2(err_p[0] / err_p[2]) / 2 >= 0.7, err_p
    nodes = [len(series[h][0].nodes) for h in (0.1, 0.05, 0.025)]
    assert nodes[-1] < 50000, f"graded meshes: {nodes} nodes"


def test_dissimilar_materials_use_the_two_body_modulus():
    """A 210 GPa roller on the 70 GPa block: the same tolerances against E* of both."""
    scene, result, summary = cylinder_on_block(0.05, E_roller=210000.0)
    a, p0 = hertz(210000.0, 70000.0)
    assert abs(summary["contact_half_width"] - a) <= 0.05
    assert abs(summary["peak_pressure"] / p0 - 1) <= 0.05 / a
    a_same, _ = hertz(70000.0, 70000.0)
    assert a < a_same - 0.2, "the stiffer roller must narrow the contact"


# --------------------------------------------------------------------------- two blocks
TWO_BLOCKS = (CASES / "two_blocks.toml").read_text()


def interface_pressure(text):
    scene = build_scene(parse_case(text, "two_blocks", CASES, ["output.figures=false"]))
    prof = contact_profile(scene, solve(scene)["snapshots"][-1])
    return prof["x"], prof["pressure"]


def non_matching(h_punch):
    text = TWO_BLOCKS.replace('kind = "node_to_node"', 'kind = "node_to_segment"')
    text = re.sub(r"\ntolerance = [^\n]*", "", text)
    return text.replace("height = 5.0\nh = 0.5", f"height = 5.0\nh = {h_punch}")


@pytest.mark.parametrize("h_punch", [0.4, 0.6])
def test_non_matching_two_blocks_agree_within_the_discretization_error(h_punch):
    """The punch meshed at 0.4 or 0.6 on the foundation's 0.5 (node-to-segment) against the
    matching 0.5 mesh (node-to-node): the rms difference of the interface pressure over
    x < 9 (away from the punch corner's singularity at x = 10) is within the discretization
    error of the matching mesh, estimated as the rms change of that pressure when the matching
    mesh is coarsened to 1.0."""
    rms = lambda d: float(np.sqrt(np.mean(d**2)))
    x5, p5 = interface_pressure(TWO_BLOCKS)
    x1, p1 = interface_pressure(TWO_BLOCKS.replace("h = 0.5", "h = 1.0"))
    xn, pn = interface_pressure(non_matching(h_punch))
    bound = rms(p1[x1 < 9] - np.interp(x1[x1 < 9], x5, p5))
    diff = rms(pn[xn < 9] - np.interp(xn[xn < 9], x5, p5))
    assert diff <= bound, f"non-matching rms difference {diff:.4f} vs discretization {bound:.4f}"
