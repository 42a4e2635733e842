"""Contact on faces (3D): the candidate rows of a ``[[contact]]`` between faces (node a, node b
or -1 for a rigid obstacle, the normal from the target towards node a, the initial gap, and a
tangent basis (t1, t2) per pair, docs/engine_api.md's 3D model) for a rigid plane, sphere,
cylinder and triangulated surface, node to node and node to surface
(:mod:`slipstep.contact.node_to_surface`), and the area each pair's force acts on.  The faces'
implementation beside :mod:`slipstep.contact.edges`; :mod:`slipstep.contact.pairs` gathers the
rows; the
checks of the pairs (facing, matching, penetration, an obstacle inside a body) are
:mod:`slipstep.validation.pairs`."""

from __future__ import annotations

import numpy as np

from ..case_record import (
    Contact,
    NodeToNode,
    NodeToSurface,
    RigidObstacle3D,
    RigidSurface,
    Window3D,
)
from .pairs import node_to_node_pairs
from ..validation.pairs import check_facing, check_gaps, check_outside
from . import node_to_surface as mortar
from .indenters import pyramid
from ..mesh.tetrahedra import node_normals, triangle_normals
from ..mesh.tetrahedron_files import read_surface
from .surfaces import (
    closest_points,
    consistently_oriented,
    enclosed_volume,
    open_edge,
    pseudo_normals,
)


def tangent_basis(normal: np.ndarray) -> np.ndarray:
    """(P, 2, 3) the tangent basis (t1, t2) of each unit normal, the contract's own:
    t1 = (e x n)/|e x n| with e the coordinate axis least aligned with n (the first of a tie),
    t2 = n x t1, so t1 x t2 = n."""
    n = np.asarray(normal, dtype=float).reshape(-1, 3)
    e = np.eye(3)[np.argmin(np.abs(n), axis=1)]
    t1 = np.cross(e, n)
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    return np.stack([t1, np.cross(n, t1)], axis=1)


def align_to_supports(normal: np.ndarray, tangent: np.ndarray, held: np.ndarray) -> np.ndarray:
    """The tangent bases with, for a contactor node held along exactly one axis k (a node on
    a symmetry plane), t1 the tangent the support takes: t1 ∝ |P n|^2 e_k - n_k P n (P drops
    component k), the one tangent whose free part is parallel to the normal's, so that the
    engine can leave its row to the support instead of a row that duplicates the normal's (a
    tilted normal on a symmetry plane); t2 = n x t1. ``held`` (P, 3) bool per pair's node.
    A basis that already has such a tangent is kept (the same axes as before for a normal in
    a coordinate plane)."""
    out = tangent.copy()
    for p in np.flatnonzero(held.sum(axis=1) == 1):
        n, k = normal[p], int(np.argmax(held[p]))
        free_n = np.where(held[p], 0.0, n)
        if any(_parallel(np.where(held[p], 0.0, t), free_n) for t in tangent[p]):
            continue
        t1 = free_n @ free_n * np.eye(3)[k] - n[k] * free_n
        t1 /= np.linalg.norm(t1)
        out[p] = [t1, np.cross(n, t1)]
    return out


def _parallel(u: np.ndarray, v: np.ndarray, tol: float = 1e-12) -> bool:
    """u has no part across v (u = 0 counts)."""
    return np.linalg.norm(u - (u @ v) / (v @ v) * v) < tol


def tributary_areas(nodes: np.ndarray, triangles: np.ndarray, ids: np.ndarray) -> np.ndarray:
    """The consistent area of each node of ``ids`` on a face: int N_i dA over its triangles, a
    third of each one's area (a uniform pressure p puts p x this area on every node)."""
    _, area = triangle_normals(nodes, triangles)
    per_node = np.zeros(len(nodes))
    for corner in range(3):
        np.add.at(per_node, triangles[:, corner], area / 3.0)
    return per_node[np.asarray(ids)]


