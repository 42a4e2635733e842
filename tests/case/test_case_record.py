"""The case records (slipstep.case_record) against the schema (slipstep.schema): every key of a
table is a field of its record and every field a key, with the type the key's kind is read as
(so a key added or dropped on either side alone fails here); and the record of every shipped
case holds the validated document's values."""

from __future__ import annotations

import copy
import dataclasses
import pickle
from dataclasses import fields

import pytest
from conftest import MINIMAL

from slipstep import shipped
from slipstep.case import load_case, parse_case
from slipstep.case_record import (
    CONTACT_KINDS,
    Analysis,
    Bc,
    Body,
    CaseInfo,
    CaseRecord,
    HertzLoad,
    LoadStage,
    Material,
    Output,
    PointLoad,
    Solver,
)
from slipstep.schema import (
    ANALYSIS_KEYS,
    ARRAYS,
    BC_KEYS,
    BODY_KEYS,
    BODY_SUBTABLES,
    CASE_KEYS,
    CONTACT_VARIANTS,
    FILE_MESH_KEYS,
    LOAD_KEYS,
    MATERIAL_KEYS,
    MESH_VARIANTS,
    OUTPUT_KEYS,
    POINT_LOAD_KEYS,
    SOLVER_KEYS,
    STAGE_KEYS,
    TABLES,
    contact_tags,
)

#: The annotation a field of each key kind has (a key whose default is None adds "| None").
ANNOTATIONS = {
    "float": "float",
    "int": "int",
    "str": "str",
    "bool": "bool",
    "vec": "tuple[float, ...]",
    "vec2": "tuple[float, float]",
    "vec3": "tuple[float, float, float]",
    "box": "tuple[float, float, float, float]",
    "axes": "tuple[str, ...]",
    "snapshots": "str | tuple[float, ...]",
    "xy": "Mapping[str, float]",
    "factors": "Mapping[str, float]",
    "points": "tuple[tuple[float, float], ...]",
}

RECORDS = {
    "case": (CaseInfo, CASE_KEYS),
    "analysis": (Analysis, ANALYSIS_KEYS),
    "load": (HertzLoad, LOAD_KEYS),
    "output": (Output, OUTPUT_KEYS),
    "solver": (Solver, SOLVER_KEYS),
    "material": (Material, MATERIAL_KEYS),
    "bc": (Bc, BC_KEYS),
    "point_load": (PointLoad, POINT_LOAD_KEYS),
    "stage": (LoadStage, STAGE_KEYS),
    **{f"contact {kind}": (CONTACT_KINDS[kind], keys) for kind, keys in CONTACT_VARIANTS.items()},
}


def expected_annotation(key) -> str:
    kind = ANNOTATIONS[key.type]
    return f"{kind} | None" if key.default is None else kind


@pytest.mark.parametrize("table", RECORDS)
def test_each_record_has_a_field_per_schema_key_and_no_other(table):
    record, keys = RECORDS[table]
    names = [f.name for f in fields(record)]
    assert sorted(set(keys) - set(names)) == [], f"schema keys of {table} without a field"
    assert sorted(set(names) - set(keys)) == [], f"fields of {table} that no schema key names"
    assert len(names) == len(set(names))


@pytest.mark.parametrize("table", RECORDS)
def test_each_field_is_typed_as_its_key_is_read(table):
    record, keys = RECORDS[table]
    wrong = {
        f.name: (f.type, expected_annotation(keys[f.name]))
        for f in fields(record)
        if f.type != expected_annotation(keys[f.name])
    }
    assert wrong == {}, "field: (annotation, the key's kind)"


def test_the_contact_kinds_are_the_schema_variants():
    assert list(CONTACT_KINDS) == list(CONTACT_VARIANTS)


def test_the_case_and_a_body_have_a_field_per_table():
    assert [f.name for f in fields(CaseRecord)] == [*TABLES, *ARRAYS]
    assert {f.name for f in fields(Body)} == set(BODY_KEYS) | set(BODY_SUBTABLES)


def shipped_cases():
    return [shipped.path(name) for name in shipped.names()]


def plain(value):
    """A record's value as the validated document holds it: tuples as lists, mappings as
    dicts, records as dicts of their fields (a body's mesh, its table's copy, as it is)."""
    if isinstance(value, Body):
        return {"name": value.name, "mesh": dict(value.mesh), "material": plain(value.material)}
    if dataclasses.is_dataclass(value):
        return {f.name: plain(getattr(value, f.name)) for f in fields(value)}
    if isinstance(value, tuple):
        return [plain(v) for v in value]
    if hasattr(value, "items"):
        return {k: plain(v) for k, v in value.items()}
    return value


@pytest.mark.parametrize("path", shipped_cases(), ids=lambda p: p.stem)
def test_a_shipped_case_record_holds_the_validated_values(path):
    case = load_case(path)
    assert plain(case.record) == case.data
    assert case.record is case.record  # built once
    for contact, table in zip(case.record.contact, case.data["contact"]):
        assert list(contact.surfaces) == [tuple(t) for t in contact_tags(table)]
    for body in case.record.body:
        mesh = dict(body.mesh)
        keys = FILE_MESH_KEYS if "file" in mesh else MESH_VARIANTS[mesh["generator"]]
        assert set(mesh) == {*keys, "edges"}


def test_the_records_are_read_only():
    record = parse_case(MINIMAL).record
    with pytest.raises(dataclasses.FrozenInstanceError):
        record.analysis.plane = "stress"
    with pytest.raises(TypeError):
        record.body[0].mesh["width"] = 3.0
    assert record.body_named(record.body[0].name) is record.body[0]


def test_a_case_with_its_record_copies_and_pickles():
    case = parse_case(MINIMAL)
    record = case.record
    assert pickle.loads(pickle.dumps(case)).record == record
    assert copy.deepcopy(case).record == record
