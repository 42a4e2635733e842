"""The case interface for load paths (issue 13): named loads, `displacement`, `motion`,
`[[stage]]`, path times, `--set stage...`, their errors, and the engine model they give.

Pure Python (no engine): ``parse_case`` and ``build_scene`` only.  The contract is
notes/stages_contract.md; the schema is documented in cases/README.md.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import CASES, MINIMAL, needs_gmsh, shipped_cases

from slipstep import schema
from slipstep.mesh import triangles as M
from slipstep.mesh import triangle_generators as generators
from slipstep.case import CaseError, load_case, parse_case
from slipstep.build import build_scene
from slipstep.loads.vectors import edge_load, hertz_cut_pressure

SOURCE = "cases/x.toml"

# MINIMAL: a 2 x 1 block (4 x 2 cells), bottom fixed, a rigid line above its top.
# STAGED: the same with three named loads and a rigid line that moves, in two stages.
LOADS = """
[[bc]]
name = "side"
body = "b"
edge = "right"
pressure = 2.0

[[bc]]
name = "push"
body = "b"
nodes = "corner_top_left"
displacement = {x = 0.01}

[[point_load]]
name = "poke"
at = [1.0, 1.0]
force = [0.0, -3.0]
"""
STAGED = (
    MINIMAL.replace("mu = 0.3", 'mu = 0.3\nname = "lid"\nmotion = [0.0, -0.1]')
    + LOADS
    + '\n[analysis]\nthickness = 2.0\n'
    '\n[[stage]]\nname = "first"\nfactors = {side = 1.0, lid = 0.5}\n'
    '\n[[stage]]\nfactors = {push = 1.0, side = -1.0}\n'
    '\n[[stage]]\nname = "last"\nfactors = {poke = 2.0}\n'
)


def error_of(text: str, overrides=(), build=False) -> str:
    """The one-line CaseError of parsing (and, with ``build``, building) a case."""
    with pytest.raises(CaseError) as info:
        case = parse_case(text, source=SOURCE, overrides=overrides)
        if build:
            build_scene(case)
    message = str(info.value)
    assert "\n" not in message, "errors must be one line"
    assert message.startswith((SOURCE, "--set")), message
    return message


# --------------------------------------------------------------------------- unchanged models
def old_fixed_dofs(scene) -> np.ndarray:
    """The supports as built before issue 13 (fix and symmetry components), verbatim."""
    dofs = []
    for bc in scene.case.data["bc"]:
        mesh = scene.meshes[bc["body"]]
        nodes = mesh.edge_nodes(bc["edge"]) if bc["edge"] else mesh.node_sets[bc["nodes"]]
        nodes = np.asarray(nodes, dtype=np.int64) + scene.offsets[bc["body"]]
        components = {"xy".index(c) for c in bc["fix"]}
        if bc["symmetry"]:
            n = M.outward_normals(scene.nodes, scene.global_edge(bc["body"], bc["edge"]))
            components.add(0 if np.all(np.abs(n[:, 0]) > 1 - 1e-9) else 1)
        dofs += [2 * nodes + c for c in sorted(components)]
    return np.unique(np.concatenate(dofs)).astype(np.int64) if dofs else np.zeros(0, dtype=np.int64)


def old_load_vector(scene) -> np.ndarray:
    """The summed load as built before issue 13 (bc, then [load], then point loads), verbatim."""
    data, n = scene.case.data, len(scene.nodes)
    t = data["analysis"]["thickness"]
    f = np.zeros(2 * n)
    for bc in data["bc"]:
        if bc["edge"] and (bc["pressure"] != 0.0 or bc["traction"] != [0.0, 0.0]):
            f += edge_load(
                scene.nodes,
                scene.global_edge(bc["body"], bc["edge"]),
                n,
                t,
                bc["pressure"],
                bc["traction"],
            )
    if data["load"] is not None:
        f += edge_load(
            scene.nodes,
            scene.global_edge(data["load"]["body"], "top"),
            n,
            t,
            pressure=hertz_cut_pressure(scene.case),
        )
    for pl in data["point_load"]:
        ids = np.concatenate(
            [
                np.arange(scene.meshes[b].n_nodes) + scene.offsets[b]
                for b in ([pl["body"]] if pl["body"] else scene.bodies)
            ]
        )
        node = ids[np.argmin(np.linalg.norm(scene.nodes[ids] - np.asarray(pl["at"]), axis=1))]
        f[2 * node : 2 * node + 2] += np.asarray(pl["force"]) * t
    return f


def assert_old_model(scene) -> None:
    """The model is exactly the pre-issue-13 one: same keys, same arrays bit for bit; beside
    them only the support groups whose reactions every increment records (issue 38), each
    [[bc]]'s DOFs, a DOF in the first that holds it."""
    m = scene.model
    assert set(m) == {
        "nodes",
        "triangles",
        "element_material",
        "materials",
        "plane",
        "thickness",
        "fixed_dofs",
        "load",
        "pairs",
        "options",
        "body_names",
        "element_body",
        "contact_names",
        "support_names",
        "support_dofs",
    }
    assert m["support_names"] == list(scene.support_dofs)
    groups = m["support_dofs"]
    for k, (name, dofs) in enumerate(zip(m["support_names"], groups)):
        earlier = np.concatenate([np.zeros(0, np.int64), *groups[:k]])
        assert np.array_equal(dofs, np.setdiff1d(scene.support_dofs[name], earlier)), name
    fixed, load = old_fixed_dofs(scene), old_load_vector(scene)
    assert m["fixed_dofs"].dtype == fixed.dtype and np.array_equal(m["fixed_dofs"], fixed)
    assert m["load"].dtype == load.dtype and m["load"].tobytes() == load.tobytes()
    snaps = scene.case.data["output"]["snapshots"]
    if snaps == "events":
        assert m["options"]["output"] == "events" and "times" not in m["options"]
    else:
        assert m["options"]["output"] == "fractions" and "times" not in m["options"]
        assert m["options"]["fractions"].tolist() == sorted(set(snaps) | {1.0})
    # the scene's load path of a one-stage case
    assert scene.load_names == ["load"] and scene.stage_names == ["stage 1"]
    assert scene.n_stages == 1 and scene.factors.tolist() == [[0.0], [1.0]]
    assert scene.prescribed == {} and scene.motions == {}
    held = [d for d in scene.support_dofs.values()]
    joined = np.unique(np.concatenate(held)) if held else np.zeros(0, dtype=np.int64)
    assert np.array_equal(joined, fixed)


