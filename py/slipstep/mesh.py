"""Triangle meshes: the built-in generators (gmsh / structured) and file readers.

Every mesh is a :class:`Mesh` of linear (CST) triangles, counter-clockwise, with named edge
tags whose segments are oriented with the body on their left (so the outward normal of a
segment p -> q is the right-hand normal (t_y, -t_x) / |t|, t = q - p).
"""

from __future__ import annotations

import contextlib
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .errors import InputError


class MeshError(InputError):
    """A mesh that cannot be used; one-line message naming the element/edge and the fix."""


@dataclass
class Mesh:
    """A 2D triangle mesh of one body.

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
        self.nodes = np.ascontiguousarray(self.nodes, dtype=np.float64)
        self.triangles = np.ascontiguousarray(self.triangles, dtype=np.int64)
        self.edges = {k: np.asarray(v, dtype=np.int64).reshape(-1, 2) for k, v in self.edges.items()}
        for tag, segs in self.edges.items():
            self.node_sets.setdefault(tag, np.unique(segs))
        self.node_sets = {k: np.asarray(v, dtype=np.int64) for k, v in self.node_sets.items()}

    @property
    def n_nodes(self) -> int:
        return len(self.nodes)

    @property
    def n_elements(self) -> int:
        return len(self.triangles)

    def edge_nodes(self, tag: str) -> np.ndarray:
        """Sorted unique nodes of an edge tag."""
        return np.unique(self.edges[tag])

    def area(self) -> float:
        return float(signed_areas(self.nodes, self.triangles).sum())


# --------------------------------------------------------------------------- checks
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
        longest2 = (sides ** 2).sum(-1).max(1)
    if not (np.isfinite(area).all() and np.isfinite(longest2).all()):
        e = int(np.argmin(np.isfinite(area) & np.isfinite(longest2)))
        raise MeshError(f"{prefix}element {e}: its size overflows (coordinates up to "
                        f"{np.abs(nodes).max():.3g}): rescale the mesh (mesh.scale)")
    # the engine's threshold (rust/src/mesh.rs): twice the area <= 1e-10 (longest side)^2
    degenerate = np.abs(area) <= 0.5e-10 * longest2
    if degenerate.any():
        e = int(np.nonzero(degenerate)[0][0])
        raise MeshError(f"{prefix}element {e} is degenerate (area {area[e]:.3g}, nodes "
                        f"{triangles[e].tolist()}): remove it or fix its nodes")
    if (area < 0).any():
        e = int(np.nonzero(area < 0)[0][0])
        raise MeshError(f"{prefix}element {e} is inverted (signed area {area[e]:.3g}): reorder "
                        f"its nodes counter-clockwise")


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
                raise MeshError(f"{prefix}edge '{tag}' segment {int(p)}-{int(q)} is not a side of "
                                f"any triangle")
            raise MeshError(f"{prefix}edge '{tag}' segment {int(p)}-{int(q)} is inside the "
                            f"mesh (shared by {counts[k[i]]} triangles): tag boundary sides only")
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


def _finish(nodes, triangles, edges, node_sets=None, where="", flip_clockwise=False) -> Mesh:
    """Drop unused nodes, fix a consistently clockwise mesh if asked, check, orient edges."""
    nodes = np.asarray(nodes, dtype=np.float64)
    triangles = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    node_sets = dict(node_sets or {})
    prefix = f"{where}: " if where else ""
    if len(triangles) == 0:
        raise MeshError(f"{prefix}the mesh has no triangles: give each body at least one "
                        f"3-node triangle")
    if triangles.min() < 0 or triangles.max() >= len(nodes):
        bad = int(np.nonzero((triangles < 0).any(1) | (triangles >= len(nodes)).any(1))[0][0])
        raise MeshError(f"{prefix}element {bad} refers to a node outside 0..{len(nodes) - 1}: "
                        f"fix the connectivity")
    for k, v in [*edges.items(), *node_sets.items()]:
        v = np.asarray(v, dtype=np.int64)
        if v.size and (v.min() < 0 or v.max() >= len(nodes)):
            raise MeshError(f"{prefix}tag '{k}' refers to a node that is not in the mesh: fix "
                            f"the file")
    used = np.unique(triangles)
    finite = np.isfinite(nodes[used]).all(axis=1)
    if not finite.all():
        k = int(used[np.argmin(finite)])
        raise MeshError(f"{prefix}node {k} has a non-finite coordinate "
                        f"({nodes[k, 0]}, {nodes[k, 1]}): fix the mesh file")
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
    return Mesh(nodes, triangles, edges, node_sets)


# --------------------------------------------------------------------------- gmsh
@contextlib.contextmanager
def _gmsh_session():
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


def _mesh_with_size_field(gmsh, size: int):
    """Mesh the current gmsh model in 2D with the element size given by field ``size`` alone
    (no size from points, boundaries or curvature); return its triangles and tagged edges."""
    gmsh.model.mesh.field.setAsBackgroundMesh(size)
    for opt in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
        gmsh.option.setNumber(f"Mesh.{opt}", 0)
    gmsh.model.mesh.generate(2)
    return _gmsh_triangles_and_edges(gmsh)


def _mesh_graded_around(gmsh, points: list[int], h_contact: float, contact_zone: float,
                        h_max: float, growth: float):
    """Mesh the model with h = h_contact within contact_zone of the geometry points ``points``
    (d = the distance from the nearest), growing linearly, h = h_contact + growth
    (d - contact_zone), up to h_max (Distance + Threshold)."""
    fields = gmsh.model.mesh.field
    dist = fields.add("Distance")
    fields.setNumbers(dist, "PointsList", points)
    size = fields.add("Threshold")
    fields.setNumber(size, "InField", dist)
    fields.setNumber(size, "SizeMin", h_contact)
    fields.setNumber(size, "SizeMax", h_max)
    fields.setNumber(size, "DistMin", contact_zone)
    fields.setNumber(size, "DistMax", contact_zone + (h_max - h_contact) / growth)
    return _mesh_with_size_field(gmsh, size)


def _gmsh_triangles_and_edges(gmsh) -> tuple[np.ndarray, np.ndarray, dict, dict]:
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


def quarter_cylinder(R: float, h_contact: float, contact_zone: float, h_max: float,
                     growth: float = 0.1) -> Mesh:
    """The quarter cylinder of radius R: centre (0, R), bottom point (0, 0), region x >= 0,
    y <= R (Fig. 4 of the paper, right quarter).

    Edge tags: ``arc`` (the circular surface, from (0, 0) to (R, R)), ``top`` (the cut y = R),
    ``symmetry`` (x = 0).  Element size: h_contact within ``contact_zone`` of (0, 0), growing
    linearly, h = h_contact + growth (d - contact_zone), up to h_max (gmsh Distance+Threshold).
    A node sits exactly at (0, 0) (geometry point); arc nodes lie on the circle.
    """
    with _gmsh_session() as gmsh:
        gmsh.model.add("quarter_cylinder")
        geo = gmsh.model.geo
        bottom = geo.addPoint(0.0, 0.0, 0.0)
        centre = geo.addPoint(0.0, R, 0.0)
        right = geo.addPoint(R, R, 0.0)
        arc = geo.addCircleArc(bottom, centre, right)
        top = geo.addLine(right, centre)
        sym = geo.addLine(centre, bottom)
        surface = geo.addPlaneSurface([geo.addCurveLoop([arc, top, sym])])
        geo.synchronize()
        for name, curve in (("arc", arc), ("top", top), ("symmetry", sym)):
            gmsh.model.setPhysicalName(1, gmsh.model.addPhysicalGroup(1, [curve]), name)
        gmsh.model.setPhysicalName(0, gmsh.model.addPhysicalGroup(0, [bottom]), "bottom_point")
        gmsh.model.addPhysicalGroup(2, [surface])

        xyz, triangles, edges, node_sets = _mesh_graded_around(gmsh, [bottom], h_contact,
                                                               contact_zone, h_max, growth)

    nodes = xyz[:, :2].copy()
    return _finish(nodes, triangles, edges, node_sets, where="quarter_cylinder mesh",
                   flip_clockwise=True)


def half_cylinder(R: float, h_contact: float, contact_zone: float, h_max: float,
                  growth: float = 0.1) -> Mesh:
    """The lower half of the cylinder of radius R, centre (0, R), bottom point (0, 0): the
    quarter_cylinder mirrored across x = 0 (so the mesh is symmetric, and its nodes on x = 0
    are shared). For tangential loads, which a symmetric quarter cannot carry.

    Edge tags: ``arc`` (from (-R, R) through (0, 0) to (R, R)) and ``top`` (the cut y = R).
    """
    quarter = quarter_cylinder(R, h_contact, contact_zone, h_max, growth)
    nodes, triangles, edges = _mirrored(quarter, ("arc", "top"), R)
    return _finish(nodes, triangles, edges, {"bottom_point": quarter.node_sets["bottom_point"]},
                   where="half_cylinder mesh")


def _mirrored(half: Mesh, tags, size: float):
    """(nodes, triangles, edges) of ``half`` (x >= 0) and its mirror image across x = 0, the
    nodes on x = 0 (within 1e-12 size) shared: each edge tag joined with its mirror."""
    x = half.nodes[:, 0]
    on_axis = np.abs(x) <= 1e-12 * size
    mirror = np.arange(len(x))
    mirror[~on_axis] = len(x) + np.arange(int((~on_axis).sum()))
    nodes = np.vstack([half.nodes, half.nodes[~on_axis] * [-1.0, 1.0]])
    triangles = np.vstack([half.triangles, mirror[half.triangles][:, ::-1]])
    edges = {tag: np.vstack([half.edges[tag], mirror[half.edges[tag]][:, ::-1]])
             for tag in tags}
    return nodes, triangles, edges


def disc(R: float, h_contact: float, contact_zone: float, h_max: float,
         growth: float = 0.1) -> Mesh:
    """The whole disc of radius R, centre (0, R), bottom point (0, 0), top point (0, 2R): a
    roller on a flat loaded at its top (a diametrically compressed disc).  Meshed as its right
    half x >= 0 and mirrored across x = 0 (symmetric, nodes on x = 0 shared).

    Edge tags: ``lower_arc`` (y <= R, from (-R, R) through (0, 0) to (R, R)), ``upper_arc``
    (y >= R, from (R, R) through (0, 2R) to (-R, R)) and ``circle`` (both).  Node sets
    ``bottom_point``, ``top_point`` and ``centre_point``, each a node exactly there (geometry
    points; arc nodes lie on the circle).  Element size h_contact within ``contact_zone`` of
    the bottom and of the top point, growing linearly, h = h_contact + growth (d -
    contact_zone), up to h_max (as :func:`quarter_cylinder`).
    """
    with _gmsh_session() as gmsh:
        gmsh.model.add("disc")
        geo = gmsh.model.geo
        bottom, centre = geo.addPoint(0.0, 0.0, 0.0), geo.addPoint(0.0, R, 0.0)
        right, top = geo.addPoint(R, R, 0.0), geo.addPoint(0.0, 2.0 * R, 0.0)
        lower = geo.addCircleArc(bottom, centre, right)
        upper = geo.addCircleArc(right, centre, top)
        axis = [geo.addLine(top, centre), geo.addLine(centre, bottom)]
        surface = geo.addPlaneSurface([geo.addCurveLoop([lower, upper, *axis])])
        geo.synchronize()
        for name, curve in (("lower_arc", lower), ("upper_arc", upper)):
            gmsh.model.setPhysicalName(1, gmsh.model.addPhysicalGroup(1, [curve]), name)
        for name, point in (("bottom_point", bottom), ("top_point", top),
                            ("centre_point", centre)):
            gmsh.model.setPhysicalName(0, gmsh.model.addPhysicalGroup(0, [point]), name)
        gmsh.model.addPhysicalGroup(2, [surface])
        xyz, triangles, edges, node_sets = _mesh_graded_around(gmsh, [bottom, top], h_contact,
                                                               contact_zone, h_max, growth)
    half = _finish(xyz[:, :2].copy(), triangles, edges, node_sets, where="disc mesh",
                   flip_clockwise=True)
    nodes, triangles, edges = _mirrored(half, ("lower_arc", "upper_arc"), R)
    edges["circle"] = np.vstack([edges["lower_arc"], edges["upper_arc"]])
    points = {name: half.node_sets[name] for name in ("bottom_point", "top_point",
                                                       "centre_point")}
    return _finish(nodes, triangles, edges, points, where="disc mesh")


def quarter_annulus(a: float, b: float, h: float, h_outer: float = 0.0) -> Mesh:
    """The quarter of a thick-walled cylinder a <= r <= b, x >= 0, y >= 0, centre (0, 0).

    Edge tags: ``inner`` (r = a, the bore), ``outer`` (r = b), ``x_axis`` (y = 0) and
    ``y_axis`` (x = 0).  Element size h at the bore, growing linearly in r to ``h_outer`` at
    r = b (``h_outer = 0``: uniform h).  Nodes of ``inner``/``outer`` lie on their circles
    (so the polygonal bore is inscribed: its chords sit up to h^2/(8a) inside r = a).
    """
    if not 0.0 < a < b:
        raise MeshError(f"quarter_annulus: need 0 < a < b (got a = {a:g}, b = {b:g})")
    h_outer = h_outer if h_outer > 0.0 else h
    with _gmsh_session() as gmsh:
        gmsh.model.add("quarter_annulus")
        geo = gmsh.model.geo
        centre = geo.addPoint(0.0, 0.0, 0.0)
        inner_x, outer_x = geo.addPoint(a, 0.0, 0.0), geo.addPoint(b, 0.0, 0.0)
        outer_y, inner_y = geo.addPoint(0.0, b, 0.0), geo.addPoint(0.0, a, 0.0)
        x_axis = geo.addLine(inner_x, outer_x)
        outer = geo.addCircleArc(outer_x, centre, outer_y)
        y_axis = geo.addLine(outer_y, inner_y)
        inner = geo.addCircleArc(inner_y, centre, inner_x)
        surface = geo.addPlaneSurface([geo.addCurveLoop([x_axis, outer, y_axis, inner])])
        geo.synchronize()
        for name, curve in (("inner", inner), ("outer", outer), ("x_axis", x_axis),
                            ("y_axis", y_axis)):
            gmsh.model.setPhysicalName(1, gmsh.model.addPhysicalGroup(1, [curve]), name)
        gmsh.model.addPhysicalGroup(2, [surface])

        # h(r) = h + (h_outer - h) (r - a) / (b - a): linear grading in the radius
        fields = gmsh.model.mesh.field
        size = fields.add("MathEval")
        slope = (h_outer - h) / (b - a)
        # (slope) in brackets: gmsh's MathEval aborts the process on "+ -0.02"
        fields.setString(size, "F", f"{h!r} + ({slope!r}) * (sqrt(x*x + y*y) - {a!r})")
        xyz, triangles, edges, node_sets = _mesh_with_size_field(gmsh, size)

    nodes = xyz[:, :2].copy()
    # the geometry points on the axes are exact; snap round-off of the other axis nodes
    nodes[np.unique(edges["x_axis"]), 1] = 0.0
    nodes[np.unique(edges["y_axis"]), 0] = 0.0
    return _finish(nodes, triangles, edges, node_sets, where="quarter_annulus mesh",
                   flip_clockwise=True)


def _grid_triangles(i: np.ndarray, j: np.ndarray, nid) -> np.ndarray:
    """Cells (i, j) of a structured grid, each cut into two counter-clockwise triangles; the
    diagonal alternates with the cell's parity: even i + j a-c, odd b-d (a, b, c, d the cell's
    corners counter-clockwise from its lower left; ``nid(i, j)`` numbers the grid's nodes)."""
    a, b, c, d = nid(i, j), nid(i + 1, j), nid(i + 1, j + 1), nid(i, j + 1)
    even = (i + j) % 2 == 0
    t1 = np.where(even[:, None], np.column_stack([a, b, c]), np.column_stack([a, b, d]))
    t2 = np.where(even[:, None], np.column_stack([a, c, d]), np.column_stack([b, c, d]))
    return np.concatenate([t1, t2])