def pair_rows(scene, c: Contact, key: str) -> dict:
    """The candidate pairs of one 3D ``[[contact]]`` (``key`` names it in messages): node_a,
    node_b (-1 rigid), normal, initial gap, the node-to-surface weights, foot and own gap, and
    ``area``, node a's area on its face (:func:`slipstep.contact.pairs.contact_pairs` gathers
    them, with the tangent basis of :func:`tangent_basis`)."""
    if c.kind == "node_to_surface":
        return _node_to_surface_pairs(scene, c, key)
    if c.kind == "node_to_node":
        return _node_to_node_pairs(scene, c, key)
    return _rigid_pairs(scene, c, key)


def _window(scene, c: Window3D, key: str, body: str, face: str) -> np.ndarray:
    """Global ids (sorted) of a face's nodes inside the contact's x/y/z window."""
    candidates = np.unique(scene.global_boundary(body, face))
    x = scene.nodes[candidates]
    inside = np.ones(len(candidates), dtype=bool)
    for axis, name in enumerate("xyz"):
        low, high = c.window(name)
        inside &= (x[:, axis] >= low) & (x[:, axis] <= high)
    if not inside.any():
        raise scene.case.error(
            f"{key}.x_max",
            f"no node of face '{face}' of body '{body}' lies "
            f"in the candidate window: widen x_min/x_max/y_min/y_max/z_min/"
            f"z_max",
        )
    return candidates[inside]


def _rigid_pairs(scene, c: RigidObstacle3D, key: str) -> dict:
    """The pairs of a rigid obstacle: its shape gives each candidate's normal (from the obstacle
    into the body, fixed: small sliding) and gap; then the facing, penetration and
    outside-the-body checks, gaps within tolerance snapped to 0, node_b = -1."""
    a = _window(scene, c, key, c.body, c.face)
    n, gap, what, fix = SHAPES[c.kind](scene, c, key, a)
    face = scene.global_boundary(c.body, c.face)
    check_facing(
        scene,
        a,
        n,
        gap,
        c.tolerance,
        face,
        None,
        None,
        key,
        f"check the obstacle's side or normal ({what})",
    )
    check_gaps(scene, a, gap, c.tolerance, key, fix)
    check_outside(scene, a, n, gap, c.tolerance, key, what)
    if c.kind == "rigid_surface" and c.indenter:
        check_indenter_size(scene, c, key, float(gap.min()))
    gap = np.where(np.abs(gap) <= c.tolerance, 0.0, gap)
    return {
        "node_a": a,
        "node_b": np.full(len(a), -1, dtype=np.int64),
        "normal": n,
        "gap": gap,
        "area": tributary_areas(scene.nodes, face, a),
        "foot": np.tile([-1.0, -1.0, -1.0, 0.0, 0.0, 0.0], (len(a), 1)),
        "point_gap": np.full(len(a), np.nan),
    }


def check_indenter_size(scene, c: RigidSurface, key: str, gap: float) -> None:
    """A pyramid must stand higher than it is pressed in: its depth is its tip's largest travel
    down the path (the motion's -z times the factor, largest at a stage end) less its starting
    gap; a base at ``size`` above the tip within that depth would enter the body."""
    path = scene.case.path
    index = next(i for i, x in enumerate(scene.case.record.contact) if x is c)
    load = next((x for x in path.loads if x.array == "contact" and x.index == index), None)
    if load is None:
        return
    column = path.names.index(load.label)
    depth = max(-row[column] * c.motion[2] for row in path.factors) - max(gap, 0.0)
    if depth >= c.size:
        raise scene.case.error(
            f"{key}.size",
            f"= {c.size:g} is not allowed: the "
            f"{c.indenter} pyramid is pressed {depth:.4g} deep, deeper "
            f"than its height above the tip: its base would enter the body; "
            f"give size > {depth:.4g} (e.g. {2 * depth:.3g})",
        )


