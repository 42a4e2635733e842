"""3D mesh files: a body's tetrahedra from ``.msh`` (gmsh; physical surfaces are the face tags,
physical points node sets) or ``.xdmf`` (meshio; triangle cells tagged by an integer cell-data
array, in the file or in a ``face_file``), and the triangles of a rigid surface from ``.stl`` or
``.msh``.  The 3D counterpart of :mod:`slipstep.mesh.triangle_files`, whose isolated gmsh reader and
meshio helpers it uses."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .gmsh_api import tetrahedra_and_faces
from .base import MeshError
from .triangle_files import mesh_file, read_msh_isolated, tagged_cells, xdmf_mesh
from .tetrahedra import TetMesh, checked_tet_mesh


def read_tet_mesh(
    path: str | Path, face_file: str | Path | None = None, scale: float = 1.0
) -> TetMesh:
    """Read a tetrahedron mesh (``.msh`` or ``.xdmf``).  A mesh whose tetrahedra are ALL
    negatively oriented is flipped; a mix is an error naming the first inverted one, as is a
    flat one."""
    path, where, suffix = mesh_file(path)
    if suffix == ".msh":
        xyz, tets, faces, node_sets = read_msh_isolated(path, where, tetrahedra_and_faces)
    elif suffix == ".xdmf":
        xyz, tets, faces = _xdmf_tetrahedra(path)
        node_sets = {}
        if face_file:
            extra = xdmf_mesh(Path(face_file))
            if any(b.type == "tetra" for b in extra.cells):
                raise MeshError(
                    f"{face_file}: holds tetrahedra too: keep only the triangle "
                    f"cells (the faces)"
                )
            faces.update(tagged_cells(extra, "triangle", str(face_file)))
    else:
        raise MeshError(f"{where}: unknown mesh format '{suffix}': use .msh or .xdmf")
    xyz = np.asarray(xyz, dtype=np.float64)
    if xyz.ndim != 2 or xyz.shape[1] != 3:
        raise MeshError(
            f"{where}: the node coordinates have {xyz.shape[-1]} columns: a 3D mesh "
            f"needs x, y, z"
        )
    if len(tets) == 0:
        raise MeshError(
            f"{where}: no tetrahedra: a 3D case (analysis.dimension = 3) needs a "
            f"volume mesh of 4-node tetrahedra (a surface mesh or a 2D mesh is "
            f"not one)"
        )
    if not np.isfinite(xyz[np.unique(tets)]).all():
        k = int(np.flatnonzero(~np.isfinite(xyz).all(axis=1))[0])
        raise MeshError(
            f"{where}: node {k} has a non-finite coordinate "
            f"({', '.join(str(c) for c in xyz[k])}): fix the mesh file"
        )
    return checked_tet_mesh(xyz * scale, tets, faces, node_sets, where=where, flip_inverted=True)


def _xdmf_tetrahedra(path: Path):
    """(points, tetrahedra, faces) of an .xdmf mesh: tetra cells, tagged triangle cells."""
    m = xdmf_mesh(path)
    for b in m.cells:
        if b.type not in ("tetra", "triangle", "vertex"):
            raise MeshError(
                f"{path}: cells of type '{b.type}': a 3D mesh has tetrahedra (and "
                f"tagged triangles) only"
            )
    tets = [b.data for b in m.cells if b.type == "tetra"]
    if not tets:  # a surface or 2D mesh: read_tet_mesh says why it is none
        return m.points, np.zeros((0, 4), np.int64), {}
    return m.points, np.concatenate(tets), tagged_cells(m, "triangle", str(path))


def read_surface(path: str | Path, scale: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """(points (P, 3), triangles (T, 3)) of a triangulated surface: an ``.stl`` (ASCII or
    binary) or the triangles of a ``.msh``, read with meshio; points that coincide (an STL
    repeats every vertex per triangle) merged, unused ones dropped."""
    path = Path(path)
    where = str(path)
    if not path.exists():
        raise MeshError(f"{where}: no such surface file")
    if path.suffix.lower() not in (".stl", ".msh"):
        raise MeshError(f"{where}: unknown surface format '{path.suffix}': use .stl or .msh")
    try:
        import meshio

        m = meshio.read(str(path))
    except SystemExit:
        raise MeshError(f"{where}: meshio cannot read it") from None
    except Exception as exc:  # noqa: BLE001 - meshio's readers raise anything
        why = " ".join(str(exc).split()) or type(exc).__name__
        raise MeshError(f"{where}: meshio cannot read it: {why}") from None
    tris = [b.data for b in m.cells if b.type == "triangle"]
    if not tris:
        raise MeshError(f"{where}: no triangles: a rigid surface is a triangulated surface")
    points = np.asarray(m.points, dtype=np.float64) * scale
    if points.shape[1] != 3 or not np.isfinite(points).all():
        raise MeshError(f"{where}: the points must be finite x, y, z coordinates")
    return merged_surface(points, np.concatenate(tris).astype(np.int64), where)


def merged_surface(points: np.ndarray, triangles: np.ndarray, where: str):
    """Coincident points merged (within 1e-12 of the surface's size), unused points dropped;
    a triangle with two equal corners is an error naming it."""
    size = float(np.ptp(points, axis=0).max()) or 1.0
    key = np.round(points / (1e-12 * size)).astype(np.int64)
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    tris = inverse.reshape(-1)[triangles]
    degenerate = (
        (tris[:, 0] == tris[:, 1]) | (tris[:, 1] == tris[:, 2]) | (tris[:, 0] == tris[:, 2])
    )
    if degenerate.any():
        k = int(np.argmax(degenerate))
        raise MeshError(f"{where}: triangle {k} has two equal corners: remove it")
    corners = points[first][tris]
    twice_area = np.linalg.norm(
        np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1
    )
    flat = twice_area <= 1e-12 * size * size  # three distinct corners on one line
    if flat.any():
        k = int(np.argmax(flat))
        raise MeshError(
            f"{where}: triangle {k} has no area (its corners lie on one line, so "
            f"it has no normal): remove it"
        )
    used, tris = np.unique(tris, return_inverse=True)
    return points[first][used], tris.reshape(-1, 3)
