"""The dolfinx API across versions: every dolfinx, UFL, petsc4py and mpi4py call of
:mod:`slipstep.fenicsx` goes through this module.

The rest of the package reads like the physics (forms, dof maps, load steps).  Where a call
is spelled differently between dolfinx 0.5 and 0.11, the function here branches on the parsed
``dolfinx.__version__`` (:func:`branch`), never on a caught AttributeError; :data:`SPELLINGS`
names, for every such point, the release (and the pull request listed in its changelog) each
branch follows.  Which versions were run is in docs/dolfinx.md.

Importing this module imports nothing of dolfinx: :func:`require_dolfinx` does (once), and
raises :class:`DolfinxMissing` naming the fix.  The UFL operators used by the package
(``grad``, ``sym``, ``inner``, ``dot``, ``as_vector``, ``Measure``, ...) are spelled the same
in every UFL paired with dolfinx 0.5 to 0.11, so :func:`ufl` hands out the module itself.

Serial only (one MPI process): the package's maps are built from process-local numbering.
"""

from __future__ import annotations

import contextlib
import logging
import re
import warnings
from dataclasses import dataclass
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from ..errors import SlipstepError

OLDEST = (0, 5)  # the oldest release the branches below start from
NEWEST = (0, 11)  # the newest release whose notes were read for them


class DolfinxMissing(SlipstepError, ImportError):
    """dolfinx is not importable, or older than 0.5: install it (the message says how)."""


# --------------------------------------------------------------------------- version dispatch
@dataclass(frozen=True)
class Spelling:
    """How one API point is spelled from release ``since`` on (until the next spelling)."""

    since: tuple[int, int]
    branch: str
    note: str  # the release note / changelog entry this branch follows


SPELLINGS: dict[str, tuple[Spelling, ...]] = {
    "function_space": (
        Spelling(
            (0, 5),
            "VectorFunctionSpace",
            "0.5/0.6: FunctionSpace(mesh, (family, k)), VectorFunctionSpace(..., dim=n), "
            "TensorFunctionSpace(..., shape=(n, m))",
        ),
        Spelling(
            (0, 7),
            "functionspace",
            "v0.7.0, #2766: functionspace(mesh, (family, k, shape)); the capitalised "
            "constructors removed in v0.8.0 (release notes: #2818)",
        ),
    ),
    "compiled_form": (
        Spelling((0, 5), "FormMetaClass", "0.5/0.6: fem.form returns a fem.FormMetaClass"),
        Spelling((0, 7), "Form", "v0.7.0, #2683 'Remove Python meta classes': fem.Form"),
    ),
    "scalar_type": (
        Spelling((0, 5), "PETSc.ScalarType", "0.5/0.6: petsc4py's PETSc.ScalarType"),
        Spelling((0, 7), "default_scalar_type", "v0.7.0, #2610: dolfinx.default_scalar_type"),
    ),
    "dofmap_list": (
        Spelling((0, 5), "AdjacencyList", "0.5/0.6: V.dofmap.list is an AdjacencyList (.array)"),
        Spelling((0, 7), "array", "v0.7.0, #2632 'Flatten dofmap storage': (cells, dofs) array"),
    ),
    "geometry_dofmap": (
        Spelling((0, 5), "AdjacencyList", "0.5/0.6: mesh.geometry.dofmap is an AdjacencyList"),
        Spelling((0, 7), "dofmap", "v0.7.0, #2632: mesh.geometry.dofmap is a (cells, nodes) array"),
        Spelling(
            (0, 11),
            "dofmaps[0]",
            "v0.11.0, #4227: geometry.dofmaps, one per cell type; dofmap deprecated",
        ),
    ),
    "coordinate_element": (
        Spelling((0, 5), "cmap", "0.5/0.6: mesh.geometry.cmap"),
        Spelling((0, 7), "cmaps[0]", "v0.7.0, #2597 'Mixed topology': mesh.geometry.cmaps list"),
        Spelling((0, 8), "cmap", "v0.8.0, #2954: mesh.geometry.cmap again"),
        Spelling((0, 11), "cmaps[0]", "v0.11.0, #4227: geometry.cmaps; cmap deprecated"),
    ),
    "petsc_vector": (
        Spelling(
            (0, 5), "Function.vector", "0.5-0.7: Function.vector wraps the dofs in a PETSc Vec"
        ),
        Spelling(
            (0, 8),
            "x.petsc_vec",
            "v0.8.0, #3092: Function.x.petsc_vec; Function.vector deprecated, removed in "
            "v0.9.0 (#3435)",
        ),
    ),
    "interpolation_points": (
        Spelling((0, 5), "method", "0.5-0.9: V.element.interpolation_points()"),
        Spelling(
            (0, 10), "property", "v0.10.0, #3542 'Add FiniteElement python wrapper': a property"
        ),
    ),
    "write_meshtags": (
        Spelling((0, 5), "tags", "0.5/0.6: XDMFFile.write_meshtags(tags)"),
        Spelling(
            (0, 7),
            "tags, geometry",
            "v0.7.0, #2522 'Wrap mesh tags from Python': write_meshtags(tags, geometry)",
        ),
    ),
    "gmsh_io": (
        Spelling(
            (0, 5),
            "gmshio",
            "0.5-0.9: dolfinx.io.gmshio.model_to_mesh -> (mesh, cell " "tags, facet tags)",
        ),
        Spelling(
            (0, 10),
            "io.gmsh MeshData",
            "v0.10.0 release notes, IO/GMSH (#3547, #3881): gmshio renamed dolfinx.io.gmsh, "
            "model_to_mesh returns a MeshData",
        ),
    ),
}


