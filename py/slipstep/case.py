"""Reading a case: load a case TOML file, apply ``--set`` overrides (:mod:`slipstep.overrides`),
validate (:mod:`slipstep.validation`).

A case is a TOML file (schema in ``cases/README.md``; the same schema is declared in
:mod:`slipstep.schema` and every key there is checked).  ``load_case`` returns a :class:`Case` whose
``data`` is the validated document with every default filled in, and ``record`` the same tables
as typed records (:mod:`slipstep.case_record`), which the rest of the package reads: it never
guesses a key.

Every problem is reported as a :class:`CaseError` with a one-line message that names the
source, the key as ``--set`` would spell it, and the fix, e.g.::

    cases/x.toml: material.nu = 0.5 is not allowed: Poisson's ratio must satisfy -1 < nu < 0.5 (use 0.499 for near-incompressible)

Keys are spelled like ``--set`` paths: ``analysis.plane``, ``body.cylinder.material.E`` (an
element of an array of tables by its ``name`` or its 0-based index; the index may be left out
when the array has exactly one element, so ``contact.mu``), and for a case with a single body
``mesh.*`` and ``material.*`` are short for ``body.<it>.mesh.*`` and ``body.<it>.material.*``.
Entries of inline tables are one level further: ``stage.unload.factors.load``,
``bc.push.displacement.y``.

Load path: every load (``[load]``, a ``[[bc]]`` with pressure, traction or
displacement, a ``[[point_load]]``, a ``[[contact]]`` with motion) is a pattern at factor 1;
``[[stage]]`` tables give the factor each named load reaches at the end of each stage
(:class:`LoadPath`, ``Case.path``).
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from functools import cached_property
from importlib import resources
from pathlib import Path

from .case_record import CaseRecord
from .errors import CaseError
from .loads.path import LoadPath, load_path
from .overrides import apply_override
from .validation.document import Validator

__all__ = ["Case", "CaseError", "default_case_path", "load_case", "parse_case"]


@dataclass
class Case:
    """A validated case: ``data`` holds every table with defaults filled in, ``record`` the
    same as typed records (:class:`slipstep.case_record.CaseRecord`).

    ``source`` is how messages name the file; ``base_dir`` resolves relative mesh paths;
    ``overrides`` are the ``--set`` items applied before validation.
    """

    data: dict
    source: str
    base_dir: Path
    overrides: tuple = ()

    @cached_property
    def record(self) -> CaseRecord:
        """The validated tables as typed records (built once, from ``data``)."""
        return CaseRecord.of(self.data)

    @property
    def name(self) -> str:
        return self.record.case.name

    @property
    def dimension(self) -> int:
        """2 (a plane section or rings: triangles) or 3 (space: tetrahedra)."""
        return self.record.analysis.dimension

    def body(self, name: str) -> dict:
        """The validated [[body]] table called ``name`` (its record:
        ``record.body_named(name)``)."""
        for b in self.data["body"]:
            if b["name"] == name:
                return b
        raise KeyError(name)

    def error(self, key: str, message: str) -> CaseError:
        """A CaseError about ``key`` (found after validation, e.g. while building the model)."""
        return CaseError(f"{self.source}: {key}: {message}")

    @property
    def path(self) -> LoadPath:
        """The load path: named loads, stages and the factor table (see :func:`load_path`)."""
        return load_path(self.record, self.source)

    @property
    def units(self) -> dict[str, str]:
        """``[case] units`` read as "length, force, stress" (e.g. "mm, N, MPa"): {"length":
        "mm", "force": "N", "stress": "MPa"}; {} when the note is not three such words."""
        words = [w.strip() for w in self.record.case.units.split(",")]
        if len(words) != 3 or not all(w and " " not in w and len(w) <= 8 for w in words):
            return {}
        return dict(zip(("length", "force", "stress"), words))

    @classmethod
    def from_toml(
        cls, text: str, source: str = "<case>", base_dir: Path | str = ".", overrides=()
    ) -> "Case":
        """A case from TOML text (:func:`parse_case`)."""
        return parse_case(text, source, base_dir, overrides)

    @classmethod
    def from_dict(
        cls, data: dict, source: str = "<dict>", base_dir: Path | str = ".", overrides=()
    ) -> "Case":
        """A case from a dict shaped like the TOML document (``{"case": {...}, "body":
        [{...}], ...}``, keys as in cases/README.md), validated like a file: tuples and numpy
        arrays count as lists, numpy numbers as numbers, a None value as an absent key."""
        if not isinstance(data, dict):
            raise CaseError(f"{source}: a case is a dict of tables, not {type(data).__name__}")
        raw, overrides = _toml_like(data), tuple(overrides)
        for item in overrides:
            apply_override(raw, item, source)
        return cls(
            data=Validator(source).case(raw),
            source=source,
            base_dir=Path(base_dir),
            overrides=overrides,
        )


def default_case_path() -> Path:
    """The embedded default case (the Hertz cylinder of §5.1)."""
    return Path(str(resources.files("slipstep") / "data" / "hertz_cylinder.toml"))


def load_case(path: str | Path | None = None, overrides=()) -> Case:
    """Read a case file (the embedded default if ``path`` is None), apply ``overrides``
    (strings ``"key=value"``), validate, and return a :class:`Case`."""
    if path is None:
        path = default_case_path()
        source = "hertz_cylinder.toml (built-in)"
    else:
        source = str(path)
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise CaseError(f"{source}: no such case file") from None
    except OSError as exc:
        raise CaseError(f"{source}: cannot read the case file: {exc.strerror}") from None
    except UnicodeDecodeError as exc:
        raise CaseError(
            f"{source}: not a UTF-8 text file (byte {exc.start}): a case is a TOML " f"text file"
        ) from None
    return parse_case(text, source=source, base_dir=path.resolve().parent, overrides=overrides)


def parse_case(text: str, source: str = "<case>", base_dir: Path | str = ".", overrides=()) -> Case:
    """Like :func:`load_case`, from TOML text."""
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise CaseError(f"{source}: invalid TOML: {exc}") from None
    overrides = tuple(overrides)
    for item in overrides:
        apply_override(raw, item, source)
    data = Validator(source).case(raw)
    return Case(data=data, source=source, base_dir=Path(base_dir), overrides=overrides)


def _toml_like(value):
    """A copy of ``value`` in the types tomllib gives: dict, list, str, bool, int, float; None
    values of a dict are left out (TOML has no null)."""
    if isinstance(value, dict):
        return {str(k): _toml_like(v) for k, v in value.items() if v is not None}
    if hasattr(value, "tolist") and not isinstance(value, (str, bytes)):  # numpy
        value = value.tolist()
    if isinstance(value, (list, tuple)):
        return [_toml_like(v) for v in value]
    return value
