"""The 3D engine model (docs/engine_api.md, "3D models (dimension = 3)") that a case with
[analysis] dimension = 3 builds: its keys, shapes and dtypes checked against the contract as
written there, its supports (fix, symmetry planes, prescribed displacements) and its loads
(consistent nodal forces of pressures and tractions on faces: resultant p A and first moment
p int x dA recomputed here; [load] P on a sphere's portion).  The engine that runs it does not
exist yet: what is checked is what it will be given."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import needs_gmsh

from slipstep.build import build_scene
from slipstep.case import parse_case
from slipstep.errors import CaseError
from slipstep.mesh.tetrahedra import triangle_normals
from space3d import BOX, SPHERE, assert_contract


def box_scene(extra: str = "", sets=()):
    return build_scene(parse_case(BOX + extra, "box3.toml", overrides=list(sets)))


def test_the_box_model_meets_the_contract():
    scene = box_scene()
    assert_contract(scene.model)
    assert scene.n_dofs == 3 * len(scene.nodes)
    base = np.flatnonzero(scene.nodes[:, 2] == 0.0)
    assert set(scene.model["fixed_dofs"]) == {3 * i + c for i in base for c in range(3)}


def test_pressure_and_traction_on_a_face_are_consistent_nodal_loads():
    """Resultant p A and first moment int x p dA of the nodal forces, against the box's top
    face computed here (2 x 1 at z = 1): consistent, not lumped, loads reproduce both."""
    scene = box_scene(
        '[[bc]]\nbody = "b"\nface = "top"\npressure = 3.0\ntraction = [0.5, 0.0, 0.0]\n'
    )
    f = scene.model["load"].reshape(-1, 3)
    assert np.allclose(f.sum(axis=0), [0.5 * 2.0, 0.0, -3.0 * 2.0], rtol=1e-14, atol=1e-13)
    # moment about the y axis of the pressure: int x (-p) dA = -p * 2 * 1 (centroid x = 1)
    assert math.isclose((scene.nodes[:, 0] * f[:, 2]).sum(), -3.0 * 2.0 * 1.0, rel_tol=1e-13)
    # on a node of the top face's middle, 6 triangles of area 1/8 around it... each gives A/3
    top = scene.global_boundary("b", "top")
    _, area = triangle_normals(scene.nodes, top)
    node = np.flatnonzero((scene.nodes == [1.0, 0.5, 1.0]).all(axis=1))[0]
    share = area[(top == node).any(axis=1)].sum() / 3.0
    assert math.isclose(f[node, 2], -3.0 * share, rel_tol=1e-13)


@needs_gmsh
def test_a_pressure_on_a_curved_face_sums_to_minus_p_times_its_vector_area():
    """int n dA over a closed boundary vanishes, so the sphere's face carries -p times minus the
    vector area of the flat faces closing it: -p (-A_top e_z + A_x e_x + A_y e_y), each flat
    area recomputed here from its triangles."""
    text = (
        SPHERE.replace("[load]\nP = 30.0\n", "")
        + '[[bc]]\nbody = "sphere"\nface = "surface"\npressure = 2.0\n'
    )
    scene = build_scene(parse_case(text, "s.toml"))
    vector = np.zeros(3)
    for tag in ("top", "symmetry_x", "symmetry_y"):
        n, area = triangle_normals(scene.nodes, scene.global_boundary("sphere", tag))
        vector -= n.T @ area  # the surface's vector area
    f = scene.model["load"].reshape(-1, 3).sum(axis=0)
    assert np.allclose(f, -2.0 * vector, rtol=1e-12, atol=1e-9 * np.abs(vector).max())
    assert f[2] > 0 and f[0] < 0 and f[1] < 0  # pushes the eighth up and towards the axes


@needs_gmsh
@pytest.mark.parametrize("portion, share", [("eighth", 0.25), ("quarter", 0.5), ("half", 1.0)])
def test_load_P_gives_each_portion_its_share(portion, share):
    sets = [f"mesh.portion={portion}"]
    text = SPHERE
    if portion != "eighth":  # no symmetry_x face: hold that bc on the cut instead
        sets += ["bc.0.face=top", "bc.0.symmetry=false", 'bc.0.fix=["x"]']
    if portion == "half":
        sets += ["bc.1.face=top", "bc.1.symmetry=false", 'bc.1.fix=["y"]']
    scene = build_scene(parse_case(text, "s.toml", overrides=sets))
    assert_contract(scene.model)
    f = scene.model["load"].reshape(-1, 3)
    assert np.allclose(f.sum(axis=0), [0.0, 0.0, -30.0 * share], atol=1e-12)
    top = scene.global_boundary("sphere", "top")
    assert (f[np.setdiff1d(np.arange(len(f)), top)] == 0.0).all()  # on the cut only
    ref = scene.reference
    a = (3 * 30.0 * 10.0 / (4 * 70000.0 / (1 - 0.09))) ** (1 / 3)
    assert math.isclose(ref["a_hertz"], a, rel_tol=1e-12)
    assert math.isclose(ref["p0_hertz"], 3 * 30.0 / (2 * math.pi * a**2), rel_tol=1e-12)


@needs_gmsh
def test_symmetry_planes_hold_their_normal_component():
    scene = build_scene(parse_case(SPHERE, "s.toml"))
    fixed = set(scene.model["fixed_dofs"].tolist())
    for c, tag in ((0, "symmetry_x"), (1, "symmetry_y")):
        ids = np.unique(scene.global_boundary("sphere", tag))
        assert {3 * i + c for i in ids} <= fixed
        assert not any(3 * i + 2 in fixed for i in ids)  # z stays free
    assert len(fixed) == sum(
        len(np.unique(scene.global_boundary("sphere", t))) for t in ("symmetry_x", "symmetry_y")
    )


@needs_gmsh
def test_symmetry_on_a_curved_face_is_refused():
    with pytest.raises(
        CaseError,
        match=r"bc.0.symmetry: face 'surface' is not a plane parallel " r"to a coordinate plane",
    ):
        build_scene(parse_case(SPHERE, "s.toml", overrides=["bc.0.face=surface"]))


def test_prescribed_displacements_and_point_loads_in_3d():
    extra = """
