"""The built-in tetrahedron meshes of 3D scenes (gmsh, OpenCASCADE geometry): the sphere, the
roller, the graded box, the punch and the spherical shell, and the structured box (no gmsh).
Each returns a checked :class:`slipstep.mesh.tetrahedra.TetMesh` with the face tags of
:func:`slipstep.schema.solid.generator_faces`; the gmsh ones through the mesh cache
(:mod:`slipstep.mesh.cache`).

A body of revolution or a punch is meshed as its symmetric part (the eighth, or the quarter of
a punch) and mirrored across the planes of its ``portion``: the quarter and the half are
symmetric meshes, their nodes on the mirror planes shared.  Grading as in 2D: h = h_contact
within ``contact_zone`` of the contact point (line, rim), then h_contact + growth (d -
contact_zone), up to h_max (Distance + Threshold fields); the contact point of a sphere is a
geometry vertex, so a node sits exactly there.
"""

from __future__ import annotations

import numpy as np

from .gmsh_api import gmsh_session, size_field_only, tetrahedra_and_faces, threshold_field
from .base import MeshError
from .cache import cached
from .tetrahedra import TetMesh, boundary_faces, checked_tet_mesh, signed_volumes

#: A coordinate within SNAP x the body's size of a plane the geometry puts nodes on is that
#: plane's (gmsh's round-off): snapped, so mirrored nodes coincide and symmetry faces are flat.
SNAP = 1e-9


def _mesh_volume(gmsh, size_field: int, where: str, snap=()) -> TetMesh:
    """Mesh the current model in 3D with the element size of ``size_field`` alone; the nodes
    within SNAP of each plane (axis, value) in ``snap`` put on it."""
    size_field_only(gmsh, size_field)
    gmsh.model.mesh.generate(3)
    xyz, tets, faces, node_sets = tetrahedra_and_faces(gmsh)
    scale = float(np.ptp(xyz, axis=0).max()) or 1.0
    for axis, value in snap:
        xyz[np.abs(xyz[:, axis] - value) <= SNAP * scale, axis] = value
    return checked_tet_mesh(xyz, tets, faces, node_sets, where=where, flip_inverted=True)


def _tag_planes(gmsh, volume: int, planes: dict, curved: str) -> None:
    """Physical groups of the volume's boundary surfaces: a plane surface whose centre of mass
    lies on (axis, value) of ``planes`` (name -> (axis, value)) gets that name, every other
    surface ``curved``; the volume itself a physical group too."""
    groups: dict[str, list[int]] = {}
    size = max(np.ptp(np.reshape(gmsh.model.getBoundingBox(3, volume), (2, 3)), axis=0))
    for _, surface in gmsh.model.getBoundary([(3, volume)], oriented=False):
        centre = gmsh.model.occ.getCenterOfMass(2, surface)
        name = curved
        if gmsh.model.getType(2, surface) == "Plane":
            name = next(
                (
                    n
                    for n, (axis, value) in planes.items()
                    if abs(centre[axis] - value) <= 1e-7 * size
                ),
                curved,
            )
        groups.setdefault(name, []).append(surface)
    for name, surfaces in groups.items():
        gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, surfaces), name)
    gmsh.model.addPhysicalGroup(3, [volume])


def _vertex_at(gmsh, point, size: float) -> int:
    """The geometry vertex at ``point`` (within 1e-9 size)."""
    eps = 1e-9 * size
    found = gmsh.model.getEntitiesInBoundingBox(
        *(np.subtract(point, eps)), *(np.add(point, eps)), 0
    )
    if not found:
        raise MeshError(
            f"mesh generator: no geometry vertex at {tuple(point)}: report this " f"(gmsh version)"
        )
    return found[0][1]


def _curves_near(gmsh, low, high) -> list[int]:
    """The geometry curves inside the box [low, high]."""
    return [c for _, c in gmsh.model.getEntitiesInBoundingBox(*low, *high, 1)]


