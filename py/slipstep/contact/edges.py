"""Contact on edges (2D): the candidate rows of a ``[[contact]]`` between edges (node a, node b
or -1 for a rigid obstacle, normal from the target towards node a, initial gap: the C_n, C_t
columns of Eqs. 45-46 per pair) for rigid lines, circles and polylines, node-to-node and
node-to-segment (:mod:`slipstep.contact.node_to_segment`) contact, and the length and area each
pair's force acts on; :mod:`slipstep.contact.pairs` gathers the rows.  The
geometric checks of the pairs (facing, matching meshes, penetration) are
:mod:`slipstep.validation.pairs`."""

from __future__ import annotations

import numpy as np

from ..mesh import triangles as meshing
from . import node_to_segment as mortar
from ..engine_model import ContactPairs
from ..scene import Scene
from ..case_record import (
    Contact,
    NodeToSegment,
    RigidCircle,
    RigidLine,
    RigidObstacle2D,
    RigidPolyline,
)
from ..section import is_axisymmetric, node_shares
from ..validation.pairs import FLIP, check_facing, check_gaps
from .pairs import node_to_node_pairs


def pair_rows(scene: Scene, c: Contact, key: str) -> dict:
    """The candidate pairs of one 2D ``[[contact]]`` (``key`` names it in messages): node_a,
    node_b (-1 rigid), normal (from the target towards node_a), initial gap, the node-to-segment
    weights, foot and own gap, and ``length``, node a's tributary length on its edge
    (:func:`slipstep.contact.pairs.contact_pairs` gathers them)."""
    if c.kind == "node_to_segment":
        a, b, normal, gap, length, weights, foot, point = _node_to_segment_pairs(scene, c, key)
    else:
        if isinstance(c, RigidObstacle2D):
            a, b, normal, gap = RIGID_PAIRS[c.kind](scene, c, key)
        else:
            a, b, normal, gap = node_to_node_pairs(scene, c, key)
        length = tributary_lengths(scene.nodes, scene.global_edge(*c.contactor), a)
        weights = [[]] * len(a)
        foot, point = np.tile([-1.0, -1.0, 0.0], (len(a), 1)), np.full(len(a), np.nan)
    return {
        "node_a": a,
        "node_b": b,
        "normal": normal,
        "gap": gap,
        "length": length,
        "weights": weights,
        "foot": foot,
        "point_gap": point,
    }


def contact_areas(scene: Scene, pairs: ContactPairs) -> np.ndarray:
    """(P,) the area each candidate pair's contact force acts on (pressure = lambda_n / area):
    node a's tributary length L x the thickness in plane strain and plane stress; in
    axisymmetry its ring over the contactor edge, 2 pi int N_a r ds (:func:`node_shares`;
    2 pi r L inside a uniformly divided edge, pi L^2/3 at the axis with L its segment), times
    L / L_edge for a node-to-segment row (the part of its surface that projects).  This is the
    consistent area: a uniform pressure p puts lambda = p x area on every node, so a smooth
    pressure is read node by node to O(h^2), also at the axis (the lumped disc pi (L/2)^2 there
    would read it 4/3 too high)."""
    case = scene.case.record
    plane, t = case.analysis.plane, case.analysis.thickness
    if plane != "axisymmetric":
        return scene.pair_length * t
    area = np.zeros(len(scene.pair_length))
    for i, c in enumerate(case.contact):
        mine = np.flatnonzero(scene.pair_contact == i)
        seg = scene.global_edge(*c.contactor)
        a = pairs.node_a[mine]
        area[mine] = node_shares(scene.nodes, seg, plane, t, a)
        if c.kind == "node_to_segment":
            area[mine] *= scene.pair_length[mine] / tributary_lengths(scene.nodes, seg, a)
    return area