def parse_version(text: str) -> tuple[int, int]:
    """(major, minor) of a dolfinx version string ('0.10.0.post2' -> (0, 10))."""
    m = re.match(r"\s*v?(\d+)\.(\d+)", str(text))
    if m is None:
        raise ValueError(f"not a dolfinx version: {text!r}")
    return int(m[1]), int(m[2])


def branch(point: str, version: str | tuple[int, int]) -> str:
    """The spelling of API ``point`` in dolfinx ``version``: the newest one released by then."""
    v = parse_version(version) if isinstance(version, str) else tuple(version)
    if v < OLDEST:
        raise DolfinxMissing(
            f"dolfinx {v[0]}.{v[1]} is older than {OLDEST[0]}.{OLDEST[1]}, "
            f"the oldest slipstep.fenicsx supports: install a newer dolfinx"
        )
    chosen = [s.branch for s in SPELLINGS[point] if s.since <= v]
    return chosen[-1]


# --------------------------------------------------------------------------- loading
def hdf5_clash() -> str | None:
    """Debian's dolfinx beside an h5py that brings its own HDF5 (PyPI's wheel: a sibling
    ``h5py.libs``) cannot share a process: dolfinx leaves the dlopen flags at RTLD_GLOBAL, and
    an h5py loaded after it binds to Debian's HDF5 ("ValueError: Not a datatype").  The message
    naming the fix, or None."""
    from importlib.util import find_spec

    try:
        dolfinx, h5py = find_spec("dolfinx"), find_spec("h5py")
    except (ImportError, ValueError):  # not importable: the import below says how
        return None
    if not (dolfinx and h5py and dolfinx.origin and h5py.origin):
        return None
    bundled = Path(h5py.origin).parent.with_name("h5py.libs")
    if not (dolfinx.origin.startswith("/usr/lib/") and bundled.is_dir()):
        return None
    return (
        f"h5py in {Path(h5py.origin).parent.parent} brings its own HDF5 (from PyPI), which "
        f"clashes with the one Debian's dolfinx uses: use Debian's python3-h5py in this "
        f"venv (`pip uninstall h5py`, or ci/debian-h5py.sh VENV from a slipstep checkout, "
        f"which also keeps pip from installing it again)"
    )


