"""GetFEM 5.4 as a peer of slipstep in `make bench` (issue 16, point 5): elastoplastic Hertz.

The scene is slipstep's cases/hertz_cylinder.toml with SCENE (μ = 0.3, Sy = 200, H' = 700) at
mesh.h_contact = h: slipstep's generator meshes it and writes a gmsh file
(slipstep.mesh.triangle_files.write_msh); GetFEM (Debian python3-getfem 5.4) reads that file, so both codes
solve the same mesh.  The GetFEM model, one process per run (`one`):

- P1 displacements (the CST), one-point integration, so the plastic state is one value per
  element as in slipstep;
- small-strain J2 plasticity with linear isotropic hardening, "plane strain Prandtl Reuss linear
  hardening", return mapping (displacement-only unknowns), backward Euler (θ = 1): σy = Sy + H'α
  with α the accumulated equivalent plastic strain, so GetFEM's H_i is slipstep's H';
- nodal Alart–Curnier contact with Coulomb friction (non-symmetric version 1) on slipstep's
  candidates (arc nodes inside the contact's x/y window) against the flat y = 0: the basic
  contact brick with BN = -e_y, BT = e_x of each candidate, gap = its y (within the contact
  tolerance: 0), augmentation r α_i = E L_i (L_i its tributary length), and the friction slip
  measured from the previous load step (wt = Previous_u, γ = -1: the brick slides by
  BT (u + γ wt)), i.e. incremental Coulomb friction, backward Euler in the load.  No friction
  at the candidate on x = 0, whose u_x the symmetry holds (a stick condition there would
  repeat that constraint: a singular tangent).  add_nodal_contact_with_rigid_obstacle_brick
  builds the same nodal BN, BT and gap, but its Python interface takes no wt, so its friction
  acts on the total tangential displacement: not Coulomb's incremental law.
- symmetry u_x = 0 on x = 0 by multipliers (add_constraint_with_multipliers, exact nodal);
- the load as the traction (0, -f P/(2R)) on the cut y = R, f = k/N, k = 1..N; one Newton solve
  per step (GetFEM's standard solver, MUMPS, relative residual 1e-8, the "simplest" line
  search: the default one stalled in the first step at N = 5), then
  small_strain_elastoplasticity_next_iter stores the plastic state and u as Previous_u.  The
  first Newton iterate is a uniform strain of 1e-12, not u = 0, where the return mapping's
  tangent is undefined (`start_off_zero`).

Outputs at f = 1, defined as slipstep defines them: the contact pressure of a candidate is its
nodal contact force over its tributary length (slipstep.contact.edges.tributary_lengths), p0 its
maximum; the contact half-width a is slipstep.measures.contact_edges.contact_half_width, the far end of the
closed zone interpolated linearly in the load fraction between the outermost closed node
(closing at f_c) and the next open one (closing at f_o).  slipstep knows f_c from its events
and f_o from the rate of its last increment; here f_c is where the line through the node's gap
at the last two steps before it closed reaches 0, and f_o comes from the gap rates at f = 1,
measured by one more solve at f = 1 + PROBE (`closing_rates`; not stored, not in solve_s).

bench/getfem_results.json (written by `series`, the `make bench` entry point):
    {"what": str, "getfem": version, "scene": {"case", "overrides"}, "settings": {...},
     "host": str, "note": str,
     "runs": [{"h": element size at the contact (mm),
               "dofs": displacement DOFs (2 x nodes, as slipstep counts them),
               "steps": N, "status": "ok" | "not_converged" | "timeout" | "error",
               "newton_iterations": Newton iterations summed over the N steps,
               "p0": peak contact pressure (MPa), "a": contact half-width (mm),
               "total_normal_force": sum of the nodal contact forces (N/mm; P/2 = 500),
               "wall_s": whole process (python start-up, import getfem, mesh read, model,
                         solve, outputs), min over the repeats; "wall_s_median",
               "solve_s": the N load steps alone, min over the repeats; "solve_s_median",
               "setup_s": mesh read and model assembly, "probe_s": the solve at f = 1 + PROBE
                          for a (`closing_rates`), both of the first process and inside wall_s,
               "repeats": how many processes the min/median are over (3; 1 for a run
                          longer than REPEAT_BELOW_S = 120 s)}]}

    .venv/bin/python bench/getfem_hertz.py series [--sizes 0.05,0.025] [--steps 5,10,20,40]
    .venv/bin/python bench/getfem_hertz.py one SPEC.json     # one run, prints GETFEM {json}
"""

