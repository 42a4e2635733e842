"""A case document's terms in each dimension (``[analysis] dimension``): what a boundary is
called, the components of a vector, the body ``[load] P`` acts on, and how a key, generator,
contact kind or vector of the other dimension is refused.  :func:`terms_of` chooses them once:
the validator holds them before a scene exists, and the scene's idealisation
(:mod:`slipstep.idealisation`, which the validator cannot import: it builds scenes from
validated cases) inherits them."""

from __future__ import annotations

from abc import ABC, abstractmethod

from ..schema.solid import COUNTERPARTS
from ..toml_writing import toml_text

#: A key of one dimension and its part in the other.
COUNTER_KEYS = {"edge": "face", "edge_a": "face_a", "edge_b": "face_b", "edge_file": "face_file"}
COUNTER_KEYS.update({v: k for k, v in list(COUNTER_KEYS.items())})

#: Why a 2D key has no part in a 3D case.
_PLANE_ONLY = {
    "plane": "a body in space is not a plane section",
    "thickness": "a body in space has no out-of-plane thickness (forces are forces)",
}


class Terms(ABC):
    """What a case document says in one dimension."""

    #: coordinates and displacement components per node
    dimension: int
    #: the boundary a [[bc]] or [[contact]] names: "edge" (2D) or "face" (3D)
    boundary: str
    #: the names of a vector's components, and the schema type a "vec" key takes
    axes: tuple[str, ...]
    vector_type: str
    #: the generator of the body ``[load] P`` (the Hertz convenience) acts on
    hertz_generator: str
    #: what a ``symmetry`` boundary is: straight or flat along the coordinate axes
    axis_aligned: str
    #: what ``[output] snapshots = "auto"`` keeps: every event ("events"), or evenly spaced
    #: path times within a size budget ("times": a 3D snapshot is large)
    auto_snapshots: str

    @abstractmethod
    def wrong_dimension(self, full: str, value) -> str:
        """The message (after ``full``, the key as --set spells it) for a key given in a case
        of a dimension it has no part in."""

    @abstractmethod
    def wrong_variant(self, what: str, value: str) -> str:
        """The message (after ``generator`` / ``kind``) for a generator or contact kind of the
        other dimension."""

    @abstractmethod
    def wrong_length(self, v: list) -> str:
        """The message for a vector with the other dimension's number of components."""


class SectionTerms(Terms):
    """A 2D case: plane or axisymmetric sections, bounded by edges."""

    dimension = 2
    boundary = "edge"
    axes = ("x", "y")
    vector_type = "vec2"
    hertz_generator = "quarter_cylinder"
    axis_aligned = "a straight line parallel to the x or y axis"
    auto_snapshots = "events"

    def wrong_dimension(self, full: str, value) -> str:
        name, shown = full.rpartition(".")[2], toml_text(value)
        return (
            f"= {shown} is not allowed in a 2D case: {name} is a key of 3D cases; set "
            f"analysis.dimension = 3, or use {COUNTER_KEYS[name]}"
        )

    def wrong_variant(self, what: str, value: str) -> str:
        return (
            f"= {toml_text(value)} is not allowed in a 2D case: it is a 3D {what}; set "
            f"analysis.dimension = 3, or use {toml_text(COUNTERPARTS[value])}"
        )

    def wrong_length(self, v: list) -> str:
        return (
            f"= {toml_text(v)} is not allowed in a 2D case: give two "
            f"components [x, y] (or set analysis.dimension = 3)"
        )


class SolidTerms(Terms):
    """A 3D case: solids in space, bounded by faces."""

    dimension = 3
    boundary = "face"
    axes = ("x", "y", "z")
    vector_type = "vec3"
    hertz_generator = "sphere"
    axis_aligned = "a plane parallel to a coordinate plane (x = const, y = const or z = const)"
    auto_snapshots = "times"

    def wrong_dimension(self, full: str, value) -> str:
        name, shown = full.rpartition(".")[2], toml_text(value)
        if name in _PLANE_ONLY:
            return (
                f"= {shown} is not allowed in a 3D case (analysis.dimension = 3): "
                f"{_PLANE_ONLY[name]}; remove {full}"
            )
        return (
            f"= {shown} is not allowed in a 3D case (analysis.dimension = 3): a body in "
            f"space has faces, not edges; use {COUNTER_KEYS[name]} = {shown}"
        )

    def wrong_variant(self, what: str, value: str) -> str:
        return (
            f"= {toml_text(value)} is not allowed in a 3D case: it is a 2D {what}; use "
            f"{toml_text(COUNTERPARTS[value])}, or remove analysis.dimension = 3"
        )

    def wrong_length(self, v: list) -> str:
        return f"= {toml_text(v)} is not allowed in a 3D case: give three components [x, y, z]"


def terms_of(dimension: int) -> Terms:
    """The terms of a case of ``[analysis] dimension``: the one place it chooses them."""
    return SolidTerms() if dimension == 3 else SectionTerms()
