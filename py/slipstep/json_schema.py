"""The case schema as a JSON Schema, for editors: ``slipstep keys --json-schema``.

Built from :mod:`slipstep.schema` (the declarations the validator checks; the ``[solver]`` keys
are the engine's own, declared in rust/src/options.rs), so an editor that reads it (VS Code's
Even Better TOML: ``#:schema ./case.schema.json`` on a case's first line, or its settings)
completes keys, shows their meaning and default, and flags unknown keys and wrong types, and
the keys, generators and contact kinds of the other dimension (a 3D case, ``[analysis]
dimension = 3``, is checked against the keys of space, any other against the plane's).  What a
value check decides beyond type and choices (ranges, cross-key rules) stays with the validator:
``slipstep check CASE``.  ``docs/case.schema.json`` is this function's output, kept in step by a
test.
"""

from __future__ import annotations

import json
import math

from . import schema

_NUMBER = {"type": "number"}


def _pair(n: int, most: int | None = None) -> dict:
    """An array of n numbers (n to ``most``)."""
    return {"type": "array", "items": _NUMBER, "minItems": n, "maxItems": most or n}


#: The JSON Schema of each schema type (see :class:`slipstep.schema.Key`).
TYPES = {
    "float": _NUMBER,
    "int": {"type": "integer"},
    "str": {"type": "string"},
    "bool": {"type": "boolean"},
    "vec2": _pair(2),
    "vec3": _pair(3),
    "vec": _pair(2, 3),  # one per dimension of the case: the validator checks which
    "box": _pair(4),
    "axes": {"type": "array", "items": {"enum": ["x", "y", "z"]}, "uniqueItems": True},
    "snapshots": {"anyOf": [{"enum": ["auto", "events"]}, {"type": "array", "items": _NUMBER}]},
    "xy": {
        "type": "object",
        "properties": {"x": _NUMBER, "y": _NUMBER, "z": _NUMBER},
        "additionalProperties": False,
    },
    "factors": {"type": "object", "additionalProperties": _NUMBER},
    "points": {"type": "array", "items": _pair(2)},
}


#: The types whose form depends on the case's dimension: (2D, 3D).
DIMENSIONAL = {
    "vec": (_pair(2), _pair(3)),
    "xy": ({**TYPES["xy"], "properties": {"x": _NUMBER, "y": _NUMBER}}, TYPES["xy"]),
    "axes": ({**TYPES["axes"], "items": {"enum": ["x", "y"]}}, TYPES["axes"]),
}


def key_schema(key: schema.Key, dimension: int) -> dict:
    """One key in a case of ``dimension``: its type (or choices), meaning, unit and default."""
    kind = DIMENSIONAL[key.type][dimension - 2] if key.type in DIMENSIONAL else TYPES[key.type]
    out = {"enum": list(key.choices)} if key.choices else dict(kind)
    out["description"] = key.doc + (f" [{key.unit}]" if key.unit else "")
    if (
        key.default is not schema.REQUIRED
        and key.default is not None
        and not (isinstance(key.default, float) and math.isinf(key.default))
    ):
        out["default"] = key.default
    return out


def table(keys: dict, dimension: int, extra: dict | None = None) -> dict:
    """A table of the keys of a case of ``dimension`` (unknown keys and those of the other
    dimension refused); ``extra``: sub-tables by name."""
    mine = {name: k for name, k in keys.items() if dimension in k.dims}
    props = {name: key_schema(k, dimension) for name, k in mine.items()}
    props.update(extra or {})
    required = [
        name
        for name, k in mine.items()
        if k.default is schema.REQUIRED or dimension in k.required_in
    ]
    out = {"type": "object", "properties": props, "additionalProperties": False}
    if required:
        out["required"] = required
    return out


def variants(selector: str, tables: dict, dimension: int, belongs) -> list[dict]:
    """One table per distinct key table of ``tables`` (selector value -> keys) whose value
    ``belongs(value)`` to ``dimension`` (or to both: None), its ``selector`` key pinned to the
    values that choose it (``kind = "rigid_line"``)."""
    chosen: dict[int, list[str]] = {}
    for value, keys in tables.items():
        if belongs(value) in (None, dimension):
            chosen.setdefault(id(keys), []).append(value)
    out = []
    for values in chosen.values():
        t = table(tables[values[0]], dimension)
        t["properties"][selector] = {**t["properties"][selector], "enum": values}
        out.append(t)
    return out


def _mesh(dimension: int) -> dict:
    """[body.mesh]: one of the generators' tables, or a mesh file."""
    return {
        "anyOf": variants("generator", schema.MESH_VARIANTS, dimension, schema.generator_dimension)
        + [table(schema.FILE_MESH_KEYS, dimension)]
    }


def dimension_schema(dimension: int) -> dict:
    """The tables and arrays of a case of ``dimension``."""
    props = {name: table(keys, dimension) for name, keys in schema.TABLES.items()}
    for array in schema.ARRAYS:
        if array == "body":
            material = table(schema.BODY_SUBTABLES["material"], dimension)
            item = table(
                schema.BODY_KEYS, dimension, {"mesh": _mesh(dimension), "material": material}
            )
        elif array == "contact":
            item = {
                "anyOf": variants("kind", schema.CONTACT_VARIANTS, dimension, schema.kind_dimension)
            }
        else:
            item = table(schema.ARRAY_KEYS[array], dimension)
        props[array] = {"type": "array", "items": item}
    return {"properties": props, "required": ["body"], "additionalProperties": False}


def case_schema() -> dict:
    """The JSON Schema (draft 2020-12) of a case file: that of space when ``[analysis]
    dimension = 3``, else that of the plane."""
    in_space = {
        "properties": {
            "analysis": {"properties": {"dimension": {"const": 3}}, "required": ["dimension"]}
        },
        "required": ["analysis"],
    }
    return {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "$id": "https://slipstep.invalid/case.schema.json",
        "title": "slipstep case file",
        "type": "object",
        "if": in_space,
        "then": dimension_schema(3),
        "else": dimension_schema(2),
    }


def text() -> str:
    """The schema as written to ``docs/case.schema.json``."""
    return json.dumps(case_schema(), indent=1, sort_keys=False) + "\n"