# The planar and axisymmetric cases: the old model this test compares with had no third dimension
# (a 3D model is checked against its contract in tests/scene/test_scene_3d.py).
SHIPPED = shipped_cases(2)


@pytest.mark.parametrize("path", SHIPPED, ids=[p.stem for p in SHIPPED])
def test_shipped_cases_give_the_model_they_always_did(path):
    """Every shipped case without [[stage]], displacement and motion gives exactly the old
    model; one with them gives its stages (one row of factors per stage, `load` first).  The
    axisymmetric cases (issue 15) have no old model: ring loads and axis supports
    (test_axisymmetric_*.py)."""
    case = load_case(path)
    if any(
        b["mesh"].get("generator") in ("quarter_cylinder", "quarter_annulus")
        for b in case.data["body"]
    ):
        pytest.importorskip("gmsh")
    scene = build_scene(case)
    if not case.path.new:
        if case.data["analysis"]["plane"] != "axisymmetric":
            assert_old_model(scene)
        return
    stages = scene.model.get("stages", [])
    assert len(stages) == len(case.data["stage"]) and scene.n_stages == max(len(stages), 1)
    assert stages or scene.model["patterns"]
    assert all(len(s["factors"]) == len(scene.load_names) for s in stages)
    assert scene.model["options"]["output"] in ("events", "times")


def test_point_loads_and_fraction_snapshots_give_the_old_model_too():
    text = (
        MINIMAL
        + LOADS.split("[[bc]]\nname = \"push\"")[0]
        + "\n[[point_load]]\nat = [1.02, 0.49]\nforce = [0.5, -3.0]\n"
        "\n[[point_load]]\nat = [1.0, 0.5]\nforce = [0.25, 1.0]\n"
        "\n[analysis]\nthickness = 2.5\n\n[output]\nsnapshots = [0.25, 0.5]\n"
    )
    assert_old_model(build_scene(parse_case(text)))


