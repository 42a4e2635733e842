"""The built-in mesh generators: the quarter and half cylinder and the disc (gmsh, graded towards
the contact point), the quarter annulus (gmsh), the structured block, the graded block (gmsh,
fine around a focus) and the refined block (structured inside a box, gmsh outside).  Each
returns a checked :class:`slipstep.mesh.Mesh` with the edge tags of
:data:`slipstep.schema.GENERATOR_EDGES`; the gmsh ones through the mesh cache
(:mod:`slipstep.mesh.cache`).
"""

from __future__ import annotations

import numpy as np

from .gmsh_api import gmsh_session, size_field_only, threshold_field, triangles_and_edges
from .base import Mesh, MeshError
from .triangles import checked_mesh, signed_areas
from .cache import cached


def _mesh_with_size_field(gmsh, size: int):
    """Mesh the current gmsh model in 2D with the element size given by field ``size`` alone
    (no size from points, boundaries or curvature); return its triangles and tagged edges."""
    size_field_only(gmsh, size)
    gmsh.model.mesh.generate(2)
    return triangles_and_edges(gmsh)


def _mesh_graded_around(
    gmsh, points: list[int], h_contact: float, contact_zone: float, h_max: float, growth: float
):
    """Mesh the model with h = h_contact within contact_zone of the geometry points ``points``
    (d = the distance from the nearest), growing linearly, h = h_contact + growth
    (d - contact_zone), up to h_max (Distance + Threshold)."""
    size = threshold_field(gmsh, h_contact, contact_zone, h_max, growth, points=points)
    return _mesh_with_size_field(gmsh, size)


@cached
def quarter_cylinder(
    R: float, h_contact: float, contact_zone: float, h_max: float, growth: float = 0.1
) -> Mesh:
    """The quarter cylinder of radius R: centre (0, R), bottom point (0, 0), region x >= 0,
    y <= R (Fig. 4 of the paper, right quarter).

    Edge tags: ``arc`` (the circular surface, from (0, 0) to (R, R)), ``top`` (the cut y = R),
    ``symmetry`` (x = 0).  Element size: h_contact within ``contact_zone`` of (0, 0), growing
    linearly, h = h_contact + growth (d - contact_zone), up to h_max (gmsh Distance+Threshold).
    A node sits exactly at (0, 0) (geometry point); arc nodes lie on the circle.
    """
    with gmsh_session() as gmsh:
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

        xyz, triangles, edges, node_sets = _mesh_graded_around(
            gmsh, [bottom], h_contact, contact_zone, h_max, growth
        )

    nodes = xyz[:, :2].copy()
    return checked_mesh(
        nodes, triangles, edges, node_sets, where="quarter_cylinder mesh", flip_clockwise=True
    )


def half_cylinder(
    R: float, h_contact: float, contact_zone: float, h_max: float, growth: float = 0.1
) -> Mesh:
    """The lower half of the cylinder of radius R, centre (0, R), bottom point (0, 0): the
    quarter_cylinder mirrored across x = 0 (so the mesh is symmetric, and its nodes on x = 0
    are shared). For tangential loads, which a symmetric quarter cannot carry.

    Edge tags: ``arc`` (from (-R, R) through (0, 0) to (R, R)) and ``top`` (the cut y = R).
    """
    quarter = quarter_cylinder(R, h_contact, contact_zone, h_max, growth)
    nodes, triangles, edges = _mirrored(quarter, ("arc", "top"), R)
    return checked_mesh(
        nodes,
        triangles,
        edges,
        {"bottom_point": quarter.node_sets["bottom_point"]},
        where="half_cylinder mesh",
    )


def _mirrored(half: Mesh, tags, size: float):
    """(nodes, triangles, edges) of ``half`` (x >= 0) and its mirror image across x = 0, the
    nodes on x = 0 (within 1e-12 size) shared: each edge tag joined with its mirror."""
    x = half.nodes[:, 0]
    on_axis = np.abs(x) <= 1e-12 * size
    mirror = np.arange(len(x))
    mirror[~on_axis] = len(x) + np.arange(int((~on_axis).sum()))
    nodes = np.vstack([half.nodes, half.nodes[~on_axis] * [-1.0, 1.0]])
    triangles = np.vstack([half.triangles, mirror[half.triangles][:, ::-1]])
    edges = {tag: np.vstack([half.edges[tag], mirror[half.edges[tag]][:, ::-1]]) for tag in tags}
    return nodes, triangles, edges


