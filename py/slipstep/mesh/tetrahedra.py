"""Tetrahedron meshes: a :class:`TetMesh` of linear (4-node) tetrahedra, positively oriented
(det[x1 - x0, x2 - x0, x3 - x0] > 0, the engine contract), with named face tags whose
triangles are oriented with the body behind them (counter-clockwise seen from outside, so the
right-hand normal (x1 - x0) x (x2 - x0) points outwards); the checks every mesh passes, its
boundary, and a mesh from Python arrays.  The 3D implementation of :class:`slipstep.mesh.base.Mesh`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .base import Mesh, MeshError

#: A tetrahedron is flat when |det| <= FLAT * (its longest edge)^3 (the 2D threshold's analog:
#: twice a triangle's area <= 1e-10 (longest side)^2).
FLAT = 1e-10

#: The faces of a tetrahedron (0, 1, 2, 3) as node positions, each counter-clockwise seen from
#: outside a positively oriented one (its normal points away from the fourth node).
TET_FACES = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


@dataclass(repr=False)
class TetMesh(Mesh):
    """A 3D tetrahedron mesh of one body (a solid).

    nodes      (N, 3) float64 coordinates
    tetrahedra (M, 4) int64, positively oriented
    faces      tag -> (K, 3) int64 boundary triangles, outward (body behind them)
    node_sets  name -> (n,) int64 node ids (every face tag is also a node set)
    """

    nodes: np.ndarray
    tetrahedra: np.ndarray
    faces: dict[str, np.ndarray] = field(default_factory=dict)
    node_sets: dict[str, np.ndarray] = field(default_factory=dict)

    def __post_init__(self):
        self.tetrahedra, self.faces = self._normalised(self.tetrahedra, self.faces)

    dimension = 3
    element_name = "tetrahedra"
    boundary_name = "face"

    @property
    def elements(self) -> np.ndarray:
        """The element connectivity: the tetrahedra."""
        return self.tetrahedra

    @property
    def tags(self) -> dict[str, np.ndarray]:
        """The boundary tags [[bc]] and [[contact]] name: the face tags."""
        return self.faces

    def face_nodes(self, tag: str) -> np.ndarray:
        """Sorted unique nodes of a face tag."""
        return self.tag_nodes(tag)

    def volume(self) -> float:
        return float(signed_volumes(self.nodes, self.tetrahedra).sum())

    measure = volume


def signed_volumes(nodes: np.ndarray, tetrahedra: np.ndarray) -> np.ndarray:
    """Signed volume of each tetrahedron, det[x1 - x0, x2 - x0, x3 - x0] / 6 (> 0 positive)."""
    p = np.asarray(nodes)[np.asarray(tetrahedra)]
    return np.linalg.det(p[:, 1:] - p[:, :1]) / 6.0


def triangle_normals(nodes: np.ndarray, triangles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(unit normals (K, 3), areas (K,)) of triangles, the normal by the right-hand rule."""
    p = np.asarray(nodes)[np.asarray(triangles)]
    cross = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    twice = np.linalg.norm(cross, axis=1)
    return cross / np.where(twice > 0, twice, 1.0)[:, None], 0.5 * twice


def node_normals(nodes: np.ndarray, triangles: np.ndarray, ids: np.ndarray) -> np.ndarray:
    """Outward normal of a face at each node of ``ids``: the area-weighted sum of the normals of
    its triangles meeting there (not normalised; zero where they cancel)."""
    n, area = triangle_normals(nodes, triangles)
    acc = np.zeros((len(nodes), 3))
    for corner in range(3):
        np.add.at(acc, triangles[:, corner], n * area[:, None])
    return acc[np.asarray(ids)]