def _plane(scene, c, key, a):
    n = np.asarray(c.normal, dtype=float)
    n = n / np.linalg.norm(n)
    gap = (scene.nodes[a] - np.asarray(c.point)) @ n
    return (
        np.tile(n, (len(a), 1)),
        gap,
        "rigid plane",
        "move the body or the plane (contact.point) so that they do not overlap",
    )


def _radial(scene, c, key, a, d: np.ndarray, where: str):
    """Normal and gap of a body outside (inside) a round obstacle, d the offsets of the nodes
    from its centre (axis); a node at the centre (axis) has no normal: an error naming it."""
    r = np.linalg.norm(d, axis=1)
    at_centre = r <= 1e-9 * c.radius
    if at_centre.any():
        k = int(np.argmax(at_centre))
        raise scene.case.error(
            f"{key}.radius",
            f"node {int(a[k])} lies on the {where} of the "
            f"rigid obstacle, where the normal (the direction to its nearest "
            f"point) is undefined: move the obstacle, or leave the node out "
            f"of the candidates (x_min ... z_max)",
        )
    sign = 1.0 if c.side == "outside" else -1.0
    return sign * d / r[:, None], sign * (r - c.radius)


def _sphere(scene, c, key, a):
    n, gap = _radial(scene, c, key, a, scene.nodes[a] - np.asarray(c.centre), "centre")
    return (
        n,
        gap,
        "rigid sphere",
        "move the body or the sphere (contact.centre, radius) so " "that they do not overlap",
    )


def _cylinder(scene, c, key, a):
    e = np.asarray(c.axis, dtype=float)
    e = e / np.linalg.norm(e)
    d = scene.nodes[a] - np.asarray(c.point)
    n, gap = _radial(scene, c, key, a, d - np.outer(d @ e, e), "axis")
    return (
        n,
        gap,
        "rigid cylinder",
        "move the body or the cylinder (contact.point, radius) " "so that they do not overlap",
    )


def rigid_surface(case, c: RigidSurface, key: str) -> tuple[np.ndarray, np.ndarray]:
    """(points, triangles) of a ``rigid_surface``, oriented so that the body's side is the one
    the normals point to: a closed surface ("outside"/"inside") outwards (inwards), any surface
    ("front"/"back") as its first triangle (against it)."""
    if c.indenter:
        points, tris = pyramid(c.indenter, c.tip, c.size)
    else:
        points, tris = read_surface(case.base_dir / c.file, c.scale)
    where = f"{case.source}: {key}.file"
    if c.side in ("outside", "inside"):
        hole = open_edge(tris)
        if hole is not None:
            i, j, count = hole
            raise case.error(
                f"{key}.file",
                f"the surface is not closed: its edge between "
                f"vertices {i} and {j} belongs to {count} "
                f"triangle(s), not 2; side = \"{c.side}\" needs a "
                f"closed surface: close it, or use side = \"front\" "
                f"or \"back\" (the side its triangles face)",
            )
    tris = consistently_oriented(tris, where)
    if c.side in ("outside", "inside") and enclosed_volume(points, tris) < 0:
        tris = tris[:, [0, 2, 1]]  # outwards
    if c.side in ("inside", "back"):
        tris = tris[:, [0, 2, 1]]
    return points, tris