from __future__ import annotations

import time

T_START = time.perf_counter()

import argparse  # noqa: E402 - the process clock starts before any import
import json  # noqa: E402
import math  # noqa: E402
import os  # noqa: E402
import platform  # noqa: E402
import statistics  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
CASE = ROOT / "cases" / "hertz_cylinder.toml"
SCENE = ["material.Sy=200", "material.H=700", "contact.mu=0.3"]
SIZES = (0.05, 0.025, 0.0125)
STEPS = (5, 10, 20, 40)
TIMEOUT_S = 600.0  # per run, as bench/run.py
REPEATS = 3  # shared machine: min and median of 3 whole processes,
REPEAT_BELOW_S = 120.0  # for runs shorter than this (a longer one runs once)
MAX_RES = 1e-8  # Newton: relative residual (GetFEM's criterion, see `solve_steps`)
MAX_ITER = 50  # Newton iterations per load step
NEWTON = ("max_res", MAX_RES, "max_iter", MAX_ITER, "lsolver", "mumps", "lsearch", "simplest")
START_STRAIN = 1e-12  # Newton's first iterate (`start_off_zero`)
PROBE = 1e-3  # load fraction beyond 1 of the solve that measures gap rates
LAW = "plane strain Prandtl Reuss linear hardening"


# --------------------------------------------------------------------------- spec (parent side)
def scene_spec(h: float, steps: int, overrides=SCENE, msh: Path | None = None) -> dict:
    """Mesh the scene at h_contact = h with slipstep's generator, write it as ``msh`` and
    return the run spec: the file, its region numbers, the material, load and contact data
    read from slipstep's case (so both codes solve the same scene by construction)."""
    from slipstep.case import load_case
    from slipstep.mesh.triangle_files import write_msh
    from slipstep.builders.section import mesh_body
    from slipstep.loads.vectors import hertz_cut_pressure

    case = load_case(CASE, [*overrides, f"mesh.h_contact={h}"])
    body, (contact,) = case.data["body"][0], case.data["contact"]
    mesh = mesh_body(case, 0)
    msh = Path(msh or tempfile.mkstemp(suffix=".msh", prefix=f"hertz_{h:g}_")[1])
    tags = write_msh(mesh, msh)
    (sym,) = [bc["edge"] for bc in case.data["bc"] if bc["symmetry"]]
    mat = body["material"]
    return {
        "msh": str(msh),
        "h": h,
        "steps": steps,
        "nodes": mesh.n_nodes,
        "regions": {"contact": tags[contact["edge"]], "symmetry": tags[sym], "load": tags["top"]},
        "E": mat["E"],
        "nu": mat["nu"],
        "Sy": mat.get("Sy"),
        "H": mat.get("H") or 0.0,
        "mu": contact["mu"],
        "traction": hertz_cut_pressure(case),
        "thickness": case.data["analysis"]["thickness"],
        "window": [contact[k] for k in ("x_min", "x_max", "y_min", "y_max")],
        "tolerance": contact["tolerance"],
    }


# --------------------------------------------------------------------------- GetFEM (child side)
def edge_segments(gf_mesh, region: int) -> np.ndarray:
    """(K, 2) point ids of the boundary faces of ``region`` (face i of a triangle is the side
    opposite its vertex i)."""
    cvf = np.asarray(gf_mesh.region(region), dtype=int)
    pid, idx = gf_mesh.pid_from_cvid(cvf[0])
    tri = np.asarray(pid, dtype=int).reshape(-1, 3)
    keep = np.ones_like(tri, dtype=bool)
    keep[np.arange(len(tri)), cvf[1]] = False
    return tri[keep].reshape(-1, 2)


def point_x_dofs(gf_mesh, mfu, dim: int = 2) -> np.ndarray:
    """(n_points,) the x DOF of each mesh point (its y (and z) DOF the next ones) of a mesh of
    simplices in ``dim`` dimensions (triangles, tetrahedra)."""
    pid, _ = gf_mesh.pid_from_cvid()
    dof, _ = mfu.basic_dof_from_cvid()
    per_cell = dim * (dim + 1)
    x_dof = np.full(gf_mesh.nbpts(), -1)
    x_dof[np.asarray(pid, dtype=int)] = (
        np.asarray(dof, dtype=int).reshape(-1, per_cell)[:, 0::dim].ravel()
    )
    return x_dof