def block(width: float, height: float, nx: int, ny: int, x0: float = 0.0,
          y0: float = 0.0) -> Mesh:
    """A structured rectangle [x0, x0+width] x [y0, y0+height], nx by ny cells, each cut into
    two triangles (diagonals alternate, so the mesh has no preferred direction).

    Edge tags ``bottom``, ``right``, ``top``, ``left``; node coordinates are x0 + i*width/nx,
    so two blocks with the same spacing share node positions on a common interface.
    """
    if nx < 1 or ny < 1:
        raise MeshError(f"block: nx = {nx}, ny = {ny}: need at least one division each way")
    xs = x0 + width * np.arange(nx + 1) / nx
    ys = y0 + height * np.arange(ny + 1) / ny
    X, Y = np.meshgrid(xs, ys)  # row j = y index
    nodes = np.column_stack([X.ravel(), Y.ravel()])

    def nid(i, j):
        return j * (nx + 1) + i

    i, j = np.meshgrid(np.arange(nx), np.arange(ny))
    triangles = _grid_triangles(i.ravel(), j.ravel(), nid)

    bottom = np.column_stack([nid(np.arange(nx), 0), nid(np.arange(1, nx + 1), 0)])
    right = np.column_stack([nid(nx, np.arange(ny)), nid(nx, np.arange(1, ny + 1))])
    top = np.column_stack([nid(np.arange(nx, 0, -1), ny), nid(np.arange(nx - 1, -1, -1), ny)])
    left = np.column_stack([nid(0, np.arange(ny, 0, -1)), nid(0, np.arange(ny - 1, -1, -1))])
    corners = {"corner_bottom_left": [nid(0, 0)], "corner_bottom_right": [nid(nx, 0)],
               "corner_top_right": [nid(nx, ny)], "corner_top_left": [nid(0, ny)]}
    return _finish(nodes, triangles, {"bottom": bottom, "right": right, "top": top,
                                      "left": left}, corners, where="block mesh")


