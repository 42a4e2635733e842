"""Triangulated surfaces in space: closest points on triangles (Ericson's regions, vectorised),
the edges of a surface and whether it is closed, a consistent outward orientation, and the
tetrahedron that holds a point.  Used by the rigid surfaces and the pair geometry of 3D
contact."""

from __future__ import annotations

import numpy as np

from ..mesh.base import MeshError

#: Points are processed in blocks of this many against every triangle (memory ~ block x T).
BLOCK = 256


def closest_on_triangles(x: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray):
    """For points x (P, 3) and triangles (a, b, c) (T, 3 each): the closest point of each
    triangle to each point, as barycentric coordinates (P, T, 3) (Ericson, Real-Time Collision
    Detection, 5.1.5: the Voronoi region of the vertex, edge or face the point projects into)."""
    ab, ac = (b - a)[None], (c - a)[None]
    ap, bp, cp = x[:, None] - a[None], x[:, None] - b[None], x[:, None] - c[None]

    def dot(u, v):
        return np.einsum("ptk,ptk->pt", np.broadcast_to(u, v.shape), v)

    d1, d2, d3, d4, d5, d6 = (
        dot(ab, ap),
        dot(ac, ap),
        dot(ab, bp),
        dot(ac, bp),
        dot(ab, cp),
        dot(ac, cp),
    )
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        total = va + vb + vc
        v_face, w_face = vb / total, vc / total
        v_ab = d1 / (d1 - d3)
        w_ac = d2 / (d2 - d6)
        w_bc = (d4 - d3) / ((d4 - d3) + (d5 - d6))
    one, zero = np.ones_like(d1), np.zeros_like(d1)
    # the regions, first match wins (Ericson's order)
    regions = [
        ((d1 <= 0) & (d2 <= 0), (one, zero, zero)),  # vertex a
        ((d3 >= 0) & (d4 <= d3), (zero, one, zero)),  # vertex b
        ((vc <= 0) & (d1 >= 0) & (d3 <= 0), (1 - v_ab, v_ab, zero)),  # edge ab
        ((d6 >= 0) & (d5 <= d6), (zero, zero, one)),  # vertex c
        ((vb <= 0) & (d2 >= 0) & (d6 <= 0), (1 - w_ac, zero, w_ac)),  # edge ac
        ((va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0), (zero, 1 - w_bc, w_bc)),  # edge bc
    ]
    face = (1 - v_face - w_face, v_face, w_face)
    out = [
        np.select([m for m, _ in regions], [r[k] for _, r in regions], face[k]) for k in range(3)
    ]
    return np.stack(out, axis=-1)


def closest_points(x: np.ndarray, points: np.ndarray, triangles: np.ndarray) -> dict:
    """The closest point of a triangulated surface to each point of x (P, 3): ``triangle``
    (the closest one, the first of a tie), ``bary`` (P, 3) its barycentric coordinates there,
    ``foot`` (P, 3), ``distance`` (P,), and ``near`` (P, T) the distance to every triangle
    (for the triangles meeting at an edge or corner)."""
    x = np.asarray(x, dtype=float).reshape(-1, 3)
    a, b, c = (points[triangles[:, k]] for k in range(3))
    tri = np.zeros(len(x), dtype=np.int64)
    bary, near = np.zeros((len(x), 3)), np.zeros((len(x), len(triangles)))
    for start in range(0, len(x), BLOCK):
        xs = x[start : start + BLOCK]
        w = closest_on_triangles(xs, a, b, c)
        feet = w[..., 0, None] * a[None] + w[..., 1, None] * b[None] + w[..., 2, None] * c[None]
        dist = np.linalg.norm(xs[:, None] - feet, axis=2)
        k = np.argmin(dist, axis=1)
        rows = np.arange(len(xs))
        tri[start : start + BLOCK], bary[start : start + BLOCK] = k, w[rows, k]
        near[start : start + BLOCK] = dist
    foot = np.einsum("pk,pkd->pd", bary, points[triangles[tri]])
    return {
        "triangle": tri,
        "bary": bary,
        "foot": foot,
        "distance": np.linalg.norm(x - foot, axis=1),
        "near": near,
    }


