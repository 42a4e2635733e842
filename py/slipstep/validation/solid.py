"""The case document's dimension (``[analysis] dimension``): keys, generators and contact kinds
of the other dimension refused, one line each naming the key and what to use instead, and the
checks of the 3D generators' and contact kinds' values (:mod:`slipstep.schema.solid`)."""

from __future__ import annotations

from ..schema import ANALYSIS_KEYS, ARRAY_KEYS, BODY_SUBTABLES, CONTACT_VARIANTS, MESH_VARIANTS
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


def wrong_dimension(full: str, value, dimension: int) -> str:
    """The message (after ``full``, the key as --set spells it) for a key given in a case of a
    dimension it has no part in."""
    name, shown = full.rpartition(".")[2], toml_text(value)
    if dimension == 3:
        if name in _PLANE_ONLY:
            return (
                f"= {shown} is not allowed in a 3D case (analysis.dimension = 3): "
                f"{_PLANE_ONLY[name]}; remove {full}"
            )
        return (
            f"= {shown} is not allowed in a 3D case (analysis.dimension = 3): a body in "
            f"space has faces, not edges; use {COUNTER_KEYS[name]} = {shown}"
        )
    return (
        f"= {shown} is not allowed in a 2D case: {name} is a key of 3D cases; set "
        f"analysis.dimension = 3, or use {COUNTER_KEYS[name]}"
    )


def wrong_variant(what: str, value: str, dimension: int) -> str:
    """The message (after ``generator`` / ``kind``) for a generator or contact kind of the other
    dimension."""
    other = 3 if dimension == 2 else 2
    instead = COUNTERPARTS[value]
    fix = (
        f"set analysis.dimension = 3, or use {toml_text(instead)}"
        if dimension == 2
        else f"use {toml_text(instead)}, or remove analysis.dimension = 3"
    )
    return (
        f"= {toml_text(value)} is not allowed in a {dimension}D case: it is a {other}D "
        f"{what}; {fix}"
    )


def check_vector_length(validator, v, full: str) -> None:
    """A vector of the other dimension's length, named so (any other shape: the type check)."""
    if not isinstance(v, list) or len(v) not in (2, 3) or len(v) == validator.dimension:
        return
    if any(isinstance(c, bool) or not isinstance(c, (int, float)) for c in v):
        return
    if validator.dimension == 2:
        raise validator.fail(
            full,
            f"= {toml_text(v)} is not allowed in a 2D case: give two "
            f"components [x, y] (or set analysis.dimension = 3)",
        )
    raise validator.fail(
        full, f"= {toml_text(v)} is not allowed in a 3D case: give three " f"components [x, y, z]"
    )


def other_dimension_keys(data: dict) -> dict[str, tuple]:
    """Per table path (``analysis``, ``bc.<i>``, ``contact.<i>``, ``body.<i>.mesh``...), the keys
    of a validated document that belong to the other dimension: filled with their defaults,
    refused when written back."""
    dimension = data["analysis"]["dimension"]

    def foreign(table: dict, keys: dict) -> tuple:
        return tuple(k for k in table if k in keys and dimension not in keys[k].dims)

    out = {"analysis": foreign(data["analysis"], ANALYSIS_KEYS)}
    for array in ("bc", "point_load", "contact"):
        for i, element in enumerate(data[array]):
            keys = CONTACT_VARIANTS[element["kind"]] if array == "contact" else ARRAY_KEYS[array]
            out[f"{array}.{i}"] = foreign(element, keys)
    for i, body in enumerate(data["body"]):
        mesh = body["mesh"]
        keys = MESH_VARIANTS.get(mesh.get("generator"), BODY_SUBTABLES["mesh"])
        out[f"body.{i}.mesh"] = foreign(mesh, keys)
    return {k: v for k, v in out.items() if v}


