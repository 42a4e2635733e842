"""The rules of the case document's dimension (``[analysis] dimension``) that the schema does not
state key by key: the keys of the other dimension a validated document holds, a vector of the
other dimension's length (the messages: :mod:`.terms`), and the checks of the 3D generators' and
contact kinds' values (:mod:`slipstep.schema.solid`)."""

from __future__ import annotations

from ..schema import ANALYSIS_KEYS, ARRAY_KEYS, BODY_SUBTABLES, CONTACT_VARIANTS, MESH_VARIANTS
from ..toml_writing import toml_text


def check_vector_length(validator, v, full: str) -> None:
    """A vector of the other dimension's length, named so (any other shape: the type check)."""
    if not isinstance(v, list) or len(v) not in (2, 3) or len(v) == validator.terms.dimension:
        return
    if any(isinstance(c, bool) or not isinstance(c, (int, float)) for c in v):
        return
    raise validator.fail(full, validator.terms.wrong_length(v))


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
    validator.structured_sizes(mesh, prefix)
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
