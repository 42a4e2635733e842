"""The contact pairs' geometry: pairs that start closed must face each other, node-to-node
contact needs matching meshes, and no pair may start penetrating."""

from __future__ import annotations

import numpy as np

from ..mesh import node_normals
from ..scene import Scene


FLIP = "flip contact.normal (or swap the contactor and target edges)"


def check_facing(scene: Scene, a, n, gap, tol, seg_a, b, seg_b, key: str,
                  fix: str = FLIP) -> None:
    """Pairs that start closed (or penetrating) must face each other: body a's surface faces
    the target (its outward normal against n) and, node to node, body b's surface faces body a
    (its outward normal along n).  Otherwise the normal points the wrong way and the pairing
    is geometrically impossible (it would hold the bodies together, or report a penetration
    that is not there)."""
    touching = gap <= tol
    away_a = touching & (np.einsum("ij,ij->i", node_normals(scene.nodes, seg_a, a), n) > 1e-6)
    away_b = np.zeros_like(away_a)
    if b is not None:
        away_b = touching & (np.einsum("ij,ij->i", node_normals(scene.nodes, seg_b, b), n)
                             < -1e-6)
    if (away_a | away_b).any():
        k = int(np.argmax(away_a | away_b))
        x, y = scene.nodes[a[k]]
        side = "the contactor surface faces away from the target" if away_a[k] else \
            "the target surface faces away from the contactor"
        raise scene.case.error(key, f"the contact normal ({n[k, 0]:.6g}, {n[k, 1]:.6g}) at node "
                               f"{int(a[k])} ({x:.6g}, {y:.6g}) points the wrong way ({side}): "
                               f"the normal must point from the target into the contactor body; "
                               f"{fix}")


def check_matching(scene: Scene, unpaired, seg_other, tol: float, label: str, other: str,
                    key: str) -> None:
    """Node to node needs matching meshes: an unpaired node of one side that lies on the other
    side's edge (within tolerance of one of its segments) would be free to pass through it."""
    if len(unpaired) == 0 or len(seg_other) == 0:
        return
    x = scene.nodes[unpaired][:, None, :]
    p, q = scene.nodes[seg_other[:, 0]][None], scene.nodes[seg_other[:, 1]][None]
    d = q - p
    t = np.einsum("ijk,ijk->ij", x - p, d) / np.einsum("ijk,ijk->ij", d, d)
    dist = np.linalg.norm(x - (p + t[..., None] * d), axis=2)
    # on a segment: within tolerance of it and strictly between its end nodes
    on = ((dist <= tol) & (t > 1e-9) & (t < 1.0 - 1e-9)).any(axis=1)
    if on.any():
        k = int(unpaired[np.argmax(on)])
        x0, y0 = scene.nodes[k]
        raise scene.case.error(f"{key}.tolerance", f"non-matching interface: node {k} "
                               f"({x0:.6g}, {y0:.6g}) of {label} lies on {other} but is paired "
                               f"with no node of it within {tol:g}: node_to_node contact needs "
                               f"matching interface nodes (same spacing and aligned origins "
                               f"on both sides)")


def check_gaps(scene: Scene, a: np.ndarray, gap: np.ndarray, tol: float, key: str,
                fix: str) -> None:
    if (gap < -tol).any():
        k = int(np.argmin(gap))
        x, y = scene.nodes[a[k]]
        raise scene.case.error(key, f"initial penetration at node {int(a[k])} ({x:.6g}, {y:.6g}) "
                               f"by {-gap[k]:.3g}: {fix}")