# --------------------------------------------------------------------------- 3D generators
def check_mesh(validator, mesh: dict, raw: dict, prefix: str) -> None:
    """The values of a 3D generator's table that depend on each other."""
    gen = mesh["generator"]
    if gen == "shell":
        _check_shell(validator, mesh, prefix)
        return
    if gen == "box" and mesh["h_contact"] == 0:
        _check_structured_box(validator, mesh, raw, prefix)
        return
    if gen == "box":
        for key in ("nx", "ny", "nz", "h"):
            if mesh[key] > 0:
                raise validator.fail(
                    prefix + key,
                    f"= {toml_text(mesh[key])} is not allowed "
                    f"together with h_contact: nx/ny/nz/h make the structured "
                    f"box, h_contact the graded one; drop {key} (or h_contact)",
                )
        for key in ("contact_zone", "h_max"):
            if mesh[key] == 0:
                raise validator.fail(
                    prefix + key,
                    f"is missing: the graded box (h_contact > 0) "
                    f"needs it [length]; add `{key} = ...` to [body.mesh]",
                )
        _check_focus(validator, mesh, prefix)
    if mesh["h_contact"] > mesh["h_max"]:
        raise validator.fail(
            prefix + "h_contact",
            f"= {toml_text(mesh['h_contact'])} is not "
            f"allowed: it must not exceed h_max = {toml_text(mesh['h_max'])}",
        )
    size = {"sphere": "R", "roller": "R", "punch": "a"}.get(gen)
    if size and mesh["contact_zone"] >= mesh[size]:
        raise validator.fail(
            prefix + "contact_zone",
            f"= {toml_text(mesh['contact_zone'])} is "
            f"not allowed: it must be smaller than {size} = "
            f"{toml_text(mesh[size])}",
        )


def _check_shell(validator, mesh: dict, prefix: str) -> None:
    if mesh["b"] <= mesh["a"]:
        raise validator.fail(
            prefix + "b",
            f"= {toml_text(mesh['b'])} is not allowed: the outer "
            f"radius must exceed the inner radius a = {toml_text(mesh['a'])}",
        )
    for key in ("h", "h_outer"):
        if mesh[key] > mesh["b"] - mesh["a"]:
            raise validator.fail(
                prefix + key,
                f"= {toml_text(mesh[key])} is not allowed: it "
                f"must not exceed the wall thickness b - a = "
                f"{toml_text(mesh['b'] - mesh['a'])}",
            )


_GRADED_BOX = ("contact_zone", "h_max", "focus")


def _check_structured_box(validator, mesh: dict, raw: dict, prefix: str) -> None:
    """nx/ny/nz or h; the graded box's keys would do nothing."""
    for n, size in (("nx", "width"), ("ny", "depth"), ("nz", "height")):
        if mesh[n] == 0 and mesh["h"] == 0:
            raise validator.fail(
                prefix + n,
                f"is missing: give {n} (divisions along {size}) "
                f"or h (element size), or h_contact (a graded gmsh mesh)",
            )
    for key in _GRADED_BOX + ("growth",):
        if key in raw:
            raise validator.fail(
                prefix + key,
                f"= {toml_text(raw[key])} is not allowed without "
                f"h_contact: it shapes the graded box (h_contact > 0); add "
                f"h_contact or drop {key}",
            )


def _check_focus(validator, mesh: dict, prefix: str) -> None:
    if mesh["focus"] is None:
        return
    low = [mesh["x0"], mesh["y0"], mesh["z0"]]
    high = [lo + mesh[k] for lo, k in zip(low, ("width", "depth", "height"))]
    tol = 1e-9 * max(mesh["width"], mesh["depth"], mesh["height"])
    if not all(lo - tol <= f <= hi + tol for f, lo, hi in zip(mesh["focus"], low, high)):
        raise validator.fail(
            prefix + "focus",
            f"= {toml_text(mesh['focus'])} is not allowed: "
            f"it lies outside the box; move it inside or onto its boundary",
        )


# --------------------------------------------------------------------------- 3D contact
def check_rigid_surface(validator, c: dict, prefix: str) -> None:
    """A rigid surface is a file or an indenter (with its size), not both; a pyramid is a closed
    surface with the body outside it."""
    if bool(c["file"]) == bool(c["indenter"]):
        raise validator.fail(
            prefix + "file",
            'is missing: give exactly one of file (a .stl or '
            '.msh surface) or indenter = "vickers" or '
            '"berkovich"',
        )
    if c["indenter"] and c["size"] == 0:
        raise validator.fail(
            prefix + "size",
            "is missing: the indenter's height above its tip "
            "[length]; add `size = ...` to [[contact]]",
        )
    if c["indenter"] and c["side"] != "outside":
        raise validator.fail(
            prefix + "side",
            f"= {toml_text(c['side'])} is not allowed with an "
            f'indenter: the body is outside the pyramid; use '
            f'side = "outside"',
        )
