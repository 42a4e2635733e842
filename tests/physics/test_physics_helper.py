"""The independent equilibrium check (tests/physics.py) checked on hand-made states."""

import numpy as np
from physics import equilibrium_residual

# The unit square as two CST, nodes 0 (0,0), 1 (1,0), 2 (1,1), 3 (0,1).
NODES = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
TRIANGLES = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.int64)
NO_PAIRS = {
    "node_a": np.zeros(0, np.int64),
    "node_b": np.zeros(0, np.int64),
    "normal": np.zeros((0, 2)),
}


def square(load, fixed, pairs=NO_PAIRS):
    return {
        "nodes": NODES,
        "triangles": TRIANGLES,
        "thickness": 2.0,
        "load": np.asarray(load, float),
        "fixed_dofs": np.asarray(fixed, np.int64),
        "pairs": pairs,
    }


def test_uniform_tension_balances_its_edge_load():
    """σx = 3 on a unit square of thickness 2: the right edge carries 3 × 1 × 2 = 6, half on
    each of its nodes (1, 2); the left edge is supported in x (and node 0 in y)."""
    load = np.zeros(8)
    load[[2, 4]] = 3.0
    model = square(load, [0, 1, 6])
    snap = {
        "load_fraction": 1.0,
        "stress": np.tile([3.0, 0.0, 0.0, 0.0], (2, 1)),
        "lambda_n": np.zeros(0),
        "lambda_t": np.zeros(0),
    }
    assert equilibrium_residual(model, snap) < 1e-14  # exact: round-off only
    snap["stress"] = np.tile([3.3, 0.0, 0.0, 0.0], (2, 1))  # 10 % too much stress
    assert equilibrium_residual(model, snap) > 0.05


def test_contact_forces_enter_with_the_documented_sign():
    """σy = −1 (compression) on the square pressed by a unit pressure on its top and resting on
    a rigid flat through its bottom nodes 0 and 1 (normal +y): each pair carries λ_n = 1 (half of
    1 × 1 × 2).  With λ_n of the wrong sign the residual is large."""
    load = np.zeros(8)
    load[[5, 7]] = -1.0
    pairs = {
        "node_a": np.array([0, 1]),
        "node_b": np.array([-1, -1]),
        "normal": np.array([[0.0, 1.0], [0.0, 1.0]]),
    }
    model = square(load, [0, 6], pairs)
    snap = {
        "load_fraction": 1.0,
        "stress": np.tile([0.0, -1.0, 0.0, 0.0], (2, 1)),
        "lambda_n": np.array([1.0, 1.0]),
        "lambda_t": np.zeros(2),
    }
    assert equilibrium_residual(model, snap) < 1e-14
    snap["lambda_n"] = -snap["lambda_n"]
    assert equilibrium_residual(model, snap) > 1.0