def rows_of_identity(gf, n: int, dofs: np.ndarray, sign: float = 1.0):
    """The sparse matrix whose row i picks DOF dofs[i] (times sign)."""
    m = gf.Spmat("copy", gf.Spmat("identity", n), [int(d) for d in dofs], list(range(n)))
    if sign != 1.0:
        m.scale(sign)
    return m


def candidates(spec: dict, points: np.ndarray, segments: np.ndarray):
    """slipstep's candidates of the contact edge (inside the x/y window), sorted by x, with
    their tributary lengths (slipstep.contact.edges.tributary_lengths, over the whole edge)."""
    from slipstep.contact.edges import tributary_lengths

    x0, x1, y0, y1 = spec["window"]
    ids = np.unique(segments)
    xy = points[ids]
    ids = ids[(xy[:, 0] >= x0) & (xy[:, 0] <= x1) & (xy[:, 1] >= y0) & (xy[:, 1] <= y1)]
    ids = ids[np.argsort(points[ids, 0], kind="stable")]
    return ids, tributary_lengths(points, segments, ids)


def add_material(gf, md, mim, spec: dict) -> None:
    """Plane-strain elasticity, with J2 plasticity and linear isotropic hardening if Sy."""
    E, nu = spec["E"], spec["nu"]
    md.add_initialized_data("lambda", E * nu / ((1 + nu) * (1 - 2 * nu)))
    md.add_initialized_data("mu", E / (2 * (1 + nu)))
    if spec["Sy"] is None:
        md.add_isotropic_linearized_elasticity_brick(mim, "u", "lambda", "mu")
        return
    scalar, tensor = gf.MeshImData(mim, -1), gf.MeshImData(mim, -1, [2, 2])
    for name, where in (
        ("xi", scalar),
        ("Previous_xi", scalar),
        ("Previous_alpha", scalar),
        ("Previous_Ep", tensor),
    ):
        md.add_im_data(name, where)
    md.add_initialized_data("sigma_y", spec["Sy"])
    md.add_initialized_data("H_k", 0.0)
    md.add_initialized_data("H_i", spec["H"])
    md.add_small_strain_elastoplasticity_brick(mim, *plastic_args(spec))


def plastic_args(spec: dict) -> tuple:
    """The arguments shared by the plasticity brick and its next_iter (θ = 1, dt = 1)."""
    return (
        LAW,
        "displacement only",
        "u",
        "xi",
        "Previous_Ep",
        "Previous_alpha",
        "lambda",
        "mu",
        "sigma_y",
        "H_k",
        "H_i",
        "1",
        "1",
    )


def add_contact(gf, md, ndof: int, ids, length, points, x_dof, spec: dict, held) -> None:
    """Nodal Alart–Curnier contact of the candidates with the flat y = 0 (module docstring).
    A candidate whose u_x the symmetry holds (``held``) gets no friction: a stick condition
    there would repeat the symmetry constraint (a singular tangent; slipstep eliminates that
    DOF, so friction there does nothing either)."""
    gap = points[ids, 1].copy()
    gap[np.abs(gap) <= spec["tolerance"]] = 0.0
    n = len(ids)
    md.add_variable("lambda_n", n)
    md.add_initialized_data("r", spec["E"])
    md.add_initialized_data("gap", gap)
    md.add_initialized_data("alpha", length)
    BN = rows_of_identity(gf, ndof, x_dof[ids] + 1, -1.0)
    if spec["mu"] == 0:
        md.add_basic_contact_brick("u", "lambda_n", "r", BN, "gap", "alpha", 1)
        return
    md.add_variable("lambda_t", n)
    md.add_initialized_data("friction", np.where(np.isin(ids, held), 0.0, spec["mu"]))
    md.add_initialized_data("gamma", -1.0)  # the brick slides by BT (u + gamma wt)
    BT = rows_of_identity(gf, ndof, x_dof[ids])
    md.add_basic_contact_brick(
        "u",
        "lambda_n",
        "lambda_t",
        "r",
        BN,
        BT,
        "friction",
        "gap",
        "alpha",
        1,
        "gamma",
        "Previous_u",
    )