def edges_of(triangles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(undirected edges (E, 2) sorted, the number of triangles sharing each)."""
    directed = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    return np.unique(np.sort(directed, axis=1), axis=0, return_counts=True)


def open_edge(triangles: np.ndarray) -> tuple[int, int, int] | None:
    """An edge of the surface not shared by exactly two triangles (vertices i, j and the count),
    or None: the surface is closed."""
    edges, counts = edges_of(triangles)
    bad = np.flatnonzero(counts != 2)
    if len(bad) == 0:
        return None
    k = bad[0]
    return int(edges[k, 0]), int(edges[k, 1]), int(counts[k])


def consistently_oriented(triangles: np.ndarray, where: str) -> np.ndarray:
    """The triangles of a surface each oriented like its neighbours (every interior edge run in
    opposite senses by its two triangles), by a walk over the edge-neighbour graph from the
    first triangle of each connected part; a surface that cannot be (a Moebius strip) is an
    error."""
    tris = np.asarray(triangles, dtype=np.int64).copy()
    neighbours: dict[tuple, list[int]] = {}
    for t, (i, j, k) in enumerate(tris.tolist()):
        for p, q in ((i, j), (j, k), (k, i)):
            neighbours.setdefault((min(p, q), max(p, q)), []).append(t)
    done = np.zeros(len(tris), dtype=bool)
    for seed in range(len(tris)):
        if done[seed]:
            continue
        done[seed], todo = True, [seed]
        while todo:
            t = todo.pop()
            i, j, k = tris[t]
            for p, q in ((i, j), (j, k), (k, i)):
                for u in neighbours[(min(p, q), max(p, q))]:
                    if u == t:
                        continue
                    runs_same = _runs(tris[u], p, q)
                    if done[u]:
                        if runs_same:
                            raise MeshError(
                                f"{where}: the surface cannot be oriented (triangles "
                                f"{t} and {u} disagree across edge {p}-{q}, a "
                                f"Moebius strip): fix the surface"
                            )
                        continue
                    if runs_same:  # a neighbour runs the shared edge the same way: flip it
                        tris[u] = tris[u][[0, 2, 1]]
                    done[u] = True
                    todo.append(u)
    return tris


def _runs(tri: np.ndarray, p: int, q: int) -> bool:
    """True when triangle ``tri`` has the directed edge p -> q."""
    i, j, k = tri
    return (i, j) == (p, q) or (j, k) == (p, q) or (k, i) == (p, q)


def enclosed_volume(points: np.ndarray, triangles: np.ndarray) -> float:
    """The signed volume a closed surface encloses (> 0 when its normals point outwards)."""
    a, b, c = (points[triangles[:, k]] for k in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def containing_tetrahedra(
    x: np.ndarray, nodes: np.ndarray, tets: np.ndarray, tol: float = 1e-9
) -> np.ndarray:
    """For each point of x (P, 3): a tetrahedron that holds it (every barycentric coordinate
    >= -tol: on its faces too), else -1."""
    out = np.full(len(x), -1, dtype=np.int64)
    if len(x) == 0:
        return out
    p = nodes[tets]
    low, high = p.min(axis=1), p.max(axis=1)
    pad = tol * float(np.ptp(nodes, axis=0).max())
    near = np.flatnonzero(
        (high + pad >= x.min(axis=0)).all(axis=1) & (low - pad <= x.max(axis=0)).all(axis=1)
    )
    if len(near) == 0:
        return out
    inverse = np.linalg.inv(np.transpose(p[near, 1:] - p[near, :1], (0, 2, 1)))
    for start in range(0, len(x), BLOCK):
        xs = x[start : start + BLOCK]
        in_box = (
            (xs[:, None] >= low[near][None] - pad) & (xs[:, None] <= high[near][None] + pad)
        ).all(-1)
        for i, t in zip(*np.nonzero(in_box)):
            lam = inverse[t] @ (xs[i] - p[near[t], 0])
            if min(lam.min(), 1.0 - lam.sum()) >= -tol and out[start + i] < 0:
                out[start + i] = near[t]
    return out


def pseudo_normals(
    points: np.ndarray,
    triangles: np.ndarray,
    triangle: np.ndarray,
    bary: np.ndarray,
    tol: float = 1e-9,
) -> np.ndarray:
    """The pseudo-normal of the surface at closest points given by their triangle and
    barycentric coordinates (Baerentzen and Aanaes, 2005): the triangle's normal inside it, the
    sum of the normals of the two triangles sharing an edge, the angle-weighted sum of the
    normals around a vertex.  The sign of (x - foot) . pseudo-normal tells the side of x for any
    closed or consistently oriented surface (a plain sum at a vertex does not)."""
    a, b, c = (points[triangles[:, k]] for k in range(3))
    face = np.cross(b - a, c - a)
    face /= np.linalg.norm(face, axis=1, keepdims=True)
    corners = np.stack([a, b, c], axis=1)
    angle = np.zeros((len(triangles), 3))
    for k in range(3):
        u = corners[:, (k + 1) % 3] - corners[:, k]
        v = corners[:, (k + 2) % 3] - corners[:, k]
        cosine = np.einsum("ij,ij->i", u, v) / (
            np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1)
        )
        angle[:, k] = np.arccos(np.clip(cosine, -1.0, 1.0))
    at_vertex = np.zeros((len(points), 3))
    for k in range(3):
        np.add.at(at_vertex, triangles[:, k], angle[:, k, None] * face)
    out = face[triangle].copy()
    zero = bary <= tol
    for p in np.flatnonzero(zero.sum(axis=1) == 2):  # a vertex: the one non-zero coordinate
        out[p] = at_vertex[triangles[triangle[p], np.argmax(bary[p])]]
    for p in np.flatnonzero(zero.sum(axis=1) == 1):  # an edge: the triangles sharing it
        i, j = triangles[triangle[p]][~zero[p]]
        sharing = np.flatnonzero(np.isin(triangles, [i, j]).sum(axis=1) == 2)
        out[p] = face[sharing].sum(axis=0)
    return out