def mirrored(mesh: TetMesh, axis: int) -> TetMesh:
    """``mesh`` (on the side coordinate ``axis`` >= 0) and its mirror image across the plane
    coordinate ``axis`` = 0, the nodes on that plane shared: every face tag joined with its
    mirror but the plane's own, ``symmetry_x`` (``_y``), now inside."""
    x = mesh.nodes[:, axis]
    on_plane = x == 0.0  # the generators snap the plane's nodes onto it
    image = np.arange(len(x))
    image[~on_plane] = len(x) + np.arange(int((~on_plane).sum()))
    flipped = mesh.nodes[~on_plane].copy()
    flipped[:, axis] *= -1.0
    nodes = np.vstack([mesh.nodes, flipped])
    tets = np.vstack([mesh.tetrahedra, image[mesh.tetrahedra][:, [0, 2, 1, 3]]])
    faces = {
        tag: np.vstack([tris, image[tris][:, [0, 2, 1]]])
        for tag, tris in mesh.faces.items()
        if tag != f"symmetry_{'xyz'[axis]}"
    }
    sets = {k: v for k, v in mesh.node_sets.items() if k not in mesh.faces}
    return checked_tet_mesh(nodes, tets, faces, sets, where="mirrored mesh")


def _mirrored_into(part: TetMesh, mirrors: int) -> TetMesh:
    """The part x, y >= 0 of a body mirrored across x = 0 (mirrors >= 1), then y = 0 (2)."""
    for axis in range(mirrors):
        part = mirrored(part, axis)
    return part


@cached
def sphere(
    R: float,
    h_contact: float,
    contact_zone: float,
    h_max: float,
    growth: float = 0.1,
    portion: str = "eighth",
) -> TetMesh:
    """A sphere of radius R, centre (0, 0, R), below its cut z = R: the eighth x, y >= 0, the
    quarter y >= 0 or the half.  Faces ``surface``, ``top`` and the symmetry planes of the
    portion (``symmetry_x``: x = 0, ``symmetry_y``: y = 0); node set ``bottom_point``, the
    node at (0, 0, 0)."""
    with gmsh_session() as gmsh:
        gmsh.model.add("sphere")
        occ = gmsh.model.occ
        ball = occ.addSphere(0.0, 0.0, R, R)
        box = occ.addBox(0.0, 0.0, -R, 2 * R, 2 * R, 2 * R)
        (volume,), _ = occ.intersect([(3, ball)], [(3, box)])
        occ.synchronize()
        bottom = _vertex_at(gmsh, (0.0, 0.0, 0.0), R)
        gmsh.model.setPhysicalName(0, gmsh.model.addPhysicalGroup(0, [bottom]), "bottom_point")
        _tag_planes(
            gmsh,
            volume[1],
            {"top": (2, R), "symmetry_x": (0, 0.0), "symmetry_y": (1, 0.0)},
            "surface",
        )
        size = threshold_field(gmsh, h_contact, contact_zone, h_max, growth, points=[bottom])
        eighth = _mesh_volume(gmsh, size, "sphere mesh", snap=((0, 0.0), (1, 0.0), (2, R)))
    return _mirrored_into(eighth, ("eighth", "quarter", "half").index(portion))


