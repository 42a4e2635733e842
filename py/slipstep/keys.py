"""The case keys as a reference: ``slipstep keys [SECTION]``.

Printed from the schema in :mod:`slipstep.schema`, the declarations the validator checks, so the
reference an installed wheel shows is the one the code enforces.  cases/README.md documents the
same keys in its tables (with longer explanations); tests/case/test_keys.py keeps the two in step:
the same keys in every table, the same defaults where the README states one.

A section is a top-level table (``solver``), an array of tables (``bc``, ``contact``) or a body
sub-table (``body.material``, ``body.mesh``); ``body.mesh`` and ``contact`` have one variant per
``generator`` / ``kind`` (and the ``file`` form of a mesh).
"""

from __future__ import annotations

import difflib
import math
import textwrap
from dataclasses import dataclass

from . import schema
from .toml_writing import toml_text
from .errors import InputError


@dataclass(frozen=True)
class Section:
    """One table of keys: ``name`` as ``--set`` spells its place, ``title`` as printed,
    ``variants`` the key that selects it and the values that do (``("generator", ("block",))``;
    the file mesh ``("file", ())``; none ``("", ())``), ``keys`` the schema's declarations."""

    name: str
    title: str
    variants: tuple[str, tuple[str, ...]]
    keys: dict


NONE = ("", ())  # a section no key selects


def _variants(name: str, selector: str, variants: dict) -> list[Section]:
    """One section per distinct key table of ``variants`` (two generators sharing one table,
    quarter and half cylinder, are one section naming both)."""
    grouped: dict[int, list[str]] = {}
    for value, keys in variants.items():
        grouped.setdefault(id(keys), []).append(value)
    out = []
    for values in grouped.values():
        chosen = " | ".join(f'"{v}"' for v in values)
        out.append(
            Section(
                name,
                f"[{name}] {selector} = {chosen}",
                (selector, tuple(values)),
                variants[values[0]],
            )
        )
    return out


def sections() -> list[Section]:
    """Every section of a case, in the order of cases/README.md."""
    out = [Section(name, f"[{name}]", NONE, keys) for name, keys in schema.TABLES.items()]
    for array in schema.ARRAYS:
        if array == "body":
            out.append(Section("body", "[[body]]", NONE, schema.BODY_KEYS))
            out.append(
                Section("body.material", "[body.material]", NONE, schema.BODY_SUBTABLES["material"])
            )
            out += _variants("body.mesh", "generator", schema.MESH_VARIANTS)
            out.append(
                Section(
                    "body.mesh",
                    '[body.mesh] file = "mesh.msh" | "mesh.xdmf"',
                    ("file", ()),
                    schema.FILE_MESH_KEYS,
                )
            )
        elif array == "contact":
            out += _variants("contact", "kind", schema.CONTACT_VARIANTS)
        else:
            out.append(Section(array, f"[[{array}]]", NONE, schema.ARRAY_KEYS[array]))
    return out


#: Short names a case with one body accepts in --set, accepted here too.
ALIASES = {"mesh": "body.mesh", "material": "body.material"}


#: How each schema type is written in a case file.
TYPE_TEXT = {
    "float": "number",
    "int": "integer",
    "str": "string",
    "bool": "true|false",
    "vec2": "[x, y]",
    "vec3": "[x, y, z]",
    "vec": "[x, y] (3D: [x, y, z])",
    "box": "[x0, y0, x1, y1]",
    "axes": '["x", "y"] (3D: "z")',
    "snapshots": '"auto"|"events"|[t, ...]',
    "xy": "{x = .., y = ..} (3D: z)",
    "factors": "{LOAD = .., ...}",
    "points": "[[x, y], ...]",
}


def default_text(key: schema.Key) -> str:
    """A key's default as a case file would spell it ("required", "absent" when unset)."""
    if key.default is schema.REQUIRED:
        return "required"
    if key.default is None:
        return "absent"
    if isinstance(key.default, float) and math.isinf(key.default):
        return "inf" if key.default > 0 else "-inf"
    if key.default == {}:
        return "{}"
    return toml_text(key.default)


def type_text(key: schema.Key) -> str:
    text = "|".join(f'"{c}"' for c in key.choices) if key.choices else TYPE_TEXT[key.type]
    return f"{text} [{key.unit}]" if key.unit else text


def render(section: Section, only: str | None = None, width: int = 100) -> str:
    """The section as a text table: key, type [unit], default, meaning (wrapped)."""
    rows = [
        (name, type_text(k), default_text(k), k.doc)
        for name, k in section.keys.items()
        if only is None or name == only
    ]
    if section.name == "body" and only is None:
        rows += [
            (sub, "table", "required", f"[body.{sub}], below") for sub in schema.BODY_SUBTABLES
        ]
    widths = [max(len(r[i]) for r in rows + [("key", "type", "default", "")]) for i in range(3)]
    indent = sum(widths) + 2 + 2 * 3
    lines = [section.title]
    for name, kind, default, doc in rows:
        head = "  " + "  ".join(text.ljust(w) for text, w in zip((name, kind, default), widths))
        meaning = textwrap.wrap(doc, max(30, width - indent)) or [""]
        lines.append(f"{head}  {meaning[0]}")
        lines += [" " * indent + more for more in meaning[1:]]
    return "\n".join(lines)


def reference(which: str | None = None, width: int = 100) -> str:
    """The reference text of ``slipstep keys [which]``: every section, one section (``solver``,
    ``contact``, ``mesh``), or one key of a section (``contact.mu``, ``solver.group_tol``)."""
    every = sections()
    if which is None:
        return "\n\n".join(render(s, width=width) for s in every)
    name = ALIASES.get(which, which)
    chosen = [s for s in every if s.name == name]
    if chosen:
        return "\n\n".join(render(s, width=width) for s in chosen)
    head, _, key = name.rpartition(".")
    head = ALIASES.get(head, head)
    chosen = [s for s in every if s.name == head and key in s.keys]
    if chosen:
        return "\n\n".join(render(s, key, width) for s in _merged(chosen, key))
    names = sorted({s.name for s in every} | set(ALIASES))
    keys = sorted({f"{s.name}.{k}" for s in every for k in s.keys})
    close = difflib.get_close_matches(which, names + keys, n=3, cutoff=0.6)
    hint = f" (did you mean {', '.join(close)}?)" if close else ""
    raise InputError(f"keys {which}: no such section or key{hint}; sections: {', '.join(names)}")


def _merged(chosen: list[Section], key: str) -> list[Section]:
    """The sections of ``chosen`` grouped by the declaration of ``key`` they share (``contact.mu``
    is one key in every contact kind: shown once, naming the kinds)."""
    groups: dict[int, list[Section]] = {}
    for s in chosen:
        groups.setdefault(id(s.keys[key]), []).append(s)
    return [
        g[0]
        if len(g) == 1
        else Section(
            g[0].name,
            f"[{g[0].name}] {g[0].variants[0]} = "
            + " | ".join(f'"{v}"' for s in g for v in s.variants[1]),
            NONE,
            g[0].keys,
        )
        for g in groups.values()
    ]