def _graded_block_focus(width, height, h_contact, contact_zone, h_max, growth, focus, x0, y0):
    """Check graded_block's arguments; the focus, snapped onto a side within round-off."""
    where = "block mesh"
    if not (width > 0 and height > 0):
        raise MeshError(f"{where}: width = {width:g}, height = {height:g}: both must be > 0")
    if not 0 < h_contact <= h_max:
        raise MeshError(f"{where}: h_contact = {h_contact:g}, h_max = {h_max:g}: need "
                        f"0 < h_contact <= h_max")
    if not (contact_zone > 0 and growth > 0):
        raise MeshError(f"{where}: contact_zone = {contact_zone:g}, growth = {growth:g}: both "
                        f"must be > 0")
    x1, y1 = x0 + width, y0 + height
    if focus is None:
        focus = (x0 + 0.5 * width, y1)
    fx, fy = float(focus[0]), float(focus[1])
    tol = 1e-9 * max(width, height)  # round-off of a focus written on the boundary
    if not (x0 - tol <= fx <= x1 + tol and y0 - tol <= fy <= y1 + tol):
        raise MeshError(f"{where}: focus ({fx:g}, {fy:g}) lies outside the block "
                        f"[{x0:g}, {x1:g}] x [{y0:g}, {y1:g}]: move it inside or onto its "
                        f"boundary")
    fx = x0 if abs(fx - x0) <= tol else x1 if abs(fx - x1) <= tol else fx
    fy = y0 if abs(fy - y0) <= tol else y1 if abs(fy - y1) <= tol else fy
    return fx, fy


