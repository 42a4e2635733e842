"""The cases and studies shipped inside the package, so that an installed wheel runs
``slipstep run NAME``, ``sweep NAME``, ``reproduce`` and ``study stability`` from any folder,
and ``slipstep new NAME --from CASE`` copies one out to edit (:func:`copy`).

They live in ``slipstep/data/cases/*.toml`` and ``slipstep/data/studies/*.toml``.  In a source
checkout those are symbolic links to the top-level ``cases/`` and ``studies/`` (the files the
README and the tests use; one copy in git), and maturin puts the linked files themselves into
the wheel.  A new case or study is shipped by adding its link (tests/package/test_wheel.py checks that
every one is linked).
"""

from __future__ import annotations

import difflib
import json
import re
from importlib import resources
from pathlib import Path

from .case import load_case
from .errors import InputError

KINDS = ("cases", "studies")


def folder(kind: str) -> Path:
    """The package's folder of shipped ``cases`` or ``studies``."""
    if kind not in KINDS:
        raise ValueError(f"kind = {kind!r}: use one of {KINDS}")
    return Path(str(resources.files("slipstep") / "data" / kind))


def names(kind: str = "cases") -> list[str]:
    """The shipped case (or study) names, sorted (file names without ``.toml``)."""
    return sorted(p.stem for p in folder(kind).glob("*.toml"))


def path(name: str, kind: str = "cases") -> Path:
    """The file of shipped case (or study) ``name`` (with or without ``.toml``)."""
    stem = name[:-5] if name.endswith(".toml") else name
    found = folder(kind) / f"{stem}.toml"
    if not found.is_file():
        raise FileNotFoundError(
            f"no shipped {kind[:-1] if kind == 'cases' else 'study'} "
            f"{name!r} (shipped: {', '.join(names(kind))})"
        )
    return found


def resolve(arg: str | Path | None, kind: str = "cases") -> str | Path | None:
    """A file the user named: ``arg`` itself when it exists (or is None or a path with a
    folder in it, so the reader reports a missing file), else the shipped file of that name;
    a bare name that is neither is an :class:`InputError` suggesting the close shipped names."""
    if arg is None or Path(arg).exists() or len(Path(arg).parts) != 1:
        return arg
    try:
        return path(str(arg), kind)
    except FileNotFoundError:
        raise InputError(unknown(str(arg), kind)) from None


def unknown(name: str, kind: str = "cases") -> str:
    """The one-line message for a name that is no file and no shipped case (or study): the
    close shipped names and where the list is."""
    what = "case" if kind == "cases" else "study"
    stem = name[:-5] if name.endswith(".toml") else name
    close = difflib.get_close_matches(stem, names(kind), n=3, cutoff=0.75)
    hint = f"; did you mean {', '.join(close)}?" if close else ""
    return (
        f"{name}: no such {what} file, and no shipped {what} of that name{hint} "
        f"(`slipstep list` shows the shipped ones)"
    )


def copy(source: str, name: str) -> Path:
    """Write ``NAME.toml`` (``name`` itself if it ends in .toml), the shipped case ``source``
    with its ``[case] name`` set to the file's stem, and beside it every file the case names
    (:func:`referenced_files`: meshes, surfaces), so the copy runs where it is; an existing
    file is not replaced (one that holds the same bytes is kept as it is)."""
    try:
        original = path(source)
    except FileNotFoundError:
        raise InputError(unknown(source)) from None
    target = Path(name if name.endswith(".toml") else f"{name}.toml")
    if target.exists():
        raise InputError(f"{target} exists: give another NAME, or remove the file first")
    files = referenced_files(load_case(original).data)
    for rel in files:
        there = target.parent / rel
        if there.exists() and there.read_bytes() != (original.parent / rel).read_bytes():
            raise InputError(
                f"{there} exists and differs from the file {source} names: "
                f"remove it, or copy the case into another folder"
            )
    for rel in files:
        there = target.parent / rel
        there.parent.mkdir(parents=True, exist_ok=True)
        if not there.exists():
            there.write_bytes((original.parent / rel).read_bytes())
    target.write_text(renamed(original.read_text(encoding="utf-8"), target.stem), encoding="utf-8")
    return target


def referenced_files(data: dict) -> list[str]:
    """The relative paths of the files a validated case names, in order: each body's mesh
    ``file``, ``edge_file``, ``face_file`` and each contact's surface ``file`` (absolute paths
    are left out: they stay where they are)."""
    named = [
        b.get("mesh", {}).get(key, "")
        for b in data.get("body", [])
        for key in ("file", "edge_file", "face_file")
    ]
    named += [c.get("file", "") for c in data.get("contact", [])]
    return list(dict.fromkeys(f for f in named if f and not Path(f).is_absolute()))


def renamed(text: str, name: str) -> str:
    """Case text with its ``[case] name`` set to ``name`` (added when it has none); comments
    and layout are kept."""
    value = json.dumps(name)  # a TOML basic string
    table = re.search(r"(?m)^\[case\][^\n]*\n", text)
    if table is None:
        return f"[case]\nname = {value}\n\n{text}"
    next_table = re.compile(r"(?m)^\[").search(text, table.end())
    end = next_table.start() if next_table else len(text)
    found = re.compile(r'(?m)^name\s*=\s*"[^"\n]*"').search(text, table.end(), end)
    if found is None:
        return f"{text[:table.end()]}name = {value}\n{text[table.end():]}"
    return f"{text[:found.start()]}name = {value}{text[found.end():]}"