# --------------------------------------------------------------------------- factors
def test_factors_carry_over_between_stages():
    """Each stage sets the loads it names; the others keep their factor; all start at 0."""
    scene = build_scene(parse_case(STAGED))
    assert scene.load_names == ["load", "side", "push", "poke", "lid"]
    assert scene.stage_names == ["first", "stage 2", "last"] and scene.n_stages == 3
    #                         load side  push poke lid
    assert scene.factors.tolist() == [
        [0.0, 0.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0, 0.5],
        [0.0, -1.0, 1.0, 0.0, 0.5],
        [0.0, -1.0, 1.0, 2.0, 0.5],
    ]
    stages = scene.model["stages"]
    assert [s["name"] for s in stages] == ["first", "", "last"]  # the engine names "stage 2"
    for s, row in zip(stages, scene.factors[1:]):
        assert s["factors"].dtype == np.float64 and np.array_equal(s["factors"], row)


def test_staged_model_layout():
    scene = build_scene(parse_case(STAGED))
    m, n = scene.model, 2 * len(scene.nodes)
    assert m["load"].shape == (n,) and not m["load"].any()  # no [load], no load named "load"
    side, push, poke, lid = m["patterns"]
    assert [p["name"] for p in m["patterns"]] == ["side", "push", "poke", "lid"]
    # forces at factor 1, thickness 2 included
    assert set(side) == {"name", "force"} and side["force"].shape == (n,)
    assert abs(side["force"][0::2].sum() + 2.0 * 1.0 * 2.0) <= 1e-12 * 4.0  # q L t, inwards
    assert set(poke) == {"name", "force"} and poke["force"][1::2].sum() == -6.0
    # the prescribed corner: its x only, never among the fixed DOFs
    corner = int(np.flatnonzero((scene.nodes == [0.0, 1.0]).all(axis=1))[0])
    assert set(push) == {"name", "displacement_dofs", "displacement_values"}
    assert push["displacement_dofs"].dtype == np.int64
    assert push["displacement_dofs"].tolist() == [2 * corner]
    assert push["displacement_values"].tolist() == [0.01]
    assert not np.isin(push["displacement_dofs"], m["fixed_dofs"]).any()
    # the moving rigid line: contact 0, [dx, dy]
    assert set(lid) == {"name", "motion_contacts", "motion"}
    assert lid["motion_contacts"].tolist() == [0] and lid["motion_contacts"].dtype == np.int64
    assert lid["motion"].shape == (1, 2) and lid["motion"].tolist() == [[0.0, -0.1]]
    # the scene's bookkeeping for the outputs
    assert scene.prescribed == {
        "push": {"dofs": push["displacement_dofs"], "values": push["displacement_values"]}
    }
    assert scene.motions == {"lid": {"contact": 0, "motion": [0.0, -0.1]}}
    assert set(scene.support_dofs) == {"bc 0", "push"}
    assert scene.support_dofs["push"].tolist() == [2 * corner]
    assert np.array_equal(scene.support_dofs["bc 0"], m["fixed_dofs"])


@needs_gmsh
def test_hertz_load_unload_puts_the_load_table_first():
    """[load] is the engine's `load` pattern; stages give its factor first."""
    text = (CASES / "hertz_cylinder.toml").read_text() + (
        '\n[[stage]]\nname = "load"\nfactors = {load = 1.0}\n'
        '\n[[stage]]\nname = "unload"\nfactors = {load = 0.0}\n'
    )
    scene = build_scene(parse_case(text))
    m = scene.model
    assert "patterns" not in m and [s["factors"].tolist() for s in m["stages"]] == [[1.0], [0.0]]
    assert m["load"].tobytes() == old_load_vector(scene).tobytes()
    assert scene.load_names == ["load"] and scene.stage_names == ["load", "unload"]
    # the file's snapshots [0.1 ... 1.0] are path times; the end of "unload" is added
    assert m["options"]["output"] == "times" and "fractions" not in m["options"]
    assert m["options"]["times"].tolist()[-2:] == [1.0, 2.0]


def test_a_force_bc_named_load_is_the_load_pattern():
    """two_blocks names its pressure "load": with stages it is the engine's `load`."""
    text = (CASES / "two_blocks.toml").read_text() + (
        '\n[[stage]]\nfactors = {load = 1.0}\n\n[[stage]]\nfactors = {load = 0.5}\n'
    )
    scene = build_scene(parse_case(text))
    assert scene.load_names == ["load"] and "patterns" not in scene.model
    assert scene.model["load"].tobytes() == old_load_vector(scene).tobytes()
    assert scene.factors[:, 0].tolist() == [0.0, 1.0, 0.5]