def _node_to_segment_pairs(scene: Scene, c: NodeToSegment, key: str):
    """Mortar-style rows of the contactor nodes of edge_a in the window against the polyline
    edge_b (slipstep.contact.node_to_segment): node_a, node_b, normal, gap, tributary length, weights."""
    seg_a = scene.global_edge(c.body_a, c.edge_a)
    seg_b = scene.global_edge(c.body_b, c.edge_b)
    candidates = np.unique(seg_a)
    xy = scene.nodes[candidates]
    inside = (
        (xy[:, 0] >= c.x_min)
        & (xy[:, 0] <= c.x_max)
        & (xy[:, 1] >= c.y_min)
        & (xy[:, 1] <= c.y_max)
    )
    length_scale = float(
        np.linalg.norm(scene.nodes[seg_a[:, 1]] - scene.nodes[seg_a[:, 0]], axis=1).min()
    )
    rows = mortar.node_to_segment_pairs(
        scene.nodes,
        seg_a,
        seg_b,
        candidates[inside],
        1e-9 * length_scale,
        radial=is_axisymmetric(scene.case),
    )
    if not rows["node_a"]:
        raise scene.case.error(
            f"{key}.edge_b",
            f"no node of {c.body_a}:{c.edge_a} in the "
            f"candidate window projects onto {c.body_b}:{c.edge_b}: "
            f"check the edges, or widen x_min/x_max/y_min/y_max",
        )
    a = np.asarray(rows["node_a"], dtype=np.int64)
    normal, gap, point = (np.asarray(rows[k]) for k in ("normal", "gap", "point_gap"))
    check_gaps(
        scene,
        a,
        np.minimum(gap, point),
        c.tolerance,
        key,
        f"move body '{c.body_a}' away from body '{c.body_b}'",
    )
    # a node that touches starts its row closed (slipstep.contact.node_to_segment: first point of contact)
    gap = np.where((np.abs(gap) <= c.tolerance) | (np.abs(point) <= c.tolerance), 0.0, gap)
    return (
        a,
        np.asarray(rows["node_b"], dtype=np.int64),
        normal,
        gap,
        np.asarray(rows["length"]),
        rows["weights"],
        np.asarray(rows["foot"], dtype=float),
        point,
    )


def tributary_lengths(nodes: np.ndarray, segments: np.ndarray, ids: np.ndarray) -> np.ndarray:
    """Half the summed length of the edge segments touching each node (lumped length L)."""
    length = np.linalg.norm(nodes[segments[:, 1]] - nodes[segments[:, 0]], axis=1)
    per_node = np.zeros(len(nodes))
    np.add.at(per_node, segments[:, 0], 0.5 * length)
    np.add.at(per_node, segments[:, 1], 0.5 * length)
    return per_node[ids]


def _window_candidates(scene: Scene, c: RigidObstacle2D, key: str) -> np.ndarray:
    """Global ids (sorted) of the nodes of a rigid contact's ``edge`` inside its x/y window."""
    candidates = np.unique(scene.global_edge(c.body, c.edge))
    xy = scene.nodes[candidates]
    inside = (
        (xy[:, 0] >= c.x_min)
        & (xy[:, 0] <= c.x_max)
        & (xy[:, 1] >= c.y_min)
        & (xy[:, 1] <= c.y_max)
    )
    a = candidates[inside]
    if len(a) == 0:
        raise scene.case.error(
            f"{key}.x_max",
            f"no node of edge '{c.edge}' of body "
            f"'{c.body}' lies in the candidate window: widen x_min/x_max/"
            f"y_min/y_max",
        )
    return a


def _rigid_pairs(scene: Scene, c: RigidObstacle2D, key: str, a, n, gap, fix: str, flip: str):
    """The pairs of a rigid obstacle from its candidates ``a``, their normals ``n`` (from the
    obstacle into the body, fixed: small sliding) and initial gaps: the facing and penetration
    checks, gaps within tolerance snapped to 0, node_b = -1."""
    check_facing(
        scene,
        a,
        n,
        gap,
        c.tolerance,
        scene.global_edge(c.body, c.edge),
        None,
        None,
        key,
        flip,
    )
    check_gaps(scene, a, gap, c.tolerance, key, fix)
    gap = np.where(np.abs(gap) <= c.tolerance, 0.0, gap)
    return a, np.full(len(a), -1, dtype=np.int64), n, gap


def _rigid_line_pairs(scene: Scene, c: RigidLine, key: str):
    """Body nodes on ``edge`` within the x/y window, against the line through ``point``."""
    a = _window_candidates(scene, c, key)
    n = np.asarray(c.normal) / np.linalg.norm(c.normal)
    gap = (scene.nodes[a] - np.asarray(c.point)) @ n
    return _rigid_pairs(
        scene,
        c,
        key,
        a,
        np.tile(n, (len(a), 1)),
        gap,
        "move the body away from the line or the line (contact.point) away " "from the body",
        FLIP,
    )


