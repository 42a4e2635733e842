"""The 2D section: plane strain, plane stress or axisymmetry (``[analysis] plane``).  They
differ in the Python front only in how a boundary integral is weighted
(:func:`boundary_shares`: t ds, or 2 pi r ds over the full ring), which edge loads, point
loads, contact areas and the supports on the axis x = 0 follow.
"""

from __future__ import annotations

import math

import numpy as np

from .case import Case


#: A node within this x the scene's size of x = 0 lies on the axis (the engine's AXIS_TOLERANCE).
AXIS_TOLERANCE = 1e-9


def is_axisymmetric(case: Case) -> bool:
    """True for ``[analysis] plane = "axisymmetric"`` (x = r, y = z, rings about x = 0)."""
    return case.record.analysis.plane == "axisymmetric"


def boundary_shares(
    nodes: np.ndarray, segments: np.ndarray, plane: str, thickness: float
) -> np.ndarray:
    """(S, 2): int N_k w ds over each linear segment for its end nodes k = 0, 1, the weight of a
    uniform traction at each end (its consistent nodal force = traction x share, exact for
    linear N).  Plane strain and plane stress: w = t, so t L/2 each; axisymmetric: w = 2 pi r,
    the full ring, so 2 pi L (2 r_k + r_other)/6 (r linear along the segment)."""
    length = np.linalg.norm(nodes[segments[:, 1]] - nodes[segments[:, 0]], axis=1)
    if plane == "axisymmetric":
        r0, r1 = nodes[segments[:, 0], 0], nodes[segments[:, 1], 0]
        return (2.0 * math.pi / 6.0) * length[:, None] * np.stack([2 * r0 + r1, r0 + 2 * r1], 1)
    half = 0.5 * (length * thickness)
    return np.stack([half, half], axis=1)


def node_shares(
    nodes: np.ndarray, segments: np.ndarray, plane: str, thickness: float, ids: np.ndarray
) -> np.ndarray:
    """Sum of :func:`boundary_shares` at each node of ``ids`` over the segments touching it:
    t L (L the tributary length) in the plane, int N_i 2 pi r ds (its ring) in axisymmetry."""
    per_node = np.zeros(len(nodes))
    if len(segments):
        share = boundary_shares(nodes, segments, plane, thickness)
        np.add.at(per_node, segments[:, 0], share[:, 0])
        np.add.at(per_node, segments[:, 1], share[:, 1])
    return per_node[ids]
