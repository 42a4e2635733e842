"""dolfinx bulk solvers on the exchanged mesh, driven by a slipstep case with contact removed.

:class:`BulkProblem` reads the scene's mesh through the XDMF/HDF5 exchange
(:mod:`.exchange`) and sets up, on the dolfinx side only:

- P1 vector displacement (= CST), materials from the exchanged cell tags;
- the supports of the case's ``[[bc]]`` (``fix``, ``symmetry``) located on the exchanged
  facet tags with ``locate_dofs_topological`` (node sets through the node map); in
  axisymmetry also u_r = 0 on the axis, located by dolfinx's dof coordinates;
- the load: edge pressures/tractions (and the Hertz ``[load] P``) assembled by UFL on the
  facet tags, ``dot(traction - q n, v) dGamma(tag)``, point loads at their nodes.

Both are checked against the slipstep model in the tests (same dofs, same vector to round-off).
One weak form serves both solvers (:mod:`.forms`: strain(v) in Voigt notation, dOmega = t dx,
or the ring's four strains and 2 pi r dx in axisymmetry):
residual ``s . strain(v) dOmega`` and tangent ``(C strain(u)) . strain(v) dOmega`` with DG0
stress s and tangent C set from numpy (:mod:`.plasticity`: the CST's one point per cell).

- :meth:`BulkProblem.solve_elastic`: linear elasticity, C the elastic stiffness (plane strain,
  or plane stress condensed on sigma_z = 0), one LU solve (PETSc MUMPS);
- :meth:`BulkProblem.solve_plastic`: small-strain von Mises with linear hardening, C the
  consistent tangent, full Newton per load step, the load in N equal steps (or at given load
  fractions).

Extra constraints (prescribed displacements, any value) and extra nodal loads can be given
in slipstep numbering: that is how a contact state is replayed (:mod:`.replay`).  Every
array in and out is in slipstep numbering (nodes, elements, dof = 2 node + component).

A 3D scene (tetrahedra, ``plane = "space"`` here) runs through the same solvers: P1 vectors of
three components (dof = 3 node + component), the six strains of :class:`.forms.SpaceSection`,
the six-component return of :mod:`.plasticity`, supports and loads on the exchanged face tags
(a symmetry face holds the component of its plane's normal, found from its triangles here).
"""

from __future__ import annotations

import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError
from . import dolfinx_api as api
from . import plasticity
from .exchange import DolfinxMesh, scene_to_dolfinx
from .forms import CENTROID_RULE, section


@dataclass
class BulkResult:
    """A dolfinx solution in slipstep numbering."""

    load_fraction: float
    u: np.ndarray  # (N, 2); 3D: (N, 3)
    stress: np.ndarray  # (M, 4) sigma_x, sigma_y, sigma_z, tau_xy; 3D: (M, 6) Voigt
    plastic_strain: np.ndarray  # (M,) equivalent plastic strain
    plastic: np.ndarray  # (M,) bool, yielded in the last step
    reaction: np.ndarray  # (2N,) (3D: (3N,)) K u - f_ext: support and contact reactions
    newton: list = field(default_factory=list)  # per load step: iterations, final residual


def _refuse_unmodelled_loads(scene) -> None:
    """The bulk problem scales the case's forces by load fractions only: prescribed
    displacements and obstacle motions (model patterns) would silently be dropped."""
    for pattern in scene.model.get("patterns", []):
        if "displacement_dofs" in pattern or "motion" in pattern:
            raise InputError(
                f"{scene.case.source}: load '{pattern['name']}' prescribes a "
                f"displacement or moves an obstacle, which the dolfinx bulk "
                f"cross-check does not model: cross-check a force-driven variant"
            )


#: A Newton correction below this fraction of the displacement is round-off: the residual has
#: reached its floor (small loads on a stiff, nearly rigidly translating body, e.g. the Hertz
#: sphere's first contact states, floor at ~1e-10 relative), and the step is converged.
ROUND_OFF_STEP = 1e-12


def _edge_name(scene, body: str, tag: str) -> str:
    return f"{body}.{tag}" if len(scene.bodies) > 1 else tag


