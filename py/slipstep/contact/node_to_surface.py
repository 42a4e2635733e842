"""Node-to-surface contact between independently meshed bodies in space, mortar-weighted on
triangles as :mod:`slipstep.contact.node_to_segment` weights segments (the same compressed rows for the engine).

One constraint row per contactor node j; with N_j its linear shape function on the contactor
face, N̂_l the target's, y(x) the point of the target triangle whose plane x projects onto
along its normal n (small sliding: everything fixed at the start):

    S_j  = ∫ N_j dA                          D_jk = ∫ N_j N_k dA       M_jl = ∫ N_j N̂_l(y) dA
    g_j  = ∫ N_j (x − y)·n dA / S_j          w^j  = (Σ_k D_jk e_k − Σ_l M_jl e_l) / S_j

applied to n_j (the N_j-weighted mean of the target normals) and to its tangents.  The integrals
run over the pieces of each contactor triangle that project into one target triangle: the
target triangle clipped by the contactor triangle's projection (Sutherland–Hodgman in the target
plane), mapped back onto the contactor plane, each piece cut into triangles and integrated by the
interior three-point rule (exact for the products of two linear functions and for the linear
gap).  Hence Σ_k D_jk = Σ_l M_jl = S_j (the weights sum to 1 and −1) and, on coinciding
surfaces, a linear displacement u = a + B x gives Σ_k D_jk u_k − Σ_l M_jl u_l = ∫ N_j (u(x) − u(y))
dA = 0 in every row, for any pair of meshes: the kinematic half of the contact patch test.  A
uniform pressure p, λ_j = p S_j, loads both faces with their consistent nodal forces.

Only the target triangles within the contactor window's diameter of it are searched (small
sliding: nothing farther can be reached).  Where the target is curved, a contactor point is
kept for the target triangle closest to it only (the projections of two triangles overlap at a convex edge); contactor area whose
projection falls in no target triangle (beyond the target face, or a sliver at a convex edge)
adds nothing, and a contactor node none of whose area projects gets no row.  A contactor
triangle facing away from the target triangle (n_c · n ≥ −1e−3) is not projected onto it.
"""

from __future__ import annotations

import numpy as np

from ..mesh.tetrahedra import triangle_normals
from .surfaces import closest_points

#: The interior three-point rule on a triangle, exact for quadratics: barycentric points
#: (2/3, 1/6, 1/6) and permutations, each weighing a third of the area.
RULE = np.array([[2 / 3, 1 / 6, 1 / 6], [1 / 6, 2 / 3, 1 / 6], [1 / 6, 1 / 6, 2 / 3]])


def clip(polygon: np.ndarray, triangle: np.ndarray) -> np.ndarray:
    """The part of a 2D polygon (K, 2) inside the counter-clockwise triangle (3, 2)
    (Sutherland–Hodgman); (0, 2) when they do not overlap."""
    out = polygon
    for i in range(3):
        p, q = triangle[i], triangle[(i + 1) % 3]
        edge = q - p
        if len(out) == 0:
            break
        side = edge[0] * (out[:, 1] - p[1]) - edge[1] * (out[:, 0] - p[0])  # > 0: inside
        kept = []
        for k in range(len(out)):
            a, b, sa, sb = out[k], out[(k + 1) % len(out)], side[k], side[(k + 1) % len(out)]
            if sa >= 0:
                kept.append(a)
            if (sa >= 0) != (sb >= 0):
                kept.append(a + (b - a) * (sa / (sa - sb)))
        out = np.array(kept).reshape(-1, 2)
    return out