_LOADED: SimpleNamespace | None = None


def require_dolfinx() -> SimpleNamespace:
    """Import dolfinx (with ``fem.petsc`` and ``io``), UFL, petsc4py and mpi4py once, check the
    version and that the run is serial; return them as a namespace.  Raises
    :class:`DolfinxMissing` naming the fix."""
    global _LOADED
    if _LOADED is None:
        _LOADED = _import()
    return _LOADED


def _import() -> SimpleNamespace:
    clash = hdf5_clash()
    if clash:
        raise DolfinxMissing(clash)
    try:
        from mpi4py import MPI  # first, as dolfinx's demos do: MPI before the bindings load

        import dolfinx
        import dolfinx.fem.petsc  # explicit since v0.7.0 (#2703): no branch needed
        import dolfinx.io
        import ufl as ufl_module
        from petsc4py import PETSc
    except ImportError as exc:
        raise DolfinxMissing(
            f"dolfinx is not available ({exc}): install Debian's "
            f"python3-dolfinx (make setup does) and use a venv made with "
            f"--system-site-packages"
        ) from None
    version = parse_version(dolfinx.__version__)
    branch("function_space", version)  # refuses < 0.5
    if version > NEWEST:
        warnings.warn(
            f"dolfinx {dolfinx.__version__} is newer than {NEWEST[0]}.{NEWEST[1]}, "
            f"the newest release slipstep.fenicsx was written for: its "
            f"{NEWEST[0]}.{NEWEST[1]} spellings are used",
            RuntimeWarning,
            stacklevel=3,
        )
    if MPI.COMM_WORLD.size != 1:
        raise RuntimeError("slipstep.fenicsx runs in serial only (one MPI process)")
    return SimpleNamespace(
        dolfinx=dolfinx,
        fem=dolfinx.fem,
        petsc=dolfinx.fem.petsc,
        io=dolfinx.io,
        ufl=ufl_module,
        PETSc=PETSc,
        MPI=MPI,
        version=version,
    )


def start_petsc():
    """PETSc for the MUMPS factorization backend (``[solver] factorization = "mumps"``, see
    :mod:`slipstep.ranks`): petsc4py started (MPI with it), dolfinx not imported.  Raises
    ImportError when petsc4py is missing."""
    import petsc4py

    petsc4py.init()
    from petsc4py import PETSc

    return PETSc


def _uses(point: str) -> str:
    """The branch of ``point`` for the loaded dolfinx."""
    return branch(point, require_dolfinx().version)


def ufl():
    """The UFL module (the same operators in every version this module supports)."""
    return require_dolfinx().ufl


# --------------------------------------------------------------------------- spaces, functions
def function_space(mesh, family: str, degree: int, shape: tuple = ()):
    """The space of ``family`` ('Lagrange', 'DG') elements of ``degree``, values of ``shape``
    (() scalar, (n,) vector, (n, m) tensor)."""
    fem = require_dolfinx().fem
    if _uses("function_space") == "functionspace":
        return fem.functionspace(mesh, (family, degree, tuple(shape)))
    if len(shape) == 0:
        return fem.FunctionSpace(mesh, (family, degree))
    if len(shape) == 1:
        return fem.VectorFunctionSpace(mesh, (family, degree), dim=shape[0])
    return fem.TensorFunctionSpace(mesh, (family, degree), shape=tuple(shape))


def function(V, name: str | None = None):
    """A zero Function on V."""
    return require_dolfinx().fem.Function(V, name=name)


def constant(mesh, value: float):
    """A Constant of the scalar type on ``mesh``."""
    return require_dolfinx().fem.Constant(mesh, scalar(value))


def scalar(value: float):
    """``value`` in the scalar type of PETSc and dolfinx."""
    d = require_dolfinx()
    if _uses("scalar_type") == "default_scalar_type":
        return d.dolfinx.default_scalar_type(value)
    return d.PETSc.ScalarType(value)


