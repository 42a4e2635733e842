"""The element-size keys the mesh generators of both dimensions share: the grading of a gmsh
mesh (h_contact within contact_zone of a point or line, growing to h_max) and the divisions of a
structured block (2D) or box (3D) along its sides."""

from __future__ import annotations

from ..key import REQUIRED, Key, non_negative, positive

#: The sides of each structured generator: (its divisions, the size they divide).
SIDES = {
    "block": (("nx", "width"), ("ny", "height")),
    "box": (("nx", "width"), ("ny", "depth"), ("nz", "height")),
}


def graded_keys(around: str, structured: str = "", refined: str = "") -> dict[str, Key]:
    """The keys of a mesh gmsh grades: element size h_contact within contact_zone of ``around``,
    then growing by ``growth`` up to h_max.  Required of a curved body.  Optional (0: not
    graded) of a ``structured`` generator (:data:`SIDES`), structured unless h_contact > 0; h_max
    and growth shape its ``refined`` variant too when it has one (its growth law given)."""
    default = 0.0 if structured else REQUIRED
    law = "h = h_contact + growth * (d - contact_zone)"
    graded = both = ""
    first = f"element size within contact_zone of {around}"
    if structured:
        graded = f"graded {structured}: "
        both = f"graded or refined {structured}: " if refined else graded
        sides = "/".join(n for n, _ in SIDES[structured])
        first = (
            f"graded {structured} (gmsh): {first} (0 = the structured {structured} of {sides} or h)"
        )
    return {
        "h_contact": Key(
            "float",
            default,
            unit="length",
            doc=first,
            check=(non_negative if structured else positive)("h_contact"),
        ),
        "contact_zone": Key(
            "float",
            default,
            unit="length",
            doc=f"{graded}radius of the fine zone around {around}",
            check=positive("contact_zone"),
        ),
        "h_max": Key(
            "float",
            default,
            unit="length",
            doc=f"{both}largest element size",
            check=positive("h_max"),
        ),
        "growth": Key(
            "float",
            0.1,
            doc=f"{both}size growth per unit distance outside the fine zone "
            + (f"(graded: {law}; refined: {refined})" if refined else f"({law})"),
            check=positive("growth"),
        ),
    }


def divisions(mesh: dict) -> tuple[int, ...]:
    """A structured block's or box's cells along its sides (:data:`SIDES`): as given, or
    round(size / h)."""
    return tuple(
        mesh[n] or max(1, round(mesh[size] / mesh["h"])) for n, size in SIDES[mesh["generator"]]
    )
