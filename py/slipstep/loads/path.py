"""The load path of a validated case: every load ([load], a [[bc]] with pressure, traction or
displacement, a [[point_load]], a [[contact]] with motion) is a pattern at factor 1, and
[[stage]] tables give the factor each named load reaches at the end of each stage."""

from __future__ import annotations

from dataclasses import dataclass

from ..case_record import CaseRecord
from ..errors import CaseError
from ..overrides import element_key
from ..toml_writing import toml_text


@dataclass(frozen=True)
class Load:
    """One load pattern at factor 1: ``[load]``, a ``[[bc]]`` with pressure, traction or
    displacement, a ``[[point_load]]``, or a ``[[contact]]`` with motion."""

    name: str  # its `name` ("load" for [load]); "" when unnamed
    key: str  # the element as --set spells it: "load", "bc", "bc.1", "bc.push"
    array: str  # "load", "bc", "point_load" or "contact"
    index: int  # its position in that array
    force: bool  # applies forces (P, pressure, traction, a point force)
    kinematic: bool  # prescribes displacements or moves a rigid obstacle

    @property
    def label(self) -> str:
        """Its name, else "<array> <index>" (like the engine's "contact <i>")."""
        return self.name or f"{self.array} {self.index}"

    @property
    def place(self) -> str:
        """How messages point at it: its --set key, "[load]" for the table."""
        return "[load]" if self.array == "load" else self.key


@dataclass(frozen=True)
class LoadPath:
    """Named loads, their grouping into the engine's patterns, and the stages.

    ``names`` is the factor order: "load" (the engine's ``load`` vector), then ``patterns``.
    ``head`` is the load whose force is the engine's ``load`` in a staged case (None: zeros);
    without ``[[stage]]`` every force is summed into ``load`` and only displacement and motion
    loads are patterns.  ``factors[k]`` holds the factors at path time t = k.
    """

    loads: tuple
    head: Load | None
    patterns: tuple
    names: tuple
    stage_names: tuple
    factors: tuple
    staged: bool

    @property
    def n_stages(self) -> int:
        return len(self.stage_names)

    @property
    def new(self) -> bool:
        """The model needs the engine's `patterns`/`stages` (else it is the one without stages)."""
        return self.staged or bool(self.patterns)


def case_loads(case: CaseRecord) -> tuple:
    """Every load of a validated case, in order: [load], bc, point_load, contact."""
    out = [Load("load", "load", "load", 0, True, False)] if case.load is not None else []
    for i, bc in enumerate(case.bc):
        if bc.force or bc.displacement:
            key = element_key("bc", case.bc, i)
            out.append(Load(bc.name, key, "bc", i, bc.force, bool(bc.displacement)))
    for i, pl in enumerate(case.point_load):
        key = element_key("point_load", case.point_load, i)
        out.append(Load(pl.name, key, "point_load", i, True, False))
    for i, c in enumerate(case.contact):
        if c.motion_load is not None:
            key = element_key("contact", case.contact, i)
            out.append(Load(c.name, key, "contact", i, False, True))
    return tuple(out)


def load_path(case: CaseRecord, source: str = "<case>") -> LoadPath:
    """The load path of a validated case; CaseError for unnamed or duplicate loads, a
    displacement/motion load named "load", unknown names in factors, a stage that changes
    nothing."""
    loads = case_loads(case)
    stages = case.stage
    if not stages:
        patterns = tuple(x for x in loads if x.kinematic)
        _check_load_names(patterns, source)
        n = 1 + len(patterns)
        return LoadPath(
            loads,
            None,
            patterns,
            ("load", *(x.label for x in patterns)),
            ("stage 1",),
            ((0.0,) * n, (1.0,) * n),
            False,
        )
    for x in loads:
        if not x.name:
            raise CaseError(
                f"{source}: {x.key} is a load without a name: with [[stage]] every "
                f'load needs one; add name = "..." to it (stages name loads in '
                f"factors)"
            )
    _check_load_names(loads, source)
    head = next((x for x in loads if x.name == "load"), None)
    patterns = tuple(x for x in loads if x is not head)
    names = ("load", *(x.name for x in patterns))
    rows = _factor_rows(stages, names, head is not None, source)
    stage_names = tuple(s.name or f"stage {k + 1}" for k, s in enumerate(stages))
    return LoadPath(loads, head, patterns, names, stage_names, rows, True)


def _check_load_names(loads, source: str) -> None:
    """Unique names; "load" only for a force load (it is the engine's `load` vector)."""
    seen = {}
    for x in loads:
        if x.label == "load" and x.kinematic:
            raise CaseError(
                f'{source}: {x.key}.name = "load" is not allowed: "load" names the '
                f"force pattern ([load], or a force [[bc]]/[[point_load]] named so); "
                f'a displacement or motion load needs another name, e.g. "push"'
            )
        if x.label in seen:  # by index: --set finds the first of a shared name
            raise CaseError(
                f"{source}: {x.array}.{x.index}.name = {toml_text(x.label)} is used twice "
                f"(also by {seen[x.label]}): load names must be unique; rename one"
            )
        seen[x.label] = x.place


def _factor_rows(stages: tuple, names: tuple, has_load: bool, source: str) -> tuple:
    """Factors at t = 0, 1, ..., n_stages: all 0 at first; a stage sets the loads it names,
    the others keep theirs."""
    valid = [n for n in names if n != "load" or has_load]
    current, rows = [0.0] * len(names), [(0.0,) * len(names)]
    for k, stage in enumerate(stages):
        key = element_key("stage", stages, k) + ".factors"
        for name, value in stage.factors.items():
            if name not in valid:
                raise CaseError(
                    f"{source}: {key}.{name} = {toml_text(value)} is not allowed: no load "
                    f"is named {toml_text(name)} (loads: {', '.join(valid) or 'none'}); "
                    f'a load is named by its name key ([load] is "load")'
                )
            current[names.index(name)] = value
        if tuple(current) == rows[-1]:
            raise CaseError(
                f"{source}: {key} changes nothing: every factor equals its value at "
                f"the end of the previous stage (all start at 0); give a factor that "
                f"changes, or remove the stage"
            )
        rows.append(tuple(current))
    return tuple(rows)