def test_without_stages_forces_are_summed_and_displacements_are_patterns():
    """No [[stage]]: `load` is the summed force (also of a bc that prescribes a displacement
    too); displacement and motion loads are patterns at factor 1, without force; no stages."""
    text = MINIMAL.replace("mu = 0.3", "mu = 0.3\nmotion = [0.0, -0.1]").replace(
        'fix = ["x", "y"]', 'fix = ["y"]'
    ) + LOADS.replace("pressure = 2.0", "pressure = 2.0\ndisplacement = {x = 0.0}")
    scene = build_scene(parse_case(text, overrides=["output.snapshots=[0.5]"]))
    m = scene.model
    assert "stages" not in m and m["load"].tobytes() == old_load_vector(scene).tobytes()
    assert [p["name"] for p in m["patterns"]] == ["side", "push", "contact 0"]
    assert all("force" not in p for p in m["patterns"])
    assert scene.load_names == ["load", "side", "push", "contact 0"]
    assert scene.factors.tolist() == [[0.0] * 4, [1.0] * 4]
    assert m["options"]["output"] == "times" and m["options"]["times"].tolist() == [0.5, 1.0]
    right = np.unique(scene.global_edge("b", "right"))
    assert scene.prescribed["side"]["dofs"].tolist() == (2 * right).tolist()
    assert scene.prescribed["side"]["values"].tolist() == [0.0] * len(right)


def test_snapshot_times_run_over_every_stage():
    case = parse_case(STAGED, overrides=["output.snapshots=[0.5, 2.25, 3.0]"])
    options = build_scene(case).model["options"]
    assert options["output"] == "times"
    assert options["times"].tolist() == [0.5, 1.0, 2.0, 2.25, 3.0]


def test_a_bc_with_only_a_displacement_is_valid():
    text = MINIMAL.replace('fix = ["x", "y"]', 'fix = ["x"]\ndisplacement = {y = 0.0}')
    scene = build_scene(parse_case(text))
    bottom = np.unique(scene.global_edge("b", "bottom"))
    assert scene.model["fixed_dofs"].tolist() == (2 * bottom).tolist()
    assert scene.model["patterns"][0]["displacement_dofs"].tolist() == (2 * bottom + 1).tolist()


def test_bcs_sharing_a_name_share_their_support_dofs():
    text = MINIMAL + '\n[[bc]]\nbody = "b"\nedge = "left"\nfix = ["x"]\n'
    text = text.replace('[[bc]]\nbody = "b"', '[[bc]]\nname = "wall"\nbody = "b"')
    scene = build_scene(parse_case(text))
    assert list(scene.support_dofs) == ["wall"]
    assert np.array_equal(scene.support_dofs["wall"], scene.model["fixed_dofs"])


# --------------------------------------------------------------------------- errors
def test_unknown_load_in_factors_lists_the_names():
    msg = error_of(STAGED, ["stage.last.factors.pokee=1.0"])
    assert msg == (
        f'{SOURCE}: stage.last.factors.pokee = 1.0 is not allowed: no load is named '
        f'"pokee" (loads: side, push, poke, lid); a load is named by its name key '
        f'([load] is "load")'
    )


def test_load_is_no_factor_name_when_there_is_no_load_pattern():
    msg = error_of(STAGED, ["stage.0.factors.load=1.0"])
    assert "stage.first.factors.load = 1.0 is not allowed" in msg
    assert "(loads: side, push, poke, lid)" in msg


def test_unnamed_load_with_stages_names_the_element():
    msg = error_of(STAGED.replace('name = "side"\n', ""))
    assert msg.startswith(
        f"{SOURCE}: bc.1 is a load without a name: with [[stage]] every load "
        f"needs one; add name = "
    )
    msg = error_of(STAGED.replace('name = "lid"\n', ""))
    assert "contact is a load without a name" in msg


def test_unnamed_supports_need_no_name_with_stages():
    case = parse_case(STAGED)  # MINIMAL's bottom support is unnamed
    assert case.data["bc"][0]["name"] == "" and case.path.staged


def test_duplicate_load_names():
    msg = error_of(STAGED.replace('name = "poke"', 'name = "side"'))
    assert msg.startswith(
        f'{SOURCE}: point_load.0.name = "side" is used twice (also by '
        f'bc.side): load names must be unique; rename one'
    )
    text = (CASES / "hertz_cylinder.toml").read_text() + (
        '\n[[point_load]]\nname = "load"\nat = [0.0, 125.0]\nforce = [0.0, -1.0]\n'
        '\n[[stage]]\nfactors = {load = 1.0}\n'
    )
    assert 'point_load.0.name = "load" is used twice (also by [load])' in error_of(text)