def _rigid_circle_pairs(scene: Scene, c: RigidCircle, key: str):
    """Body nodes on ``edge`` within the x/y window, against the circle (``centre``,
    ``radius``): per node the closest point of the circle, the normal from the circle into the
    body, (x - c)/|x - c| for a body ``outside`` it and (c - x)/|x - c| ``inside``, and the gap
    |x - c| - R (outside) or R - |x - c| (inside).  A candidate at the centre (within 1e-9 R:
    round-off) has no closest point, hence no normal: an error naming it."""
    a = _window_candidates(scene, c, key)
    centre, radius = np.asarray(c.centre, dtype=float), float(c.radius)
    d = scene.nodes[a] - centre
    r = np.linalg.norm(d, axis=1)
    at_centre = r <= 1e-9 * radius
    if at_centre.any():
        k = int(np.argmax(at_centre))
        x, y = scene.nodes[a[k]]
        raise scene.case.error(
            f"{key}.centre",
            f"node {int(a[k])} ({x:.6g}, {y:.6g}) lies at "
            f"the centre of the rigid circle, where the normal (the direction "
            f"to the nearest point of the circle) is undefined: move the "
            f"centre, or leave the node out of the candidates (x_min/x_max/"
            f"y_min/y_max)",
        )
    sign = 1.0 if c.side == "outside" else -1.0
    n = sign * d / r[:, None]
    gap = sign * (r - radius)
    return _rigid_pairs(
        scene,
        c,
        key,
        a,
        n,
        gap,
        "move the body or the circle (contact.centre, contact.radius) so that "
        "they do not overlap",
        'check contact.side ("outside": the body is outside the circle; '
        '"inside": in a hole or cup) and contact.centre',
    )


def _rigid_polyline_pairs(scene: Scene, c: RigidPolyline, key: str):
    """Body nodes on ``edge`` within the x/y window, against the polyline ``points``
    (:func:`polyline_closest`, told the body's outward normal at each node and the contact's
    tolerance, which set the contact direction of a node sitting on a convex corner).  A node
    that projects nowhere (its closest point is an end point of an open polyline and it lies
    beyond it) is not a candidate."""
    a = _window_candidates(scene, c, key)
    outward = meshing.node_normals(scene.nodes, scene.global_edge(c.body, c.edge), a)
    near = polyline_closest(
        np.asarray(c.points, dtype=float), c.side, scene.nodes[a], outward, c.tolerance
    )
    if not near["onto"].any():
        raise scene.case.error(
            f"{key}.points",
            f"no candidate node of edge '{c.edge}' of "
            f"body '{c.body}' projects onto the rigid polyline (a "
            f"contactor node that projects nowhere is not a candidate): "
            f"extend the polyline (points) or widen the window (x_min/x_max/"
            f"y_min/y_max)",
        )
    keep = near["onto"]
    return _rigid_pairs(
        scene,
        c,
        key,
        a[keep],
        near["normal"][keep],
        near["gap"][keep],
        "move the body or the polyline (contact.points) so that they do not " "overlap",
        'check contact.side (the side the body lies on, walking the polyline '
        'from its first point to its last)',
    )


def polyline_closest(
    points: np.ndarray,
    side: str,
    xy: np.ndarray,
    outward: np.ndarray | None = None,
    touch: float = 0.0,
) -> dict:
    """The closest points of the polyline ``points`` (M, 2) to the points ``xy`` (N, 2).

    Per point: ``segment`` (the closest segment, the first one of a tie), ``vertex`` (the index
    of the vertex that is the closest point, else -1), ``foot`` (the closest point), ``normal``
    (the direction in which the obstacle resists the point: the unit normal of its segment
    towards ``side``, "left" or "right" walking from the first point to the last; at a vertex
    :func:`_vertex_normals`), ``gap`` = (x - foot).normal, ``onto`` (False for a point that
    projects nowhere: its closest point is an end point of an open polyline and its
    projection on that end segment lies beyond it, by more than 1e-9 of the segment's length)
    and ``s`` (the arc length of the foot from the first point; beyond an end, the projection
    on the extended end segment, so s < 0 before the first point and s > the length after the
    last).  ``outward`` (N, 2), the body's outward surface normals at the points, and
    ``touch``, the distance within which a point sits on a vertex, serve convex corners."""
    points, xy = np.asarray(points, dtype=float), np.asarray(xy, dtype=float).reshape(-1, 2)
    start, d = points[:-1], np.diff(points, axis=0)
    length = np.linalg.norm(d, axis=1)
    cum = np.concatenate([[0.0], np.cumsum(length)])
    seg_n = np.stack([-d[:, 1], d[:, 0]], axis=1) / length[:, None]  # left normals
    if side == "right":
        seg_n = -seg_n
    raw = np.einsum("psk,sk->ps", xy[:, None, :] - start[None], d) / length**2
    t = np.clip(raw, 0.0, 1.0)
    dist = np.linalg.norm(xy[:, None, :] - (start[None] + t[..., None] * d[None]), axis=2)
    seg = np.argmin(dist, axis=1)
    rows = np.arange(len(xy))
    t_seg, raw_seg = t[rows, seg], raw[rows, seg]
    vertex = np.where(t_seg == 0.0, seg, np.where(t_seg == 1.0, seg + 1, -1))
    foot = start[seg] + t_seg[:, None] * d[seg]
    at = vertex >= 0
    foot[at] = points[vertex[at]]
    closed = bool(np.array_equal(points[0], points[-1]))
    m = np.zeros_like(xy) if outward is None else np.asarray(outward, dtype=float).reshape(-1, 2)
    normal = _vertex_normals(points, seg_n, closed, xy, vertex, seg_n[seg], m, touch)
    gap = np.einsum("pk,pk->p", xy - foot, normal)
    last = len(d) - 1
    beyond = np.zeros(len(xy), dtype=bool)
    if not closed:
        beyond = ((seg == 0) & (raw_seg < -1e-9)) | ((seg == last) & (raw_seg > 1.0 + 1e-9))
    s = cum[seg] + t_seg * length[seg]
    s = np.where(beyond & (seg == 0) & (raw_seg < 0.0), raw_seg * length[0], s)
    s = np.where(beyond & (seg == last) & (raw_seg > 1.0), cum[last] + raw_seg * length[last], s)
    return {
        "segment": seg,
        "vertex": vertex,
        "foot": foot,
        "normal": normal,
        "gap": gap,
        "onto": ~beyond,
        "s": s,
    }


