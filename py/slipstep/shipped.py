"""The cases and studies shipped inside the package, so that an installed wheel runs
``slipstep run NAME``, ``sweep NAME``, ``reproduce`` and ``study stability`` from any folder.

They live in ``slipstep/data/cases/*.toml`` and ``slipstep/data/studies/*.toml``.  In a source
checkout those are symbolic links to the top-level ``cases/`` and ``studies/`` (the files the
README and the tests use; one copy in git), and maturin puts the linked files themselves into
the wheel.  A new case or study is shipped by adding its link (tests/test_wheel.py checks that
every one is linked).
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

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
        raise FileNotFoundError(f"no shipped {kind[:-1] if kind == 'cases' else 'study'} "
                                f"{name!r} (shipped: {', '.join(names(kind))})")
    return found


def resolve(arg: str | Path | None, kind: str = "cases") -> str | Path | None:
    """A file the user named: ``arg`` itself when it exists (or is None or a path with a
    folder in it), else the shipped file of that name when there is one, else ``arg`` unchanged
    (so the reader reports the missing file)."""
    if arg is None or Path(arg).exists() or len(Path(arg).parts) != 1:
        return arg
    try:
        return path(str(arg), kind)
    except FileNotFoundError:
        return arg
