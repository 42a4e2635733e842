# %% [markdown]
# # Your own gmsh mesh
#
# A quarter cylinder meshed with the gmsh API (OpenCASCADE geometry, a distance/threshold size
# field of your choosing), handed to slipstep as numpy arrays: no mesh file, no generator.
# The case names the body's mesh `generator = "given"` and `slipstep.run(..., meshes=...)`
# supplies it; the edge tags of the [[bc]] and [[contact]] tables are gmsh's physical names.
# (With a mesh file, `slipstep.from_meshio(meshio.read("body.msh"))` gives the same object.)

# %%
import math

import gmsh
import numpy as np

import slipstep

R, P, E, NU = 125.0, 1000.0, 70000.0, 0.3


def quarter_cylinder(h_fine: float = 0.05, h_max: float = 6.0):
    """nodes, triangles, {tag: segments} of the quarter x >= 0 of a disc of radius R centred
    at (0, R), fine near the contact point (0, 0)."""
    gmsh.initialize(["", "-v", "0"], readConfigFiles=False, interruptible=False)
    try:
        occ = gmsh.model.occ
        disc = occ.addDisk(0.0, R, 0.0, R, R)
        box = occ.addRectangle(0.0, 0.0, 0.0, R, R)
        quarter = occ.intersect([(2, disc)], [(2, box)])[0][0][1]
        occ.synchronize()
        tags = {}
        for dim, curve in gmsh.model.getBoundary([(2, quarter)], oriented=False):
            x, y, _ = occ.getCenterOfMass(dim, curve)
            name = "symmetry" if abs(x) < 1e-9 else "top" if abs(y - R) < 1e-9 else "arc"
            tags[name] = gmsh.model.addPhysicalGroup(1, [curve], name=name)
        gmsh.model.addPhysicalGroup(2, [quarter])
        point = occ.addPoint(0.0, 0.0, 0.0)
        occ.synchronize()
        field = gmsh.model.mesh.field
        dist = field.add("Distance")
        field.setNumbers(dist, "PointsList", [point])
        size = field.add("Threshold")
        field.setNumber(size, "InField", dist)
        for key, value in (
            ("SizeMin", h_fine),
            ("SizeMax", h_max),
            ("DistMin", 2.5),
            ("DistMax", 60.0),
        ):
            field.setNumber(size, key, value)
        field.setAsBackgroundMesh(size)
        for key in ("MeshSizeFromPoints", "MeshSizeFromCurvature", "MeshSizeExtendFromBoundary"):
            gmsh.option.setNumber(f"Mesh.{key}", 0)
        gmsh.model.mesh.generate(2)
        ids, xyz, _ = gmsh.model.mesh.getNodes()
        row = {int(t): i for i, t in enumerate(ids)}
        _, _, tri = gmsh.model.mesh.getElements(2, quarter)
        triangles = np.array([row[int(t)] for t in tri[0]]).reshape(-1, 3)
        edges = {}
        for name, group in tags.items():
            segs = [
                gmsh.model.mesh.getElements(1, c)[2][0]
                for c in gmsh.model.getEntitiesForPhysicalGroup(1, group)
            ]
            edges[name] = np.array([row[int(t)] for t in np.concatenate(segs)]).reshape(-1, 2)
        return xyz.reshape(-1, 3), triangles, edges
    finally:
        gmsh.finalize()


# %%
nodes, triangles, edges = quarter_cylinder()
mesh = slipstep.from_arrays(nodes, triangles, edges)
print(f"{mesh.n_nodes} nodes, {mesh.n_elements} triangles, edges {sorted(mesh.edges)}")

case = {
    "case": {"name": "my_gmsh_cylinder", "units": "mm, N, MPa"},
    "output": {"snapshots": [0.5, 1.0], "figures": False, "xdmf": False},
    "body": [{"name": "cylinder", "material": {"E": E, "nu": NU}}],  # mesh: given below
    "bc": [
        {"body": "cylinder", "edge": "symmetry", "symmetry": True},
        {"body": "cylinder", "edge": "top", "pressure": P / (2 * R)},
    ],  # P/2 on the quarter
    "contact": [{"kind": "rigid_line", "body": "cylinder", "edge": "arc", "x_max": 4.0}],
}
r = slipstep.run(case, meshes={"cylinder": mesh}, progress=False)
r  # noqa: B018

# %%
E_star = E / (1 - NU**2)
a = math.sqrt(4 * P * R / (math.pi * E_star))
print(f"a  = {r.summary['contact_half_width']:.4f} mm   (Hertz {a:.4f})")
print(f"p0 = {r.summary['peak_pressure']:.1f} MPa   (Hertz {2 * P / (math.pi * a):.1f})")