def build_model(gf, spec: dict):
    """Mesh read, model assembled; returns (md, mim, bookkeeping)."""
    gf_mesh = gf.Mesh("import", "gmsh", spec["msh"])
    points = np.asarray(gf_mesh.pts()).T.copy()
    mfu = gf.MeshFem(gf_mesh, 2)
    mfu.set_classical_fem(1)
    mim = gf.MeshIm(gf_mesh, gf.Integ("IM_TRIANGLE(1)"))
    ndof, x_dof = mfu.nbdof(), point_x_dofs(gf_mesh, mfu)
    md = gf.Model("real")
    md.add_fem_variable("u", mfu)
    md.add_fem_data("Previous_u", mfu)
    add_material(gf, md, mim, spec)
    sym = np.unique(edge_segments(gf_mesh, spec["regions"]["symmetry"]))
    md.add_variable("lambda_sym", len(sym))
    md.add_constraint_with_multipliers(
        "u", "lambda_sym", rows_of_identity(gf, ndof, x_dof[sym]), np.zeros(len(sym))
    )
    md.add_initialized_data("traction", [0.0, 0.0])
    md.add_source_term_brick(mim, "u", "traction", spec["regions"]["load"])
    segments = edge_segments(gf_mesh, spec["regions"]["contact"])
    ids, length = candidates(spec, points, segments)
    add_contact(gf, md, ndof, ids, length * spec["thickness"], points, x_dof, spec, sym)
    return md, mim, {"ids": ids, "length": length, "points": points, "x_dof": x_dof, "ndof": ndof}


def start_off_zero(md, book: dict) -> None:
    """Newton's first iterate: the uniform strain (START_STRAIN, -START_STRAIN) instead of 0,
    where the return mapping's tangent is undefined (0/0 in the norm of the deviator; GetFEM
    then perturbs the state at random and, measured, may not converge at all)."""
    u = np.zeros(book["ndof"])
    u[book["x_dof"]] = START_STRAIN * book["points"][:, 0]
    u[book["x_dof"] + 1] = -START_STRAIN * book["points"][:, 1]
    md.set_variable("u", u)


def solve_steps(md, mim, spec: dict, book: dict) -> dict:
    """N equal load steps, one Newton solve each.  GetFEM stops Newton when min(|r|_1 /
    |external load|_1, |du|_1 / |state|_1) <= MAX_RES (its standard criterion)."""
    n, y_dof = spec["steps"], book["x_dof"][book["ids"]] + 1
    start_off_zero(md, book)
    gaps, forces = [book["points"][book["ids"], 1].copy()], [np.zeros(len(book["ids"]))]
    iterations, converged = 0, True
    for k in range(1, n + 1):
        md.set_variable("traction", [0.0, -spec["traction"] * k / n])
        its, ok = md.solve(*NEWTON)
        iterations += int(its)
        converged = converged and bool(ok)
        if spec["Sy"] is not None:
            md.small_strain_elastoplasticity_next_iter(mim, *plastic_args(spec))
        else:
            md.set_variable("Previous_u", md.variable("u"))
        u = md.variable("u")
        gaps.append(book["points"][book["ids"], 1] + u[y_dof])
        forces.append(-np.asarray(md.variable("lambda_n")))
    lt = md.variable("lambda_t") if spec["mu"] else np.zeros(len(book["ids"]))
    return {
        "gaps": np.array(gaps),
        "forces": np.array(forces),
        "iterations": iterations,
        "tangential": -np.asarray(lt),
        "converged": converged,
    }


def closing_rates(md, spec: dict, book: dict, gaps: np.ndarray) -> np.ndarray:
    """d(gap)/df of every candidate at f = 1, from one more solve at f = 1 + PROBE (the state
    is not stored): the rate slipstep's last trial solution gives (its predicted_closure)."""
    y_dof = book["x_dof"][book["ids"]] + 1
    md.set_variable("traction", [0.0, -spec["traction"] * (1.0 + PROBE)])
    md.solve(*NEWTON)
    return (book["points"][book["ids"], 1] + md.variable("u")[y_dof] - gaps[-1]) / PROBE