def space_of(func):
    return func.function_space


def mesh_of(V):
    return V.mesh


def dof_values(func) -> np.ndarray:
    """The Function's local dof values (a writable view; call :func:`scatter` after writing)."""
    return func.x.array


def scatter(func) -> None:
    func.x.scatter_forward()


def block_size(V) -> int:
    return int(V.dofmap.index_map_bs)


def dofs_per_cell(V) -> int:
    return int(V.dofmap.dof_layout.num_dofs)


def cell_dofs(V) -> np.ndarray:
    """(cells, dofs per cell) dof blocks of V, in dolfinx cell order."""
    dofs = V.dofmap.list
    if _uses("dofmap_list") == "AdjacencyList":
        dofs = dofs.array
    return np.asarray(dofs).reshape(-1, dofs_per_cell(V))


def dof_coordinates(V) -> np.ndarray:
    return V.tabulate_dof_coordinates()


def expression(ufl_expr, W):
    """``ufl_expr`` compiled for interpolation into W (at W's interpolation points)."""
    points = W.element.interpolation_points
    if _uses("interpolation_points") == "method":
        points = points()
    with quiet_compiler():
        return require_dolfinx().fem.Expression(ufl_expr, points)


def interpolate(func, expr) -> None:
    """func <- the interpolation of a compiled :func:`expression`."""
    func.interpolate(expr)


# --------------------------------------------------------------------------- forms, assembly
def compile_form(form):
    """A compiled form (``fem.form``); a form compiled already is returned as it is."""
    fem = require_dolfinx().fem
    compiled = fem.Form if _uses("compiled_form") == "Form" else fem.FormMetaClass
    if isinstance(form, compiled):
        return form
    with quiet_compiler():
        return fem.form(form)


class _WarningsOnly(logging.Filter):
    def filter(self, record: logging.LogRecord) -> bool:
        return record.levelno >= logging.WARNING


@contextlib.contextmanager
def quiet_compiler():
    """dolfinx compiles a new form with cffi through distutils, whose log is the root logger:
    it sets that logger to INFO and logs every compiler call, which ffcx's logging.basicConfig
    prints as ``INFO:root:...`` lines on a first run.  While compiling, the root logger passes
    warnings and errors only, and its level is restored after."""
    root = logging.getLogger()
    level, quiet = root.level, _WarningsOnly()
    root.addFilter(quiet)
    try:
        yield
    finally:
        root.removeFilter(quiet)
        root.setLevel(level)


def assemble_matrix(form):
    """The assembled PETSc matrix of a bilinear form (no boundary conditions)."""
    A = require_dolfinx().petsc.assemble_matrix(compile_form(form))
    A.assemble()
    return A


def assemble_vector(form) -> np.ndarray:
    """The assembled vector of a linear form, as a numpy array."""
    b = require_dolfinx().petsc.assemble_vector(compile_form(form))
    out = b.array.copy()
    b.destroy()
    return out


def assemble_scalar(form) -> float:
    return float(require_dolfinx().fem.assemble_scalar(compile_form(form)))


def locate_dofs(V, facets: np.ndarray, component: int | None = None) -> np.ndarray:
    """Dofs of V (unrolled; of its ``component`` sub-space if given) on the given facets, in
    dolfinx's integer type (what :func:`dirichletbc` takes)."""
    fem = require_dolfinx().fem
    sub = V if component is None else V.sub(component)
    fdim = V.mesh.topology.dim - 1
    return fem.locate_dofs_topological(sub, fdim, facets)


def dirichletbc(value: float, dofs: np.ndarray, V, component: int | None = None):
    """u = value (u_component = value if given) on ``dofs`` of V (from :func:`locate_dofs`)."""
    sub = V if component is None else V.sub(component)
    return require_dolfinx().fem.dirichletbc(scalar(value), dofs, sub)