def check_tetrahedra(nodes: np.ndarray, tetrahedra: np.ndarray, where: str = "") -> None:
    """Raise MeshError naming the first tetrahedron that is flat (|det| <= FLAT (longest
    edge)^3) or inverted (det < 0); element ids are 0-based rows of ``tetrahedra``, the
    engine's numbering."""
    prefix = f"{where}: " if where else ""
    if len(tetrahedra) == 0:
        raise MeshError(f"{prefix}the mesh has no tetrahedra")
    if tetrahedra.min() < 0 or tetrahedra.max() >= len(nodes):
        bad = int(np.flatnonzero((tetrahedra < 0).any(1) | (tetrahedra >= len(nodes)).any(1))[0])
        raise MeshError(f"{prefix}element {bad} refers to a node outside 0..{len(nodes) - 1}")
    with np.errstate(all="ignore"):
        p = nodes[tetrahedra]
        det = np.linalg.det(p[:, 1:] - p[:, :1])
        pairs = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]
        longest = np.sqrt(np.max([((p[:, i] - p[:, j]) ** 2).sum(-1) for i, j in pairs], axis=0))
    if not (np.isfinite(det).all() and np.isfinite(longest).all()):
        e = int(np.argmin(np.isfinite(det) & np.isfinite(longest)))
        raise MeshError(
            f"{prefix}element {e}: its size overflows (coordinates up to "
            f"{np.abs(nodes).max():.3g}): rescale the mesh (mesh.scale)"
        )
    flat = np.abs(det) <= FLAT * longest**3
    if flat.any():
        e = int(np.flatnonzero(flat)[0])
        raise MeshError(
            f"{prefix}element {e} is flat (volume {det[e] / 6:.3g}, nodes "
            f"{tetrahedra[e].tolist()}, its four nodes in one plane): remove it or "
            f"fix its nodes"
        )
    if (det < 0).any():
        e = int(np.flatnonzero(det < 0)[0])
        raise MeshError(
            f"{prefix}element {e} is inverted (signed volume {det[e] / 6:.3g}): "
            f"swap two of its nodes so that det[x1 - x0, x2 - x0, x3 - x0] > 0"
        )


def _face_keys(triangles: np.ndarray, n: int) -> np.ndarray:
    """One integer per undirected triangle (its sorted nodes)."""
    s = np.sort(triangles, axis=1).astype(np.int64)
    return (s[:, 0] * n + s[:, 1]) * n + s[:, 2]


def all_faces(tetrahedra: np.ndarray) -> np.ndarray:
    """(4M, 3) every face of every tetrahedron, outward for it (:data:`TET_FACES`)."""
    return np.asarray(tetrahedra)[:, TET_FACES].reshape(-1, 3)


def boundary_faces(tetrahedra: np.ndarray) -> np.ndarray:
    """(K, 3) the faces that belong to one tetrahedron only, outward."""
    faces = all_faces(tetrahedra)
    keys = _face_keys(faces, int(np.max(tetrahedra)) + 1)
    _, first, counts = np.unique(keys, return_index=True, return_counts=True)
    return faces[first[counts == 1]]


def orient_faces(tetrahedra: np.ndarray, faces: dict[str, np.ndarray], where: str = "") -> dict:
    """Every tagged triangle as the boundary face of its tetrahedron, outward.  Raises MeshError
    if a tagged triangle is no face of a tetrahedron or an inner one (of two)."""
    prefix = f"{where}: " if where else ""
    every = all_faces(tetrahedra)
    n = int(np.max(tetrahedra)) + 1
    keys = _face_keys(every, n)
    uniq, first, counts = np.unique(keys, return_index=True, return_counts=True)
    out = {}
    for tag, tris in faces.items():
        tris = np.asarray(tris, dtype=np.int64).reshape(-1, 3)
        inside = (tris >= 0).all(axis=1) & (tris < n).all(axis=1)
        wanted = np.where(inside, _face_keys(np.clip(tris, 0, n - 1), n), -1)
        k = np.minimum(np.searchsorted(uniq, wanted), len(uniq) - 1)
        found = uniq[k] == wanted
        bad = np.flatnonzero(~found | (counts[k] != 1))
        if len(bad):
            t = tris[bad[0]].tolist()
            if not found[bad[0]]:
                raise MeshError(
                    f"{prefix}face '{tag}' triangle {t} is not a face of any " f"tetrahedron"
                )
            raise MeshError(
                f"{prefix}face '{tag}' triangle {t} is inside the mesh (shared by 2 "
                f"tetrahedra): tag boundary faces only"
            )
        out[tag] = every[first[k]]
    return out


