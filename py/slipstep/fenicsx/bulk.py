"""dolfinx bulk solvers on the exchanged mesh, driven by a slipstep case with contact removed.

:class:`BulkProblem` reads the scene's mesh through the XDMF/HDF5 exchange
(:mod:`.exchange`) and sets up, on the dolfinx side only:

- P1 vector displacement (= CST), DG0 materials from the exchanged cell tags;
- the supports of the case's ``[[bc]]`` (``fix``, ``symmetry``) located on the exchanged
  facet tags with ``locate_dofs_topological`` (node sets through the node map);
- the load: edge pressures/tractions (and the Hertz ``[load] P``) assembled by UFL on the
  facet tags, ``t * dot(traction - q n, v) ds(tag)``, point loads at their nodes.

Both are checked against the slipstep model in the tests (same dofs, same vector to round-off).
Solvers:

- :meth:`BulkProblem.solve_elastic`: linear elasticity, UFL form ``t sigma(u):eps(v) dx``
  (plane strain, or plane stress with lambda* = 2 lambda mu / (lambda + 2 mu)), PETSc LU;
- :meth:`BulkProblem.solve_plastic`: small-strain von Mises with linear hardening
  (:mod:`.plasticity`): stresses and the equivalent plastic strain are DG0 (the CST's one
  point), residual ``t s:B(v) dx`` and consistent tangent ``t (C B du):B(v) dx`` with DG0
  coefficients updated from numpy, full Newton per load step, the load in N equal steps (or at
  given load fractions).

Extra constraints (prescribed displacements, any value) and extra nodal loads can be given
in slipstep numbering: that is how a contact state is replayed (:mod:`.replay`).  Every
array in and out is in slipstep numbering (nodes, elements, dof = 2 node + component).
"""

from __future__ import annotations

import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError
from . import plasticity, require_dolfinx
from .exchange import DolfinxMesh, scene_to_dolfinx

LU_OPTIONS = {"ksp_type": "preonly", "pc_type": "lu", "pc_factor_mat_solver_type": "mumps"}


@dataclass
class BulkResult:
    """A dolfinx solution in slipstep numbering."""

    load_fraction: float
    u: np.ndarray                 # (N, 2)
    stress: np.ndarray            # (M, 4) sigma_x, sigma_y, sigma_z, tau_xy
    plastic_strain: np.ndarray    # (M,) equivalent plastic strain
    plastic: np.ndarray           # (M,) bool, yielded in the last step
    reaction: np.ndarray          # (2N,) K u - f_ext: support and contact reactions
    newton: list = field(default_factory=list)  # per load step: iterations, final residual


def _refuse_unmodelled_loads(scene) -> None:
    """The bulk problem scales the case's forces by load fractions only: prescribed
    displacements and obstacle motions (model patterns) would silently be dropped."""
    for pattern in scene.model.get("patterns", []):
        if "displacement_dofs" in pattern or "motion" in pattern:
            raise InputError(f"{scene.case.source}: load '{pattern['name']}' prescribes a "
                             f"displacement or moves an obstacle, which the dolfinx bulk "
                             f"cross-check does not model: cross-check a force-driven variant")


def _edge_name(scene, body: str, tag: str) -> str:
    return f"{body}.{tag}" if len(scene.bodies) > 1 else tag