def dirichlet_values(V, bcs) -> tuple[np.ndarray, np.ndarray]:
    """(dofs, values) the Dirichlet conditions ``bcs`` prescribe on V (unrolled dofs)."""
    d = require_dolfinx()
    probe = function(V)  # alive while its PETSc wrapper is used
    if _uses("petsc_vector") == "x.petsc_vec":
        x = probe.x.petsc_vec
    else:
        x = probe.vector
    x.set(np.nan)
    d.petsc.set_bc(x, list(bcs))
    values = x.array.copy()
    dofs = np.flatnonzero(~np.isnan(values))
    return dofs, values[dofs]


# --------------------------------------------------------------------------- PETSc algebra
def solve_constrained(A, rhs: np.ndarray, dofs: np.ndarray, values: np.ndarray) -> np.ndarray:
    """x with A x = rhs on the free dofs and x[dofs] = values, by symmetric elimination
    (MatZeroRowsColumns) and a direct LU solve (MUMPS)."""
    PETSc = require_dolfinx().PETSc
    Ac = A.copy()
    b, xb, x = A.createVecRight(), A.createVecRight(), A.createVecRight()
    b.array[:] = rhs
    xb.array[dofs] = values
    Ac.zeroRowsColumns(np.asarray(dofs, dtype=np.int32), 1.0, xb, b)
    ksp = PETSc.KSP().create(Ac.comm)
    ksp.setOperators(Ac)
    ksp.setType("preonly")
    ksp.getPC().setType("lu")
    ksp.getPC().setFactorSolverType("mumps")
    ksp.solve(b, x)
    reason = ksp.getConvergedReason()
    out = x.array.copy()
    destroy(ksp, Ac, b, xb, x)
    if reason < 0:
        raise RuntimeError(f"dolfinx: the linear solve failed (PETSc reason {reason})")
    return out


def matvec(A, x: np.ndarray) -> np.ndarray:
    """A x as a numpy array."""
    xv, y = A.createVecRight(), A.createVecLeft()
    xv.array[:] = x
    A.mult(xv, y)
    out = y.array.copy()
    destroy(xv, y)
    return out


def csr(A) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(indptr, indices, values) of a PETSc AIJ matrix."""
    return A.getValuesCSR()


def destroy(*objects) -> None:
    """Free PETSc objects now rather than at garbage collection."""
    for obj in objects:
        obj.destroy()


# --------------------------------------------------------------------------- mesh
def node_coordinates(mesh) -> np.ndarray:
    """(N, gdim) coordinates of the geometry nodes."""
    return mesh.geometry.x[:, : mesh.geometry.dim]


def cell_nodes(mesh) -> np.ndarray:
    """(cells, nodes per cell) geometry nodes of each cell, in dolfinx cell order."""
    geometry = mesh.geometry
    spelling = _uses("geometry_dofmap")
    if spelling == "dofmaps[0]":
        nodes = geometry.dofmaps[0]
    elif spelling == "dofmap":
        nodes = geometry.dofmap
    else:
        nodes = geometry.dofmap.array
    return np.asarray(nodes).reshape(num_cells(mesh), -1)


def num_cells(mesh) -> int:
    topology = mesh.topology
    return int(topology.index_map(topology.dim).size_local)


def mesh_kind(mesh) -> tuple[str, int, int]:
    """(cell name, geometry degree, geometric dimension): ('triangle', 1, 2) for affine 2D
    triangles."""
    geometry = mesh.geometry
    cmap = geometry.cmaps[0] if _uses("coordinate_element") == "cmaps[0]" else geometry.cmap
    return mesh.topology.cell_name(), int(cmap.degree), int(geometry.dim)


def facet_nodes(mesh, facets: np.ndarray) -> np.ndarray:
    """(F, 2) geometry nodes at the two vertices of each facet of a P1 triangle mesh; (F, 3) at
    the three of a P1 tetrahedron mesh's."""
    topology = mesh.topology
    tdim = topology.dim
    topology.create_connectivity(tdim - 1, 0)
    f2v = topology.connectivity(tdim - 1, 0)
    c2v = topology.connectivity(tdim, 0).array.reshape(-1, tdim + 1)
    geom_of_vertex = np.full(topology.index_map(0).size_local, -1, dtype=np.int64)
    geom_of_vertex[c2v.ravel()] = cell_nodes(mesh).ravel()
    vertices = np.array([f2v.links(f) for f in facets], dtype=np.int64).reshape(-1, tdim)
    return geom_of_vertex[vertices]