@cached
def disc(
    R: float, h_contact: float, contact_zone: float, h_max: float, growth: float = 0.1
) -> Mesh:
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
    with gmsh_session() as gmsh:
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
        for name, point in (("bottom_point", bottom), ("top_point", top), ("centre_point", centre)):
            gmsh.model.setPhysicalName(0, gmsh.model.addPhysicalGroup(0, [point]), name)
        gmsh.model.addPhysicalGroup(2, [surface])
        xyz, triangles, edges, node_sets = _mesh_graded_around(
            gmsh, [bottom, top], h_contact, contact_zone, h_max, growth
        )
    half = checked_mesh(
        xyz[:, :2].copy(), triangles, edges, node_sets, where="disc mesh", flip_clockwise=True
    )
    nodes, triangles, edges = _mirrored(half, ("lower_arc", "upper_arc"), R)
    edges["circle"] = np.vstack([edges["lower_arc"], edges["upper_arc"]])
    points = {name: half.node_sets[name] for name in ("bottom_point", "top_point", "centre_point")}
    return checked_mesh(nodes, triangles, edges, points, where="disc mesh")


@cached
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
    with gmsh_session() as gmsh:
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
        for name, curve in (
            ("inner", inner),
            ("outer", outer),
            ("x_axis", x_axis),
            ("y_axis", y_axis),
        ):
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
    return checked_mesh(
        nodes, triangles, edges, node_sets, where="quarter_annulus mesh", flip_clockwise=True
    )


def _grid_triangles(i: np.ndarray, j: np.ndarray, nid) -> np.ndarray:
    """Cells (i, j) of a structured grid, each cut into two counter-clockwise triangles; the
    diagonal alternates with the cell's parity: even i + j a-c, odd b-d (a, b, c, d the cell's
    corners counter-clockwise from its lower left; ``nid(i, j)`` numbers the grid's nodes)."""
    a, b, c, d = nid(i, j), nid(i + 1, j), nid(i + 1, j + 1), nid(i, j + 1)
    even = (i + j) % 2 == 0
    t1 = np.where(even[:, None], np.column_stack([a, b, c]), np.column_stack([a, b, d]))
    t2 = np.where(even[:, None], np.column_stack([a, c, d]), np.column_stack([b, c, d]))
    return np.concatenate([t1, t2])


def block(width: float, height: float, nx: int, ny: int, x0: float = 0.0, y0: float = 0.0) -> Mesh:
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
    corners = {
        "corner_bottom_left": [nid(0, 0)],
        "corner_bottom_right": [nid(nx, 0)],
        "corner_top_right": [nid(nx, ny)],
        "corner_top_left": [nid(0, ny)],
    }
    return checked_mesh(
        nodes,
        triangles,
        {"bottom": bottom, "right": right, "top": top, "left": left},
        corners,
        where="block mesh",
    )


def _graded_block_focus(width, height, h_contact, contact_zone, h_max, growth, focus, x0, y0):
    """Check graded_block's arguments; the focus, snapped onto a side within round-off."""
    where = "block mesh"
    if not (width > 0 and height > 0):
        raise MeshError(f"{where}: width = {width:g}, height = {height:g}: both must be > 0")
    if not 0 < h_contact <= h_max:
        raise MeshError(
            f"{where}: h_contact = {h_contact:g}, h_max = {h_max:g}: need "
            f"0 < h_contact <= h_max"
        )
    if not (contact_zone > 0 and growth > 0):
        raise MeshError(
            f"{where}: contact_zone = {contact_zone:g}, growth = {growth:g}: both " f"must be > 0"
        )
    x1, y1 = x0 + width, y0 + height
    if focus is None:
        focus = (x0 + 0.5 * width, y1)
    fx, fy = float(focus[0]), float(focus[1])
    tol = 1e-9 * max(width, height)  # round-off of a focus written on the boundary
    if not (x0 - tol <= fx <= x1 + tol and y0 - tol <= fy <= y1 + tol):
        raise MeshError(
            f"{where}: focus ({fx:g}, {fy:g}) lies outside the block "
            f"[{x0:g}, {x1:g}] x [{y0:g}, {y1:g}]: move it inside or onto its "
            f"boundary"
        )
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


