# %% [markdown]
# # Hybrid mode: slipstep's event-driven frictional contact on a plain dolfinx model
#
# A dolfinx user's workflow: a quarter cylinder (R = 125 mm, centre (0, R)) meshed with gmsh
# and loaded into dolfinx (`model_to_mesh`), a P1 vector space, the UFL forms of plane-strain
# elasticity, a pressure q = P/(2R) on the cut y = R, a symmetry condition on x = 0.  slipstep
# then solves the contact of the arc with the rigid flat y = 0 (Coulomb mu) and hands back
# dolfinx Functions: displacement and contact pressure.
#
# The dolfinx calls whose spelling changed between releases (function spaces, gmsh import,
# scalar type, XDMF) go through `slipstep.fenicsx.dolfinx_api`, so that the example runs on
# dolfinx 0.5 to 0.11 (docs/dolfinx.md); `api.function_space(mesh, "Lagrange", 1, (2,))` is
# `fem.functionspace(mesh, ("Lagrange", 1, (2,)))` on dolfinx >= 0.7.
#
# It prints the contact half-width and peak pressure against Hertz (a = 1.4384 mm,
# p0 = 442.6 MPa at P = 1000 N/mm) and writes OUT/hybrid_hertz.xdmf (u, contact pressure)
# with dolfinx's XDMFFile.  Restriction (see `slipstep.fenicsx.hybrid`): P1 triangles,
# isotropic linear elasticity with the E, nu given, homogeneous Dirichlet conditions, a rigid
# line.  A notebook takes the parameters below; a script also reads them from its command line:
#
#     .venv/bin/python examples/hybrid_hertz.py [--h-contact 0.05] [--mu 0.2] [--out DIR]

# %%
import argparse
import math
import sys
import time
from pathlib import Path

H_CONTACT = 0.05  # element size at the contact, mm
MU = 0.2  # Coulomb friction coefficient
OUT = "results/hybrid_hertz"  # output folder

R, P, E, NU = 125.0, 1000.0, 70000.0, 0.3
TOP, SYMMETRY, ARC = 1, 2, 3  # facet tags (gmsh physical groups)


# %%
def cylinder_mesh(h_contact: float, h_max: float = 8.0):
    """The quarter cylinder as a dolfinx mesh with facet tags, straight from gmsh."""
    import gmsh

    from slipstep.fenicsx import dolfinx_api as api

    gmsh.initialize(["", "-v", "0"], readConfigFiles=False, interruptible=False)
    try:
        gmsh.model.add("quarter_cylinder")
        geo = gmsh.model.geo
        bottom, centre, right = (
            geo.addPoint(0, 0, 0),
            geo.addPoint(0, R, 0),
            geo.addPoint(R, R, 0),
        )
        arc = geo.addCircleArc(bottom, centre, right)
        top = geo.addLine(right, centre)
        sym = geo.addLine(centre, bottom)
        surface = geo.addPlaneSurface([geo.addCurveLoop([arc, top, sym])])
        geo.synchronize()
        gmsh.model.addPhysicalGroup(1, [top], TOP)
        gmsh.model.addPhysicalGroup(1, [sym], SYMMETRY)
        gmsh.model.addPhysicalGroup(1, [arc], ARC)
        gmsh.model.addPhysicalGroup(2, [surface], 1)
        f = gmsh.model.mesh.field
        dist = f.add("Distance")
        f.setNumbers(dist, "PointsList", [bottom])
        thr = f.add("Threshold")
        f.setNumber(thr, "InField", dist)
        f.setNumber(thr, "SizeMin", h_contact)
        f.setNumber(thr, "SizeMax", h_max)
        f.setNumber(thr, "DistMin", 2.5)
        f.setNumber(thr, "DistMax", 2.5 + (h_max - h_contact) / 0.1)
        f.setAsBackgroundMesh(thr)
        for opt in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
            gmsh.option.setNumber(f"Mesh.{opt}", 0)
        gmsh.model.mesh.generate(2)
        mesh, _, facet_tags = api.mesh_from_gmsh(gmsh.model, gdim=2)
    finally:
        gmsh.finalize()
    return mesh, facet_tags


