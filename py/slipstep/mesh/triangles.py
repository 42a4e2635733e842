"""Triangle meshes: a :class:`TriangleMesh` of linear (CST) triangles, counter-clockwise, with named
edge tags whose segments are oriented with the body on their left (so the outward normal of a
segment p -> q is the right-hand normal (t_y, -t_x) / |t|, t = q - p); the checks every mesh
passes, and a mesh from Python arrays.  The built-in generators are
:mod:`slipstep.mesh.triangle_generators`, the file readers and writer :mod:`slipstep.mesh.triangle_files`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .base import Mesh, MeshError


@dataclass(repr=False)
class TriangleMesh(Mesh):
    """A 2D triangle mesh of one body (a plane or axisymmetric section).

    nodes     (N, 2) float64 coordinates
    triangles (M, 3) int64, counter-clockwise
    edges     tag -> (K, 2) int64 node pairs (boundary segments, body on the left)
    node_sets name -> (n,) int64 node ids (every edge tag is also a node set)
    """

    nodes: np.ndarray
    triangles: np.ndarray
    edges: dict[str, np.ndarray] = field(default_factory=dict)
    node_sets: dict[str, np.ndarray] = field(default_factory=dict)

    def __post_init__(self):
        self.triangles, self.edges = self._normalised(self.triangles, self.edges)

    dimension = 2
    element_name = "triangles"
    boundary_name = "edge"

    @property
    def tags(self) -> dict[str, np.ndarray]:
        """The boundary tags [[bc]] and [[contact]] name: the edge tags."""
        return self.edges

    @property
    def elements(self) -> np.ndarray:
        """The element connectivity: the triangles."""
        return self.triangles

    def edge_nodes(self, tag: str) -> np.ndarray:
        """Sorted unique nodes of an edge tag."""
        return self.tag_nodes(tag)

    def area(self) -> float:
        return float(signed_areas(self.nodes, self.triangles).sum())

    measure = area


def signed_areas(nodes: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Signed area of each triangle (> 0 for counter-clockwise)."""
    p = nodes[triangles]
    a, b = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    return 0.5 * (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])


def check_triangles(nodes: np.ndarray, triangles: np.ndarray, where: str = "") -> None:
    """Raise MeshError naming the first inverted or degenerate element.

    Degenerate: |area| <= 0.5e-10 * (longest side)^2 (as in the engine).  Element ids are 0-based rows of
    ``triangles`` (the engine uses the same numbering).
    """
    prefix = f"{where}: " if where else ""
    if len(triangles) == 0:
        raise MeshError(f"{prefix}the mesh has no triangles")
    if triangles.min() < 0 or triangles.max() >= len(nodes):
        bad = int(np.nonzero((triangles < 0).any(1) | (triangles >= len(nodes)).any(1))[0][0])
        raise MeshError(f"{prefix}element {bad} refers to a node outside 0..{len(nodes) - 1}")
    with np.errstate(all="ignore"):
        area = signed_areas(nodes, triangles)
        p = nodes[triangles]
        sides = np.stack([p[:, 1] - p[:, 0], p[:, 2] - p[:, 1], p[:, 0] - p[:, 2]], axis=1)
        longest2 = (sides**2).sum(-1).max(1)
    if not (np.isfinite(area).all() and np.isfinite(longest2).all()):
        e = int(np.argmin(np.isfinite(area) & np.isfinite(longest2)))
        raise MeshError(
            f"{prefix}element {e}: its size overflows (coordinates up to "
            f"{np.abs(nodes).max():.3g}): rescale the mesh (mesh.scale)"
        )
    # the engine's threshold (rust/src/mesh.rs): twice the area <= 1e-10 (longest side)^2
    degenerate = np.abs(area) <= 0.5e-10 * longest2
    if degenerate.any():
        e = int(np.nonzero(degenerate)[0][0])
        raise MeshError(
            f"{prefix}element {e} is degenerate (area {area[e]:.3g}, nodes "
            f"{triangles[e].tolist()}): remove it or fix its nodes"
        )
    if (area < 0).any():
        e = int(np.nonzero(area < 0)[0][0])
        raise MeshError(
            f"{prefix}element {e} is inverted (signed area {area[e]:.3g}): reorder "
            f"its nodes counter-clockwise"
        )


def orient_edges(triangles: np.ndarray, edges: dict[str, np.ndarray], where: str = "") -> dict:
    """Orient every tagged segment with the body on its left (as in its CCW triangle).

    Raises MeshError if a tagged segment is not a boundary side of exactly one triangle.
    """
    prefix = f"{where}: " if where else ""
    t = np.asarray(triangles, dtype=np.int64)
    directed = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    n = int(directed.max()) + 1 if len(directed) else 1

    def side_key(pairs: np.ndarray) -> np.ndarray:  # one integer per undirected side
        return pairs.min(axis=1) * n + pairs.max(axis=1)

    # count sides: a boundary side belongs to one triangle only
    keys = side_key(directed)
    uniq, first, counts = np.unique(keys, return_index=True, return_counts=True)
    out = {}
    for tag, segs in edges.items():
        segs = np.asarray(segs, dtype=np.int64).reshape(-1, 2)
        inside = (segs >= 0).all(axis=1) & (segs < n).all(axis=1)
        wanted = np.where(inside, side_key(np.clip(segs, 0, n - 1)), -1)  # -1: no side's key
        k = np.minimum(np.searchsorted(uniq, wanted), len(uniq) - 1)
        found = uniq[k] == wanted
        bad = np.nonzero(~found | (counts[k] != 1))[0]
        if len(bad):
            i = bad[0]
            p, q = segs[i]
            if not found[i]:
                raise MeshError(
                    f"{prefix}edge '{tag}' segment {int(p)}-{int(q)} is not a side of "
                    f"any triangle"
                )
            raise MeshError(
                f"{prefix}edge '{tag}' segment {int(p)}-{int(q)} is inside the "
                f"mesh (shared by {counts[k[i]]} triangles): tag boundary sides only"
            )
        out[tag] = directed[first[k]]
    return out