def test_duplicate_names_of_displacement_loads_without_stages():
    text = MINIMAL.replace('fix = ["x", "y"]', 'fix = ["y"]') + (
        '\n[[bc]]\nname = "p"\nbody = "b"\nnodes = "corner_top_left"\ndisplacement = {x = 0.1}\n'
        '\n[[bc]]\nname = "p"\nbody = "b"\nnodes = "corner_top_right"\n'
        'displacement = {x = 0.1}\n'
    )
    assert 'bc.2.name = "p" is used twice (also by bc.p)' in error_of(text)


def test_displacement_load_named_load_is_refused():
    text = (CASES / "two_blocks.toml").read_text()
    msg = error_of(text, ["bc.load.pressure=0.0", "bc.load.displacement.y=-0.01"])
    assert msg.startswith(
        f'{SOURCE}: bc.load.name = "load" is not allowed: "load" names the ' f"force pattern"
    )
    assert 'needs another name, e.g. "push"' in msg
    # renamed, it is a valid displacement-controlled punch
    case = parse_case(
        text,
        overrides=["bc.load.pressure=0.0", "bc.load.displacement.y=-0.01", "bc.load.name=push"],
    )
    assert case.path.names == ("load", "push")


def test_stage_that_changes_nothing():
    msg = error_of(STAGED, ["stage.last.factors.poke=0.0"])
    assert msg == (
        f"{SOURCE}: stage.last.factors changes nothing: every factor equals its value "
        f"at the end of the previous stage (all start at 0); give a factor that "
        f"changes, or remove the stage"
    )
    # repeating the values reached, or naming nothing, changes nothing either
    assert "stage.1.factors changes nothing" in error_of(STAGED, ["stage.1.factors={side = 1.0}"])
    assert "stage.first.factors changes nothing" in error_of(STAGED, ["stage.0.factors={}"])


def test_stage_needs_factors_and_unique_names():
    msg = error_of(STAGED.replace("factors = {poke = 2.0}", ""))
    assert "stage.last.factors is missing" in msg and "add `factors = ...`" in msg
    msg = error_of(STAGED, ["stage.2.name=first"])
    assert msg.startswith(
        f'{SOURCE}: stage.2.name = "first" is used twice (also by stage.0): '
        f"stage names must be unique"
    )


@pytest.mark.parametrize(
    "value, expected",
    [
        ('"one"', 'stage.last.factors.poke = "one" is not allowed: expected a number'),
        ("true", "stage.last.factors.poke = true is not allowed: expected a number"),
        ("[1.0]", "stage.last.factors.poke = [1.0] is not allowed: expected a number"),
        ("inf", "stage.last.factors.poke = inf is not allowed: expected a finite number"),
        ("nan", "stage.last.factors.poke = nan is not allowed: expected a finite number"),
    ],
)
def test_non_number_factor(value, expected):
    assert expected in error_of(STAGED, [f"stage.last.factors.poke={value}"])


def test_factors_must_be_an_inline_table():
    msg = error_of(STAGED, ["stage.last.factors=2.0"])
    assert "stage.last.factors = 2.0 is not allowed: expected an inline table of load names" in msg


@pytest.mark.parametrize(
    "value, expected",
    [
        (
            "{z = 1.0}",
            "bc.push.displacement.z is not allowed in a 2D case: z is the third component "
            "(set analysis.dimension = 3",
        ),
        (
            "{w = 1.0}",
            "bc.push.displacement.w is not allowed: a displacement has components x and y " "only",
        ),
        ("{}", "bc.push.displacement = {} is not allowed: give x and/or y"),
        ('{x = "a"}', 'bc.push.displacement.x = "a" is not allowed: expected a number'),
        ("{x = nan}", "bc.push.displacement.x = nan is not allowed: expected a finite number"),
        (
            "0.1",
            "bc.push.displacement = 0.1 is not allowed: expected an inline table of numbers x "
            "and/or y",
        ),
    ],
)
def test_bad_displacement_table(value, expected):
    assert expected in error_of(STAGED, [f"bc.push.displacement={value}"])


