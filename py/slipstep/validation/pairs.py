"""The contact pairs' geometry: pairs that start closed must face each other, node-to-node
contact needs matching meshes, no pair may start penetrating, and (3D) no rigid obstacle may
start inside a body.  Edges in 2D, faces (triangles) in 3D."""

from __future__ import annotations

import numpy as np

from ..scene import Scene
from ..mesh import tetrahedra as space_mesh
from ..contact.surfaces import closest_points, containing_tetrahedra
from ..toml_writing import point_text


FLIP = "flip contact.normal (or swap the contactor and target edges)"


def check_facing(scene: Scene, a, n, gap, tol, seg_a, b, seg_b, key: str, fix: str = FLIP) -> None:
    """Pairs that start closed (or penetrating) must face each other: body a's surface faces
    the target (its outward normal against n) and, node to node, body b's surface faces body a
    (its outward normal along n).  Otherwise the normal points the wrong way and the pairing
    is geometrically impossible (it would hold the bodies together, or report a penetration
    that is not there)."""
    touching = gap <= tol
    normals = scene.idealisation.surface_normals
    away_a = touching & (np.einsum("ij,ij->i", normals(scene.nodes, seg_a, a), n) > 1e-6)
    away_b = np.zeros_like(away_a)
    if b is not None:
        away_b = touching & (np.einsum("ij,ij->i", normals(scene.nodes, seg_b, b), n) < -1e-6)
    if (away_a | away_b).any():
        k = int(np.argmax(away_a | away_b))
        side = (
            "the contactor surface faces away from the target"
            if away_a[k]
            else "the target surface faces away from the contactor"
        )
        raise scene.case.error(
            key,
            f"the contact normal {point_text(n[k])} at node "
            f"{int(a[k])} {point_text(scene.nodes[a[k]])} points the wrong way "
            f"({side}): the normal must point from the target into the "
            f"contactor body; {fix}",
        )


def unit_face_normals(nodes: np.ndarray, triangles, ids) -> np.ndarray:
    """A face's outward unit normal at each node of ``ids``: its triangles' area-weighted
    normal, normalised (the 3D surface normal of :func:`check_facing`; 2D:
    :func:`slipstep.mesh.triangles.node_normals`, not normalised)."""
    m = space_mesh.node_normals(nodes, triangles, ids)
    return m / np.maximum(np.linalg.norm(m, axis=1), 1e-300)[:, None]


def on_segments(nodes: np.ndarray, points, segments, tol: float) -> np.ndarray:
    """Whether each of ``points`` lies on one of the ``segments`` (within tolerance of it and
    strictly between its end nodes)."""
    x = nodes[points][:, None, :]
    p, q = nodes[segments[:, 0]][None], nodes[segments[:, 1]][None]
    d = q - p
    t = np.einsum("ijk,ijk->ij", x - p, d) / np.einsum("ijk,ijk->ij", d, d)
    dist = np.linalg.norm(x - (p + t[..., None] * d), axis=2)
    return ((dist <= tol) & (t > 1e-9) & (t < 1.0 - 1e-9)).any(axis=1)


def on_triangles(nodes: np.ndarray, points, triangles, tol: float) -> np.ndarray:
    """Whether each of ``points`` lies on one of the ``triangles`` (within tolerance of it, not
    at one of its corners)."""
    near = closest_points(nodes[points], nodes, triangles)
    return (near["distance"] <= tol) & (near["bary"].max(axis=1) < 1.0 - 1e-9)


def check_matching(
    scene: Scene, unpaired, seg_other, tol: float, label: str, other: str, key: str
) -> None:
    """Node to node needs matching meshes: an unpaired node of one side that lies on the other
    side's edge (within tolerance of one of its segments) would be free to pass through it."""
    if len(unpaired) == 0 or len(seg_other) == 0:
        return
    on = scene.idealisation.on_boundary(scene.nodes, unpaired, seg_other, tol)
    if on.any():
        k = int(unpaired[np.argmax(on)])
        raise scene.case.error(
            f"{key}.tolerance",
            f"non-matching interface: node {k} "
            f"{point_text(scene.nodes[k])} of {label} lies on {other} but is paired "
            f"with no node of it within {tol:g}: node_to_node contact needs "
            f"matching interface nodes (same spacing and aligned origins "
            f"on both sides)",
        )


def check_gaps(
    scene: Scene, a: np.ndarray, gap: np.ndarray, tol: float, key: str, fix: str
) -> None:
    if (gap < -tol).any():
        k = int(np.argmin(gap))
        raise scene.case.error(
            key,
            f"initial penetration at node {int(a[k])} "
            f"{point_text(scene.nodes[a[k]])} by {-gap[k]:.3g}: {fix}",
        )


def check_outside(
    scene: Scene,
    a: np.ndarray,
    normal: np.ndarray,
    gap: np.ndarray,
    tol: float,
    key: str,
    what: str,
) -> None:
    """3D: a rigid obstacle must start outside every body.  The obstacle's point closest to a
    candidate that does not touch it (x_a - gap n, gap > tol) must not lie inside a body's
    volume (in one of its tetrahedra, not on the body's boundary): else the obstacle is beneath
    the surface, not in front of it (a plane through the body, an indenter buried in it)."""
    apart = np.flatnonzero(gap > tol)
    feet = scene.nodes[a[apart]] - gap[apart, None] * normal[apart]
    inside = containing_tetrahedra(feet, scene.nodes, scene.tetrahedra)
    found = np.flatnonzero(inside >= 0)
    if len(found):  # those on a body's boundary touch it from outside
        skin = space_mesh.boundary_faces(scene.tetrahedra)
        size = float(np.ptp(scene.nodes, axis=0).max())
        on_skin = closest_points(feet[found], scene.nodes, skin)["distance"] <= 1e-9 * size
        inside[found[on_skin]] = -1
    if (inside >= 0).any():
        k = int(np.argmax(inside >= 0))
        body = scene.bodies[int(scene.element_body[inside[k]])]
        raise scene.case.error(
            key,
            f"the {what} starts inside body '{body}': its point "
            f"{point_text(feet[k])} closest to node {int(a[apart[k]])} lies "
            f"inside the body (element {int(inside[k])}): move the {what} "
            f"out of the body, in front of the contact face",
        )