def checked_tet_mesh(
    nodes, tetrahedra, faces, node_sets=None, where="", flip_inverted=False
) -> TetMesh:
    """The :class:`TetMesh` of raw arrays, as every 3D mesh is made: unused nodes dropped, a
    consistently inverted mesh flipped if asked, checked, faces oriented outwards."""
    nodes = np.asarray(nodes, dtype=np.float64)
    tets = np.asarray(tetrahedra, dtype=np.int64).reshape(-1, 4)
    faces = {k: np.asarray(v, dtype=np.int64).reshape(-1, 3) for k, v in faces.items()}
    node_sets = {k: np.asarray(v, dtype=np.int64) for k, v in (node_sets or {}).items()}
    prefix = f"{where}: " if where else ""
    if nodes.ndim != 2 or nodes.shape[1] != 3:
        raise MeshError(
            f"{prefix}the node coordinates have shape {nodes.shape}: a 3D mesh "
            f"needs three columns x, y, z"
        )
    if len(tets) == 0:
        raise MeshError(
            f"{prefix}the mesh has no tetrahedra: a 3D case (analysis.dimension = "
            f"3) needs a volume mesh of 4-node tetrahedra"
        )
    check_tetrahedra_indices(nodes, tets, faces, node_sets, prefix)
    used = np.unique(tets)
    finite = np.isfinite(nodes[used]).all(axis=1)
    if not finite.all():
        k = int(used[np.argmin(finite)])
        raise MeshError(
            f"{prefix}node {k} has a non-finite coordinate "
            f"({', '.join(str(c) for c in nodes[k])}): fix the mesh"
        )
    if len(used) != len(nodes):
        new = np.full(len(nodes), -1, dtype=np.int64)
        new[used] = np.arange(len(used))
        nodes, tets = nodes[used], new[tets]
        faces = {k: new[v] for k, v in faces.items()}
        node_sets = {k: new[v] for k, v in node_sets.items()}
        for k, v in [*faces.items(), *node_sets.items()]:
            if (v < 0).any():
                raise MeshError(f"{prefix}tag '{k}' uses a node that belongs to no tetrahedron")
    with np.errstate(all="ignore"):
        inverted = (signed_volumes(nodes, tets) < 0).all()
    if flip_inverted and inverted:
        tets = tets[:, [0, 2, 1, 3]]
    check_tetrahedra(nodes, tets, where)
    return TetMesh(nodes, tets, orient_faces(tets, faces, where), node_sets)


def check_tetrahedra_indices(nodes, tets, faces, node_sets, prefix: str) -> None:
    """Connectivity and tags within the node range."""
    if tets.min() < 0 or tets.max() >= len(nodes):
        bad = int(np.flatnonzero((tets < 0).any(1) | (tets >= len(nodes)).any(1))[0])
        raise MeshError(
            f"{prefix}element {bad} refers to a node outside 0..{len(nodes) - 1}: "
            f"fix the connectivity"
        )
    for k, v in [*faces.items(), *node_sets.items()]:
        if v.size and (v.min() < 0 or v.max() >= len(nodes)):
            raise MeshError(
                f"{prefix}tag '{k}' refers to a node that is not in the mesh: fix " f"the file"
            )


def from_tetrahedra(
    nodes,
    tetrahedra,
    faces: dict | None = None,
    node_sets: dict | None = None,
    where: str = "mesh from arrays",
) -> TetMesh:
    """A body's 3D mesh from numpy arrays, without files: ``nodes`` (N, 3), ``tetrahedra``
    (M, 4), ``faces`` tag -> (K, 3) boundary triangles (the tags [[bc]] and [[contact]] name),
    ``node_sets`` name -> node ids.  Checked and cleaned like a file mesh: unused nodes dropped,
    an all-inverted mesh flipped, faces oriented outwards."""
    return checked_tet_mesh(
        nodes, tetrahedra, dict(faces or {}), node_sets, where=where, flip_inverted=True
    )