class BulkProblem:
    """The scene's bulk problem in dolfinx (contact removed).  See the module doc."""

    def __init__(
        self,
        scene,
        dm: DolfinxMesh | None = None,
        workdir: str | Path | None = None,
        quadrature_degree: int = CENTROID_RULE,
    ):
        """``quadrature_degree``: of the ring's bulk integrals (axisymmetry only; the default
        one-point rule is slipstep's ring element, see :mod:`.forms`)."""
        api.require_dolfinx()
        t0 = time.perf_counter()
        self.scene = scene
        _refuse_unmodelled_loads(scene)
        if dm is None:
            if workdir is None:
                self._tmp = tempfile.TemporaryDirectory(prefix="slipstep-fenicsx-")
                workdir = self._tmp.name
            dm = scene_to_dolfinx(scene, workdir)
        self.dm = dm
        self.dim = scene.dimension
        self.plane = scene.model.get("plane", "space")  # a 3D model has no plane
        self.n_nodes, self.n_elements = dm.n_nodes, dm.n_cells
        self.section = section(
            dm.mesh, self.plane, scene.model.get("thickness", 1.0), dm.facet_tags, quadrature_degree
        )
        self.V = api.function_space(dm.mesh, "Lagrange", 1, (self.dim,))
        block = dm.block_of_node(self.V)
        # perm[slipstep dof] = dolfinx (unrolled) dof
        self.perm = (self.dim * block[:, None] + np.arange(self.dim)[None, :]).ravel()
        self.n_stress = plasticity.stress_size(self.plane)
        self._materials(scene.model["materials"])
        self._forms()
        self.fixed_dofs = self._case_fixed_dofs()  # slipstep numbering
        self.load = self._case_load()  # slipstep numbering, fraction 1
        self.timings = {"setup": time.perf_counter() - t0}

    def _materials(self, materials: list) -> None:
        """Per element E, nu, Sy, H from the exchanged cell tags (body index + 1)."""
        indices, values = api.tag_arrays(self.dm.cell_tags)
        tag_of_cell = np.zeros(self.dm.n_cells, dtype=np.int64)
        tag_of_cell[indices] = values
        self.material_of_element = m = tag_of_cell[self.dm.cell_of_element] - 1
        self.E = np.array([materials[i]["E"] for i in m], dtype=float)
        self.nu = np.array([materials[i]["nu"] for i in m], dtype=float)
        self.Sy = np.array([materials[i].get("Sy") or np.inf for i in m], dtype=float)
        self.H = np.array([materials[i].get("H") or 0.0 for i in m], dtype=float)

    def _forms(self) -> None:
        """The weak form (:mod:`.forms`) with DG0 stress s and tangent C, and the strain of
        the displacement ``u_fn`` interpolated per cell."""
        ufl, mesh = api.ufl(), self.dm.mesh
        strain, dOmega = self.section.strain, self.section.dOmega
        n = len(self.section.STRAIN)
        W_strain = api.function_space(mesh, "DG", 0, (n,))
        self.stress_fn = api.function(W_strain)  # s
        self.tangent_fn = api.function(api.function_space(mesh, "DG", 0, (n, n)))  # C
        s, C = self.stress_fn, self.tangent_fn
        u, v = ufl.TrialFunction(self.V), ufl.TestFunction(self.V)
        self.residual = api.compile_form(ufl.inner(s, strain(v)) * dOmega)
        self.jacobian = api.compile_form(ufl.inner(ufl.dot(C, strain(u)), strain(v)) * dOmega)
        self.u_fn = api.function(self.V, "u")
        self.strain_fn = api.function(W_strain)
        self._strain_expr = api.expression(strain(self.u_fn), W_strain)

    # ------------------------------------------------------------------ case -> dolfinx
    def _case_fixed_dofs(self) -> np.ndarray:
        """The case's supports located on the exchanged facet tags (slipstep dof numbers)."""
        scene, dm = self.scene, self.dm
        x = api.node_coordinates(dm.mesh)
        inv = np.empty(len(self.perm), dtype=np.int64)
        inv[self.perm] = np.arange(len(self.perm))
        out = []
        for bc in scene.case.record.bc:
            comps = {"xyz".index(c) for c in bc.fix}
            if bc.boundary_tag:
                facets = dm.facets(_edge_name(scene, bc.body, bc.boundary_tag))
                if bc.symmetry:
                    comps.add(_facet_normal_axis(x, api.facet_nodes(dm.mesh, facets)))
                for c in sorted(comps):
                    out.append(inv[api.locate_dofs(self.V, facets, component=c)])
            elif bc.nodes:
                nodes = (
                    np.asarray(scene.meshes[bc.body].node_sets[bc.nodes]) + scene.offsets[bc.body]
                )
                for c in sorted(comps):
                    out.append(self.dim * nodes + c)
        if self.plane == "axisymmetric":
            out.append(self._axis_dofs(inv))
        if not out:
            return np.zeros(0, dtype=np.int64)
        return np.unique(np.concatenate(out)).astype(np.int64)

    def _axis_dofs(self, inv: np.ndarray) -> np.ndarray:
        """Axisymmetry: the u_r dofs (slipstep numbers) of the nodes on the axis r = 0, found
        by dolfinx's dof coordinates within the engine's tolerance of the section's size."""
        from ..section import AXIS_TOLERANCE

        xyz = api.dof_coordinates(self.V)
        size = float(np.linalg.norm(np.ptp(xyz[:, :2], axis=0))) or 1.0
        blocks = np.flatnonzero(np.abs(xyz[:, 0]) <= AXIS_TOLERANCE * size)
        return inv[2 * blocks]

    def _case_load(self) -> np.ndarray:
        """Edge (3D: face) loads assembled by UFL on the facet tags, plus point loads (slipstep
        dofs)."""
        scene, dm, ufl = self.scene, self.dm, api.ufl()
        case = scene.case.record
        n, v, dGamma = ufl.FacetNormal(dm.mesh), ufl.TestFunction(self.V), self.section.dGamma
        terms = []
        for bc in case.bc:
            if bc.boundary_tag and bc.force:
                tag = dm.edge_id(_edge_name(scene, bc.body, bc.boundary_tag))
                traction = ufl.as_vector([float(c) for c in bc.traction])
                terms.append(ufl.dot(traction - float(bc.pressure) * n, v) * dGamma(tag))
        if case.load is not None:
            tag = dm.edge_id(_edge_name(scene, case.load.body, "top"))
            terms.append(ufl.dot(-scene.idealisation.cut_pressure(scene) * n, v) * dGamma(tag))
        f = np.zeros(self.dim * self.n_nodes)
        if terms:
            f = api.assemble_vector(sum(terms[1:], terms[0]))[self.perm]
        for pl in case.point_load:  # per unit thickness (axisymmetry: the ring's total)
            bodies = [pl.body] if pl.body else scene.bodies
            ids = np.concatenate(
                [np.arange(scene.meshes[b].n_nodes) + scene.offsets[b] for b in bodies]
            )
            node = ids[np.argmin(np.linalg.norm(scene.nodes[ids] - np.asarray(pl.at), axis=1))]
            f[self.dim * node : self.dim * (node + 1)] += self.section.point_force(
                np.asarray(pl.force)
            )
        return f

    # ------------------------------------------------------------------ numbering, constraints
    def _to_dolfinx(self, x_slipstep: np.ndarray) -> np.ndarray:
        out = np.zeros(len(self.perm))
        out[self.perm] = x_slipstep
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

    def _cell_strain(self, x: np.ndarray) -> np.ndarray:
        """(M, len(STRAIN)) strain per element of the displacement x (dolfinx dof order)."""
        api.dof_values(self.u_fn)[:] = x
        api.interpolate(self.strain_fn, self._strain_expr)
        return self.dm.cell_function_values(self.strain_fn)

    # ------------------------------------------------------------------ elastic
    def solve_elastic(
        self,
        fraction: float = 1.0,
        prescribed: dict | None = None,
        extra_load: np.ndarray | None = None,
    ) -> BulkResult:
        """Linear elasticity under the case load x ``fraction`` plus ``extra_load`` (slipstep
        dofs, as given), with the supports and the ``prescribed`` displacements
        (slipstep dof -> value, as given)."""
        t0 = time.perf_counter()
        M = self.n_elements
        self.dm.set_cell_function(
            self.tangent_fn, plasticity.section_d(self.E, self.nu, self.plane).reshape(M, -1)
        )
        A = api.assemble_matrix(self.jacobian)
        f = self.load * fraction + (extra_load if extra_load is not None else 0.0)
        dofs, vals = self._constraints(prescribed)
        x = api.solve_constrained(A, self._to_dolfinx(f), dofs, vals)
        reaction = api.matvec(A, x)[self.perm] - f
        api.destroy(A)
        stress = plasticity.integrate(
            np.zeros((M, self.n_stress)),
            np.zeros(M),
            self._cell_strain(x),
            self.E,
            self.nu,
            np.inf,
            0.0,
            self.plane,
        )[0]
        self.timings["elastic"] = time.perf_counter() - t0
        return BulkResult(
            fraction,
            x[self.perm].reshape(-1, self.dim),
            stress,
            np.zeros(M),
            np.zeros(M, bool),
            reaction,
        )

    # ------------------------------------------------------------------ elastoplastic
    def solve_plastic(
        self,
        n_steps: int = 10,
        fractions=None,
        prescribed: dict | None = None,
        extra_load=None,
        schedule=None,
        substeps: int = 1,
        tol: float = 1e-10,
        max_iter: int = 40,
        callback=None,
    ) -> BulkResult:
        """Elastoplastic solution by load steps.

        Proportional loading: the case load, ``extra_load`` and the ``prescribed`` values
        (given at fraction 1) scaled by each of ``fractions`` (default: ``n_steps`` equal
        steps).  Or a general ``schedule``: a list of ``(fraction, prescribed, extra_load)``
        with absolute values (the constrained set may change from one entry to the next);
        each entry is reached in ``substeps`` steps, every value ramped linearly from where
        the previous entry left it (a newly constrained dof from its current displacement).
        Full Newton per step with the consistent tangent; converged when the free-dof
        residual <= tol * the largest |f_ext| of the path so far (so that unloading to zero
        load converges too), or when a correction falls below ROUND_OFF_STEP of the
        displacement (the residual is then at its round-off floor).  ``callback(result)`` after
        every entry.
        """
        t0 = time.perf_counter()
        if schedule is None:
            if fractions is None:
                fractions = np.arange(1, n_steps + 1) / n_steps
            schedule = [
                (
                    float(lf),
                    {d: v * lf for d, v in (prescribed or {}).items()},
                    None if extra_load is None else extra_load * lf,
                )
                for lf in fractions
            ]
        M, n_strain = self.n_elements, len(self.section.STRAIN)
        state = (np.zeros((M, self.n_stress)), np.zeros(M), np.zeros((M, n_strain)))
        x = np.zeros(len(self.perm))  # dolfinx order
        newton_log, result = [], None
        lf_prev, f_prev = 0.0, np.zeros(len(self.perm))
        f_scale = 0.0  # the largest load so far: residuals of an unloaded state are relative to it
        for lf, presc, extra in schedule:
            f_end = self._to_dolfinx(self.load * lf + (extra if extra is not None else 0.0))
            f_scale = max(f_scale, np.linalg.norm(f_end))
            dofs, target_end = self._constraints(presc)
            start = x[dofs].copy()
            for k in range(1, substeps + 1):
                s = k / substeps
                f_d = f_prev + s * (f_end - f_prev)
                fnorm = max(np.linalg.norm(f_d), f_scale, 1e-300)
                x, state, plastic, r, it, res, done = self._equilibrate(
                    x, state, f_d, dofs, start + s * (target_end - start), fnorm, tol, max_iter
                )
                if not done:
                    raise RuntimeError(
                        f"dolfinx Newton did not converge at load fraction "
                        f"{lf_prev + s * (lf - lf_prev):.4g}: residual {res:.3g} "
                        f"after {it} iterations (use more steps)"
                    )
                newton_log.append(
                    {
                        "load_fraction": lf_prev + s * (lf - lf_prev),
                        "iterations": it,
                        "residual": res,
                    }
                )
            lf_prev, f_prev = lf, f_end
            # reaction = internal - external forces at the solution (slipstep numbering)
            result = BulkResult(
                float(lf),
                x[self.perm].reshape(-1, self.dim),
                state[0].copy(),
                state[1].copy(),
                plastic.copy(),
                (r + f_d - f_end)[self.perm],
                list(newton_log),
            )
            if callback is not None:
                callback(result)
        self.timings["plastic"] = time.perf_counter() - t0
        return result

    def _equilibrate(self, x, state, f_ext, dofs, target, fnorm, tol, max_iter):
        """Full Newton from x to equilibrium with f_ext and x[dofs] = target, the stresses
        integrated from ``state`` (stress, alpha, strain at the last converged step).
        Returns (x, new state, plastic, residual vector, iterations, relative residual,
        converged)."""
        sig, alpha, eps_prev = state
        free = np.ones(len(self.perm), bool)
        free[dofs] = False
        it, step = 0, np.inf
        while True:
            strain = self._cell_strain(x)
            s_new, a_new, C, plastic, _ = plasticity.integrate(
                sig, alpha, strain - eps_prev, self.E, self.nu, self.Sy, self.H, self.plane
            )
            self.dm.set_cell_function(
                self.stress_fn, s_new[:, plasticity.section_columns(self.plane)]
            )
            self.dm.set_cell_function(self.tangent_fn, C.reshape(len(C), -1))
            r = api.assemble_vector(self.residual) - f_ext
            res = np.linalg.norm(r[free]) / fnorm
            done = (res <= tol or step <= ROUND_OFF_STEP) and np.array_equal(x[dofs], target)
            if done or it >= max_iter:
                return x, (s_new, a_new, strain), plastic, r, it, res, done
            J = api.assemble_matrix(self.jacobian)
            dx = api.solve_constrained(J, -r, dofs, target - x[dofs])
            api.destroy(J)
            step = np.linalg.norm(dx) / max(np.linalg.norm(x + dx), 1e-300)
            x = x + dx
            x[dofs] = target
            it += 1

    # ------------------------------------------------------------------ output
    def write_xdmf(self, path: str | Path, results: list[BulkResult]) -> Path:
        """Write results with dolfinx's XDMFFile (time = load fraction): P1 ``u``, the DG0
        stresses named as in results.xdmf (``sigma_x``, ``sigma_y``, ``sigma_z``, ``tau_xy`` in
        the plane: the idealisation's ``stress_names``) and ``plastic_strain``."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        W0 = api.function_space(self.dm.mesh, "DG", 0)
        u = api.function(self.V, "u")
        names = self.scene.idealisation.stress_names
        cells = {n: api.function(W0, n) for n in (*names, "plastic_strain")}

        def frames():
            for res in results:
                self.dm.set_vector_function(u, res.u)
                for k, name in enumerate(names):
                    self.dm.set_cell_function(cells[name], res.stress[:, k])
                self.dm.set_cell_function(cells["plastic_strain"], res.plastic_strain)
                yield res.load_fraction, [u, *cells.values()]

        api.write_functions(path, self.dm.mesh, frames())
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
                        val = arr[self.dm.geom_of_node, : self.dim]
                    else:  # DG0: topology (cell) order
                        val = arr.reshape(-1)[self.dm.cell_of_element]
                    out.setdefault(t, {})[name] = val
        return out


def _facet_normal_axis(x: np.ndarray, facets: np.ndarray) -> int:
    """The coordinate axis every facet's normal lies along (a symmetry edge or plane face):
    facets (F, 2) segments or (F, 3) triangles of geometry nodes at coordinates x."""
    p = x[facets]
    if facets.shape[1] == 2:
        d = p[:, 1] - p[:, 0]
        n = np.stack([d[:, 1], -d[:, 0]], axis=1)
    else:
        n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    n = np.abs(n) / np.linalg.norm(n, axis=1, keepdims=True)
    return int(np.argmax(n.min(axis=0)))


def relative_difference(a: np.ndarray, b: np.ndarray) -> float:
    """max |a - b| / max |b| (0 if both vanish)."""
    scale = np.abs(b).max(initial=0.0)
    diff = np.abs(np.asarray(a) - np.asarray(b)).max(initial=0.0)
    return float(diff / scale) if scale > 0 else float(diff)
