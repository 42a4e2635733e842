"""Loads on the faces of 3D bodies: the consistent nodal forces of a uniform pressure and
traction on linear triangles (the face counterpart of :func:`slipstep.loads.vectors.edge_load`)."""

from __future__ import annotations

import numpy as np

from ..mesh.tetrahedra import triangle_normals


def face_load(
    nodes: np.ndarray,
    triangles: np.ndarray,
    n_nodes: int,
    pressure: float = 0.0,
    traction=(0.0, 0.0, 0.0),
) -> np.ndarray:
    """Consistent nodal loads of a uniform pressure and/or traction on linear triangles
    (outward, body behind them): the traction t = traction - pressure * n on a triangle of area
    A gives each corner t A / 3 (int N_i dA = A/3, exact for linear N), so the forces sum to
    t times the face's area.  Returns a (3 n_nodes,) vector."""
    f = np.zeros(3 * n_nodes)
    if len(triangles) == 0:
        return f
    normal, area = triangle_normals(nodes, triangles)
    t = np.asarray(traction, dtype=np.float64)[None, :] - pressure * normal
    share = t * (area / 3.0)[:, None]
    for corner in range(3):
        for c in range(3):
            np.add.at(f, 3 * triangles[:, corner] + c, share[:, c])
    return f


#: The part of a sphere's cut disc (z = R) each portion meshes.
DISC_SHARE = {"eighth": 0.25, "quarter": 0.5, "half": 1.0}


def sphere_cut_pressure(
    P: float, R: float, portion: str, nodes: np.ndarray, top: np.ndarray
) -> float:
    """The pressure on a sphere's cut face ``top`` under ``[load] P``: its share of P (a quarter
    for the eighth, a half for the quarter, all of it for the half) over the face's meshed area,
    so the portion carries exactly its share (q = P / (pi R^2) up to the polygon's area deficit,
    0.4 % at 26 triangles on the quarter disc)."""
    _, area = triangle_normals(nodes, top)
    return P * DISC_SHARE[portion] / float(area.sum())


def sphere_load_pressure(scene) -> float:
    """The pressure of ``[load] P`` on the cut face ``top`` of its sphere body
    (:func:`sphere_cut_pressure` over the face as meshed)."""
    load = scene.case.record.load
    mesh = scene.case.record.hertz_body.mesh
    return sphere_cut_pressure(
        load.P,
        mesh["R"],
        mesh["portion"],
        scene.nodes,
        scene.global_boundary(load.body, "top"),
    )