def input_node_index(mesh) -> np.ndarray:
    """(N,) index in the input file of each geometry node."""
    return np.asarray(mesh.geometry.input_global_indices, dtype=np.int64)


def input_cell_index(mesh) -> np.ndarray:
    """(M,) index in the input file of each cell."""
    return np.asarray(mesh.topology.original_cell_index, dtype=np.int64)


def tag_arrays(tags) -> tuple[np.ndarray, np.ndarray]:
    """(entity indices, values) of MeshTags."""
    return np.asarray(tags.indices), np.asarray(tags.values)


def tagged(tags, value: int) -> np.ndarray:
    """The entities of MeshTags carrying ``value``."""
    indices, values = tag_arrays(tags)
    return indices[values == value]


# --------------------------------------------------------------------------- files
def read_tagged_mesh(mesh_file, mesh_grid: str, facet_file, facet_grid: str):
    """(mesh, cell tags, facet tags) from XDMF: the mesh and its cell tags from grid
    ``mesh_grid`` of ``mesh_file``, the facet tags from grid ``facet_grid`` of ``facet_file``."""
    d = require_dolfinx()
    comm = d.MPI.COMM_WORLD
    with d.io.XDMFFile(comm, str(mesh_file), "r") as f:
        mesh = f.read_mesh(name=mesh_grid)
        cell_tags = f.read_meshtags(mesh, name=mesh_grid)
    tdim = mesh.topology.dim
    mesh.topology.create_connectivity(tdim - 1, tdim)  # needed before reading facet tags
    with d.io.XDMFFile(comm, str(facet_file), "r") as f:
        facet_tags = f.read_meshtags(mesh, name=facet_grid)
    return mesh, cell_tags, facet_tags


def write_tagged_mesh(path, mesh, tags: dict, mesh_name: str = "mesh") -> None:
    """One XDMF file: the mesh (grid ``mesh_name``) and each MeshTags of ``tags``
    (name -> MeshTags) as a grid of that name."""
    d = require_dolfinx()
    mesh.name = mesh_name
    with d.io.XDMFFile(mesh.comm, str(path), "w") as f:
        f.write_mesh(mesh)
        for name, meshtags in tags.items():
            meshtags.name = name
            if _uses("write_meshtags") == "tags, geometry":
                f.write_meshtags(meshtags, mesh.geometry)
            else:
                f.write_meshtags(meshtags)


def write_functions(path, mesh, frames) -> None:
    """One XDMF file: the mesh, then for each ``(time, functions)`` of ``frames`` (read as the
    file is written, so a generator may set the values) every function at that time."""
    d = require_dolfinx()
    with d.io.XDMFFile(mesh.comm, str(path), "w") as f:
        f.write_mesh(mesh)
        for time, functions in frames:
            for func in functions:
                f.write_function(func, time)


def mesh_from_gmsh(model, gdim: int = 2):
    """(mesh, cell tags, facet tags) of a meshed gmsh model (its physical groups)."""
    d = require_dolfinx()
    if _uses("gmsh_io") == "io.gmsh MeshData":
        from dolfinx.io import gmsh as gmsh_io

        data = gmsh_io.model_to_mesh(model, d.MPI.COMM_WORLD, 0, gdim=gdim)
        return data.mesh, data.cell_tags, data.facet_tags
    from dolfinx.io import gmshio

    return gmshio.model_to_mesh(model, d.MPI.COMM_WORLD, 0, gdim=gdim)
