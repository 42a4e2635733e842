"""The meshes of pin_on_disc_3d.toml, made as a user makes their own with gmsh: two bodies, each
written to its own .msh file, its physical surfaces named as the case's [[bc]] and [[contact]]
tables name faces (slipstep reads a .msh's physical surfaces as face tags).

    python cases/pin_on_disc_3d_mesh.py      # writes pin_on_disc_3d_pin.msh, ..._disc.msh

The pin: a rod of radius R = 3 mm with a hemispherical end (centre (0, 0, R)), its lowest point
at the origin, cut at z = 8 mm; the disc: a block 6 x 6 x 4 mm under the plane z = 0.  Both are
the quarter x, y >= 0 (faces symmetry_x, symmetry_y), meshed finely (H_FINE) within FINE_ZONE
of the contact point and coarser away from it (a gmsh Distance + Threshold size field).
"""

from __future__ import annotations

from pathlib import Path

import gmsh

R, LENGTH = 3.0, 8.0  # mm: the pin's radius and height
DISC = (6.0, 6.0, 4.0)  # mm: the disc block's width, depth, height
H_FINE, FINE_ZONE, H_COARSE = 0.03, 0.3, 1.5
HERE = Path(__file__).resolve().parent


def _size_field(point: int) -> None:
    """Element size H_FINE within FINE_ZONE of ``point``, growing to H_COARSE 3 mm away."""
    field = gmsh.model.mesh.field
    distance = field.add("Distance")
    field.setNumbers(distance, "PointsList", [point])
    threshold = field.add("Threshold")
    field.setNumber(threshold, "InField", distance)
    field.setNumber(threshold, "SizeMin", H_FINE)
    field.setNumber(threshold, "SizeMax", H_COARSE)
    field.setNumber(threshold, "DistMin", FINE_ZONE)
    field.setNumber(threshold, "DistMax", 3.0)
    field.setAsBackgroundMesh(threshold)
    for option in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
        gmsh.option.setNumber(f"Mesh.{option}", 0)


def _name_faces(volume: int, name_of) -> None:
    """A physical surface per name, ``name_of(x, y, z)`` naming each boundary surface by its
    centre of mass; the volume a physical volume."""
    faces: dict[str, list[int]] = {}
    for _, surface in gmsh.model.getBoundary([(3, volume)], oriented=False):
        faces.setdefault(name_of(*gmsh.model.occ.getCenterOfMass(2, surface)), []).append(surface)
    for name, tags in faces.items():
        gmsh.model.addPhysicalGroup(2, tags, name=name)
    gmsh.model.addPhysicalGroup(3, [volume], name="body")


def _pin_face(x: float, y: float, z: float) -> str:
    if abs(x) < 1e-9:
        return "symmetry_x"
    if abs(y) < 1e-9:
        return "symmetry_y"
    return "top" if abs(z - LENGTH) < 1e-9 else "tip" if z < R else "side"


def _disc_face(x: float, y: float, z: float) -> str:
    if abs(x) < 1e-9:
        return "symmetry_x"
    if abs(y) < 1e-9:
        return "symmetry_y"
    return "top" if abs(z) < 1e-9 else "bottom" if abs(z + DISC[2]) < 1e-9 else "side"


def mesh(name: str, build, name_of) -> Path:
    """Mesh the volume ``build()`` makes (fine at the origin, a node), name its faces, and
    write ``pin_on_disc_3d_<name>.msh`` beside this script."""
    gmsh.initialize(["", "-v", "0"], readConfigFiles=False, interruptible=False)
    try:
        gmsh.model.add(name)
        volume = build(gmsh.model.occ)
        point = gmsh.model.occ.addPoint(0.0, 0.0, 0.0)
        gmsh.model.occ.fragment([(3, volume)], [(0, point)])  # the contact point a node
        gmsh.model.occ.synchronize()
        volume = gmsh.model.getEntities(3)[0][1]
        _name_faces(volume, name_of)
        eps = 1e-9
        ((_, point),) = gmsh.model.getEntitiesInBoundingBox(-eps, -eps, -eps, eps, eps, eps, 0)
        _size_field(point)
        gmsh.model.mesh.generate(3)
        path = HERE / f"pin_on_disc_3d_{name}.msh"
        gmsh.option.setNumber("Mesh.Binary", 0)
        gmsh.write(str(path))
        return path
    finally:
        gmsh.finalize()


def pin(occ) -> int:
    """The quarter of the rod with its hemispherical end."""
    ball = occ.addSphere(0.0, 0.0, R, R)
    rod = occ.addCylinder(0.0, 0.0, R, 0.0, 0.0, LENGTH - R, R)
    whole, _ = occ.fuse([(3, ball)], [(3, rod)])
    quarter = occ.addBox(0.0, 0.0, 0.0, R, R, LENGTH)
    (volume,), _ = occ.intersect(whole, [(3, quarter)])
    return volume[1]


def disc(occ) -> int:
    return occ.addBox(0.0, 0.0, -DISC[2], DISC[0], DISC[1], DISC[2])


if __name__ == "__main__":
    for name, build, name_of in (("pin", pin, _pin_face), ("disc", disc, _disc_face)):
        print(mesh(name, build, name_of))