def _uniform_near_focus(geo, lines, ends, focus, h_contact, contact_zone):
    """Divide each of the two side lines from `focus` to a corner `ends[i]` no farther than
    contact_zone uniformly at (about) h_contact: n = round(length / h_contact) segments."""
    for line, end in zip(lines, ends):
        length = float(np.hypot(end[0] - focus[0], end[1] - focus[1]))
        if length <= contact_zone * (1 + 1e-12):
            geo.mesh.setTransfiniteCurve(line, max(1, round(length / h_contact)) + 1)


def graded_block(width: float, height: float, h_contact: float, contact_zone: float,
                 h_max: float, growth: float = 0.1, focus=None, x0: float = 0.0,
                 y0: float = 0.0, uniform_edges: bool = False) -> Mesh:
    """The rectangle [x0, x0+width] x [y0, y0+height], meshed unstructured by gmsh, fine
    around the point ``focus`` (default: the middle of the top edge, (x0 + width/2, y0 +
    height)).

    Edge tags ``bottom``, ``right``, ``top``, ``left`` (body on the left, as :func:`block`);
    node sets ``corner_bottom_left``, ``corner_bottom_right``, ``corner_top_right``,
    ``corner_top_left`` and ``focus``.  Element size, with d the distance from focus:
    h = h_contact for d <= contact_zone, then h = h_contact + growth (d - contact_zone), up
    to h_max (gmsh Distance+Threshold, as :func:`quarter_cylinder`).  There is a node exactly
    at focus (a geometry point: on the boundary it splits its edge, inside it is embedded);
    the nodes of each edge lie exactly on its line.  ``focus`` may lie on the boundary or
    inside, within 1e-9 max(width, height) of the rectangle; nearer than that to a side it
    is moved onto it.  ``uniform_edges``: the side from a boundary focus to a corner no farther
    than contact_zone is divided uniformly, n = round(length / h_contact) segments, so that
    another body's structured nodes can match it (a punch on a graded half-space, node_to_node).
    """
    fx, fy = _graded_block_focus(width, height, h_contact, contact_zone, h_max, growth, focus,
                                 x0, y0)
    x1, y1 = x0 + width, y0 + height
    with _gmsh_session() as gmsh:
        gmsh.model.add("graded_block")
        geo = gmsh.model.geo
        corners = {"corner_bottom_left": (x0, y0), "corner_bottom_right": (x1, y0),
                   "corner_top_right": (x1, y1), "corner_top_left": (x0, y1)}
        points = {name: geo.addPoint(x, y, 0.0) for name, (x, y) in corners.items()}
        at_corner = [name for name, xy in corners.items() if xy == (fx, fy)]
        # the sides counter-clockwise (body on the left), each a list of its gmsh lines
        sides = {"bottom": ("corner_bottom_left", "corner_bottom_right", fy == y0),
                 "right": ("corner_bottom_right", "corner_top_right", fx == x1),
                 "top": ("corner_top_right", "corner_top_left", fy == y1),
                 "left": ("corner_top_left", "corner_bottom_left", fx == x0)}
        focus_point = points[at_corner[0]] if at_corner else geo.addPoint(fx, fy, 0.0)
        lines = {}
        for tag, (a, b, on_it) in sides.items():
            if on_it and not at_corner:  # split the side at focus
                lines[tag] = [geo.addLine(points[a], focus_point),
                              geo.addLine(focus_point, points[b])]
                if uniform_edges:
                    _uniform_near_focus(geo, lines[tag], [corners[a], corners[b]], (fx, fy),
                                        h_contact, contact_zone)
            else:
                lines[tag] = [geo.addLine(points[a], points[b])]
        loop = geo.addCurveLoop([c for tag in sides for c in lines[tag]])
        surface = geo.addPlaneSurface([loop])
        geo.synchronize()
        inside = x0 < fx < x1 and y0 < fy < y1
        if inside:
            gmsh.model.mesh.embed(0, [focus_point], 2, surface)
        for tag in sides:
            gmsh.model.setPhysicalName(1, gmsh.model.addPhysicalGroup(1, lines[tag]), tag)
        for name, p in [*points.items(), ("focus", focus_point)]:
            gmsh.model.setPhysicalName(0, gmsh.model.addPhysicalGroup(0, [p]), name)
        gmsh.model.addPhysicalGroup(2, [surface])

        xyz, triangles, edges, node_sets = _mesh_graded_around(gmsh, [focus_point], h_contact,
                                                               contact_zone, h_max, growth)

    nodes = xyz[:, :2].copy()
    # the sides are exact lines; snap round-off of their nodes (the corners and focus are exact)
    for tag, axis, value in (("bottom", 1, y0), ("right", 0, x1), ("top", 1, y1),
                             ("left", 0, x0)):
        nodes[np.unique(edges[tag]), axis] = value
    return _finish(nodes, triangles, edges, node_sets, where="block mesh", flip_clockwise=True)