@cached
def roller(
    R: float,
    length: float,
    h_contact: float,
    contact_zone: float,
    h_max: float,
    growth: float = 0.1,
    portion: str = "eighth",
) -> TetMesh:
    """A roller: the cylinder of radius R along y, y in [-length/2, length/2], axis at height
    z = R, below its cut z = R; the eighth x, y >= 0, the quarter y >= 0 or the half.  Faces
    ``surface``, ``end`` (y = +-length/2), ``top`` and the symmetry planes of the portion; fine
    along the contact line x = z = 0."""
    half = 0.5 * length
    with gmsh_session() as gmsh:
        gmsh.model.add("roller")
        occ = gmsh.model.occ
        cylinder = occ.addCylinder(0.0, 0.0, R, 0.0, half, 0.0, R)
        box = occ.addBox(0.0, 0.0, -R, 2 * R, half, 2 * R)
        (volume,), _ = occ.intersect([(3, cylinder)], [(3, box)])
        occ.synchronize()
        eps = 1e-6 * R
        line = _curves_near(gmsh, (-eps, -eps, -eps), (eps, half + eps, eps))
        _tag_planes(
            gmsh,
            volume[1],
            {"top": (2, R), "end": (1, half), "symmetry_x": (0, 0.0), "symmetry_y": (1, 0.0)},
            "surface",
        )
        size = threshold_field(gmsh, h_contact, contact_zone, h_max, growth, curves=line)
        eighth = _mesh_volume(
            gmsh, size, "roller mesh", snap=((0, 0.0), (1, 0.0), (1, half), (2, R))
        )
    return _mirrored_into(eighth, ("eighth", "quarter", "half").index(portion))


@cached
def punch(
    a: float,
    height: float,
    h_contact: float,
    contact_zone: float,
    h_max: float,
    growth: float = 0.1,
    shape: str = "round",
    portion: str = "quarter",
) -> TetMesh:
    """A flat-ended punch along z: a cylinder of radius a (``round``) or a square prism of side
    2a, z in [0, height]; the quarter x, y >= 0, the half y >= 0 or the whole.  Faces
    ``bottom`` (z = 0, the flat end), ``side``, ``top`` (z = height) and the symmetry planes
    of the portion; fine around the rim of the flat end."""
    with gmsh_session() as gmsh:
        gmsh.model.add("punch")
        occ = gmsh.model.occ
        if shape == "round":
            solid = occ.addCylinder(0.0, 0.0, 0.0, 0.0, 0.0, height, a)
            box = occ.addBox(0.0, 0.0, 0.0, 2 * a, 2 * a, height)
            (volume,), _ = occ.intersect([(3, solid)], [(3, box)])
        else:
            volume = (3, occ.addBox(0.0, 0.0, 0.0, a, a, height))
        occ.synchronize()
        eps = 1e-6 * a
        rim = [
            c
            for c in _curves_near(gmsh, (-eps, -eps, -eps), (a + eps, a + eps, eps))
            if not _on_symmetry_plane(gmsh, c, eps)
        ]
        planes = {
            "bottom": (2, 0.0),
            "top": (2, height),
            "symmetry_x": (0, 0.0),
            "symmetry_y": (1, 0.0),
        }
        _tag_planes(gmsh, volume[1], planes, "side")  # a square's planes x, y = a: side
        size = threshold_field(gmsh, h_contact, contact_zone, h_max, growth, curves=rim)
        snap = ((0, 0.0), (1, 0.0), (2, 0.0), (2, height)) + (
            ((0, a), (1, a)) if shape == "square" else ()
        )
        quarter = _mesh_volume(gmsh, size, "punch mesh", snap=snap)
    return _mirrored_into(quarter, ("quarter", "half", "whole").index(portion))


def _on_symmetry_plane(gmsh, curve: int, eps: float) -> bool:
    """True for a curve lying in the plane x = 0 or y = 0."""
    low = gmsh.model.getBoundingBox(1, curve)
    return (abs(low[0]) <= eps and abs(low[3]) <= eps) or (
        abs(low[1]) <= eps and abs(low[4]) <= eps
    )