def test_displacement_on_a_fixed_component():
    msg = error_of(STAGED, ["bc.push.fix=['x']"])
    assert msg == (
        f"{SOURCE}: bc.push.displacement.x is not allowed: fix also holds x (at zero): "
        f'a component is fixed or prescribed, not both; remove "x" from fix or x from '
        f"displacement"
    )


def test_displacement_on_the_symmetry_component():
    """Known only with the mesh: the left edge's normal is x."""
    text = (
        STAGED + '\n[[bc]]\nname = "mirror"\nbody = "b"\nedge = "left"\nsymmetry = true\n'
        "displacement = {x = 0.02, y = 0.0}\n"
    )
    text = text.replace('fix = ["x", "y"]', 'fix = ["y"]').replace(
        'nodes = "corner_top_left"', 'nodes = "corner_top_right"'
    )
    msg = error_of(text, build=True)
    assert msg.startswith(
        f"{SOURCE}: bc.mirror.displacement.x: symmetry = true holds x on edge "
        f"'left' (its normal component)"
    )
    assert "remove symmetry or x from displacement" in msg


def test_a_component_held_by_two_bcs_at_a_shared_node():
    """The corner (0, 0) is fixed by the bottom support and prescribed by the left edge."""
    text = STAGED.replace('nodes = "corner_top_left"', 'edge = "left"')
    msg = error_of(text, build=True)
    assert msg.startswith(
        f"{SOURCE}: bc.push.displacement.x: node 0 (0, 0) is also held in x by "
        f"bc.0 (fix/symmetry)"
    )
    assert 'fix = ["x"]' in msg and "node set" in msg
    text = STAGED + (
        '\n[[bc]]\nname = "pull"\nbody = "b"\nnodes = "corner_top_left"\n'
        "displacement = {x = 0.5}\n\n[[stage]]\nfactors = {pull = 1.0}\n"
    )
    corner = generators.block(2.0, 1.0, 4, 2).node_sets["corner_top_left"][0]
    assert (
        f"bc.pull.displacement.x: node {corner} (0, 1) is also held in x by bc.push "
        f"(displacement)"
    ) in error_of(text, build=True)


def test_motion_on_a_deformable_pair():
    expected = (
        f"{SOURCE}: contact.motion is not allowed: motion on a deformable-pair contact "
        f'(kind "node_to_node"): motion moves a rigid obstacle; prescribe a displacement '
        f"[[bc]] on one of the bodies instead"
    )
    text = (CASES / "two_blocks.toml").read_text()
    assert error_of(text, ["contact.motion=[0.0, 0.1]"]) == expected
    assert error_of(text.replace("\nmu = 0.2", "\nmu = 0.2\nmotion = [0.0, 0.1]")) == expected


def test_snapshot_times_beyond_the_last_stage():
    msg = error_of(STAGED, ["output.snapshots=[0.5, 3.5]"])
    assert msg == (
        f"{SOURCE}: output.snapshots = [0.5, 3.5] is not allowed: every snapshot time "
        f"must lie in (0, 3] (stage k runs over path time t in [k-1, k])"
    )
    msg = error_of(STAGED, ["output.snapshots=[2.5, 1.5]"])
    assert "the snapshot times must be strictly increasing" in msg
    # one stage: the words of a load fraction, as always
    assert "every load fraction must lie in (0, 1]" in error_of(
        MINIMAL, ["output.snapshots=[0.5, 1.5]"]
    )


def test_prescribed_dofs_count_as_held_for_contact_pairs():
    """A pair whose normal component is prescribed can carry no contact force."""
    text = MINIMAL.replace('fix = ["x", "y"]', 'fix = ["x"]\ndisplacement = {y = 0.0}')
    text = text.replace(
        'edge = "top"\npoint = [0.0, 2.0]\nnormal = [0.0, -1.0]',
        'edge = "bottom"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]',
    )
    msg = error_of(text, build=True)
    assert "contact: node 0 (0, 0) is held by supports" in msg and "displacement" in msg


# --------------------------------------------------------------------------- --set
def test_set_reaches_stage_factors_by_name_and_index():
    case = parse_case(
        STAGED,
        overrides=[
            "stage.last.factors.poke=4.0",
            "stage.1.factors.lid=0.0",
            "stage.first.name=up",
            "bc.push.displacement.y=0.5",
        ],
    )
    assert case.data["stage"][2]["factors"] == {"poke": 4.0}
    assert case.data["stage"][1]["factors"] == {"push": 1.0, "side": -1.0, "lid": 0.0}
    assert case.path.stage_names == ("up", "stage 2", "last")
    assert case.path.factors[-1] == (0.0, -1.0, 1.0, 4.0, 0.0)
    assert case.data["bc"][2]["displacement"] == {"x": 0.01, "y": 0.5}