# --------------------------------------------------------------------------- refined block
def refined_block(width: float, height: float, nx: int, ny: int, box, h_max: float,
                  growth: float = 0.1, x0: float = 0.0, y0: float = 0.0) -> Mesh:
    """The structured :func:`block` (nx x ny cells) kept only inside ``box`` = [bx0, by0, bx1,
    by1]; the rest of the rectangle meshed by gmsh, coarsening away from the box.

    ``box`` is rounded outwards to the block's grid lines. Inside it the nodes and triangles
    are the structured block's, bit for bit (same coordinates, same alternating diagonals,
    counted from the block's corner (x0, y0)), so the box keeps the structured block's local
    discretization; its sides keep the grid's nodes. Outside, gmsh aims at the element size
    h + growth d, up to h_max (d: distance from the box; h: the smaller grid spacing; a Box
    field). A box covering the whole block gives :func:`block` itself. Edge tags and corner
    node sets as :func:`block`; each edge tag is one chain, in order.
    """
    rect = (x0, y0, x0 + width, y0 + height)
    tol = 1e-9 * max(width, height)  # round-off of coordinates on the block's lines
    cells = _box_cells(width, height, nx, ny, box, x0, y0)
    if cells == (0, 0, nx, ny):
        return block(width, height, nx, ny, x0, y0)
    h = min(width / nx, height / ny)
    if not (h_max >= h and growth > 0):
        raise MeshError(f"block mesh: h_max = {h_max:g}, growth = {growth:g}: need h_max >= "
                        f"the grid spacing {h:g} and growth > 0")
    patch, patch_triangles = _structured_patch(width, height, nx, ny, cells, x0, y0)
    counts = (cells[2] - cells[0], cells[3] - cells[1])
    hole = (patch[0, 0], patch[0, 1], patch[-1, 0], patch[-1, 1])
    outer, outer_triangles = _mesh_outside_box(rect, hole, counts, h, h_max, growth)
    for axis, value in ((0, rect[0]), (1, rect[1]), (0, rect[2]), (1, rect[3])):
        outer[np.abs(outer[:, axis] - value) <= tol, axis] = value  # the sides are exact lines
    rows = _rows_on_patch(outer, patch, hole, counts, tol)
    rows = np.where(rows >= 0, rows, len(patch) + np.arange(len(outer)))
    nodes = np.vstack([patch, outer])
    triangles = np.vstack([patch_triangles, rows[outer_triangles]])
    edges, corners = _side_chains(nodes, np.unique(triangles), rect)
    return _finish(nodes, triangles, edges, corners, where="block mesh")


def _box_cells(width, height, nx, ny, box, x0, y0) -> tuple[int, int, int, int]:
    """The box rounded outwards to the grid lines of the nx x ny block: the cells (i, j) with
    i0 <= i < i1, j0 <= j < j1."""
    bx0, by0, bx1, by1 = (float(v) for v in box)
    x1, y1 = x0 + width, y0 + height
    tol = 1e-9 * max(width, height)
    shown = f"refine_box [{bx0:g}, {by0:g}, {bx1:g}, {by1:g}]"
    if not (bx0 < bx1 and by0 < by1):
        raise MeshError(f"block mesh: {shown} is empty: write it [x0, y0, x1, y1] with "
                        f"x0 < x1 and y0 < y1")
    if not (x0 - tol <= bx0 and bx1 <= x1 + tol and y0 - tol <= by0 and by1 <= y1 + tol):
        raise MeshError(f"block mesh: {shown} reaches outside the block [{x0:g}, {x1:g}] x "
                        f"[{y0:g}, {y1:g}]: keep it inside")
    lower = [max(0, int(np.floor((b - o) * n / size + 1e-9)))
             for b, o, n, size in ((bx0, x0, nx, width), (by0, y0, ny, height))]
    upper = [min(n, max(lo + 1, int(np.ceil((b - o) * n / size - 1e-9))))
             for b, o, n, size, lo in ((bx1, x0, nx, width, lower[0]),
                                       (by1, y0, ny, height, lower[1]))]
    return lower[0], lower[1], upper[0], upper[1]