@cached
def shell(a: float, b: float, h: float, h_outer: float = 0.0) -> TetMesh:
    """The eighth x, y, z >= 0 of the thick spherical shell a <= r <= b, centre (0, 0, 0).
    Faces ``inner``, ``outer``, ``symmetry_x``, ``symmetry_y``, ``symmetry_z``.  Element size h
    at r = a, linear in r to ``h_outer`` at r = b (0: uniform h)."""
    if not 0.0 < a < b:
        raise MeshError(f"shell: need 0 < a < b (got a = {a:g}, b = {b:g})")
    h_outer = h_outer if h_outer > 0.0 else h
    with gmsh_session() as gmsh:
        gmsh.model.add("shell")
        occ = gmsh.model.occ
        outer = occ.addSphere(0.0, 0.0, 0.0, b)
        inner = occ.addSphere(0.0, 0.0, 0.0, a)
        (hollow,), _ = occ.cut([(3, outer)], [(3, inner)])
        box = occ.addBox(0.0, 0.0, 0.0, b, b, b)
        (volume,), _ = occ.intersect([hollow], [(3, box)])
        occ.synchronize()
        groups: dict[str, list[int]] = {}
        for _, surface in gmsh.model.getBoundary([volume], oriented=False):
            centre = np.asarray(gmsh.model.occ.getCenterOfMass(2, surface))
            if gmsh.model.getType(2, surface) == "Plane":
                name = f"symmetry_{'xyz'[int(np.argmin(np.abs(centre)))]}"
            else:
                name = "inner" if np.linalg.norm(centre) < 0.5 * (a + b) else "outer"
            groups.setdefault(name, []).append(surface)
        for name, surfaces in groups.items():
            gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, surfaces), name)
        gmsh.model.addPhysicalGroup(3, [volume[1]])
        size = gmsh.model.mesh.field.add("MathEval")
        slope = (h_outer - h) / (b - a)
        gmsh.model.mesh.field.setString(
            size, "F", f"{h!r} + ({slope!r}) * " f"(sqrt(x*x + y*y + z*z) - {a!r})"
        )
        return _mesh_volume(gmsh, size, "shell mesh", snap=((0, 0.0), (1, 0.0), (2, 0.0)))


@cached
def graded_box(
    width: float,
    depth: float,
    height: float,
    h_contact: float,
    contact_zone: float,
    h_max: float,
    growth: float = 0.1,
    focus=None,
    corner=(0.0, 0.0, 0.0),
) -> TetMesh:
    """The box [x0, x0+width] x [y0, y0+depth] x [z0, z0+height] meshed by gmsh, fine around
    ``focus`` (default: the middle of the top face), a node.  Faces ``bottom`` (z = z0),
    ``top``, ``left`` (x = x0), ``right``, ``front`` (y = y0), ``back``; node set ``focus``."""
    x0, y0, z0 = (float(c) for c in corner)
    high = (x0 + width, y0 + depth, z0 + height)
    size_ = max(width, depth, height)
    focus = np.array(
        [x0 + 0.5 * width, y0 + 0.5 * depth, high[2]] if focus is None else focus, dtype=float
    )
    low = np.array([x0, y0, z0])
    tol = 1e-9 * size_
    focus = np.where(np.abs(focus - low) <= tol, low, focus)
    focus = np.where(np.abs(focus - high) <= tol, high, focus)
    if np.any(focus < low) or np.any(focus > np.array(high)):
        raise MeshError(
            f"box mesh: focus {focus.tolist()} lies outside the box: move it inside "
            f"or onto its boundary"
        )
    with gmsh_session() as gmsh:
        gmsh.model.add("box")
        occ = gmsh.model.occ
        box = occ.addBox(x0, y0, z0, width, depth, height)
        # the fragments embed the point where it lies (volume, face, edge, or a corner's own)
        occ.fragment([(3, box)], [(0, occ.addPoint(*focus))])
        occ.synchronize()
        vertex = _vertex_at(gmsh, focus, size_)
        gmsh.model.setPhysicalName(0, gmsh.model.addPhysicalGroup(0, [vertex]), "focus")
        volume = gmsh.model.getEntities(3)[0][1]
        _tag_planes(
            gmsh,
            volume,
            {
                "bottom": (2, z0),
                "top": (2, high[2]),
                "left": (0, x0),
                "right": (0, high[0]),
                "front": (1, y0),
                "back": (1, high[1]),
            },
            "side",
        )
        size = threshold_field(gmsh, h_contact, contact_zone, h_max, growth, points=[vertex])
        snap = [(c, v) for c in range(3) for v in (low[c], high[c])]
        return _mesh_volume(gmsh, size, "box mesh", snap=snap)