def _barycentric(points: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """Barycentric coordinates (K, 3) of points (K, 3) of a triangle's plane."""
    e1, e2 = tri[1] - tri[0], tri[2] - tri[0]
    g11, g12, g22 = e1 @ e1, e1 @ e2, e2 @ e2  # the Gram matrix, solved by Cramer's rule
    r1, r2 = (points - tri[0]) @ e1, (points - tri[0]) @ e2
    det = g11 * g22 - g12 * g12
    v, w = (g22 * r1 - g12 * r2) / det, (g11 * r2 - g12 * r1) / det
    return np.column_stack([1.0 - v - w, v, w])


class _Rows:
    """The integrals of every row, accumulated piece by piece."""

    def __init__(self, rows):
        self.rows = set(int(j) for j in rows)
        self.D = {j: {} for j in self.rows}
        self.M = {j: {} for j in self.rows}
        self.G = dict.fromkeys(self.rows, 0.0)
        self.NS = {j: np.zeros(3) for j in self.rows}

    def add(self, tri_c, tri_t, w, Nc, Nt, gap, normal) -> None:
        """Quadrature points of one piece: weights w, contactor and target shape values Nc, Nt
        (K, 3) at them, the gap there, the target normal."""
        for a, j in enumerate(tri_c):
            if j not in self.rows:
                continue
            wj = w * Nc[:, a]
            for b, k in enumerate(tri_c):
                self.D[j][int(k)] = self.D[j].get(int(k), 0.0) + float(wj @ Nc[:, b])
            for b, l in enumerate(tri_t):
                self.M[j][int(l)] = self.M[j].get(int(l), 0.0) + float(wj @ Nt[:, b])
            self.G[j] += float(wj @ gap)
            self.NS[j] += wj.sum() * normal


def _cross(u, v):
    """u x v of two 3-vectors (numpy's cross costs 50 us a call)."""
    return np.array(
        [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    )


def _pieces(nodes, tc, tt, n_c, n_t):
    """Quadrature points of contactor triangle ``tc`` over its part projecting into target
    triangle ``tt`` (node ids): (x (K, 3) on the contactor, y (K, 3) on the target, weights
    (K,)), or None."""
    if n_c @ n_t >= -1e-3:
        return None
    p0, p1 = nodes[tt[0]], nodes[tt[1]]
    e1 = (p1 - p0) / np.linalg.norm(p1 - p0)
    frame = np.stack([e1, _cross(n_t, e1)])
    subject, target = (nodes[tc] - p0) @ frame.T, (nodes[tt] - p0) @ frame.T
    if (subject.max(axis=0) < target.min(axis=0)).any() or (
        subject.min(axis=0) > target.max(axis=0)
    ).any():
        return None  # their boxes do not overlap
    polygon = clip(subject, target)
    if len(polygon) < 3:
        return None
    c0 = nodes[tc[0]]
    on_target = p0 + polygon @ frame
    lift = ((c0 - on_target) @ n_c) / (n_t @ n_c)  # along n_t back onto the contactor plane
    on_contactor = on_target + lift[:, None] * n_t
    xs, ys, ws = [], [], []
    for k in range(1, len(polygon) - 1):  # a fan of triangles
        fan = [0, k, k + 1]
        area = 0.5 * np.linalg.norm(
            _cross(on_contactor[k] - on_contactor[0], on_contactor[k + 1] - on_contactor[0])
        )
        if area <= 0.0:
            continue
        xs.append(RULE @ on_contactor[fan])
        ys.append(RULE @ on_target[fan])
        ws.append(np.full(3, area / 3.0))
    if not xs:
        return None
    return np.concatenate(xs), np.concatenate(ys), np.concatenate(ws)


def _overlapping(nodes, tc, targets, normal) -> np.ndarray:
    """(K,) True for the target triangles (K, 3) whose boxes overlap the contactor triangle's,
    all seen along ``normal``."""
    e1 = _cross(normal, np.eye(3)[int(np.argmin(np.abs(normal)))])
    frame = np.stack([e1, _cross(normal, e1)]) / np.linalg.norm(e1)
    mine, theirs = nodes[tc] @ frame.T, nodes[targets] @ frame.T
    return (
        (theirs.max(axis=1) >= mine.min(axis=0)) & (theirs.min(axis=1) <= mine.max(axis=0))
    ).all(axis=1)


def _within_reach(nodes, contactor, target) -> np.ndarray:
    """The target triangles whose boxes come within the contactor triangles' box grown by its
    own diameter: small sliding, the target a contactor point can reach lies no farther."""
    points = nodes[contactor].reshape(-1, 3)
    low, high = points.min(axis=0), points.max(axis=0)
    reach = float(np.linalg.norm(high - low))
    corners = nodes[target]
    near = (corners.max(axis=1) >= low - reach).all(axis=1) & (
        corners.min(axis=1) <= high + reach
    ).all(axis=1)
    return target[near]


def node_to_surface_rows(nodes, contactor, target, candidates, min_area) -> dict:
    """The rows of the contactor nodes ``candidates`` against the target triangles (module
    doc): arrays node_a, node_b (the target node of largest weight, a name), normal, gap,
    area (S_j), weights [(node, c)] per row, foot (the node's own closest target point:
    triangle nodes and barycentric coordinates) and point_gap (its gap there).  Rows with
    S_j <= min_area are dropped (they project nowhere)."""
    rows = _Rows(candidates)
    contactor = contactor[np.isin(contactor, list(rows.rows)).any(axis=1)]
    target = _within_reach(nodes, contactor, target)
    if len(target) == 0:  # nothing to project onto: no row
        return _assembled(rows, nodes, target, np.zeros((0, 3)), [], min_area)
    n_c, _ = triangle_normals(nodes, contactor)
    n_t, _ = triangle_normals(nodes, target)
    reach = _reach(nodes[contactor].mean(axis=1), nodes[np.unique(target)])
    boxes = (
        nodes[target].min(axis=1),
        nodes[target].max(axis=1),
        float(np.ptp(nodes[target].reshape(-1, 3), axis=0).max()),
    )
    for i, tc in enumerate(contactor):
        _project(rows, nodes, tc, n_c[i], target, n_t, reach[i], boxes)
    return _assembled(rows, nodes, target, n_t, candidates, min_area)


def _reach(points: np.ndarray, corners: np.ndarray, block: int = 512) -> np.ndarray:
    """The distance of each point to the nearest target corner: no less than its distance to
    the target surface, so the boxes it grows hold every triangle that one would."""
    out = np.empty(len(points))
    squared = np.einsum("vk,vk->v", corners, corners)
    for start in range(0, len(points), block):
        p = points[start : start + block]
        d2 = np.einsum("pk,pk->p", p, p)[:, None] - 2.0 * p @ corners.T + squared[None]
        out[start : start + block] = np.sqrt(np.maximum(d2.min(axis=1), 0.0))
    return out


def _project(rows: _Rows, nodes, tc, n_c, target, n_t, reach: float, boxes) -> None:
    """Add to ``rows`` the pieces of contactor triangle ``tc`` over the target triangles near
    it (their boxes ``boxes``: low and high corners and the target's size, within ``reach``,
    no less than its distance from the target, and its own size)."""
    low_t, high_t, size = boxes
    margin = reach + np.ptp(nodes[tc], axis=0).max() + 1e-9 * size
    low, high = nodes[tc].min(axis=0) - margin, nodes[tc].max(axis=0) + margin
    near = np.flatnonzero((high_t >= low).all(axis=1) & (low_t <= high).all(axis=1))
    if len(near) == 0:
        return
    # target triangles in one plane: their projections tile it, no point is claimed twice
    offset = np.einsum("tk,tk->t", n_t[near], nodes[target[near, 0]])
    flat = (
        np.abs(n_t[near] - n_t[near[0]]).max() <= 1e-12
        and np.abs(offset - offset[0]).max() <= 1e-12 * size
    )
    if flat:  # seen along that plane's normal, keep the triangles whose boxes overlap
        near = near[_overlapping(nodes, tc, target[near], n_t[near[0]])]
    for t in near:
        piece = _pieces(nodes, tc, target[t], n_c, n_t[t])
        if piece is None:
            continue
        x, y, w = piece
        if len(near) > 1 and not flat:  # keep the points closest to this triangle
            d = closest_points(x, nodes, target[near])["near"]
            w = np.where(d[:, list(near).index(t)] <= d.min(axis=1) + 1e-12 * size, w, 0.0)
        rows.add(
            tc,
            target[t],
            w,
            _barycentric(x, nodes[tc]),
            _barycentric(y, nodes[target[t]]),
            (x - y) @ n_t[t],
            n_t[t],
        )


def _assembled(rows: _Rows, nodes, target, n_t, candidates, min_area) -> dict:
    """The row arrays of the integrals (:func:`node_to_surface_rows`)."""
    out = {
        k: [] for k in ("node_a", "node_b", "normal", "gap", "area", "weights", "foot", "point_gap")
    }
    if len(candidates):
        own = closest_points(nodes[np.asarray(candidates, dtype=np.int64)], nodes, target)
    for i, j in enumerate(int(c) for c in candidates):
        S = sum(rows.D[j].values())
        if S <= min_area:
            continue
        t = int(own["triangle"][i])
        out["node_a"].append(j)
        out["node_b"].append(max(rows.M[j], key=rows.M[j].get))
        out["normal"].append(rows.NS[j] / np.linalg.norm(rows.NS[j]))
        out["gap"].append(rows.G[j] / S)
        out["area"].append(S)
        out["weights"].append(
            [(k, v / S) for k, v in rows.D[j].items() if v != 0.0]
            + [(l, -v / S) for l, v in rows.M[j].items() if v != 0.0]
        )
        out["foot"].append([*target[t].astype(float), *own["bary"][i]])
        out["point_gap"].append(float((nodes[j] - own["foot"][i]) @ n_t[t]))
    return {
        "node_a": np.asarray(out["node_a"], dtype=np.int64),
        "node_b": np.asarray(out["node_b"], dtype=np.int64),
        "normal": np.asarray(out["normal"], dtype=float).reshape(-1, 3),
        "gap": np.asarray(out["gap"], dtype=float),
        "area": np.asarray(out["area"]),
        "weights": out["weights"],
        "foot": np.asarray(out["foot"]).reshape(-1, 6),
        "point_gap": np.asarray(out["point_gap"], dtype=float),
    }