def _structured_patch(width, height, nx, ny, cells, x0, y0):
    """Nodes and triangles of the cells of block(width, height, nx, ny, x0, y0) in ``cells``,
    with the block's own coordinate formula and diagonal parity; node (i, j) is row
    (j - j0) (i1 - i0 + 1) + i - i0."""
    i0, j0, i1, j1 = cells
    X, Y = np.meshgrid(x0 + width * np.arange(i0, i1 + 1) / nx,
                       y0 + height * np.arange(j0, j1 + 1) / ny)

    def nid(i, j):
        return (j - j0) * (i1 - i0 + 1) + i - i0

    i, j = np.meshgrid(np.arange(i0, i1), np.arange(j0, j1))
    return np.column_stack([X.ravel(), Y.ravel()]), _grid_triangles(i.ravel(), j.ravel(), nid)


def _mesh_outside_box(rect, hole, counts, h, h_max, growth):
    """gmsh: the rectangle ``rect`` (x0, y0, x1, y1) minus ``hole``, the hole's sides divided
    into counts = (along x, along y) equal segments; elsewhere the size h + growth d up to
    h_max, d the distance from the hole (Box field). Nodes (2D), counter-clockwise triangles."""
    x0, y0, x1, y1 = rect
    X0, Y0, X1, Y1 = hole
    with _gmsh_session() as gmsh:
        gmsh.model.add("refined_block")
        occ = gmsh.model.occ
        occ.cut([(2, occ.addRectangle(x0, y0, 0.0, x1 - x0, y1 - y0))],
                [(2, occ.addRectangle(X0, Y0, 0.0, X1 - X0, Y1 - Y0))])
        occ.synchronize()
        tol = 1e-9 * max(x1 - x0, y1 - y0)
        for _, curve in gmsh.model.getEntities(1):
            ends = [gmsh.model.getValue(0, abs(t), [])[:2]
                    for _, t in gmsh.model.getBoundary([(1, curve)], oriented=False)]
            n = _segments_on_hole(*ends, hole, counts, tol)
            if n:
                gmsh.model.mesh.setTransfiniteCurve(curve, n + 1)
        fields = gmsh.model.mesh.field
        size = fields.add("Box")
        for key, value in (("VIn", h), ("VOut", h_max), ("XMin", X0), ("XMax", X1),
                           ("YMin", Y0), ("YMax", Y1), ("Thickness", (h_max - h) / growth)):
            fields.setNumber(size, key, value)
        xyz, triangles, _, _ = _mesh_with_size_field(gmsh, size)
    nodes = xyz[:, :2].copy()
    flip = signed_areas(nodes, triangles) < 0
    triangles[flip] = triangles[flip][:, [0, 2, 1]]
    return nodes, triangles


def _segments_on_hole(p, q, hole, counts, tol) -> int:
    """The number of grid segments of the straight curve p-q if it lies on a side of the hole
    (a part of it, when the hole touches the rectangle's boundary), else 0."""
    X0, Y0, X1, Y1 = hole
    (px, py), (qx, qy) = p, q
    if abs(py - qy) <= tol and min(abs(py - Y0), abs(py - Y1)) <= tol \
            and min(px, qx) >= X0 - tol and max(px, qx) <= X1 + tol:
        return round(abs(qx - px) / (X1 - X0) * counts[0])
    if abs(px - qx) <= tol and min(abs(px - X0), abs(px - X1)) <= tol \
            and min(py, qy) >= Y0 - tol and max(py, qy) <= Y1 + tol:
        return round(abs(qy - py) / (Y1 - Y0) * counts[1])
    return 0


def _rows_on_patch(outer, patch, hole, counts, tol) -> np.ndarray:
    """Each gmsh node's row in the structured patch if it lies on the hole's boundary (where
    it must coincide with a grid node), else -1."""
    X0, Y0, X1, Y1 = hole
    x, y = outer[:, 0], outer[:, 1]
    on = np.flatnonzero((x >= X0 - tol) & (x <= X1 + tol) & (y >= Y0 - tol) & (y <= Y1 + tol))
    i = np.rint((x[on] - X0) / (X1 - X0) * counts[0]).astype(np.int64)
    j = np.rint((y[on] - Y0) / (Y1 - Y0) * counts[1]).astype(np.int64)
    rows = np.full(len(outer), -1, dtype=np.int64)
    rows[on] = j * (counts[0] + 1) + i
    off = np.abs(patch[rows[on]] - outer[on]).max(axis=1, initial=0.0) > tol
    if off.any():
        k = on[np.argmax(off)]
        raise MeshError(f"block mesh: gmsh put a node at ({x[k]:g}, {y[k]:g}) on the refine_box "
                        f"side between the grid's nodes: report this (gmsh version)")
    return rows