def _vertex_normals(points, seg_n, closed: bool, xy, vertex, normal, outward, touch: float):
    """``normal`` with the rule for the points whose closest point is an interior vertex (or
    the joint of a closed polyline, between its last and first segments; an end point of an
    open polyline keeps its one segment's normal).

    * A concave vertex (the segment after it turns towards the body side of the one before,
      n_before . d_after >= 0; or goes straight on): the normalised average of the two
      segments' normals.  Only a point on the vertex itself has it as closest point there (a
      body in a corner of a die), pressed by both faces.
    * A convex vertex (the obstacle's corner points into the body): for a point off it, the
      direction from the vertex to the point, the true closest-point normal (gap = the
      distance).  A point that sits on it (within ``touch``, or 1e-9 of the shorter segment:
      round-off) has no such direction: :func:`_corner_contact_normal`."""
    normal = normal.copy()
    length = np.linalg.norm(np.diff(points, axis=0), axis=1)
    last = len(length) - 1
    for k in np.unique(vertex[vertex >= 0]):
        if 0 < k < len(points) - 1:
            before, after = k - 1, k
        elif closed:
            before, after = last, 0
        else:
            continue  # an end point: its one segment's normal
        here = vertex == k
        mean = seg_n[before] + seg_n[after]  # never 0: the schema refuses folding segments
        mean /= np.linalg.norm(mean)
        if seg_n[before] @ (points[after + 1] - points[after]) >= 0.0:  # concave or straight
            normal[here] = mean
            continue
        r = xy[here] - points[k]
        dist = np.linalg.norm(r, axis=1)
        sits = dist <= max(touch, 1e-9 * min(length[before], length[after]))
        on = _corner_contact_normal(seg_n[before], seg_n[after], mean, outward[here])
        normal[here] = np.where(sits[:, None], on, r / np.where(sits, 1.0, dist)[:, None])
    return normal


def _corner_contact_normal(n0, n1, mean, outward):
    """The contact normal of body points sitting on a convex corner whose faces have the
    normals n0, n1 (towards the body; ``mean`` their normalised average), given the body's
    outward surface normals there (K, 2).

    At the corner a frictionless obstacle can push along any direction of its cone of normals
    (between n0 and n1); which one acts is set by the body's own surface, whose normal m
    points at the obstacle: the contact normal is the direction of the cone nearest to -m.
    Inside the cone it is -m itself (a wedge's tip on a flat: the flat's normal); outside, the
    nearer face's normal, the face the body's surface lies along (a punch's edge node is
    pressed by the punch face, not pushed sideways by its side: the average of the faces would
    push it outwards at 45 degrees with a force no face in contact exerts).  Without a body
    normal (zero) the cone's middle, ``mean``."""
    size = np.linalg.norm(outward, axis=1)
    v = -outward / np.where(size > 0.0, size, 1.0)[:, None]
    turn = _cross(n0, n1)
    inside = (_cross(n0, v) * turn >= 0.0) & (_cross(v, n1) * turn >= 0.0) & (v @ mean > 0.0)
    nearer = np.where((v @ n0 >= v @ n1)[:, None], n0, n1)
    return np.where((size == 0.0)[:, None], mean, np.where(inside[:, None], v, nearer))


def _cross(a, b):
    """The z component of a x b for 2D vectors (any leading shape)."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


#: The pair builder of each rigid obstacle kind.
RIGID_PAIRS = {
    "rigid_line": _rigid_line_pairs,
    "rigid_circle": _rigid_circle_pairs,
    "rigid_polyline": _rigid_polyline_pairs,
}
