"""gmsh for the package: the session every gmsh call runs in (initialised quietly, finalised
afterwards, Ctrl-C left to Python), and the triangles and tagged edges of the meshed model."""

from __future__ import annotations

import contextlib

import numpy as np

from .mesh import MeshError


@contextlib.contextmanager
def gmsh_session():
    """An initialised, quiet gmsh API, finalised afterwards; Ctrl-C stays Python's."""
    try:
        import gmsh
    except ImportError:
        raise MeshError("the gmsh Python package is needed for the built-in meshes and .msh "
                        "files: pip install gmsh") from None
    if gmsh.isInitialized():
        gmsh.finalize()
    gmsh.initialize(["", "-v", "0"], readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        yield gmsh
    finally:
        gmsh.finalize()


def triangles_and_edges(gmsh) -> tuple[np.ndarray, np.ndarray, dict, dict]:
    """Nodes (2D), triangles and the physical line / point groups of the current model."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    if len(tags) == 0:
        raise MeshError("the file holds no mesh (no nodes): save the mesh, not only the "
                        "geometry")
    xyz = coords.reshape(-1, 3)
    order = np.argsort(tags, kind="stable")
    sorted_tags = tags[order].astype(np.int64)

    def index(t):  # node tags -> rows, -1 for a tag that is not a node (tags may be huge)
        t = np.asarray(t).astype(np.int64)
        pos = np.clip(np.searchsorted(sorted_tags, t), 0, len(sorted_tags) - 1)
        return np.where(sorted_tags[pos] == t, order[pos], -1)

    types = {int(t) for t in gmsh.model.mesh.getElementTypes(dim=2)}
    if types - {2}:
        names = [gmsh.model.mesh.getElementProperties(t)[0] for t in sorted(types - {2})]
        raise MeshError(f"only 3-node triangles are supported; the mesh has {', '.join(names)}")
    _, tri_nodes = gmsh.model.mesh.getElementsByType(2)
    triangles = index(tri_nodes).reshape(-1, 3)

    edges, node_sets = {}, {}
    for dim, ptag in gmsh.model.getPhysicalGroups():
        name = gmsh.model.getPhysicalName(dim, ptag) or str(ptag)
        if dim == 1:
            segs = []
            for ent in gmsh.model.getEntitiesForPhysicalGroup(dim, ptag):
                etypes, _, enodes = gmsh.model.mesh.getElements(1, ent)
                for et, en in zip(etypes, enodes):
                    if et != 1:
                        raise MeshError(f"edge '{name}': only 2-node lines are supported")
                    segs.append(index(en).reshape(-1, 2))
            edges[name] = np.concatenate(segs) if segs else np.zeros((0, 2), np.int64)
        elif dim == 0:
            ids = []
            for ent in gmsh.model.getEntitiesForPhysicalGroup(dim, ptag):
                ntags, _, _ = gmsh.model.mesh.getNodes(0, ent)
                ids.extend(index(ntags))
            node_sets[name] = np.asarray(ids, dtype=np.int64)
    return xyz, triangles, edges, node_sets
