"""``--set KEY=VALUE``: overrides applied to the raw TOML document before it is validated, and
the keys as ``--set`` spells them (an element of an array of tables by its name or index, the
index left out when the array has one element; see :mod:`slipstep.case`)."""

from __future__ import annotations

import tomllib
from typing import Any

from .errors import CaseError
from .schema import (
    ARRAY_KEYS,
    ARRAYS,
    BODY_SUBTABLES,
    CONTACT_VARIANTS,
    FILE_MESH_KEYS,
    MESH_VARIANTS,
    RIGID_LINE_KEYS,
    TABLES,
)


def parse_override(item: str) -> tuple[str, Any]:
    """Split ``"key=value"``; the value is a TOML literal (``0.35``, ``[0, 1]``, ``"strain"``,
    ``true``); a bare word that is no TOML literal is taken as a string (``plane=stress``)."""
    key, sep, text = item.partition("=")
    key, text = key.strip(), text.strip()
    if not sep or not key:
        raise CaseError(f"--set {item}: expected KEY=VALUE, e.g. --set contact.mu=0.35")
    try:
        value = tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        if text and all(c.isalnum() or c in "_-./" for c in text):
            value = text
        else:
            raise CaseError(
                f"--set {item}: {text!r} is not a TOML value "
                f'(numbers as 0.35, strings as "text", lists as [0, 1])'
            ) from None
    return key, value


def apply_override(raw: dict, item: str, source: str = "<case>") -> None:
    """Apply one ``--set key=value`` to the raw TOML document, in place."""
    key, value = parse_override(item)
    where = f"--set {item}"
    parts = key.split(".")
    head, rest = parts[0], parts[1:]

    if head in ("mesh", "material"):  # shorthand for the single body
        bodies = raw.get("body", [])
        if len(bodies) != 1:
            raise CaseError(
                f"{where}: '{head}.*' is short for body.<name>.{head}.* only in a "
                f"case with one body; this one has {len(bodies)}: use "
                f"body.<name>.{key}"
            )
        head, rest = "body", ["0", head, *rest]

    if head in TABLES:
        table = raw.setdefault(head, {})
        if not isinstance(table, dict):
            raise CaseError(f"{where}: {head} must be a table, written [{head}]")
        _set_in_table(table, TABLES[head], rest, value, where, f"[{head}]")
        return
    if head in ARRAYS:
        elements = raw.get(head, [])
        if not isinstance(elements, list) or any(not isinstance(e, dict) for e in elements):
            raise CaseError(f"{where}: {head} must be an array of tables, written [[{head}]]")
        index, rest = _array_index(elements, head, rest, where)
        element = elements[index]
        if head == "body" and rest and rest[0] in BODY_SUBTABLES:
            sub = rest[0]
            table = element.setdefault(sub, {})
            if not isinstance(table, dict):
                raise CaseError(f"{where}: {sub} must be a table, written [body.{sub}]")
            keys = BODY_SUBTABLES[sub]
            if sub == "mesh":  # the keys of this mesh's form, if it has a known one
                form = "file" if "file" in table else table.get("generator")
                keys = (
                    FILE_MESH_KEYS
                    if form == "file"
                    else MESH_VARIANTS.get(form if isinstance(form, str) else "", keys)
                )
            _set_in_table(table, keys, rest[1:], value, where, f"[body.{sub}]")
            return
        keys = ARRAY_KEYS[head]
        if head == "contact":  # the keys of this contact's kind, if it has a known one
            kind = element.get("kind")
            keys = CONTACT_VARIANTS.get(kind if isinstance(kind, str) else "", keys)
            if kind in ("node_to_node", "node_to_segment") and rest == [
                "motion"
            ]:  # refused by the validator,
                keys = {**keys, "motion": RIGID_LINE_KEYS["motion"]}  # with the reason
        _set_in_table(
            element,
            keys,
            rest,
            value,
            where,
            f"[[{head}]]",
            extra=tuple(BODY_SUBTABLES) if head == "body" else (),
        )
        return
    valid = ", ".join([*TABLES, *ARRAYS, "mesh", "material"])
    raise CaseError(f"{where}: unknown key '{head}'; valid first parts are {valid}")


def _array_index(elements: list, head: str, rest: list[str], where: str) -> tuple[int, list]:
    """Pick the element of an array of tables that an override addresses."""
    if not elements:
        raise CaseError(f"{where}: the case has no [[{head}]] entry to change")
    if rest:
        first = rest[0]
        if first.isdigit():
            i = int(first)
            if i >= len(elements):
                raise CaseError(
                    f"{where}: [[{head}]] has {len(elements)} entries: "
                    f"use an index 0..{len(elements) - 1}"
                )
            return i, rest[1:]
        names = [e.get("name") for e in elements]
        if first in names:
            return names.index(first), rest[1:]
    if len(elements) == 1:
        return 0, rest
    names = [str(e["name"]) for e in elements if "name" in e]
    hint = f" or a name ({', '.join(names)})" if names else ""
    raise CaseError(
        f"{where}: the case has {len(elements)} [[{head}]] entries: say which, "
        f"e.g. {head}.0.{'.'.join(rest) or 'KEY'} (an index{hint})"
    )


def _set_in_table(
    table: dict, keys: dict, rest: list[str], value, where: str, label: str, extra: tuple = ()
) -> None:
    """Set ``rest`` = [key] in ``table``, or [key, entry] of an inline-table key
    (``factors.load``, ``displacement.y``); entries are checked by the validator."""
    valid = ", ".join([*keys, *extra])
    inline = len(rest) == 2 and rest[0] in keys and keys[rest[0]].type in ("xy", "factors")
    if not inline and (len(rest) != 1 or rest[0] not in keys):
        name = ".".join(rest) or "(nothing)"
        raise CaseError(f"{where}: unknown key '{name}' in {label}; valid keys: {valid}")
    if not inline:
        table[rest[0]] = value
        return
    sub = table.setdefault(rest[0], {})
    if not isinstance(sub, dict):
        raise CaseError(
            f"{where}: {rest[0]} must be an inline table, e.g. " f"{rest[0]} = {{{rest[1]} = 1.0}}"
        )
    sub[rest[1]] = value


def element_prefix(array: str, elements: list, i: int) -> str:
    """How --set addresses element i of an array, with a trailing dot: ``bc.``, ``bc.push.`` or
    ``bc.1.``."""
    if len(elements) == 1:
        return f"{array}."
    element = elements[i]  # a raw table, or a record of a validated one
    name = element.get("name") if isinstance(element, dict) else getattr(element, "name", None)
    return f"{array}.{name}." if isinstance(name, str) and name else f"{array}.{i}."


def element_key(array: str, elements: list, i: int) -> str:
    """How --set addresses element i of an array: ``bc``, ``bc.push`` or ``bc.1``."""
    return element_prefix(array, elements, i)[:-1]
