"""tests/physics.py on hand-made states whose answers are known without any solver.

A uniform stress σ = (σx, σy, τxy) = (3, −2, 1.5) in a unit square of two CSTs (thickness 2)
is in equilibrium with the consistent nodal loads of its boundary tractions σ·n (each edge of
length 1 gives ½ (σ·n) L t to each end node): the recomputed residual must vanish to round-off
(1e-14 relative: a dozen operations on numbers of order 1), whichever way the boundary is held
(loads, supports, a rigid flat through contact pairs, another body through node-to-node
pairs).  Any error in a stress component, a force sign or the tangent convention
t = (−n_y, n_x) leaves an unbalanced force of order the error: the residual must be large
(> 1e-2 relative for a 10 % error in one stress component, twelve orders above round-off).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from physics import equilibrium_residual, von_mises
from slipstep.measures.references import hertz_line

SIGMA = np.array([3.0, -2.0, 0.0, 1.5])  # σx, σy, σz (no work in plane), τxy
T = 2.0  # thickness
SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
TRIANGLES = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.int64)
EDGES = {
    "bottom": ((0, 1), (0.0, -1.0)),
    "right": ((1, 2), (1.0, 0.0)),
    "top": ((2, 3), (0.0, 1.0)),
    "left": ((3, 0), (-1.0, 0.0)),
}
NO_PAIRS = {
    "node_a": np.zeros(0, np.int64),
    "node_b": np.zeros(0, np.int64),
    "normal": np.zeros((0, 2)),
}
ROUND_OFF = 1e-14


def traction(sigma, normal):
    sx, sy, _, txy = sigma
    return np.array([sx * normal[0] + txy * normal[1], txy * normal[0] + sy * normal[1]])


def edge_loads(n_nodes, edges, sigma=SIGMA, offset=0):
    f = np.zeros((n_nodes, 2))
    for (i, j), normal in edges:
        half = 0.5 * traction(sigma, normal) * 1.0 * T
        f[i + offset] += half
        f[j + offset] += half
    return f.ravel()


def model(nodes, triangles, load, fixed=(), pairs=NO_PAIRS):
    return {
        "nodes": nodes,
        "triangles": triangles,
        "thickness": T,
        "plane": "strain",
        "load": np.asarray(load, float),
        "fixed_dofs": np.asarray(fixed, np.int64),
        "pairs": pairs,
    }


def snapshot(stress, n_elements, lambda_n=(), lambda_t=()):
    return {
        "load_fraction": 1.0,
        "stress": np.tile(stress, (n_elements, 1)),
        "lambda_n": np.asarray(lambda_n, float),
        "lambda_t": np.asarray(lambda_t, float),
    }


def test_free_patch_under_its_boundary_tractions():
    m = model(SQUARE, TRIANGLES, edge_loads(4, EDGES.values()))
    assert equilibrium_residual(m, snapshot(SIGMA, 2)) < ROUND_OFF
    for k in (0, 1, 3):  # each in-plane component matters
        wrong = SIGMA.copy()
        wrong[k] *= 1.1
        assert equilibrium_residual(m, snapshot(wrong, 2)) > 1e-2, k
    wrong = SIGMA.copy()
    wrong[2] = 100.0  # σz does no in-plane work: no effect
    assert equilibrium_residual(m, snapshot(wrong, 2)) < ROUND_OFF
    # half the load fraction with the full stress is out of balance
    s = snapshot(SIGMA, 2)
    s["load_fraction"] = 0.5
    assert equilibrium_residual(m, s) > 1e-2


def test_clockwise_triangles_give_the_same_forces():
    m = model(SQUARE, TRIANGLES[:, ::-1].copy(), edge_loads(4, EDGES.values()))
    assert equilibrium_residual(m, snapshot(SIGMA, 2)) < ROUND_OFF


def test_supports_take_the_reactions():
    # the bottom nodes held in both directions: their (unknown) reactions are not checked
    loads = edge_loads(4, [EDGES[k] for k in ("right", "top", "left")])
    loads[:4] = 0.0
    m = model(SQUARE, TRIANGLES, loads, fixed=[0, 1, 2, 3])
    assert equilibrium_residual(m, snapshot(SIGMA, 2)) < ROUND_OFF


@pytest.mark.parametrize("angle", [0.0, 0.3, -1.0])
def test_rigid_flat_forces_with_the_documented_tangent(angle):
    """The bottom edge rests on a rigid line (node_b = −1) with normal n at any inclination:
    each bottom node receives the force F = ½ T (σ·(0, −1)) = λ_n n + λ_t t, t = (−n_y, n_x)."""
    n = np.array([math.sin(angle), math.cos(angle)])
    t = np.array([-n[1], n[0]])
    force = 0.5 * T * traction(SIGMA, (0.0, -1.0))
    ln, lt = force @ n, force @ t
    pairs = {"node_a": np.array([0, 1]), "node_b": np.array([-1, -1]), "normal": np.tile(n, (2, 1))}
    m = model(
        SQUARE, TRIANGLES, edge_loads(4, [EDGES[k] for k in ("right", "top", "left")]), pairs=pairs
    )
    assert equilibrium_residual(m, snapshot(SIGMA, 2, [ln, ln], [lt, lt])) < ROUND_OFF
    # the opposite tangent convention, or λ_t of the wrong sign, is out of balance
    assert equilibrium_residual(m, snapshot(SIGMA, 2, [ln, ln], [-lt, -lt])) > 1e-2
    assert equilibrium_residual(m, snapshot(SIGMA, 2, [-ln, -ln], [lt, lt])) > 1e-2


def test_node_to_node_pairs_act_on_both_bodies():
    """Two unit squares, one above the other (nodes 0-3 above, 4-7 below), in the same uniform
    stress, joined by pairs from the upper bottom nodes (a) to the lower top nodes (b),
    normal +y (from b towards a): the force on a is the upper bottom traction's share, the
    opposite on b balances the lower top traction."""
    lower = SQUARE - [0.0, 1.0]
    nodes = np.vstack([SQUARE, lower])
    triangles = np.vstack([TRIANGLES, TRIANGLES + 4])
    upper_loads = edge_loads(8, [EDGES[k] for k in ("right", "top", "left")])
    lower_loads = edge_loads(8, [EDGES[k] for k in ("bottom", "right", "left")], offset=4)
    n = np.array([0.0, 1.0])
    force = 0.5 * T * traction(SIGMA, (0.0, -1.0))
    ln, lt = force @ n, force @ np.array([-n[1], n[0]])
    pairs = {"node_a": np.array([0, 1]), "node_b": np.array([7, 6]), "normal": np.tile(n, (2, 1))}
    m = model(nodes, triangles, upper_loads + lower_loads, pairs=pairs)
    assert equilibrium_residual(m, snapshot(SIGMA, 4, [ln, ln], [lt, lt])) < ROUND_OFF
    pairs_rigid = dict(pairs, node_b=np.array([-1, -1]))  # the lower body left unbalanced
    m_rigid = model(nodes, triangles, upper_loads + lower_loads, pairs=pairs_rigid)
    assert equilibrium_residual(m_rigid, snapshot(SIGMA, 4, [ln, ln], [lt, lt])) > 1e-2


def test_no_load_gives_an_absolute_residual():
    m = model(SQUARE, TRIANGLES, np.zeros(8))
    assert equilibrium_residual(m, snapshot(np.zeros(4), 2)) == 0.0
    assert equilibrium_residual(m, snapshot(SIGMA, 2)) > 1.0


def test_von_mises_and_hertz_references():
    s = np.array(
        [
            [100.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, 10.0],
            [50.0, 50.0, 50.0, 0.0],
            [1.0, 2.0, 3.0, 0.0],
        ]
    )
    # uniaxial, pure shear (√3 τ), hydrostatic (0), and √(((1-2)² + (2-3)² + (3-1)²)/2) = √3
    np.testing.assert_allclose(
        von_mises(s), [100.0, 10.0 * math.sqrt(3.0), 0.0, math.sqrt(3.0)], rtol=1e-14, atol=1e-12
    )
    a, p0 = hertz_line(1000.0, 125.0, 70000.0, 0.3, "strain")
    assert a == pytest.approx(1.4384, abs=1e-4) and p0 == pytest.approx(442.6, abs=0.05)
    a_s, p0_s = hertz_line(1000.0, 125.0, 70000.0, 0.3, "stress")
    assert a_s / a == pytest.approx(1 / math.sqrt(1 - 0.09), rel=1e-14)
    assert p0_s * a_s == pytest.approx(p0 * a, rel=1e-14)  # P = π a p0 / 2 either way
