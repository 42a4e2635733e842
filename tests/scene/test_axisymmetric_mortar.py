"""The ring contact patch test for node-to-segment (mortar) rows in axisymmetry
(py/slipstep/contact/node_to_segment.py, ``radial``): two coaxial cylinders of the same material, meshed on
their own, pressed together by p on the top.  The exact solution is uniform uniaxial stress
sigma_z = -p, sigma_r = sigma_theta = tau_rz = 0 with the same radial expansion on both sides
(no slip), and every row carries its ring share of p: lambda_j = p x 2 pi int N_j r ds.

With the ring weight r in the integrals every row reads p, the row at the axis too.  Planar
weights would balance the same nodal forces (r is linear along the flat interface, so the
multiplier field 2 pi p r is reproduced exactly) but put lambda = 2 pi p r_j S_j on the rows:
zero at the axis, p (1 - O(h/r)) at the ends of the contactor."""

from __future__ import annotations

import numpy as np
import pytest
from physics import EQUILIBRIUM_TOL, worst_equilibrium
from test_node_to_segment import P, two_blocks

from slipstep import build_scene, parse_case, solve
from slipstep.contact.node_to_segment import node_to_segment_pairs


def rings(n_lower: int, n_upper: int, mu: float) -> str:
    """tests/scene/test_node_to_segment.py's two blocks as two cylinders about x = 0 (the axis holds
    u_r = 0 by itself: the blocks' left-edge supports go)."""
    text = two_blocks(n_lower, n_upper, mu)
    for body in ("lower", "upper"):
        text = text.replace(f'[[bc]]\nbody = "{body}"\nedge = "left"\nfix = ["x"]\n', "")
    return '[analysis]\nplane = "axisymmetric"\n' + text


@pytest.mark.parametrize("mu", [0.0, 0.3])
@pytest.mark.parametrize("n_lower,n_upper", [(7, 5), (5, 7), (3, 8), (10, 10)])
def test_ring_patch_test_transmits_a_uniform_pressure_exactly(n_lower, n_upper, mu):
    """Every row's pressure lambda_n / (its ring area, scene.pair_area) is p and every element
    uniaxial, to round-off: 1e-11 relative (these ~100-dof systems solve to ~1e-14; measured
    <= 1.4e-12 for the pressures, 2.3e-13 for the stresses); no tangential force (relative to
    the largest lambda_n)."""
    scene = build_scene(parse_case(rings(n_lower, n_upper, mu), "rings", "."))
    result = solve(scene)
    snap = result["snapshots"][-1]
    node_a = scene.model["pairs"]["node_a"]
    assert scene.nodes[node_a, 0].min() == 0.0  # a row at the axis
    pressure = np.asarray(snap["lambda_n"]) / scene.pair_area
    assert len(pressure) == n_upper + 1
    assert np.abs(pressure - P).max() <= 1e-11 * P
    stress = np.asarray(snap["stress"])
    assert np.abs(stress[:, 1] + P).max() <= 1e-11 * P
    assert np.abs(stress[:, [0, 2, 3]]).max() <= 1e-11 * P
    assert np.abs(snap["lambda_t"]).max() <= 1e-11 * np.max(snap["lambda_n"])
    worst, _, _ = worst_equilibrium(scene.model, result["snapshots"])
    assert worst <= EQUILIBRIUM_TOL


def test_ring_rows_weigh_by_the_radius():
    """The row at the axis: its ring-weighted tributary is int_0^h (1 - s/h) s ds = h^2/6, the
    plain one h/2; the weights still cancel (a rigid axial translation keeps the gap) and the
    row's length stays the plain one."""
    scene = build_scene(parse_case(rings(7, 5, 0.0), "rings", "."))
    upper = scene.global_edge("upper", "bottom")
    lower = scene.global_edge("lower", "top")
    axis_node = int(np.unique(upper)[np.argmin(scene.nodes[np.unique(upper), 0])])
    h = 10.0 / 5
    for radial in (False, True):
        rows = node_to_segment_pairs(
            scene.nodes, upper, lower, np.array([axis_node]), 1e-12, radial=radial
        )
        (weights,) = rows["weights"]
        assert rows["length"] == [pytest.approx(h / 2, rel=1e-12)]
        assert sum(c for _, c in weights) == pytest.approx(0.0, abs=1e-14)
        own = dict(weights)[axis_node]
        # the node's own weight D_jj / S_j: (h/3)/(h/2) planar, (h^2/12)/(h^2/6) ring-weighted
        assert own == pytest.approx(0.5 if radial else 2 / 3, rel=1e-12)
