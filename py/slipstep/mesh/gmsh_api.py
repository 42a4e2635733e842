"""gmsh for the package: the session every gmsh call runs in (initialised quietly, finalised
afterwards, Ctrl-C left to Python), and the elements of the meshed model with its physical
groups: triangles and tagged edges (2D), tetrahedra and tagged faces (3D)."""

from __future__ import annotations

import contextlib

import numpy as np

from .base import MeshError


@contextlib.contextmanager
def gmsh_session():
    """An initialised, quiet gmsh API, finalised afterwards; Ctrl-C stays Python's."""
    try:
        import gmsh
    except ImportError:
        raise MeshError(
            "the gmsh Python package is needed for the built-in meshes and .msh "
            "files: pip install gmsh"
        ) from None
    if gmsh.isInitialized():
        gmsh.finalize()
    gmsh.initialize(["", "-v", "0"], readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        yield gmsh
    finally:
        gmsh.finalize()


def size_field_only(gmsh, field: int) -> None:
    """Make ``field`` the element size everywhere: no size from points, boundaries or
    curvature."""
    gmsh.model.mesh.field.setAsBackgroundMesh(field)
    for opt in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
        gmsh.option.setNumber(f"Mesh.{opt}", 0)


def threshold_field(
    gmsh, h_contact: float, contact_zone: float, h_max: float, growth: float, points=(), curves=()
) -> int:
    """The size field h = h_contact within contact_zone of the geometry ``points`` and
    ``curves`` (d = the distance from the nearest), growing linearly, h = h_contact + growth
    (d - contact_zone), up to h_max (Distance + Threshold)."""
    fields = gmsh.model.mesh.field
    dist = fields.add("Distance")
    if points:
        fields.setNumbers(dist, "PointsList", list(points))
    if curves:
        fields.setNumbers(dist, "CurvesList", list(curves))
        fields.setNumber(dist, "Sampling", 200)
    size = fields.add("Threshold")
    fields.setNumber(size, "InField", dist)
    fields.setNumber(size, "SizeMin", h_contact)
    fields.setNumber(size, "SizeMax", h_max)
    fields.setNumber(size, "DistMin", contact_zone)
    fields.setNumber(size, "DistMax", contact_zone + (h_max - h_contact) / growth)
    return size


def _node_rows(gmsh):
    """(xyz (N, 3), index): the model's nodes, and the map from gmsh node tags to their rows
    (-1 for a tag that is not a node; tags may be huge)."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    if len(tags) == 0:
        raise MeshError(
            "the file holds no mesh (no nodes): save the mesh, not only the " "geometry"
        )
    order = np.argsort(tags, kind="stable")
    sorted_tags = tags[order].astype(np.int64)

    def index(t):
        t = np.asarray(t).astype(np.int64)
        pos = np.clip(np.searchsorted(sorted_tags, t), 0, len(sorted_tags) - 1)
        return np.where(sorted_tags[pos] == t, order[pos], -1)

    return coords.reshape(-1, 3), index


def _physical_cells(gmsh, dim: int, gmsh_type: int, per: int, index, what: str) -> dict:
    """name -> (K, per) node rows of the elements of each physical group of dimension ``dim``
    (``gmsh_type``: 1 lines, 2 triangles; ``what`` names them in the error)."""
    out = {}
    for _, ptag in gmsh.model.getPhysicalGroups(dim):
        name = gmsh.model.getPhysicalName(dim, ptag) or str(ptag)
        cells = []
        for ent in gmsh.model.getEntitiesForPhysicalGroup(dim, ptag):
            etypes, _, enodes = gmsh.model.mesh.getElements(dim, ent)
            for et, en in zip(etypes, enodes):
                if et != gmsh_type:
                    raise MeshError(f"{what} '{name}': only {per}-node elements are supported")
                cells.append(index(en).reshape(-1, per))
        out[name] = np.concatenate(cells) if cells else np.zeros((0, per), np.int64)
    return out


def _node_sets(gmsh, index) -> dict:
    """name -> node rows of each physical point group."""
    out = {}
    for _, ptag in gmsh.model.getPhysicalGroups(0):
        name = gmsh.model.getPhysicalName(0, ptag) or str(ptag)
        ids = []
        for ent in gmsh.model.getEntitiesForPhysicalGroup(0, ptag):
            ntags, _, _ = gmsh.model.mesh.getNodes(0, ent)
            ids.extend(index(ntags))
        out[name] = np.asarray(ids, dtype=np.int64)
    return out


def triangles_and_edges(gmsh) -> tuple[np.ndarray, np.ndarray, dict, dict]:
    """Nodes (2D), triangles and the physical line / point groups of the current model."""
    xyz, index = _node_rows(gmsh)
    types = {int(t) for t in gmsh.model.mesh.getElementTypes(dim=2)}
    if types - {2}:
        names = [gmsh.model.mesh.getElementProperties(t)[0] for t in sorted(types - {2})]
        raise MeshError(f"only 3-node triangles are supported; the mesh has {', '.join(names)}")
    _, tri_nodes = gmsh.model.mesh.getElementsByType(2)
    triangles = index(tri_nodes).reshape(-1, 3)
    edges = _physical_cells(gmsh, 1, 1, 2, index, "edge")
    return xyz, triangles, edges, _node_sets(gmsh, index)


def tetrahedra_and_faces(gmsh) -> tuple[np.ndarray, np.ndarray, dict, dict]:
    """Nodes (3D), tetrahedra and the physical surface (face tags, triangles) and point groups
    of the current model."""
    xyz, index = _node_rows(gmsh)
    types = {int(t) for t in gmsh.model.mesh.getElementTypes(dim=3)}
    if types - {4}:
        names = [gmsh.model.mesh.getElementProperties(t)[0] for t in sorted(types - {4})]
        raise MeshError(f"only 4-node tetrahedra are supported; the mesh has {', '.join(names)}")
    tets = np.zeros((0, 4), np.int64)
    if 4 in types:
        _, tet_nodes = gmsh.model.mesh.getElementsByType(4)
        tets = index(tet_nodes).reshape(-1, 4)
    faces = _physical_cells(gmsh, 2, 2, 3, index, "face")
    return xyz, tets, faces, _node_sets(gmsh, index)
