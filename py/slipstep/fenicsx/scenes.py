"""Extra cross-check scenes that need a mesh file: written with gmsh, used through a case
file's ``file = ...`` mesh (so they go through slipstep's ordinary .msh reader)."""

from __future__ import annotations

from pathlib import Path

PLATE_CASE = """\
# Quarter of a plate with a central circular hole under uniaxial tension (x), plane stress,
# linear hardening: a bulk-only elastoplastic scene with shear and non-proportional stress
# paths near the hole.  Written by slipstep.fenicsx.scenes.plate_with_hole.
[case]
name = "plate_with_hole"
description = "Plate {width} x {height} with hole r = {radius}, tension {traction} MPa, plane {plane}, H = {H}"
units = "mm, N, MPa"

[analysis]
plane = "{plane}"
thickness = 1.0

[output]
snapshots = [1.0]
figures = false
xdmf = false

[[body]]
name = "plate"
[body.mesh]
file = "{mesh}"
[body.material]
E = {E}
nu = {nu}
Sy = {Sy}
H = {H}

[[bc]]
body = "plate"
edge = "left"
symmetry = true

[[bc]]
body = "plate"
edge = "bottom"
symmetry = true

[[bc]]
name = "tension"
body = "plate"
edge = "right"
traction = [{traction}, 0.0]
"""


def plate_with_hole_mesh(
    path: str | Path,
    width: float = 20.0,
    height: float = 20.0,
    radius: float = 5.0,
    h_hole: float = 0.5,
    h_far: float = 2.0,
) -> Path:
    """Quarter plate [0, width] x [0, height] minus the disc r < radius at the origin, as a
    gmsh .msh with physical lines ``hole``, ``bottom`` (y = 0), ``right``, ``top``, ``left``
    (x = 0).  Element size h_hole at the hole growing linearly to h_far."""
    import gmsh

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if gmsh.isInitialized():
        gmsh.finalize()
    gmsh.initialize(["", "-v", "0"], readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("plate_with_hole")
        geo = gmsh.model.geo
        o = geo.addPoint(0, 0, 0)
        p1, p2 = geo.addPoint(radius, 0, 0), geo.addPoint(width, 0, 0)
        p3, p4 = geo.addPoint(width, height, 0), geo.addPoint(0, height, 0)
        p5 = geo.addPoint(0, radius, 0)
        lines = {
            "bottom": geo.addLine(p1, p2),
            "right": geo.addLine(p2, p3),
            "top": geo.addLine(p3, p4),
            "left": geo.addLine(p4, p5),
            "hole": geo.addCircleArc(p5, o, p1),
        }
        loop = geo.addCurveLoop([lines[k] for k in ("bottom", "right", "top", "left", "hole")])
        surface = geo.addPlaneSurface([loop])
        geo.synchronize()
        for name, curve in lines.items():
            gmsh.model.setPhysicalName(1, gmsh.model.addPhysicalGroup(1, [curve]), name)
        gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, [surface]), "plate")
        f = gmsh.model.mesh.field
        size = f.add("MathEval")
        slope = (h_far - h_hole) / (max(width, height) - radius)
        f.setString(size, "F", f"{h_hole!r} + {slope!r} * (sqrt(x*x + y*y) - {radius!r})")
        f.setAsBackgroundMesh(size)
        for opt in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
            gmsh.option.setNumber(f"Mesh.{opt}", 0)
        gmsh.model.mesh.generate(2)
        gmsh.write(str(path))
    finally:
        gmsh.finalize()
    return path


def plate_with_hole(
    folder: str | Path,
    plane: str = "stress",
    traction: float = 160.0,
    E: float = 70000.0,
    nu: float = 0.3,
    Sy: float = 250.0,
    H: float = 5000.0,
    **mesh,
) -> Path:
    """Write ``plate.msh`` and ``plate_with_hole.toml`` into ``folder``; returns the case path."""
    folder = Path(folder)
    msh = plate_with_hole_mesh(folder / "plate.msh", **mesh)
    dims = {k: mesh.get(k, d) for k, d in (("width", 20.0), ("height", 20.0), ("radius", 5.0))}
    case = folder / "plate_with_hole.toml"
    case.write_text(
        PLATE_CASE.format(
            mesh=msh.name, plane=plane, traction=traction, E=E, nu=nu, Sy=Sy, H=H, **dims
        )
    )
    return case