@cached
def graded_block(
    width: float,
    height: float,
    h_contact: float,
    contact_zone: float,
    h_max: float,
    growth: float = 0.1,
    focus=None,
    x0: float = 0.0,
    y0: float = 0.0,
    uniform_edges: bool = False,
) -> Mesh:
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
    fx, fy = _graded_block_focus(
        width, height, h_contact, contact_zone, h_max, growth, focus, x0, y0
    )
    x1, y1 = x0 + width, y0 + height
    with gmsh_session() as gmsh:
        gmsh.model.add("graded_block")
        geo = gmsh.model.geo
        corners = {
            "corner_bottom_left": (x0, y0),
            "corner_bottom_right": (x1, y0),
            "corner_top_right": (x1, y1),
            "corner_top_left": (x0, y1),
        }
        points = {name: geo.addPoint(x, y, 0.0) for name, (x, y) in corners.items()}
        at_corner = [name for name, xy in corners.items() if xy == (fx, fy)]
        # the sides counter-clockwise (body on the left), each a list of its gmsh lines
        sides = {
            "bottom": ("corner_bottom_left", "corner_bottom_right", fy == y0),
            "right": ("corner_bottom_right", "corner_top_right", fx == x1),
            "top": ("corner_top_right", "corner_top_left", fy == y1),
            "left": ("corner_top_left", "corner_bottom_left", fx == x0),
        }
        focus_point = points[at_corner[0]] if at_corner else geo.addPoint(fx, fy, 0.0)
        lines = {}
        for tag, (a, b, on_it) in sides.items():
            if on_it and not at_corner:  # split the side at focus
                lines[tag] = [
                    geo.addLine(points[a], focus_point),
                    geo.addLine(focus_point, points[b]),
                ]
                if uniform_edges:
                    _uniform_near_focus(
                        geo, lines[tag], [corners[a], corners[b]], (fx, fy), h_contact, contact_zone
                    )
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

        xyz, triangles, edges, node_sets = _mesh_graded_around(
            gmsh, [focus_point], h_contact, contact_zone, h_max, growth
        )

    nodes = xyz[:, :2].copy()
    # the sides are exact lines; snap round-off of their nodes (the corners and focus are exact)
    for tag, axis, value in (("bottom", 1, y0), ("right", 0, x1), ("top", 1, y1), ("left", 0, x0)):
        nodes[np.unique(edges[tag]), axis] = value
    return checked_mesh(nodes, triangles, edges, node_sets, where="block mesh", flip_clockwise=True)


@cached
def refined_block(
    width: float,
    height: float,
    nx: int,
    ny: int,
    box,
    h_max: float,
    growth: float = 0.1,
    x0: float = 0.0,
    y0: float = 0.0,
) -> Mesh:
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
        raise MeshError(
            f"block mesh: h_max = {h_max:g}, growth = {growth:g}: need h_max >= "
            f"the grid spacing {h:g} and growth > 0"
        )
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
    return checked_mesh(nodes, triangles, edges, corners, where="block mesh")


def _box_cells(width, height, nx, ny, box, x0, y0) -> tuple[int, int, int, int]:
    """The box rounded outwards to the grid lines of the nx x ny block: the cells (i, j) with
    i0 <= i < i1, j0 <= j < j1."""
    bx0, by0, bx1, by1 = (float(v) for v in box)
    x1, y1 = x0 + width, y0 + height
    tol = 1e-9 * max(width, height)
    shown = f"refine_box [{bx0:g}, {by0:g}, {bx1:g}, {by1:g}]"
    if not (bx0 < bx1 and by0 < by1):
        raise MeshError(
            f"block mesh: {shown} is empty: write it [x0, y0, x1, y1] with " f"x0 < x1 and y0 < y1"
        )
    if not (x0 - tol <= bx0 and bx1 <= x1 + tol and y0 - tol <= by0 and by1 <= y1 + tol):
        raise MeshError(
            f"block mesh: {shown} reaches outside the block [{x0:g}, {x1:g}] x "
            f"[{y0:g}, {y1:g}]: keep it inside"
        )
    lower = [
        max(0, int(np.floor((b - o) * n / size + 1e-9)))
        for b, o, n, size in ((bx0, x0, nx, width), (by0, y0, ny, height))
    ]
    upper = [
        min(n, max(lo + 1, int(np.ceil((b - o) * n / size - 1e-9))))
        for b, o, n, size, lo in ((bx1, x0, nx, width, lower[0]), (by1, y0, ny, height, lower[1]))
    ]
    return lower[0], lower[1], upper[0], upper[1]