def step_closure(gaps: np.ndarray, closed: np.ndarray, rate: np.ndarray):
    """Per candidate: the load fraction at which it last closed (closed at the end; 0 if closed
    from the start) and at which it would close (open at the end; inf if not closing).  The
    gap is linear in f between events, so these are lines through the history (f_k = k/N):
    closure where the line through the last two open states reaches 0 (within the step it
    closed in), prediction from the final gap and its rate (`closing_rates`)."""
    n = len(gaps) - 1
    f = np.arange(n + 1) / n
    closure = np.full(gaps.shape[1], np.nan)
    closing = rate < 0
    predicted = np.full(gaps.shape[1], np.inf)
    predicted[closing] = 1.0 - gaps[-1, closing] / rate[closing]
    for i in np.flatnonzero(closed[-1]):
        open_steps = np.flatnonzero(~closed[:, i])
        if len(open_steps) == 0:
            closure[i] = 0.0
            continue
        k = open_steps[-1]
        closure[i] = (
            f[k + 1]
            if k == 0
            else np.clip(_secant_zero(f[k - 1 : k + 1], gaps[k - 1 : k + 1, i]), f[k], f[k + 1])
        )
    return closure, predicted


def _secant_zero(f: np.ndarray, g: np.ndarray) -> float:
    """Where the line through (f[0], g[0]), (f[1], g[1]) reaches g = 0 (inf if g grows)."""
    return float(f[1] + g[1] * (f[1] - f[0]) / (g[0] - g[1])) if g[0] > g[1] else math.inf


def contact_numbers(spec: dict, book: dict, hist: dict) -> dict:
    """p0, a, total normal force at f = 1, as slipstep defines them (module docstring)."""
    from slipstep.measures.contact_edges import contact_half_width

    forces = hist["forces"]
    closed = forces > 1e-12 * max(forces[-1].sum(), 1e-300)
    closure, predicted = step_closure(hist["gaps"], closed, hist["rate"])
    x = book["points"][book["ids"], 0]
    pressure = forces[-1] / (book["length"] * spec["thickness"])
    return {
        "p0": float(pressure.max()),
        "total_normal_force": float(forces[-1].sum()),
        "a": contact_half_width(x, closed[-1].astype(int), closure, predicted, 1.0),
        "n_closed": int(closed[-1].sum()),
        "x_outer_closed": float(x[closed[-1]].max()),
        "x": x.tolist(),
        "pressure": pressure.tolist(),
        "tangential": (hist["tangential"] / (book["length"] * spec["thickness"])).tolist(),
    }


def one(spec: dict) -> dict:
    """One GetFEM run in this process (the module docstring describes the model)."""
    import getfem as gf

    gf.util_trace_level(0)  # no per-assembly trace lines (GetFEM's default level prints them)
    t0 = time.perf_counter()
    md, mim, book = build_model(gf, spec)
    t1 = time.perf_counter()
    hist = solve_steps(md, mim, spec, book)
    t2 = time.perf_counter()
    hist["rate"] = closing_rates(md, spec, book, hist["gaps"])
    t3 = time.perf_counter()
    out = contact_numbers(spec, book, hist)
    status = "ok" if hist["converged"] else "not_converged"
    return {
        "status": status,
        "h": spec["h"],
        "steps": spec["steps"],
        "dofs": book["ndof"],
        "n_candidates": len(book["ids"]),
        "newton_iterations": hist["iterations"],
        **out,
        "import_s": t0 - T_START,
        "setup_s": t1 - t0,
        "solve_s": t2 - t1,
        "probe_s": t3 - t2,
        "post_s": time.perf_counter() - t3,
    }


# --------------------------------------------------------------------------- runs (parent side)
def run_child(spec: dict, timeout: float = TIMEOUT_S, script: str = __file__) -> dict:
    """``one`` of ``script`` (this one, or bench/getfem_hertz_3d.py) in its own process;
    wall_s is that whole process (start-up to exit)."""
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
        json.dump(spec, f)
    cmd = [sys.executable, str(Path(script).resolve()), "one", f.name]
    t0 = time.perf_counter()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, cwd=ROOT)
    except subprocess.TimeoutExpired:
        return {"status": "timeout", "error": f"no result within {timeout:.0f} s"}
    finally:
        os.unlink(f.name)
    wall = time.perf_counter() - t0
    lines = [ln for ln in p.stdout.splitlines() if ln.startswith("GETFEM ")]
    if not lines:
        tail = " | ".join((p.stderr or "").strip().splitlines()[-3:])
        return {"status": "error", "error": f"exit code {p.returncode}: {tail}"}
    return {**json.loads(lines[-1][len("GETFEM ") :]), "wall_s": wall}


