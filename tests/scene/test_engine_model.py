"""The engine model's records (slipstep.engine_model) against what the binding reads: the keys
bindings/src/lib.rs reads, parsed from its source, are the records' fields, record by record
(so a key added or dropped on either side alone fails here); and a built scene's
``scene.model`` is its ``engine_model.to_engine()``, which the engine runs."""

from __future__ import annotations

import re
from dataclasses import fields, replace
from pathlib import Path

import numpy as np
import pytest
from conftest import MINIMAL, needs_gmsh

from slipstep.build import build_scene
from slipstep.case import parse_case
from slipstep.engine_model import (
    ContactPairs,
    EngineMaterial,
    EngineModel,
    LoadPattern,
    Stage,
)
from space3d import BOX

BINDING = Path(__file__).resolve().parents[2] / "bindings" / "src" / "lib.rs"

#: Per function of the binding, the record each dict variable it reads is: ``d`` the model,
#: ``p`` its pairs (a pattern in read_path), ``m`` a material, ``s`` a stage, ``o`` the options.
READERS = {
    "read_scene": {"d": "model"},
    "read_materials": {"d": "model", "m": "material"},
    "read_model": {"d": "model", "p": "pairs"},
    "read_plane": {"d": "model"},
    "read_tangents": {"p": "pairs"},
    "read_pair_weights": {"p": "pairs"},
    "read_path": {"d": "model", "p": "pattern", "s": "stage"},
    "read_options": {"d": "model", "o": "options"},
    "read_names": {"d": "model"},
}

#: The readers of one key: the binding's helpers (key after the dict), ``x.get_item("key")``,
#: and the closures over the model of read_names (``strings``) and read_path (``list``).
KEYED = re.compile(r"\b(?:get|f64_2d|f64_1d|i64_1d|index_rows::<\d+>|optional)\(&?(\w+), \"(\w+)\"")
GET_ITEM = re.compile(r"\b(\w+)\.get_item\(\"(\w+)\"\)")
CLOSURE = re.compile(r"\b(?:strings|list)\(\"(\w+)\"\)")
REFUSED = re.compile(r"refuse\(\s*&\[([^\]]*)\]")


def functions(source: str) -> dict[str, str]:
    """The binding's top-level functions by name (their text up to the next one)."""
    starts = [(m.start(), m.group(1)) for m in re.finditer(r"^(?:pub )?fn (\w+)", source, re.M)]
    ends = [s for s, _ in starts[1:]] + [len(source)]
    return {name: source[start:end] for (start, name), end in zip(starts, ends)}


def keys_read() -> dict[str, set[str]]:
    """Record -> the keys the binding reads of it; a read in a function or on a variable that
    :data:`READERS` does not name fails (a new reader must be placed)."""
    out: dict[str, set[str]] = {}
    for name, body in functions(BINDING.read_text()).items():
        reads = KEYED.findall(body) + GET_ITEM.findall(body)
        reads += [("d", k) for k in CLOSURE.findall(body)]
        for keys in REFUSED.findall(body):
            reads += [("d", k) for k in re.findall(r"\"(\w+)\"", keys)]
        if name == "solve":  # the result's own "stop" entry, not the model
            reads = [r for r in reads if r != ("out", "stop")]
        for var, key in reads:
            record = READERS.get(name, {}).get(var)
            assert record, f"lib.rs {name}: reads {var}[{key!r}]; name its record in READERS"
            out.setdefault(record, set()).add(key)
    return out


def field_names(record) -> set[str]:
    return {f.name for f in fields(record)}


@pytest.fixture(scope="module")
def read():
    return keys_read()


def test_the_parser_sees_the_keys_it_should(read):
    # guards against a vacuous pass: keys known to be read, in each record
    assert {"nodes", "pairs", "dimension", "tetrahedra"} <= read["model"]
    assert {"mu", "node_a", "weight_value", "tangent"} <= read["pairs"]
    assert read["material"] == {"E", "nu", "Sy", "H"}


@pytest.mark.parametrize(
    "record, name",
    [
        (EngineModel, "model"),
        (ContactPairs, "pairs"),
        (EngineMaterial, "material"),
        (LoadPattern, "pattern"),
        (Stage, "stage"),
    ],
)
def test_each_record_has_a_field_for_every_key_the_engine_reads_and_no_other(read, record, name):
    assert field_names(record) == read[name]


def test_the_options_keys_the_binding_names_are_the_snapshot_request(read):
    # every other option key is read through slipstep_core::options::SPECS: the options
    # stay a dict, checked by the engine and slipstep.schema's [solver] table
    assert read["options"] == {"output", "times", "fractions"}


@needs_gmsh
def test_a_2d_scene_model_is_its_record_without_dimension():
    scene = build_scene(parse_case(MINIMAL, "minimal.toml"))
    model = scene.engine_model
    assert model.dimension == 2 and model.plane == "strain"
    assert "dimension" not in scene.model and "tetrahedra" not in scene.model
    assert scene.model["triangles"] is model.triangles is scene.triangles
    assert scene.model["pairs"]["mu"] is model.pairs.mu
    assert scene.model["materials"] == [m.to_engine() for m in model.materials]
    given = {f for f in field_names(EngineModel) if getattr(model, f) is not None}
    assert set(scene.model) == given - {"dimension"}


@needs_gmsh
def test_a_3d_scene_model_names_its_dimension_and_runs():
    from slipstep import solve

    scene = build_scene(parse_case(BOX, "box3.toml"))
    model = scene.engine_model
    assert model.dimension == scene.model["dimension"] == 3
    assert model.elements is model.tetrahedra is scene.model["tetrahedra"]
    assert {"plane", "thickness", "triangles"}.isdisjoint(scene.model)
    assert scene.model["pairs"]["tangent"] is model.pairs.tangent is scene.pair_tangent
    assert solve(scene)["stop"]["kind"] == "completed"


def test_a_model_without_the_elements_of_its_dimension_is_refused():
    pairs = ContactPairs(
        node_a=np.zeros(0, np.int64),
        node_b=np.zeros(0, np.int64),
        normal=np.zeros((0, 2)),
        gap=np.zeros(0),
        mu=np.zeros(0),
        contact=np.zeros(0, np.int64),
    )
    common = dict(
        nodes=np.zeros((3, 2)),
        element_material=np.zeros(1, np.int64),
        materials=(EngineMaterial(E=1.0, nu=0.3),),
        fixed_dofs=np.zeros(0, np.int64),
        load=np.zeros(6),
        pairs=pairs,
        options={},
        body_names=("b",),
        element_body=np.zeros(1, np.int64),
        contact_names=(),
        support_names=(),
        support_dofs=(),
    )
    model = EngineModel(**common, triangles=np.array([[0, 1, 2]]), plane="strain", thickness=1.0)
    assert list(model.to_engine())[:2] == ["nodes", "triangles"]
    with pytest.raises(ValueError, match="dimension 3 needs tetrahedra"):
        replace(model, dimension=3)
    with pytest.raises(ValueError, match="dimension 2 needs triangles"):
        EngineModel(**common)