def _structured_patch(width, height, nx, ny, cells, x0, y0):
    """Nodes and triangles of the cells of block(width, height, nx, ny, x0, y0) in ``cells``,
    with the block's own coordinate formula and diagonal parity; node (i, j) is row
    (j - j0) (i1 - i0 + 1) + i - i0."""
    i0, j0, i1, j1 = cells
    X, Y = np.meshgrid(
        x0 + width * np.arange(i0, i1 + 1) / nx, y0 + height * np.arange(j0, j1 + 1) / ny
    )

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
    with gmsh_session() as gmsh:
        gmsh.model.add("refined_block")
        occ = gmsh.model.occ
        occ.cut(
            [(2, occ.addRectangle(x0, y0, 0.0, x1 - x0, y1 - y0))],
            [(2, occ.addRectangle(X0, Y0, 0.0, X1 - X0, Y1 - Y0))],
        )
        occ.synchronize()
        tol = 1e-9 * max(x1 - x0, y1 - y0)
        for _, curve in gmsh.model.getEntities(1):
            ends = [
                gmsh.model.getValue(0, abs(t), [])[:2]
                for _, t in gmsh.model.getBoundary([(1, curve)], oriented=False)
            ]
            n = _segments_on_hole(*ends, hole, counts, tol)
            if n:
                gmsh.model.mesh.setTransfiniteCurve(curve, n + 1)
        fields = gmsh.model.mesh.field
        size = fields.add("Box")
        for key, value in (
            ("VIn", h),
            ("VOut", h_max),
            ("XMin", X0),
            ("XMax", X1),
            ("YMin", Y0),
            ("YMax", Y1),
            ("Thickness", (h_max - h) / growth),
        ):
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
    if (
        abs(py - qy) <= tol
        and min(abs(py - Y0), abs(py - Y1)) <= tol
        and min(px, qx) >= X0 - tol
        and max(px, qx) <= X1 + tol
    ):
        return round(abs(qx - px) / (X1 - X0) * counts[0])
    if (
        abs(px - qx) <= tol
        and min(abs(px - X0), abs(px - X1)) <= tol
        and min(py, qy) >= Y0 - tol
        and max(py, qy) <= Y1 + tol
    ):
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
        raise MeshError(
            f"block mesh: gmsh put a node at ({x[k]:g}, {y[k]:g}) on the refine_box "
            f"side between the grid's nodes: report this (gmsh version)"
        )
    return rows


def _side_chains(nodes, used, rect) -> tuple[dict, dict]:
    """Edge tags bottom / right / top / left of a rectangle's mesh (the used nodes on each side,
    counter-clockwise, joined into segments) and its corner node sets."""
    x0, y0, x1, y1 = rect
    sides = {
        "bottom": (1, y0, 0, 1.0),
        "right": (0, x1, 1, 1.0),
        "top": (1, y1, 0, -1.0),
        "left": (0, x0, 1, -1.0),
    }
    edges = {}
    for tag, (axis, value, along, sense) in sides.items():
        on = used[nodes[used, axis] == value]
        on = on[np.argsort(sense * nodes[on, along], kind="stable")]
        edges[tag] = np.column_stack([on[:-1], on[1:]])
    corners = {}
    for name, (cx, cy) in (
        ("corner_bottom_left", (x0, y0)),
        ("corner_bottom_right", (x1, y0)),
        ("corner_top_right", (x1, y1)),
        ("corner_top_left", (x0, y1)),
    ):
        corners[name] = used[(nodes[used, 0] == cx) & (nodes[used, 1] == cy)]
    return edges, corners