def repeated(spec: dict, repeats: int) -> dict:
    """min and median of wall_s and solve_s over ``repeats`` processes; one process only for
    a run longer than REPEAT_BELOW_S (its noise is relatively small) or one that fails."""
    runs = []
    for _ in range(repeats):
        r = run_child(spec)
        runs.append(r)
        if r["status"] != "ok":
            return {**spec, **r}
        if r["wall_s"] > REPEAT_BELOW_S:
            break
    repeats = len(runs)
    out = {**runs[0], "repeats": repeats}
    for key in ("wall_s", "solve_s"):
        values = [r[key] for r in runs]
        out[key], out[f"{key}_median"] = min(values), statistics.median(values)
    return out


def record(r: dict) -> dict:
    """The JSON row of a run (module docstring)."""
    keys = (
        "h",
        "dofs",
        "steps",
        "status",
        "newton_iterations",
        "p0",
        "a",
        "total_normal_force",
        "wall_s",
        "wall_s_median",
        "solve_s",
        "solve_s_median",
        "setup_s",
        "probe_s",
        "repeats",
        "error",
    )
    return {k: r[k] for k in keys if k in r}


def series(sizes, steps, repeats: int, out: Path) -> list[dict]:
    """GetFEM at every size and N; a size stops at its first run that times out or fails."""
    import getfem as gf

    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for h in sizes:
            msh = Path(tmp) / f"hertz_{h:g}.msh"
            for n in steps:
                r = repeated(scene_spec(h, n, msh=msh), repeats)
                rows.append(record(r))
                print(line_of(r), flush=True)
                write_results(rows, out, gf)
                if r["status"] in ("timeout", "error"):
                    break  # more steps on this mesh would not finish either
    return rows


def line_of(r: dict) -> str:
    head = f"h={r['h']:<7g} N={r['steps']:<3d}"
    if r["status"] not in ("ok", "not_converged"):
        return f"{head} {r['status']}: {r.get('error', '')}"
    return (
        f"{head} {r['dofs']:7d} DOFs {r['newton_iterations']:4d} Newton  wall "
        f"{r['wall_s']:7.2f} s (median {r.get('wall_s_median', r['wall_s']):7.2f})  solve "
        f"{r['solve_s']:7.2f} s  p0={r['p0']:.2f} a={r['a']:.4f} "
        f"F={r['total_normal_force']:.3f} {r['status']}"
    )


def write_results(rows: list[dict], out: Path, gf) -> None:
    doc = {
        "what": "GetFEM 5.4 on slipstep's elastoplastic Hertz scene, same mesh (bench/"
        "getfem_hertz.py; schema in its docstring)",
        "getfem": getattr(gf, "__version__", "5.4 (Debian python3-getfem)"),
        "scene": {"case": str(CASE.relative_to(ROOT)), "overrides": SCENE},
        "settings": {
            "law": LAW,
            "newton_max_res": MAX_RES,
            "newton_max_iter": MAX_ITER,
            "lsolver": "mumps",
            "contact": "basic contact brick, Alart-Curnier "
            "non-symmetric, incremental Coulomb (wt = Previous_u)",
        },
        "host": f"{platform.node()} ({os.cpu_count()} cores)",
        "note": "shared machine (other engineers' jobs): times are noisy; min and median of "
        "the repeats",
        "runs": rows,
    }
    out.write_text(json.dumps(doc, indent=1) + "\n")


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = p.add_subparsers(dest="command", required=True)
    s = sub.add_parser("one", help="one GetFEM run from a spec file; prints GETFEM {json}")
    s.add_argument("spec")
    s = sub.add_parser("series", help="the bench series; writes bench/getfem_results.json")
    s.add_argument("--sizes", default=",".join(map(str, SIZES)))
    s.add_argument("--steps", default=",".join(map(str, STEPS)))
    s.add_argument("--repeat", type=int, default=REPEATS)
    s.add_argument("--out", default=str(HERE / "getfem_results.json"))
    args = p.parse_args(argv)
    if args.command == "one":
        result = one(json.loads(Path(args.spec).read_text()))
        print("GETFEM " + json.dumps(result), flush=True)
        return 0
    series(
        [float(h) for h in args.sizes.split(",")],
        [int(n) for n in args.steps.split(",")],
        args.repeat,
        Path(args.out),
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
