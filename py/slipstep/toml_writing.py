"""TOML spelling: a value as a case file would write it (in messages), and a whole validated
case written back as a case file (the resolved case of a run, beside its results)."""

from __future__ import annotations


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
