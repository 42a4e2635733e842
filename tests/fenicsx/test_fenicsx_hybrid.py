"""Hybrid mode: slipstep's event loop on a user's dolfinx model, Functions back."""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest

from conftest import ROOT, needs_gmsh
from slipstep import prepare
from slipstep.fenicsx.crosscheck import engine_result

pytest.importorskip("dolfinx")
from slipstep.fenicsx import dolfinx_api as api  # noqa: E402
from slipstep.fenicsx.exchange import scene_to_dolfinx  # noqa: E402
from slipstep.fenicsx.hybrid import solve_contact  # noqa: E402

E, NU = 70000.0, 0.3


def _user_model(dm, E_form=E, bc_value=0.0):
    """What a dolfinx user writes: P1 space, elasticity forms, pressure 4 MPa on `top`,
    symmetry on x = 0."""
    ufl, mesh = api.ufl(), dm.mesh
    V = api.function_space(mesh, "Lagrange", 1, (2,))
    mu, lam = E_form / (2 * (1 + NU)), E_form * NU / ((1 + NU) * (1 - 2 * NU))
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)

    def eps(w):
        return ufl.sym(ufl.grad(w))

    a = ufl.inner(2 * mu * eps(u) + lam * ufl.tr(eps(u)) * ufl.Identity(2), eps(v)) * ufl.dx
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=dm.facet_tags)
    L = ufl.dot(-4.0 * ufl.FacetNormal(mesh), v) * ds(dm.edge_id("top"))
    dofs = api.locate_dofs(V, dm.facets("symmetry"), component=0)
    bc = api.dirichletbc(bc_value, dofs, V, component=0)
    return V, a, L, [bc], ds


@pytest.fixture(scope="module")
def hertz(tmp_path_factory):
    scene = prepare(None, ["contact.mu=0.2", "mesh.h_contact=0.15"])
    dm = scene_to_dolfinx(scene, tmp_path_factory.mktemp("hybrid"))
    return scene, dm


@needs_gmsh
def test_hybrid_on_the_exchanged_mesh_equals_slipstep(hertz):
    scene, dm = hertz
    V, a, L, bcs, ds = _user_model(dm)
    out = solve_contact(V, a, L, dm.facet_tags, dm.edge_id("arc"), E=E, nu=NU, bcs=bcs, mu=0.2)
    assert out.operator_difference < 1e-12  # the user's form is the CST operator
    result, _ = engine_result(scene)
    snap = result["snapshots"][-1]
    # dolfinx numbering -> slipstep numbering through the exchange's node map
    u = dm.vector_function_values(out.u)
    assert np.abs(u - snap["u"]).max() < 1e-8 * np.abs(snap["u"]).max()  # measured 7e-14
    assert len(out.result["events"]["kind"]) == len(result["events"]["kind"])
    # the pressure Function integrates to the total normal force (= P/2 = 500 N/mm)
    force = api.assemble_scalar(out.pressure * ds(dm.edge_id("arc")))
    assert force == pytest.approx(out.result["snapshots"][-1]["lambda_n"].sum(), rel=1e-12)
    assert force == pytest.approx(500.0, rel=1e-9)
    # nodal pressure equals slipstep's per pair (pairs matched by node)
    geom = dm.geom_of_node[scene.model["pairs"]["node_a"]]
    order = np.argsort(out.contact_nodes)
    k = order[np.searchsorted(out.contact_nodes[order], geom)]
    p_engine = snap["lambda_n"] / scene.pair_length
    assert (
        np.abs(
            out.result["snapshots"][-1]["lambda_n"][k] / out.tributary_length[k] - p_engine
        ).max()
        < 1e-8 * p_engine.max()
    )


@needs_gmsh
def test_a_form_with_another_material_is_refused(hertz):
    _, dm = hertz
    V, a, L, bcs, _ = _user_model(dm, E_form=2 * E)
    with pytest.raises(ValueError, match="not the plane-strain CST elasticity operator"):
        solve_contact(V, a, L, dm.facet_tags, dm.edge_id("arc"), E=E, nu=NU, bcs=bcs)


def test_an_axisymmetric_plane_is_refused_before_any_work():
    # the operator check compares with a planar CST, so an axisymmetric form would be refused
    # with a misleading message, or (check_operator=False) solved as the wrong element
    with pytest.raises(ValueError, match="plane = 'axisymmetric' is not supported"):
        solve_contact(None, None, None, None, 1, E=E, nu=NU, plane="axisymmetric")


@needs_gmsh
def test_inhomogeneous_dirichlet_is_refused(hertz):
    _, dm = hertz
    V, a, L, bcs, _ = _user_model(dm, bc_value=0.1)
    with pytest.raises(ValueError, match="homogeneous"):
        solve_contact(V, a, L, dm.facet_tags, dm.edge_id("arc"), E=E, nu=NU, bcs=bcs)


@needs_gmsh
def test_the_example_runs(tmp_path):
    spec = importlib.util.spec_from_file_location(
        "hybrid_hertz", ROOT / "examples" / "hybrid_hertz.py"
    )
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    s = mod.main(["--h-contact", "0.2", "--out", str(tmp_path)])
    assert s["force_from_pressure"] == pytest.approx(500.0, rel=1e-9)
    assert s["outermost_closed_x"] == pytest.approx(s["a_hertz"], rel=0.2)
    assert s["operator_check"] < 1e-12
    assert (tmp_path / "hybrid_hertz.xdmf").exists()