def _side_chains(nodes, used, rect) -> tuple[dict, dict]:
    """Edge tags bottom / right / top / left of a rectangle's mesh (the used nodes on each side,
    counter-clockwise, joined into segments) and its corner node sets."""
    x0, y0, x1, y1 = rect
    sides = {"bottom": (1, y0, 0, 1.0), "right": (0, x1, 1, 1.0), "top": (1, y1, 0, -1.0),
             "left": (0, x0, 1, -1.0)}
    edges = {}
    for tag, (axis, value, along, sense) in sides.items():
        on = used[nodes[used, axis] == value]
        on = on[np.argsort(sense * nodes[on, along], kind="stable")]
        edges[tag] = np.column_stack([on[:-1], on[1:]])
    corners = {}
    for name, (cx, cy) in (("corner_bottom_left", (x0, y0)), ("corner_bottom_right", (x1, y0)),
                           ("corner_top_right", (x1, y1)), ("corner_top_left", (x0, y1))):
        corners[name] = used[(nodes[used, 0] == cx) & (nodes[used, 1] == cy)]
    return edges, corners

# --------------------------------------------------------------------------- files
def read_mesh(path: str | Path, edge_file: str | Path | None = None, scale: float = 1.0) -> Mesh:
    """Read a triangle mesh: ``.msh`` (through gmsh; physical line names are the edge tags,
    physical points the node sets) or ``.xdmf`` (through meshio; line cells, from the same file
    or from ``edge_file``, tagged by the first integer cell-data array; a tag is named by its
    meshio field_data name if present, else by its number).

    A mesh whose triangles are ALL clockwise is flipped; a mix is an error naming the first
    inverted element.
    """
    path = Path(path)
    where = str(path)
    if not path.exists():
        raise MeshError(f"{where}: no such mesh file")
    suffix = path.suffix.lower()
    if suffix == ".msh":
        xyz, triangles, edges, node_sets = _read_msh_isolated(path, where)
    elif suffix == ".xdmf":
        xyz, triangles, edges = _read_xdmf(path)
        node_sets = {}
        if edge_file:
            _, extra_tris, extra = _read_xdmf(Path(edge_file), need_triangles=False)
            if len(extra_tris) and not np.array_equal(extra_tris, triangles):
                raise MeshError(f"{edge_file}: holds triangles too: keep only the line cells")
            edges.update(extra)
    else:
        raise MeshError(f"{where}: unknown mesh format '{suffix}': use .msh or .xdmf")
    xy = _planar(xyz, where)
    if not np.isfinite(xy).all():
        k = int(np.nonzero(~np.isfinite(xy).all(axis=1))[0][0])
        raise MeshError(f"{where}: node {k} has a non-finite coordinate "
                        f"({', '.join(str(c) for c in xy[k])}): fix the mesh file")
    return _finish(xy * scale, triangles, edges, node_sets, where=where, flip_clockwise=True)


def _planar(xyz, where: str) -> np.ndarray:
    """(N, 2) float64 coordinates from (N, 2) or (N, 3) with z = 0."""
    xyz = np.asarray(xyz, dtype=np.float64)
    if xyz.ndim != 2 or xyz.shape[1] not in (2, 3):
        raise MeshError(f"{where}: the node coordinates have shape {xyz.shape}: expected 2 or "
                        f"3 columns")
    if xyz.shape[1] == 3:
        zmax = np.abs(xyz[:, 2]).max(initial=0.0)
        if zmax > 1e-12 * max(np.abs(xyz[:, :2]).max(initial=1.0), 1.0):
            raise MeshError(f"{where}: the mesh is not planar (|z| up to {zmax:.3g}): slipstep "
                            f"meshes lie in the x-y plane")
    return xyz[:, :2]


def _read_msh(path: str, where: str):
    """Nodes, triangles, edges and node sets of a .msh file, through gmsh."""
    with _gmsh_session() as gmsh:
        try:
            gmsh.open(path)
        except Exception as exc:  # gmsh raises bare Exception
            raise MeshError(f"{where}: gmsh cannot read it: {' '.join(str(exc).split())}") \
                from None
        try:
            return _gmsh_triangles_and_edges(gmsh)
        except MeshError as exc:
            raise MeshError(f"{where}: {exc}") from None


def _msh_child(path: str, where: str, conn) -> None:
    import faulthandler

    faulthandler.disable()  # a crashing gmsh must not print a Python stack (pytest enables it)
    devnull = os.open(os.devnull, os.O_WRONLY)  # nor libc/C++ noise
    os.dup2(devnull, 1)
    os.dup2(devnull, 2)
    try:
        conn.send(("ok", _read_msh(path, where)))
    except MeshError as exc:
        conn.send(("error", str(exc)))
    except BaseException as exc:  # noqa: BLE001 - anything else gmsh raises
        conn.send(("error", f"{where}: gmsh cannot read it: {' '.join(str(exc).split())}"))
    finally:
        conn.close()


def _read_msh_isolated(path: Path, where: str):
    """:func:`_read_msh` in a forked child process: gmsh corrupts its memory on some damaged
    .msh files and crashes the whole process (segmentation fault, abort; found by
    tests/case/test_fuzz.py), so a crash there becomes a MeshError here."""
    import multiprocessing

    try:
        ctx = multiprocessing.get_context("fork")
    except ValueError:  # no fork on this platform: read in-process
        return _read_msh(str(path), where)
    receive, send = ctx.Pipe(duplex=False)
    child = ctx.Process(target=_msh_child, args=(str(path), where, send), daemon=True)
    child.start()
    send.close()
    try:
        kind, payload = receive.recv()
    except EOFError:  # the child died without an answer
        kind, payload = None, None
    finally:
        receive.close()
        child.join()
    if kind == "ok":
        return payload
    if kind == "error":
        raise MeshError(payload)
    raise MeshError(f"{where}: gmsh crashed while reading it (exit code {child.exitcode}): the "
                    f"file is damaged or truncated; export the mesh again")