def _surface(scene, c, key, a):
    """Per node its closest point on the surface: inside a triangle its normal; at an edge or
    corner the direction from the closest point to the node (on the body's side of the
    triangles that meet there), and for a node sitting on it the direction of the feature's cone
    of normals (spanned by the meeting triangles' normals) nearest to minus the body's own
    outward normal: that normal itself under a pyramid's tip or along an edge it fits in, else
    the cone's nearest side (`nearest_in_cone`)."""
    points, tris = rigid_surface(scene.case, c, key)
    x = scene.nodes[a]
    near = closest_points(x, points, tris)
    face_n, _ = triangle_normals(points, tris)
    n = face_n[near["triangle"]].copy()
    gap = np.einsum("pk,pk->p", x - near["foot"], n)
    size = float(np.ptp(points, axis=0).max())
    meeting = near["near"] <= near["distance"][:, None] + 1e-9 * size
    on_feature = near["bary"].min(axis=1) <= 1e-9
    touch = max(c.tolerance, 1e-9 * size)
    outward = node_normals(scene.nodes, scene.global_boundary(c.body, c.face), a)
    side = pseudo_normals(points, tris, near["triangle"], near["bary"])
    for p in np.flatnonzero(on_feature):
        mine = np.flatnonzero(meeting[p])
        if near["distance"][p] > touch:
            r = (x[p] - near["foot"][p]) / near["distance"][p]
            sign = 1.0 if r @ side[p] >= 0 else -1.0
            n[p], gap[p] = sign * r, sign * near["distance"][p]
        else:
            n[p] = nearest_in_cone(face_n[mine], -outward[p])
            gap[p] = (x[p] - near["foot"][p]) @ n[p]
    return (
        n,
        gap,
        "rigid surface",
        "move the body or the surface (its file, or tip) so that " "they do not overlap",
    )


def nearest_in_cone(normals: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The unit direction of the cone spanned by ``normals`` (rows, unit) nearest to the unit
    ``v``: the projection of v onto the cone (non-negative least squares), normalized; the
    normal most aligned with v if v projects onto the cone's apex."""
    from scipy.optimize import nnls

    c, _ = nnls(normals.T, v)
    d = normals.T @ c
    size = np.linalg.norm(d)
    return d / size if size > 1e-12 else normals[np.argmax(normals @ v)]


#: Each rigid obstacle's normals and gaps.
SHAPES = {
    "rigid_plane": _plane,
    "rigid_sphere": _sphere,
    "rigid_cylinder": _cylinder,
    "rigid_surface": _surface,
}


def _node_to_node_pairs(scene, c: NodeToNode, key: str) -> dict:
    """Matching face nodes (:func:`slipstep.contact.pairs.node_to_node_pairs`), with the
    contactor nodes' areas."""
    a, b, n, gap = node_to_node_pairs(scene, c, key)
    face_a = scene.global_boundary(c.body_a, c.face_a)
    return {
        "node_a": a,
        "node_b": b,
        "normal": n,
        "gap": gap,
        "area": tributary_areas(scene.nodes, face_a, a),
        "foot": np.tile([-1.0, -1.0, -1.0, 0.0, 0.0, 0.0], (len(a), 1)),
        "point_gap": np.full(len(a), np.nan),
    }


def _node_to_surface_pairs(scene, c: NodeToSurface, key: str) -> dict:
    """Mortar rows of the contactor nodes of face_a in the window against the triangles of
    face_b (:mod:`.mortar`)."""
    face_a = scene.global_boundary(c.body_a, c.face_a)
    face_b = scene.global_boundary(c.body_b, c.face_b)
    candidates = _window(scene, c, key, c.body_a, c.face_a)
    _, areas = triangle_normals(scene.nodes, face_a)
    rows = mortar.node_to_surface_rows(
        scene.nodes, face_a, face_b, candidates, 1e-9 * float(areas.min())
    )
    if not len(rows["node_a"]):
        raise scene.case.error(
            f"{key}.face_b",
            f"no node of {c.body_a}:{c.face_a} in "
            f"the candidate window projects onto {c.body_b}:"
            f"{c.face_b}: check the faces, or widen the window",
        )
    a = rows["node_a"]
    check_gaps(
        scene,
        a,
        np.minimum(rows["gap"], rows["point_gap"]),
        c.tolerance,
        key,
        f"move body '{c.body_a}' away from body '{c.body_b}'",
    )
    touching = (np.abs(rows["gap"]) <= c.tolerance) | (np.abs(rows["point_gap"]) <= c.tolerance)
    rows["gap"] = np.where(touching, 0.0, rows["gap"])  # first point of contact: closed
    return rows