def test_set_replaces_a_whole_factors_table_and_a_single_stage_needs_no_index():
    text = MINIMAL + LOADS + '\n[[stage]]\nfactors = {side = 1.0}\n'
    case = parse_case(text, overrides=["stage.factors={side = 0.5, poke = 1.0}"])
    assert case.data["stage"][0]["factors"] == {"side": 0.5, "poke": 1.0}
    case = parse_case(text, overrides=["stage.factors.push=2"])
    assert case.data["stage"][0]["factors"] == {"side": 1.0, "push": 2.0}


def test_set_errors_on_stages():
    with pytest.raises(
        CaseError,
        match=r"--set stage.3.factors.poke=1: \[\[stage\]\] has 3 " r"entries: use an index 0..2",
    ):
        parse_case(STAGED, overrides=["stage.3.factors.poke=1"])
    with pytest.raises(
        CaseError,
        match=r"unknown key 'factor.poke' in \[\[stage\]\]; valid " r"keys: name, factors",
    ):
        parse_case(STAGED, overrides=["stage.last.factor.poke=1"])
    with pytest.raises(CaseError, match=r"the case has no \[\[stage\]\] entry to change"):
        parse_case(MINIMAL, overrides=["stage.factors.load=1"])
    with pytest.raises(CaseError, match=r"unknown key 'factors.poke.x' in \[\[stage\]\]"):
        parse_case(STAGED, overrides=["stage.last.factors.poke.x=1"])


# --------------------------------------------------------------------------- documentation
def test_readme_documents_the_load_path():
    readme = (CASES / "README.md").read_text()
    for key in [
        *schema.STAGE_KEYS,
        "displacement",
        "motion",
        "[[stage]]",
        "path time",
        "stage.<name or index>.factors.<LOAD>",
    ]:
        assert f"`{key}`" in readme or key in readme, key
    # every error above has its line in the README's table
    for words in (
        "no load is named",
        "is a load without a name",
        "is used twice",
        "changes nothing",
        "expected a number",
        "components x and y only",
        "fix also holds",
        "symmetry = true holds",
        "is also held in x by",
        "deformable-pair contact",
        "every snapshot time must lie in",
    ):
        assert words in readme, words


# --------------------------------------------------------------------------- robustness
LITERALS = [
    "1.0",
    "-2",
    "0",
    "nan",
    "inf",
    "true",
    '"one"',
    "[1.0, 2.0]",
    "{}",
    "{x = 1.0}",
    "{y = -0.5, x = 0.0}",
    "{z = 1.0}",
    "{load = 1.0}",
    "{side = 0.0, lid = 1.0}",
    "{push = nan}",
    '{poke = "a"}',
    "[0.5, 1.5]",
    "[2.5, 3.0]",
    "events",
    "[]",
]
PLACES = [
    "stage.0.factors",
    "stage.1.factors.side",
    "stage.last.factors.lid",
    "stage.last.factors.load",
    "stage.2.name",
    "stage.first.factors.push",
    "bc.push.displacement",
    "bc.push.displacement.y",
    "bc.side.displacement.x",
    "bc.0.fix",
    "bc.side.name",
    "point_load.name",
    "contact.motion",
    "contact.name",
    "output.snapshots",
    "bc.push.nodes",
]


def test_random_load_path_overrides_give_a_model_or_one_case_error():
    """Any --set of the load-path keys: a model, or a one-line CaseError (never another
    exception)."""
    hypothesis = pytest.importorskip("hypothesis")
    st = hypothesis.strategies
    pair = st.tuples(st.sampled_from(PLACES), st.sampled_from(LITERALS))

    @hypothesis.settings(max_examples=200, deadline=None, database=None)
    @hypothesis.given(st.lists(pair, max_size=3))
    def check(sets):
        overrides = [f"{k}={v}" for k, v in sets]
        try:
            build_scene(parse_case(STAGED, source=SOURCE, overrides=overrides))
        except CaseError as exc:
            assert "\n" not in str(exc) and str(exc).startswith((SOURCE, "--set")), str(exc)

    check()