def box(
    width: float, depth: float, height: float, nx: int, ny: int, nz: int, corner=(0.0, 0.0, 0.0)
) -> TetMesh:
    """A structured box, nx x ny x nz cells, each cut into six tetrahedra around one of its
    diagonals (Kuhn's), the cell mirrored by the parity of each of its indices, so the diagonal
    alternates and neighbours' faces match (no preferred direction).  Node coordinates are
    x0 + i width / nx, ...: boxes of the same spacing share node positions on a common face.
    Faces ``bottom`` (z = z0), ``top``, ``left`` (x = x0), ``right``, ``front`` (y = y0),
    ``back``."""
    if min(nx, ny, nz) < 1:
        raise MeshError(
            f"box: nx = {nx}, ny = {ny}, nz = {nz}: need at least one division " f"each way"
        )
    x0, y0, z0 = (float(c) for c in corner)
    axes = [
        lo + size * np.arange(n + 1) / n
        for lo, size, n in ((x0, width, nx), (y0, depth, ny), (z0, height, nz))
    ]
    X, Y, Z = np.meshgrid(*axes, indexing="ij")
    nodes = np.column_stack([X.ravel(), Y.ravel(), Z.ravel()])

    def nid(i, j, k):
        return (i * (ny + 1) + j) * (nz + 1) + k

    i, j, k = (
        a.ravel() for a in np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz), indexing="ij")
    )
    tets = []
    # Kuhn's six tetrahedra of the unit cube: the paths from corner 000 to 111 one axis at a time
    for order in ((0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)):
        steps = [np.zeros(3, int)]
        for axis in order:
            steps.append(steps[-1] + np.eye(3, dtype=int)[axis])
        corners = []
        for s in steps:  # the corner, mirrored in each axis whose cell index is odd
            ci = np.where(i % 2 == 1, 1 - s[0], s[0])
            cj = np.where(j % 2 == 1, 1 - s[1], s[1])
            ck = np.where(k % 2 == 1, 1 - s[2], s[2])
            corners.append(nid(i + ci, j + cj, k + ck))
        tets.append(np.column_stack(corners))
    tets = _oriented(nodes, np.concatenate(tets))
    # the planes as the nodes have them (x0 + nx width / nx may differ from x0 + width)
    faces = _box_faces(nodes, tets, [a[0] for a in axes], [a[-1] for a in axes])
    return checked_tet_mesh(nodes, tets, faces, where="box mesh")


def _oriented(nodes, tets) -> np.ndarray:
    """Each tetrahedron positively oriented (a cell mirrored an odd number of times gives
    negative ones)."""
    negative = signed_volumes(nodes, tets) < 0
    out = tets.copy()
    out[negative] = out[negative][:, [0, 2, 1, 3]]
    return out


def _box_faces(nodes, tets, low, high) -> dict:
    """The boundary triangles of a box's mesh, by the plane they lie on."""
    tris = boundary_faces(tets)
    out = {}
    for name, axis, value in (
        ("bottom", 2, low[2]),
        ("top", 2, high[2]),
        ("left", 0, low[0]),
        ("right", 0, high[0]),
        ("front", 1, low[1]),
        ("back", 1, high[1]),
    ):
        # all three corners on the plane: a mean of three equal coordinates is not always the
        # coordinate ((h + h + h)/3 != h for some h), which left a face tag empty
        out[name] = tris[(nodes[tris][:, :, axis] == value).all(axis=1)]
    return out