def outward_normals(nodes: np.ndarray, segments: np.ndarray) -> np.ndarray:
    """Unit outward normals of segments oriented with the body on the left."""
    t = nodes[segments[:, 1]] - nodes[segments[:, 0]]
    n = np.stack([t[:, 1], -t[:, 0]], axis=1)
    return n / np.linalg.norm(n, axis=1, keepdims=True)


def node_normals(nodes: np.ndarray, segments: np.ndarray, ids: np.ndarray) -> np.ndarray:
    """Outward normal of an edge at each node of ``ids``: the segment normals meeting there,
    summed (not normalised; zero where they cancel)."""
    acc = np.zeros((len(nodes), 2))
    seg_n = outward_normals(nodes, segments)
    np.add.at(acc, segments[:, 0], seg_n)
    np.add.at(acc, segments[:, 1], seg_n)
    return acc[ids]


def planar_coordinates(xyz, where: str) -> np.ndarray:
    """(N, 2) float64 coordinates from (N, 2) or (N, 3) with z = 0."""
    xyz = np.asarray(xyz, dtype=np.float64)
    if xyz.ndim != 2 or xyz.shape[1] not in (2, 3):
        raise MeshError(
            f"{where}: the node coordinates have shape {xyz.shape}: expected 2 or " f"3 columns"
        )
    if xyz.shape[1] == 3:
        zmax = np.abs(xyz[:, 2]).max(initial=0.0)
        if zmax > 1e-12 * max(np.abs(xyz[:, :2]).max(initial=1.0), 1.0):
            raise MeshError(
                f"{where}: the mesh is not planar (|z| up to {zmax:.3g}): slipstep "
                f"meshes lie in the x-y plane"
            )
    return xyz[:, :2]


def checked_mesh(
    nodes, triangles, edges, node_sets=None, where="", flip_clockwise=False
) -> TriangleMesh:
    """The :class:`TriangleMesh` of raw arrays, as every mesh is made: unused nodes dropped, a
    consistently clockwise mesh flipped if asked, checked, edges oriented."""
    nodes = np.asarray(nodes, dtype=np.float64)
    triangles = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    node_sets = dict(node_sets or {})
    prefix = f"{where}: " if where else ""
    if len(triangles) == 0:
        raise MeshError(
            f"{prefix}the mesh has no triangles: give each body at least one " f"3-node triangle"
        )
    if triangles.min() < 0 or triangles.max() >= len(nodes):
        bad = int(np.nonzero((triangles < 0).any(1) | (triangles >= len(nodes)).any(1))[0][0])
        raise MeshError(
            f"{prefix}element {bad} refers to a node outside 0..{len(nodes) - 1}: "
            f"fix the connectivity"
        )
    for k, v in [*edges.items(), *node_sets.items()]:
        v = np.asarray(v, dtype=np.int64)
        if v.size and (v.min() < 0 or v.max() >= len(nodes)):
            raise MeshError(
                f"{prefix}tag '{k}' refers to a node that is not in the mesh: fix " f"the file"
            )
    used = np.unique(triangles)
    finite = np.isfinite(nodes[used]).all(axis=1)
    if not finite.all():
        k = int(used[np.argmin(finite)])
        raise MeshError(
            f"{prefix}node {k} has a non-finite coordinate "
            f"({nodes[k, 0]}, {nodes[k, 1]}): fix the mesh file"
        )
    if len(used) != len(nodes):
        new = np.full(len(nodes), -1, dtype=np.int64)
        new[used] = np.arange(len(used))
        nodes, triangles = nodes[used], new[triangles]
        edges = {k: new[np.asarray(v, dtype=np.int64)] for k, v in edges.items()}
        node_sets = {k: new[np.asarray(v, dtype=np.int64)] for k, v in node_sets.items()}
        for k, v in [*edges.items(), *node_sets.items()]:
            if (v < 0).any():
                raise MeshError(f"{where}: tag '{k}' uses a node that belongs to no triangle")
    with np.errstate(all="ignore"):  # overflow is reported by check_triangles
        clockwise = (signed_areas(nodes, triangles) < 0).all()
    if flip_clockwise and clockwise:
        triangles = triangles[:, [0, 2, 1]]
    check_triangles(nodes, triangles, where)
    edges = orient_edges(triangles, edges, where)
    return TriangleMesh(nodes, triangles, edges, node_sets)


def from_arrays(
    nodes,
    triangles,
    edges: dict | None = None,
    node_sets: dict | None = None,
    where: str = "mesh from arrays",
) -> TriangleMesh:
    """A body's mesh from numpy arrays, without files: ``nodes`` (N, 2) (or (N, 3) with z = 0),
    ``triangles`` (M, 3) node ids, ``edges`` tag -> (K, 2) boundary segments (the tags that
    [[bc]] and [[contact]] name), ``node_sets`` name -> node ids.  Checked and cleaned like a
    file mesh: unused nodes dropped, an all-clockwise mesh flipped, edges oriented with the
    body on the left."""
    return checked_mesh(
        planar_coordinates(nodes, where),
        triangles,
        dict(edges or {}),
        node_sets,
        where=where,
        flip_clockwise=True,
    )
