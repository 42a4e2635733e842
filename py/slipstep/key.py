"""One key of a case file: its declaration (:class:`Key`: type, default, unit, meaning, value
check, the case dimensions it belongs to) and the value checks that keys of every table share.
:mod:`slipstep.schema` declares the tables of 2D and shared keys with it,
:mod:`slipstep.schema.solid` those of 3D scenes."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable

REQUIRED = object()  # marker: the key has no default


@dataclass(frozen=True)
class Key:
    """One key of a table: its type, default, unit, meaning and an optional value check.

    ``type`` is one of ``"float"``, ``"int"``, ``"str"``, ``"bool"``, ``"vec2"`` (two floats),
    ``"vec3"`` (three floats), ``"vec"`` (one float per dimension of the case: [x, y] or
    [x, y, z]), ``"box"`` (four floats [x0, y0, x1, y1]),
    ``"axes"`` (a list of ``"x"``/``"y"``/``"z"``, z in 3D only), ``"snapshots"`` (``"auto"``,
    ``"events"`` or a list of path times), ``"xy"`` (an inline table of floats x, y and, in 3D, z),
    ``"factors"`` (an inline table of floats by load name), ``"points"`` (a list of [x, y]).
    ``check(value)`` returns ``None`` or the reason the value is not allowed.  ``dims``: the
    case dimensions (``[analysis] dimension``) the key belongs to; given in a case of another
    dimension it is refused.  ``required_in``: the dimensions in which a key with a default must
    be given all the same (``edge_a`` of a 2D node-to-node contact, ``face_a`` of a 3D one).
    """

    type: str
    default: Any = REQUIRED
    unit: str = ""
    doc: str = ""
    check: Callable[[Any], str | None] | None = None
    choices: tuple = ()
    dims: tuple = (2, 3)
    required_in: tuple = ()


def positive(what: str) -> Callable[[Any], str | None]:
    """The check of a key that must be > 0."""
    return lambda v: None if v > 0 else f"{what} must be > 0"


def non_negative(what: str) -> Callable[[Any], str | None]:
    """The check of a key that must be >= 0."""
    return lambda v: None if v >= 0 else f"{what} must be >= 0"


def check_unit_free_vector(v) -> str | None:
    """A normal or an axis: any length but zero."""
    return None if math.hypot(*v) > 0 else "the normal must be a non-zero vector"
