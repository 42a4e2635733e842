"""The case schema as a JSON Schema, for editors: ``slipstep keys --json-schema``.

Built from :mod:`slipstep.schema` (the declarations the validator checks; the ``[solver]`` keys
are the engine's own, declared in rust/src/options.rs), so an editor that reads it (VS Code's
Even Better TOML: ``#:schema ./case.schema.json`` on a case's first line, or its settings)
completes keys, shows their meaning and default, and flags unknown keys and wrong types.  What a
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
    "snapshots": {"anyOf": [{"const": "events"}, {"type": "array", "items": _NUMBER}]},
    "xy": {"type": "object", "properties": {"x": _NUMBER, "y": _NUMBER, "z": _NUMBER},
           "additionalProperties": False},
    "factors": {"type": "object", "additionalProperties": _NUMBER},
    "points": {"type": "array", "items": _pair(2)},
}


def key_schema(key: schema.Key) -> dict:
    """One key: its type (or choices), meaning, unit and default."""
    out = {"enum": list(key.choices)} if key.choices else dict(TYPES[key.type])
    out["description"] = key.doc + (f" [{key.unit}]" if key.unit else "")
    if key.default is not schema.REQUIRED and key.default is not None and not (
            isinstance(key.default, float) and math.isinf(key.default)):
        out["default"] = key.default
    return out


def table(keys: dict, extra: dict | None = None) -> dict:
    """A table of keys (unknown keys refused); ``extra``: sub-tables by name."""
    props = {name: key_schema(k) for name, k in keys.items()}
    props.update(extra or {})
    required = [name for name, k in keys.items() if k.default is schema.REQUIRED]
    out = {"type": "object", "properties": props, "additionalProperties": False}
    if required:
        out["required"] = required
    return out


def variants(selector: str, tables: dict) -> list[dict]:
    """One table per distinct key table of ``tables`` (selector value -> keys), its
    ``selector`` key pinned to the values that choose it (``kind = "rigid_line"``)."""
    chosen: dict[int, list[str]] = {}
    for value, keys in tables.items():
        chosen.setdefault(id(keys), []).append(value)
    out = []
    for values in chosen.values():
        t = table(tables[values[0]])
        t["properties"][selector] = {**t["properties"][selector], "enum": values}
        out.append(t)
    return out


def _mesh() -> dict:
    """[body.mesh]: one of the generators' tables, or a mesh file."""
    return {"anyOf": variants("generator", schema.MESH_VARIANTS) + [table(schema.FILE_MESH_KEYS)]}


def case_schema() -> dict:
    """The JSON Schema (draft 2020-12) of a case file."""
    props = {name: table(keys) for name, keys in schema.TABLES.items()}
    for array in schema.ARRAYS:
        if array == "body":
            item = table(schema.BODY_KEYS, {"mesh": _mesh(),
                                            "material": table(schema.BODY_SUBTABLES["material"])})
        elif array == "contact":
            item = {"anyOf": variants("kind", schema.CONTACT_VARIANTS)}
        else:
            item = table(schema.ARRAY_KEYS[array])
        props[array] = {"type": "array", "items": item}
    return {"$schema": "https://json-schema.org/draft/2020-12/schema",
            "$id": "https://slipstep.invalid/case.schema.json",
            "title": "slipstep case file",
            "type": "object", "properties": props, "required": ["body"],
            "additionalProperties": False}


def text() -> str:
    """The schema as written to ``docs/case.schema.json``."""
    return json.dumps(case_schema(), indent=1, sort_keys=False) + "\n"