[[bc]]
name = "push"
body = "b"
face = "top"
displacement = {z = -0.01, x = 0.002}
[[point_load]]
name = "poke"
at = [2.0, 1.0, 1.0]
force = [0.0, 5.0, 0.0]
"""
    scene = box_scene(extra)
    assert_contract(scene.model)
    push = scene.prescribed["push"]
    top = np.unique(scene.global_boundary("b", "top"))
    assert set(push["dofs"]) == {3 * i + c for i in top for c in (0, 2)}
    assert set(np.round(push["values"], 12)) == {-0.01, 0.002}
    f = scene.model["load"].reshape(-1, 3)
    corner = np.flatnonzero((scene.nodes == [2.0, 1.0, 1.0]).all(axis=1))[0]
    assert (f[corner] == [0.0, 5.0, 0.0]).all() and f.sum() == 5.0


def test_the_case_keys_of_the_other_dimension_are_one_line_each():
    def error(extra="", sets=()):
        with pytest.raises(CaseError) as info:
            box_scene(extra, sets)
        return str(info.value)

    assert error(sets=["analysis.thickness=2"]) == (
        "box3.toml: analysis.thickness = 2 is not allowed in a 3D case (analysis.dimension = 3)"
        ": a body in space has no out-of-plane thickness (forces are forces); remove "
        "analysis.thickness"
    )
    assert "bc.edge = \"top\" is not allowed in a 3D case" in error(sets=["bc.edge=top"])
    assert "use face = \"top\"" in error(sets=["bc.edge=top"])
    line = error(sets=["bc.fix=[\"x\", \"y\"]", "analysis.dimension=2", "bc.face=bottom"])
    assert line.startswith(
        "box3.toml: mesh.generator = \"box\" is not allowed in a 2D case: it "
        "is a 3D generator; set analysis.dimension = 3, or use \"block\""
    )
    assert "give three components [x, y, z]" in error(
        '[[point_load]]\nat = [0.0, 0.0]\n' 'force = [1.0, 0.0]\n'
    )


def test_a_given_tetrahedron_mesh_from_python():
    """generator = "given" in 3D: the mesh comes from slipstep.from_tetrahedra (a 2D mesh is
    refused for a 3D case, and a missing one names the function)."""
    import slipstep
    from slipstep.mesh.tetrahedron_generators import box

    text = BOX.replace(
        'generator = "box"\nwidth = 2.0\ndepth = 1.0\nheight = 1.0\nnx = 4\n' 'ny = 2\nnz = 2',
        'generator = "given"',
    )
    grid = box(2.0, 1.0, 1.0, 2, 1, 1)
    mesh = slipstep.from_tetrahedra(grid.nodes, grid.tetrahedra, grid.faces)
    scene = build_scene(parse_case(text, "g.toml"), {"b": mesh})
    assert_contract(scene.model)
    assert scene.given_meshes == ("b",) and len(scene.tetrahedra) == 12
    with pytest.raises(CaseError, match=r"pass its mesh from Python.*slipstep.from_tetrahedra"):
        build_scene(parse_case(text, "g.toml"))
    flat = slipstep.from_arrays([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]])
    with pytest.raises(slipstep.InputError, match="the mesh given for 'b' is 2D, the case 3D"):
        build_scene(parse_case(text, "g.toml"), {"b": flat})
