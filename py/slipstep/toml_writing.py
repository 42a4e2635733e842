"""TOML spelling: a value as a case file would write it (in messages), and tables written as
TOML text (the resolved case of a run, :mod:`slipstep.output.resolved_case`)."""

from __future__ import annotations

import re


def toml_text(value) -> str:
    """A value as TOML would spell it, for messages."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, list):
        return "[" + ", ".join(toml_text(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{...}"
    return repr(value)


def toml_value(value) -> str:
    """A value as TOML text that reads back equal: strings escaped, tuples as arrays, dicts as
    inline tables; a float by its shortest round-trip repr (``inf``, ``-inf`` as TOML has
    them)."""
    if isinstance(value, str):
        return (
            '"'
            + "".join(
                _ESCAPES.get(c) or (f"\\u{ord(c):04x}" if _is_control(c) else c) for c in value
            )
            + '"'
        )
    if isinstance(value, dict):
        return "{" + ", ".join(f"{toml_key(k)} = {toml_value(v)}" for k, v in value.items()) + "}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    return toml_text(value)


def toml_key(key: str) -> str:
    """A bare key when TOML allows one, else a quoted key."""
    return key if re.fullmatch(r"[A-Za-z0-9_-]+", key) else toml_value(key)


def toml_table(header: str, table: dict) -> list[str]:
    """A table's lines: its header (``[name]``, ``[[name]]``) and ``key = value`` per entry."""
    return [header, *(f"{toml_key(k)} = {toml_value(v)}" for k, v in table.items())]


_ESCAPES = {'"': '\\"', "\\": "\\\\", "\n": "\\n", "\t": "\\t", "\r": "\\r"}


def _is_control(c: str) -> bool:
    return ord(c) < 0x20 or ord(c) == 0x7F


def point_text(point) -> str:
    """A point as messages write it: ``(x, y)`` or ``(x, y, z)``, each to 6 digits."""
    return "(" + ", ".join(f"{float(c):.6g}" for c in point) + ")"