def main(argv=None) -> dict:
    """The example with the command line's options (``argv``; None: ``sys.argv``), the
    parameters above by default."""
    ap = argparse.ArgumentParser(description="slipstep's contact on a plain dolfinx model")
    ap.add_argument(
        "--h-contact", type=float, default=H_CONTACT, help="element size at the contact"
    )
    ap.add_argument("--mu", type=float, default=MU, help="Coulomb friction coefficient")
    ap.add_argument("--out", default=OUT, help="output folder")
    args = ap.parse_args(argv)
    return solve(args.h_contact, args.mu, args.out)


def solve(h_contact: float = H_CONTACT, mu: float = MU, out_dir: str = OUT) -> dict:
    """The dolfinx model, its contact solved by slipstep, checked against Hertz; the summary."""
    from slipstep.fenicsx import dolfinx_api as api
    from slipstep.fenicsx.hybrid import solve_contact

    ufl = api.ufl()

    start = time.perf_counter()
    # ---- the user's dolfinx model --------------------------------------------------------
    mesh, facet_tags = cylinder_mesh(h_contact)
    V = api.function_space(mesh, "Lagrange", 1, (2,))
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    mu_l, lam = E / (2 * (1 + NU)), E * NU / ((1 + NU) * (1 - 2 * NU))

    def eps(w):
        return ufl.sym(ufl.grad(w))

    a = ufl.inner(2 * mu_l * eps(u) + lam * ufl.tr(eps(u)) * ufl.Identity(2), eps(v)) * ufl.dx
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags)
    q = P / (2 * R)  # the quarter carries P/2 across its cut of length R
    L = ufl.dot(-q * ufl.FacetNormal(mesh), v) * ds(TOP)
    sym_dofs = api.locate_dofs(V, api.tagged(facet_tags, SYMMETRY), component=0)
    bcs = [api.dirichletbc(0.0, sym_dofs, V, component=0)]

    # ---- slipstep: event-driven contact of the arc on the flat y = 0 ----------------------
    out = solve_contact(
        V,
        a,
        L,
        facet_tags,
        ARC,
        E=E,
        nu=NU,
        plane="strain",
        bcs=bcs,
        flat_point=(0.0, 0.0),
        flat_normal=(0.0, 1.0),
        mu=mu,
    )

    # ---- back in dolfinx: Functions to keep using ------------------------------------------
    p = api.dof_values(out.pressure)
    xq = api.dof_coordinates(api.space_of(out.pressure))[:, 0]
    contact = p > 0
    a_num = float(xq[contact].max()) if contact.any() else 0.0
    force = api.assemble_scalar(out.pressure * ds(ARC))  # = P/2 (thickness 1)
    E_star = E / (1 - NU**2)
    a_h = math.sqrt(4 * P * R / (math.pi * E_star))
    p0_h = 2 * P / (math.pi * a_h)
    Path(out_dir).mkdir(parents=True, exist_ok=True)
    api.write_functions(Path(out_dir) / "hybrid_hertz.xdmf", mesh, [(0.0, [out.u, out.pressure])])
    summary = {
        "n_cells": api.num_cells(mesh),
        "n_nodes": len(api.node_coordinates(mesh)),
        "events": int(len(out.result["events"]["kind"])),
        "outermost_closed_x": a_num,
        "a_hertz": a_h,
        "peak_pressure": float(p.max()),
        "p0_hertz": p0_h,
        "force_from_pressure": float(force),
        "half_load": P / 2,
        "operator_check": out.operator_difference,
        "wall_time_s": time.perf_counter() - start,
    }
    print(
        f"{summary['n_cells']} cells, {summary['events']} events, "
        f"{summary['wall_time_s']:.2f} s: outermost closed node x = {a_num:.4f} mm "
        f"(Hertz a = {a_h:.4f}), peak pressure {p.max():.1f} MPa (Hertz p0 = {p0_h:.1f}), "
        f"integral of the pressure {force:.6g} N/mm (P/2 = {P / 2:g}) -> {out_dir}"
    )
    return summary


# %% [markdown]
# Run: a script takes its command line; a notebook kernel's command line is the kernel's own,
# so there the parameters above are used as they are.

# %%
if __name__ == "__main__":
    summary = main([] if "ipykernel" in sys.modules else None)