class BulkProblem:
    """The scene's bulk problem in dolfinx (contact removed).  See the module doc."""

    def __init__(self, scene, dm: DolfinxMesh | None = None, workdir: str | Path | None = None):
        require_dolfinx()
        import ufl
        from dolfinx import fem

        t0 = time.perf_counter()
        self.scene = scene
        _refuse_unmodelled_loads(scene)
        if dm is None:
            if workdir is None:
                self._tmp = tempfile.TemporaryDirectory(prefix="slipstep-fenicsx-")
                workdir = self._tmp.name
            dm = scene_to_dolfinx(scene, workdir)
        self.dm = dm
        mesh = dm.mesh
        model = scene.model
        self.plane = model["plane"]
        self.thickness = float(model["thickness"])
        self.n_nodes, self.n_elements = dm.n_nodes, dm.n_cells

        self.V = fem.VectorFunctionSpace(mesh, ("CG", 1))
        self.W0 = fem.FunctionSpace(mesh, ("DG", 0))
        self.W3 = fem.VectorFunctionSpace(mesh, ("DG", 0), dim=3)
        self.W4 = fem.VectorFunctionSpace(mesh, ("DG", 0), dim=4)
        self.WT = fem.TensorFunctionSpace(mesh, ("DG", 0), shape=(3, 3))
        block = dm.block_of_node(self.V)
        # perm[slipstep dof] = dolfinx (unrolled) dof
        self.perm = (2 * block[:, None] + np.arange(2)[None, :]).ravel()

        # materials: exchanged cell tags (body index + 1) -> the scene's material list
        ct = dm.cell_tags
        tag_of_cell = np.zeros(dm.n_cells, dtype=np.int64)
        tag_of_cell[ct.indices] = ct.values
        self.material_of_element = tag_of_cell[dm.cell_of_element] - 1
        mats = model["materials"]
        m = self.material_of_element
        self.E = np.array([mats[i]["E"] for i in m], dtype=float)
        self.nu = np.array([mats[i]["nu"] for i in m], dtype=float)
        self.Sy = np.array([mats[i].get("Sy") or np.inf for i in m], dtype=float)
        self.H = np.array([mats[i].get("H") or 0.0 for i in m], dtype=float)

        # UFL elasticity with DG0 Lame parameters
        K, G, lam = plasticity.lame(self.E, self.nu)
        if self.plane == "stress":
            lam = 2.0 * lam * G / (lam + 2.0 * G)
        self.lam_fn, self.mu_fn = fem.Function(self.W0), fem.Function(self.W0)
        dm.set_cell_function(self.lam_fn, lam)
        dm.set_cell_function(self.mu_fn, G)
        u, v = ufl.TrialFunction(self.V), ufl.TestFunction(self.V)
        t = fem.Constant(mesh, self.thickness)

        def eps(w):
            return ufl.sym(ufl.grad(w))

        def sigma(w):
            return 2.0 * self.mu_fn * eps(w) + self.lam_fn * ufl.tr(eps(w)) * ufl.Identity(2)

        def voigt(w):  # (eps_x, eps_y, gamma_xy)
            return ufl.as_vector([w[0].dx(0), w[1].dx(1), w[0].dx(1) + w[1].dx(0)])

        self._t = t
        self.a_elastic = fem.form(t * ufl.inner(sigma(u), eps(v)) * ufl.dx)
        self.u_fn = fem.Function(self.V, name="u")
        s = sigma(self.u_fn)
        sz = (self.lam_fn * ufl.tr(eps(self.u_fn)) if self.plane == "strain"
              else 0.0 * s[0, 0])
        self._stress_expr = fem.Expression(ufl.as_vector([s[0, 0], s[1, 1], sz, s[0, 1]]),
                                           self.W4.element.interpolation_points())
        self._strain_expr = fem.Expression(voigt(self.u_fn), self.W3.element.interpolation_points())
        # plasticity forms: DG0 stress (x, y, xy) and DG0 in-plane tangent
        self.sig3_fn = fem.Function(self.W3)
        self.ct_fn = fem.Function(self.WT)
        self.r_form = fem.form(t * ufl.inner(self.sig3_fn, voigt(v)) * ufl.dx)
        self.j_form = fem.form(t * ufl.inner(ufl.dot(self.ct_fn, voigt(u)), voigt(v)) * ufl.dx)

        self.fixed_dofs = self._case_fixed_dofs()       # slipstep numbering
        self.load = self._case_load()                   # slipstep numbering, fraction 1
        self.timings = {"setup": time.perf_counter() - t0}

    # ------------------------------------------------------------------ case -> dolfinx
    def _case_fixed_dofs(self) -> np.ndarray:
        """The case's supports located on the exchanged facet tags (slipstep dof numbers)."""
        from dolfinx import fem

        scene, dm = self.scene, self.dm
        tdim = dm.mesh.topology.dim
        dm.mesh.topology.create_connectivity(tdim - 1, 0)
        f2v = dm.mesh.topology.connectivity(tdim - 1, 0)
        geom_of_vertex = self.geom_of_vertex()
        inv = np.empty(len(self.perm), dtype=np.int64)
        inv[self.perm] = np.arange(len(self.perm))
        out = []
        for bc in scene.case.data["bc"]:
            comps = {"xy".index(c) for c in bc["fix"]}
            if bc["edge"]:
                facets = dm.facets(_edge_name(scene, bc["body"], bc["edge"]))
                if bc["symmetry"]:
                    x = dm.mesh.geometry.x[:, :2]
                    vv = np.array([f2v.links(f) for f in facets])
                    d = x[geom_of_vertex[vv[:, 1]]] - x[geom_of_vertex[vv[:, 0]]]
                    d /= np.linalg.norm(d, axis=1, keepdims=True)
                    comps.add(1 if np.all(np.abs(d[:, 0]) > 1 - 1e-9) else 0)
                for c in sorted(comps):
                    dofs = fem.locate_dofs_topological(self.V.sub(c), tdim - 1, facets)
                    out.append(inv[np.asarray(dofs, dtype=np.int64)])
            elif bc["nodes"]:
                nodes = np.asarray(scene.meshes[bc["body"]].node_sets[bc["nodes"]]) \
                    + scene.offsets[bc["body"]]
                for c in sorted(comps):
                    out.append(2 * nodes + c)
        if not out:
            return np.zeros(0, dtype=np.int64)
        return np.unique(np.concatenate(out)).astype(np.int64)

    def geom_of_vertex(self) -> np.ndarray:
        """Geometry node of each topology vertex (P1 mesh: via the cells' local order)."""
        mesh = self.dm.mesh
        c2v = mesh.topology.connectivity(2, 0).array.reshape(-1, 3)
        geo = mesh.geometry.dofmap.array.reshape(-1, 3)
        out = np.full(mesh.topology.index_map(0).size_local, -1, dtype=np.int64)
        out[c2v.ravel()] = geo.ravel()
        return out

    def _case_load(self) -> np.ndarray:
        """Edge loads assembled by UFL on the facet tags, plus point loads (slipstep dofs)."""
        import ufl
        from dolfinx import fem
        from dolfinx.fem.petsc import assemble_vector

        from ..model import hertz_cut_pressure

        scene, dm = self.scene, self.dm
        data = scene.case.data
        mesh = dm.mesh
        ds = ufl.Measure("ds", domain=mesh, subdomain_data=dm.facet_tags)
        n = ufl.FacetNormal(mesh)
        v = ufl.TestFunction(self.V)
        terms = []
        for bc in data["bc"]:
            if bc["edge"] and (bc["pressure"] != 0.0 or bc["traction"] != [0.0, 0.0]):
                tag = dm.edge_id(_edge_name(scene, bc["body"], bc["edge"]))
                tr = ufl.as_vector([float(bc["traction"][0]), float(bc["traction"][1])])
                terms.append(ufl.dot(tr - float(bc["pressure"]) * n, v) * ds(tag))
        if data["load"] is not None:
            tag = dm.edge_id(_edge_name(scene, data["load"]["body"], "top"))
            terms.append(ufl.dot(-hertz_cut_pressure(scene.case) * n, v) * ds(tag))
        f = np.zeros(2 * self.n_nodes)
        if terms:
            b = assemble_vector(fem.form(self._t * sum(terms[1:], terms[0])))
            f = b.array[self.perm].copy()
        t = self.thickness
        for pl in data["point_load"]:
            bodies = [pl["body"]] if pl["body"] else scene.bodies
            ids = np.concatenate([np.arange(scene.meshes[b].n_nodes) + scene.offsets[b]
                                  for b in bodies])
            node = ids[np.argmin(np.linalg.norm(scene.nodes[ids] - np.asarray(pl["at"]), axis=1))]
            f[2 * node:2 * node + 2] += np.asarray(pl["force"]) * t
        return f

    # ------------------------------------------------------------------ linear algebra
    def _to_dolfinx(self, x_slipstep: np.ndarray) -> np.ndarray:
        out = np.zeros(len(self.perm))
        out[self.perm] = x_slipstep
        return out

    def assemble_elastic(self):
        """The elastic stiffness (PETSc Mat, dolfinx dof order, no constraints)."""
        from dolfinx.fem.petsc import assemble_matrix

        A = assemble_matrix(self.a_elastic)
        A.assemble()
        return A

    def _solve_constrained(self, A, rhs: np.ndarray, dofs: np.ndarray, values: np.ndarray):
        """Solve A x = rhs with x[dofs] = values (dolfinx numbering) by symmetric elimination
        (PETSc MatZeroRowsColumns) and LU (MUMPS)."""
        from petsc4py import PETSc

        Ac = A.copy()
        b = A.createVecRight()
        b.array[:] = rhs
        xb = A.createVecRight()
        xb.array[dofs] = values
        Ac.zeroRowsColumns(np.asarray(dofs, dtype=np.int32), 1.0, xb, b)
        ksp = PETSc.KSP().create(Ac.comm)
        ksp.setOperators(Ac)
        ksp.setType("preonly")
        pc = ksp.getPC()
        pc.setType("lu")
        pc.setFactorSolverType("mumps")
        x = A.createVecRight()
        ksp.solve(b, x)
        if ksp.getConvergedReason() < 0:
            raise RuntimeError(f"dolfinx: the linear solve failed (reason {ksp.getConvergedReason()})")
        out = x.array.copy()
        for obj in (ksp, Ac, b, xb, x):
            obj.destroy()
        return out

    def _constraints(self, prescribed: dict | None):
        """(dolfinx dofs, values): the supports (0) and the prescribed slipstep dofs
        (dof -> value)."""
        dofs = {int(d): 0.0 for d in self.fixed_dofs}
        if prescribed:
            for d, val in prescribed.items():
                dofs[int(d)] = float(val)
        keys = np.fromiter(dofs.keys(), dtype=np.int64, count=len(dofs))
        vals = np.fromiter(dofs.values(), dtype=float, count=len(dofs))
        return self.perm[keys], vals

    # ------------------------------------------------------------------ elastic
    def solve_elastic(self, fraction: float = 1.0, prescribed: dict | None = None,
                      extra_load: np.ndarray | None = None) -> BulkResult:
        """Linear elasticity under the case load x ``fraction`` plus ``extra_load`` (slipstep
        dofs, as given), with the supports and the ``prescribed`` displacements
        (slipstep dof -> value, as given)."""
        t0 = time.perf_counter()
        A = self.assemble_elastic()
        f = self.load * fraction + (extra_load if extra_load is not None else 0.0)
        dofs, vals = self._constraints(prescribed)
        x = self._solve_constrained(A, self._to_dolfinx(f), dofs, vals)
        self.u_fn.x.array[:] = x
        stress_fn = self._interpolate(self._stress_expr, self.W4)
        y = A.createVecRight()
        xv = A.createVecRight()
        xv.array[:] = x
        A.mult(xv, y)
        reaction = y.array[self.perm] - f
        for obj in (A, y, xv):
            obj.destroy()
        self.timings["elastic"] = time.perf_counter() - t0
        return BulkResult(fraction, x[self.perm].reshape(-1, 2),
                          self.dm.cell_function_values(stress_fn),
                          np.zeros(self.n_elements), np.zeros(self.n_elements, bool), reaction)

    def _interpolate(self, expr, W):
        from dolfinx import fem

        out = fem.Function(W)
        out.interpolate(expr)
        return out

    # ------------------------------------------------------------------ elastoplastic
    def solve_plastic(self, n_steps: int = 10, fractions=None, prescribed: dict | None = None,
                      extra_load=None, schedule=None, substeps: int = 1, tol: float = 1e-10,
                      max_iter: int = 40, callback=None) -> BulkResult:
        """Elastoplastic solution by load steps.

        Proportional loading: the case load, ``extra_load`` and the ``prescribed`` values
        (given at fraction 1) scaled by each of ``fractions`` (default: ``n_steps`` equal
        steps).  Or a general ``schedule``: a list of ``(fraction, prescribed, extra_load)``
        with absolute values (the constrained set may change from one entry to the next);
        each entry is reached in ``substeps`` steps, every value ramped linearly from where
        the previous entry left it (a newly constrained dof from its current displacement).
        Full Newton per step with the consistent tangent; converged when the free-dof
        residual <= tol * the largest |f_ext| of the path so far (so that unloading to zero
        load converges too).  ``callback(result)`` after every entry.
        """
        from dolfinx.fem.petsc import assemble_matrix, assemble_vector

        t0 = time.perf_counter()
        if schedule is None:
            if fractions is None:
                fractions = np.arange(1, n_steps + 1) / n_steps
            schedule = [(float(lf), {d: v * lf for d, v in (prescribed or {}).items()},
                         None if extra_load is None else extra_load * lf) for lf in fractions]
        M = self.n_elements
        sig = np.zeros((M, 4))
        alpha = np.zeros(M)
        eps_prev = np.zeros((M, 3))
        x = np.zeros(len(self.perm))          # dolfinx order
        newton_log = []
        result = None
        lf_prev, f_prev = 0.0, np.zeros(len(self.perm))
        f_scale = 0.0  # the largest load so far: residuals of an unloaded state are relative to it
        for lf, presc, extra in schedule:
            f_end = self._to_dolfinx(self.load * lf + (extra if extra is not None else 0.0))
            f_scale = max(f_scale, np.linalg.norm(f_end))
            dofs_all, target_end = self._constraints(presc)
            start = x[dofs_all].copy()
            free = np.ones(len(self.perm), bool)
            free[dofs_all] = False
            for k in range(1, substeps + 1):
                s = k / substeps
                f_d = f_prev + s * (f_end - f_prev)
                target = start + s * (target_end - start)
                fnorm = max(np.linalg.norm(f_d), f_scale, 1e-300)
                it, res = 0, np.inf
                while True:
                    self.u_fn.x.array[:] = x
                    strain = self.dm.cell_function_values(
                        self._interpolate(self._strain_expr, self.W3))
                    s_new, a_new, C3, plastic, _ = plasticity.integrate(
                        sig, alpha, strain - eps_prev, self.E, self.nu, self.Sy, self.H,
                        self.plane)
                    self.dm.set_cell_function(self.sig3_fn, s_new[:, [0, 1, 3]])
                    self.dm.set_cell_function(self.ct_fn, C3.reshape(M, 9))
                    R = assemble_vector(self.r_form)
                    r = R.array - f_d
                    R.destroy()
                    res = np.linalg.norm(r[free]) / fnorm
                    on_target = np.array_equal(x[dofs_all], target)
                    if (res <= tol and on_target) or it >= max_iter:
                        break
                    J = assemble_matrix(self.j_form)
                    J.assemble()
                    dx = self._solve_constrained(J, -r, dofs_all, target - x[dofs_all])
                    J.destroy()
                    x = x + dx
                    x[dofs_all] = target
                    it += 1
                if res > tol:
                    raise RuntimeError(f"dolfinx Newton did not converge at load fraction "
                                       f"{lf_prev + s * (lf - lf_prev):.4g}: residual {res:.3g} "
                                       f"after {it} iterations (use more steps)")
                sig, alpha, eps_prev = s_new, a_new, strain
                newton_log.append({"load_fraction": lf_prev + s * (lf - lf_prev),
                                   "iterations": it, "residual": res})
            lf_prev, f_prev = lf, f_end
            # reaction = internal - external forces at the solution (slipstep numbering)
            result = BulkResult(float(lf), x[self.perm].reshape(-1, 2), sig.copy(),
                                alpha.copy(), plastic.copy(), (r + f_d - f_end)[self.perm],
                                list(newton_log))
            if callback is not None:
                callback(result)
        self.timings["plastic"] = time.perf_counter() - t0
        return result

    # ------------------------------------------------------------------ output
    def write_xdmf(self, path: str | Path, results: list[BulkResult]) -> Path:
        """Write results with dolfinx's XDMFFile (time = load fraction): P1 ``u`` and DG0
        ``sigma_x``, ``sigma_y``, ``sigma_z``, ``tau_xy``, ``plastic_strain``."""
        from dolfinx import fem
        from dolfinx.io import XDMFFile

        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        u = fem.Function(self.V, name="u")
        cells = {n: fem.Function(self.W0, name=n)
                 for n in ("sigma_x", "sigma_y", "sigma_z", "tau_xy", "plastic_strain")}
        with XDMFFile(self.dm.mesh.comm, str(path), "w") as f:
            f.write_mesh(self.dm.mesh)
            for res in results:
                self.dm.set_vector_function(u, res.u)
                for k, name in enumerate(("sigma_x", "sigma_y", "sigma_z", "tau_xy")):
                    self.dm.set_cell_function(cells[name], res.stress[:, k])
                self.dm.set_cell_function(cells["plastic_strain"], res.plastic_strain)
                f.write_function(u, res.load_fraction)
                for fn in cells.values():
                    f.write_function(fn, res.load_fraction)
        return path

    def read_h5(self, path: str | Path) -> dict:
        """Read a file of :meth:`write_xdmf` back with h5py, in slipstep numbering:
        {time: {"u": (N, 2), "sigma_x": (M,), ...}} (times as written, '.' -> '_')."""
        import h5py

        out: dict = {}
        with h5py.File(Path(path).with_suffix(".h5"), "r") as f:
            for name, group in f["Function"].items():
                for key, ds in group.items():
                    arr = ds[()]
                    t = float(key.replace("_", "."))
                    if name == "u":  # geometry order, padded to 3 components
                        val = arr[self.dm.geom_of_node, :2]
                    else:            # DG0: topology (cell) order
                        val = arr.reshape(-1)[self.dm.cell_of_element]
                    out.setdefault(t, {})[name] = val
        return out


def relative_difference(a: np.ndarray, b: np.ndarray) -> float:
    """max |a - b| / max |b| (0 if both vanish)."""
    scale = np.abs(b).max(initial=0.0)
    diff = np.abs(np.asarray(a) - np.asarray(b)).max(initial=0.0)
    return float(diff / scale) if scale > 0 else float(diff)
