"""The dolfinx adapter: one module holds every dolfinx call, its version dispatch follows the
release notes (a table written here from them, docs/dolfinx.md), and the spellings it picks
exist, undeprecated, in the dolfinx installed."""

from __future__ import annotations

import ast
import re
import warnings

import pytest

from conftest import ROOT
from slipstep.fenicsx import DolfinxMissing
from slipstep.fenicsx import dolfinx_api as api

#: FEniCSx's own packages: nowhere in slipstep but the adapter.  mpi4py too inside
#: slipstep.fenicsx (slipstep.sweep uses it for its process pool, which is no dolfinx call).
STACK = {"dolfinx", "ufl", "petsc4py", "basix", "ffcx"}

POINTS = (
    "function_space",
    "compiled_form",
    "scalar_type",
    "dofmap_list",
    "geometry_dofmap",
    "coordinate_element",
    "petsc_vector",
    "interpolation_points",
    "write_meshtags",
    "gmsh_io",
)
OLD = (
    "VectorFunctionSpace",
    "FormMetaClass",
    "PETSc.ScalarType",
    "AdjacencyList",
    "AdjacencyList",
    "cmap",
    "Function.vector",
    "method",
    "tags",
    "gmshio",
)
V07 = (
    "functionspace",
    "Form",
    "default_scalar_type",
    "array",
    "dofmap",
    "cmaps[0]",
    "Function.vector",
    "method",
    "tags, geometry",
    "gmshio",
)
V08 = V07[:5] + ("cmap", "x.petsc_vec") + V07[7:]
V10 = V08[:7] + ("property", "tags, geometry", "io.gmsh MeshData")
V11 = V10[:4] + ("dofmaps[0]", "cmaps[0]") + V10[6:]
#: version string -> the spelling of each of POINTS in that release (from its release notes)
EXPECTED = {
    "0.5.2": OLD,
    "0.6.0": OLD,
    "0.7.3": V07,
    "0.8.0": V08,
    "0.9.0": V08,
    "0.9.0.post1": V08,
    "0.10.0": V10,
    "0.10.0.post5": V10,
    "0.11.0": V11,
}


def _imported_modules(path):
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0:
            yield node.module


def test_only_the_adapter_imports_the_dolfinx_stack():
    bridge = [*(ROOT / "py/slipstep/fenicsx").glob("*.py"), ROOT / "examples/hybrid_hertz.py"]
    forbidden = {path: STACK | {"mpi4py"} for path in bridge}
    forbidden.update(
        {path: STACK for path in (ROOT / "py/slipstep").rglob("*.py") if path not in forbidden}
    )
    offenders = {
        f"{path.relative_to(ROOT)}: {name}"
        for path, stack in forbidden.items()
        if path.name != "dolfinx_api.py"
        for name in _imported_modules(path)
        if name.split(".")[0] in stack
    }
    assert not offenders, sorted(offenders)
    adapter = set(_imported_modules(ROOT / "py/slipstep/fenicsx/dolfinx_api.py"))
    assert {"dolfinx", "ufl", "petsc4py", "mpi4py"} <= {n.split(".")[0] for n in adapter}


@pytest.mark.parametrize("version", sorted(EXPECTED))
def test_dispatch_follows_the_release_notes(version):
    got = tuple(api.branch(point, version) for point in POINTS)
    assert dict(zip(POINTS, got)) == dict(zip(POINTS, EXPECTED[version]))


def test_the_table_covers_every_dispatched_point_and_cites_each_change():
    assert set(api.SPELLINGS) == set(POINTS)
    for point, spellings in api.SPELLINGS.items():
        assert spellings[0].since == api.OLDEST, point
        assert [s.since for s in spellings] == sorted({s.since for s in spellings}), point
        for s in spellings[1:]:  # every change names its release and a pull request
            assert re.search(rf"v{s.since[0]}\.{s.since[1]}\.0", s.note), (point, s.note)
            assert re.search(r"#\d{4}", s.note), (point, s.note)


@pytest.mark.parametrize(
    "text, parsed",
    [
        ("0.5.2", (0, 5)),
        ("0.10.0.post5", (0, 10)),
        ("0.9.0.dev0", (0, 9)),
        ("v0.8.0", (0, 8)),
        ("0.11.0rc1", (0, 11)),
        ("1.0.0", (1, 0)),
    ],
)
def test_versions_parse_to_major_minor(text, parsed):
    assert api.parse_version(text) == parsed


def test_newer_releases_take_the_newest_spellings_and_older_ones_are_refused():
    assert api.branch("gmsh_io", "0.12.0") == "io.gmsh MeshData"
    with pytest.raises(DolfinxMissing, match="older than 0.5"):
        api.branch("function_space", "0.4.1")
    with pytest.raises(ValueError, match="not a dolfinx version"):
        api.parse_version("main")


# --------------------------------------------------------------------------- installed dolfinx
def test_the_spellings_chosen_exist_in_the_installed_dolfinx():
    """Not a mock: the release picked by the parsed version has the attributes the branches
    use, and calling through the adapter raises no DeprecationWarning."""
    pytest.importorskip("dolfinx")
    import importlib.util

    d = api.require_dolfinx()
    fem, v = d.fem, d.version
    use = {point: api.branch(point, v) for point in POINTS}
    assert hasattr(
        fem,
        {"functionspace": "functionspace", "VectorFunctionSpace": "VectorFunctionSpace"}[
            use["function_space"]
        ],
    )
    assert hasattr(fem, use["compiled_form"])
    if use["scalar_type"] == "default_scalar_type":
        assert hasattr(d.dolfinx, "default_scalar_type")
    if use["petsc_vector"] == "x.petsc_vec":
        assert hasattr(d.dolfinx.la.Vector, "petsc_vec")
    else:
        assert hasattr(fem.Function, "vector")
    gmsh_module = "dolfinx.io.gmsh" if use["gmsh_io"] == "io.gmsh MeshData" else "dolfinx.io.gmshio"
    assert importlib.util.find_spec(gmsh_module) is not None
    mesh = d.dolfinx.mesh.create_unit_square(d.MPI.COMM_WORLD, 3, 2)
    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)
        V = api.function_space(mesh, "Lagrange", 1, (2,))
        assert api.cell_nodes(mesh).shape == (12, 3)
        assert api.cell_dofs(V).shape == (12, 3) and api.block_size(V) == 2
        assert api.mesh_kind(mesh) == ("triangle", 1, 2)
        W = api.function_space(mesh, "DG", 0, (3, 3))
        assert api.block_size(W) == 9 and api.cell_dofs(W).shape == (12, 1)
        f = api.function(api.function_space(mesh, "DG", 0))
        api.interpolate(f, api.expression(api.ufl().SpatialCoordinate(mesh)[0], api.space_of(f)))
        # DG0 interpolation evaluates at the centroid: the mean x of each cell's vertices
        x = api.node_coordinates(mesh)[api.cell_nodes(mesh)].mean(axis=1)[:, 0]
        assert abs(api.dof_values(f)[api.cell_dofs(api.space_of(f))[:, 0]] - x).max() < 1e-14