def _read_xdmf(path: Path, need_triangles: bool = True):
    try:
        import meshio
    except ImportError:
        raise MeshError("meshio is needed to read .xdmf meshes: pip install meshio") from None
    if not path.exists():
        raise MeshError(f"{path}: no such mesh file")
    try:
        # the XDMF reader itself: meshio.read prints the reader's error and calls sys.exit
        m = meshio.xdmf.read(str(path))
    except SystemExit:
        raise MeshError(f"{path}: meshio cannot read it") from None
    except Exception as exc:  # noqa: BLE001 - XML, HDF5, numpy and meshio errors alike
        why = " ".join(str(exc).split()) or f"{type(exc).__name__} (not a valid XDMF mesh)"
        if "one grid" in why:  # meshio reads a single grid
            raise MeshError(f"{path}: meshio cannot read this XDMF (several grids, e.g. a time "
                            f"series?): write the mesh on its own") from None
        raise MeshError(f"{path}: meshio cannot read it: {why}") from None
    return _meshio_cells(m, str(path), need_triangles)


def _meshio_cells(m, where: str, need_triangles: bool = True):
    """(points, triangles, edges) of a meshio.Mesh: triangle cells, and line cells tagged by
    the first integer cell-data array (a tag named by its field_data name if any)."""
    names = {int(v[0]): k for k, v in getattr(m, "field_data", {}).items()
             if len(v) >= 2 and int(v[1]) == 1}
    triangles, edges = [], {}
    for i, block_ in enumerate(m.cells):
        if block_.type == "triangle":
            triangles.append(block_.data)
        elif block_.type == "line":
            tags = None
            for arrays in m.cell_data.values():
                a = np.asarray(arrays[i])
                if a.ndim == 1 or (a.ndim == 2 and a.shape[1] == 1):
                    if np.issubdtype(a.dtype, np.integer) or np.all(a == np.round(a)):
                        tags = a.reshape(-1).astype(np.int64)
                        break
            if tags is None:
                raise MeshError(f"{where}: line cells without an integer tag array: tag them")
            for t in np.unique(tags):
                name = names.get(int(t), str(int(t)))
                segs = block_.data[tags == t]
                edges[name] = np.concatenate([edges[name], segs]) if name in edges else segs
        elif block_.type != "vertex":
            raise MeshError(f"{where}: cells of type '{block_.type}': only triangles and lines "
                            f"are supported")
    if need_triangles and not triangles:
        raise MeshError(f"{where}: no triangle cells")
    tri = np.concatenate(triangles) if triangles else np.zeros((0, 3), np.int64)
    return m.points, tri, edges


# --------------------------------------------------------------------------- from Python
def from_arrays(nodes, triangles, edges: dict | None = None, node_sets: dict | None = None,
                where: str = "mesh from arrays") -> Mesh:
    """A body's mesh from numpy arrays, without files: ``nodes`` (N, 2) (or (N, 3) with z = 0),
    ``triangles`` (M, 3) node ids, ``edges`` tag -> (K, 2) boundary segments (the tags that
    [[bc]] and [[contact]] name), ``node_sets`` name -> node ids.  Checked and cleaned like a
    file mesh: unused nodes dropped, an all-clockwise mesh flipped, edges oriented with the
    body on the left."""
    return _finish(_planar(nodes, where), triangles, dict(edges or {}), node_sets, where=where,
                   flip_clockwise=True)


def from_meshio(mesh, where: str = "meshio mesh") -> Mesh:
    """A body's mesh from a ``meshio.Mesh`` (e.g. ``meshio.read("body.msh")``): its triangle
    cells, and its line cells as edges tagged by the first integer cell-data array (gmsh's
    physical groups), each tag named by its ``field_data`` name when there is one."""
    points, triangles, edges = _meshio_cells(mesh, where)
    return from_arrays(points, triangles, edges, where=where)


def write_msh(mesh: Mesh, path: str | Path) -> dict[str, int]:
    """Write ``mesh`` as a gmsh MSH 2.2 ASCII file that :func:`read_mesh` (and other codes, e.g.
    GetFEM's gmsh import) read back: nodes with z = 0, triangles in physical surface ``body``,
    every edge tag a named physical line group, every node set a named physical point group.
    Returns the physical tag of each group (edges first, sorted by name; then node sets; the
    surface last): readers that number regions by tag need it."""
    edges, sets = sorted(mesh.edges), sorted(set(mesh.node_sets) - set(mesh.edges))
    tags = {name: i + 1 for i, name in enumerate(edges + sets)}
    tags["body"] = len(tags) + 1
    rows = [f'1 {tags[n]} "{n}"' for n in edges] + [f'0 {tags[n]} "{n}"' for n in sets]
    rows.append(f'2 {tags["body"]} "body"')
    # elements: id type(15 point, 1 line, 2 triangle) 2 physical elementary node ids (1-based)
    elements = [(15, tags[n], [[int(k)] for k in mesh.node_sets[n]]) for n in sets]
    elements += [(1, tags[n], mesh.edges[n].tolist()) for n in edges]
    elements.append((2, tags["body"], mesh.triangles.tolist()))
    lines = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(rows)),
             *rows, "$EndPhysicalNames", "$Nodes", str(mesh.n_nodes)]
    lines += [f"{i + 1} {x!r} {y!r} 0" for i, (x, y) in enumerate(mesh.nodes.tolist())]
    lines += ["$EndNodes", "$Elements", str(sum(len(e[2]) for e in elements))]
    k = 0
    for kind, tag, conn in elements:
        for nodes in conn:
            k += 1
            lines.append(f"{k} {kind} 2 {tag} {tag} " + " ".join(str(n + 1) for n in nodes))
    lines.append("$EndElements")
    Path(path).write_text("\n".join(lines) + "\n")
    return tags
