"""The case schema as a JSON Schema (``slipstep keys --json-schema``, docs/case.schema.json),
checked by an independent validator (the ``jsonschema`` package): every shipped case is valid,
and what the case validator refuses by key or type (a misspelt key, a string for a number, an
unknown contact kind) an editor using the schema flags too."""

from __future__ import annotations

import copy
import json
import subprocess
import sys
import tomllib

import pytest

from conftest import CASES, ROOT

from slipstep import json_schema, schema

jsonschema = pytest.importorskip("jsonschema")


@pytest.fixture(scope="module")
def validator():
    return jsonschema.Draft202012Validator(json_schema.case_schema())


def test_the_committed_file_is_the_schema_the_code_makes():
    committed = (ROOT / "docs" / "case.schema.json").read_text()
    assert (
        committed == json_schema.text()
    ), "regenerate: slipstep keys --json-schema > docs/case.schema.json"
    out = subprocess.run(
        [sys.executable, "-m", "slipstep", "keys", "--json-schema"],
        capture_output=True,
        text=True,
        check=True,
    )
    assert out.stdout == committed
    jsonschema.Draft202012Validator.check_schema(json.loads(committed))


@pytest.mark.parametrize("path", sorted(CASES.glob("*.toml")), ids=lambda p: p.stem)
def test_every_shipped_case_is_valid(validator, path):
    errors = [e.message for e in validator.iter_errors(tomllib.loads(path.read_text()))]
    assert not errors, errors


def _broken(change) -> dict:
    data = tomllib.loads((CASES / "two_blocks.toml").read_text())
    change(data)
    return data


@pytest.mark.parametrize(
    "what, change",
    [
        ("misspelt solver key", lambda d: d.setdefault("solver", {}).update(group_tl=0.1)),
        ("string for a number", lambda d: d["body"][0]["material"].update(E="stiff")),
        ("unknown top-level table", lambda d: d.update(solvr={})),
        ("unknown contact kind", lambda d: d["contact"][0].update(kind="glue")),
        ("misspelt mesh key", lambda d: d["body"][0]["mesh"].update(hh=1.0)),
        ("boolean for a count", lambda d: d.setdefault("solver", {}).update(max_events=True)),
    ],
)
def test_what_the_validator_refuses_by_key_or_type_the_schema_flags(validator, what, change):
    assert list(validator.iter_errors(_broken(change))), what


def _broken_3d(change) -> dict:
    data = tomllib.loads((CASES / "mindlin_sphere_3d.toml").read_text())
    change(data)
    return data


@pytest.mark.parametrize(
    "what, change",
    [
        ("a plane in space", lambda d: d["analysis"].update(plane="strain")),
        ("a thickness in space", lambda d: d["analysis"].update(thickness=1.0)),
        ("an edge in space", lambda d: d["bc"][0].update(edge="bottom")),
        ("a 2D generator in space", lambda d: d["body"][1]["mesh"].update(generator="block")),
        ("a 2D contact kind in space", lambda d: d["contact"][0].update(kind="node_to_segment")),
        (
            "a point of two numbers in space",
            lambda d: d["body"][1]["mesh"].update(focus=[0.0, 0.0]),
        ),
    ],
)
def test_the_keys_of_the_plane_are_flagged_in_a_3d_case(validator, what, change):
    """Issue 38: the schema accepted 2D keys in a 3D case; the validator refuses each of them
    (tests/case/test_case_validation.py), and so does an editor now."""
    assert not list(validator.iter_errors(_broken_3d(lambda d: None)))
    assert list(validator.iter_errors(_broken_3d(change))), what


@pytest.mark.parametrize(
    "what, change",
    [
        ("a face in the plane", lambda d: d["bc"][0].update(face="bottom")),
        ("a 3D contact kind in the plane", lambda d: d["contact"][0].update(kind="rigid_plane")),
    ],
)
def test_the_keys_of_space_are_flagged_in_a_2d_case(validator, what, change):
    assert list(validator.iter_errors(_broken(change))), what


def test_solver_keys_carry_the_engines_defaults():
    """The [solver] keys are the engine's (rust/src/options.rs), default and meaning included."""
    from slipstep._engine import option_specs

    specs = {s["key"]: s for s in option_specs()}
    for branch in ("then", "else"):  # 3D, 2D
        solver = json_schema.case_schema()[branch]["properties"]["solver"]["properties"]
        assert set(solver) == set(specs) == set(schema.SOLVER_KEYS)
        for key, s in specs.items():
            assert solver[key]["default"] == s["default"]
            assert solver[key]["description"] == s["doc"]
