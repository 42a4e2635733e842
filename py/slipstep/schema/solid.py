"""The keys of 3D scenes (``[analysis] dimension = 3``): the tetrahedron mesh generators and
the contact kinds in space.  :mod:`slipstep.schema` adds them to its variants, so that one
schema (``slipstep keys``, cases/README.md, docs/case.schema.json) holds both dimensions; the
validator refuses a generator or kind of the other dimension, naming its counterpart.

Coordinates: z is up.  The bodies of revolution (sphere, roller) stand on the plane z = 0,
touching it at the origin, and are cut at z = R; the box and the punch are axis-aligned.
"""

from __future__ import annotations

import math

from ..key import REQUIRED, Key, check_unit_free_vector, non_negative, positive
from .sizes import divisions, graded_keys

#: The parts of a sphere or roller a generator meshes, below its cut z = R: symmetry planes
#: x = 0 and y = 0 ("eighth"), y = 0 ("quarter"), none ("half").
PORTIONS = ("eighth", "quarter", "half")


def _portion(symmetric: str) -> Key:
    return Key(
        "str",
        "eighth",
        doc=f'the part meshed below the cut z = R: "eighth" (x >= 0, '
        f'y >= 0: faces symmetry_x and symmetry_y), "quarter" '
        f'(y >= 0: face symmetry_y) or "half" ({symmetric})',
        choices=PORTIONS,
    )


SPHERE_KEYS = {
    "generator": Key(
        "str",
        REQUIRED,
        doc='"sphere" (3D): a sphere, centre (0, 0, R), its '
        "lowest point (0, 0, 0) a node; faces surface, top "
        "(the cut z = R) and its symmetry planes",
    ),
    "R": Key("float", REQUIRED, unit="length", doc="sphere radius", check=positive("R")),
    "portion": _portion("the whole lower hemisphere"),
    **graded_keys("the lowest point (0, 0, 0)"),
}

ROLLER_KEYS = {
    "generator": Key(
        "str",
        REQUIRED,
        doc='"roller" (3D): a cylinder of radius R and finite '
        "length, axis along y at height z = R, centred at "
        "y = 0; faces surface, end (y = length/2; half: both "
        "ends), top (the cut z = R) and its symmetry planes",
    ),
    "R": Key("float", REQUIRED, unit="length", doc="roller radius", check=positive("R")),
    "length": Key(
        "float", REQUIRED, unit="length", doc="its full length along y", check=positive("length")
    ),
    "portion": _portion("the whole lower half"),
    **graded_keys("the contact line x = z = 0"),
}

BOX_KEYS = {
    "generator": Key(
        "str",
        REQUIRED,
        doc='"box" (3D): [x0, x0+width] x [y0, y0+depth] x '
        "[z0, z0+height]; faces bottom (z = z0), top, left "
        "(x = x0), right, front (y = y0), back",
    ),
    "x0": Key("float", 0.0, unit="length", doc="corner x"),
    "y0": Key("float", 0.0, unit="length", doc="corner y"),
    "z0": Key("float", 0.0, unit="length", doc="corner z"),
    "width": Key("float", REQUIRED, unit="length", doc="size in x", check=positive("width")),
    "depth": Key("float", REQUIRED, unit="length", doc="size in y", check=positive("depth")),
    "height": Key("float", REQUIRED, unit="length", doc="size in z", check=positive("height")),
    "nx": Key("int", 0, doc="structured box: divisions in x (0: from h)", check=non_negative("nx")),
    "ny": Key("int", 0, doc="structured box: divisions in y (0: from h)", check=non_negative("ny")),
    "nz": Key("int", 0, doc="structured box: divisions in z (0: from h)", check=non_negative("nz")),
    "h": Key(
        "float",
        0.0,
        unit="length",
        doc="structured box: element size when nx/ny/nz are " "0 (n = round(size/h))",
        check=non_negative("h"),
    ),
    **graded_keys("focus", "box"),
    "focus": Key(
        "vec3",
        None,
        unit="length",
        doc="graded box: the point [x, y, z] it is fine "
        "around, a node (default: the middle of the "
        "top face)",
    ),
}

PUNCH_KEYS = {
    "generator": Key(
        "str",
        REQUIRED,
        doc='"punch" (3D): a flat-ended prism along z, its flat '
        "end the face bottom (z = 0), its side face side, "
        "its other end top (z = height)",
    ),
    "shape": Key(
        "str",
        "round",
        doc='"round" (a cylinder of radius a) or "square" (side 2a)',
        choices=("round", "square"),
    ),
    "a": Key(
        "float",
        REQUIRED,
        unit="length",
        doc="radius (round) or half side (square)",
        check=positive("a"),
    ),
    "height": Key(
        "float", REQUIRED, unit="length", doc="its length along z", check=positive("height")
    ),
    "portion": Key(
        "str",
        "quarter",
        doc='the part meshed: "quarter" (x >= 0, y >= 0: faces '
        'symmetry_x, symmetry_y), "half" (y >= 0) or "whole"',
        choices=("quarter", "half", "whole"),
    ),
    **graded_keys("the rim of the flat end"),
}

SHELL_KEYS = {
    "generator": Key(
        "str",
        REQUIRED,
        doc='"shell" (3D): the eighth x, y, z >= 0 of a thick '
        "spherical shell a <= r <= b, centre (0, 0, 0); "
        "faces inner, outer, symmetry_x, symmetry_y, "
        "symmetry_z",
    ),
    "a": Key(
        "float", REQUIRED, unit="length", doc="inner radius", check=positive("the inner radius a")
    ),
    "b": Key(
        "float",
        REQUIRED,
        unit="length",
        doc="outer radius, > a",
        check=positive("the outer radius b"),
    ),
    "h": Key("float", REQUIRED, unit="length", doc="element size at r = a", check=positive("h")),
    "h_outer": Key(
        "float",
        0.0,
        unit="length",
        doc="element size at r = b, linear in r in between (0: uniform h)",
        check=non_negative("h_outer"),
    ),
}

#: The 3D generators and their keys.
MESH_VARIANTS_3D = {
    "sphere": SPHERE_KEYS,
    "roller": ROLLER_KEYS,
    "box": BOX_KEYS,
    "punch": PUNCH_KEYS,
    "shell": SHELL_KEYS,
}

_SYMMETRY = {
    "eighth": ("symmetry_x", "symmetry_y"),
    "quarter": ("symmetry_y",),
    "half": (),
    "whole": (),
}


def generator_faces(mesh: dict) -> tuple[str, ...]:
    """The face tags a 3D generator creates for the validated [body.mesh] table ``mesh``."""
    gen = mesh["generator"]
    if gen == "box":
        return ("bottom", "top", "left", "right", "front", "back")
    if gen == "shell":
        return ("inner", "outer", "symmetry_x", "symmetry_y", "symmetry_z")
    if gen == "punch":
        return ("bottom", "side", "top", *_SYMMETRY[mesh["portion"]])
    ends = ("end",) if gen == "roller" else ()
    return ("surface", "top", *ends, *_SYMMETRY[mesh["portion"]])


def box_divisions(mesh: dict) -> tuple[int, int, int]:
    """The structured box's cells (nx, ny, nz): as given, or round(size / h)."""
    return divisions(mesh)


# --------------------------------------------------------------------------- contact
def _window() -> dict:
    """The candidate window x_min ... z_max of a 3D contact."""
    return {
        f"{c}_{end}": Key(
            "float",
            (-1 if end == "min" else 1) * math.inf,
            unit="length",
            doc=f"candidates: contactor nodes with {c} {'>=' if end == 'min' else '<='} "
            f"{c}_{end}",
        )
        for c in "xyz"
        for end in ("min", "max")
    }


_FACE = Key("str", REQUIRED, doc="its candidate face tag", dims=(3,))
_TOLERANCE = Key(
    "float",
    1e-9,
    unit="length",
    doc="initial gaps in [-tolerance, 0) count as 0 (touching); below -tolerance is "
    "an initial penetration (an error)",
    check=non_negative("tolerance"),
)
_SIDE = Key(
    "str",
    "outside",
    doc='where the body is: "outside" the obstacle or "inside" it (a ' "cup or bore)",
    choices=("outside", "inside"),
)


def _rigid(shape: dict, what: str, common: dict) -> dict:
    """The keys of a rigid obstacle in space: the common ones, body, face, the ``shape``
    keys, the window, tolerance and motion."""
    return {
        **common,
        "body": Key("str", REQUIRED, doc="the deformable body"),
        "face": _FACE,
        **shape,
        **_window(),
        "tolerance": _TOLERANCE,
        "motion": Key(
            "vec3",
            None,
            unit="length",
            doc=f"translation [dx, dy, dz] of the {what} at factor 1 (a load)",
        ),
    }


def contact_variants_3d(common: dict) -> dict:
    """The 3D contact kinds and their keys, each with the keys every kind shares
    (``common``: kind, name, mu)."""
    plane = _rigid(
        {
            "point": Key("vec3", [0.0, 0.0, 0.0], unit="length", doc="a point of the rigid plane"),
            "normal": Key(
                "vec3",
                [0.0, 0.0, 1.0],
                doc="normal of the plane pointing to the body " "side",
                check=check_unit_free_vector,
            ),
        },
        "plane",
        common,
    )
    sphere = _rigid(
        {
            "centre": Key(
                "vec3", REQUIRED, unit="length", doc="centre [x, y, z] of the rigid " "sphere"
            ),
            "radius": Key(
                "float", REQUIRED, unit="length", doc="its radius", check=positive("the radius")
            ),
            "side": _SIDE,
        },
        "sphere",
        common,
    )
    cylinder = _rigid(
        {
            "point": Key("vec3", REQUIRED, unit="length", doc="a point [x, y, z] of its axis"),
            "axis": Key(
                "vec3",
                REQUIRED,
                doc="the direction of its axis (an infinite cylinder)",
                check=check_unit_free_vector,
            ),
            "radius": Key(
                "float", REQUIRED, unit="length", doc="its radius", check=positive("the radius")
            ),
            "side": _SIDE,
        },
        "cylinder",
        common,
    )
    surface = _rigid(
        {
            "file": Key(
                "str",
                "",
                doc="a triangulated surface: .stl, or .msh (its triangles); "
                "relative to the case file (or give indenter)",
            ),
            "scale": Key(
                "float", 1.0, doc="multiply the file's coordinates by this", check=positive("scale")
            ),
            "indenter": Key(
                "str",
                "",
                doc='a pyramid instead of a file: "vickers" (four faces, '
                '136 degrees between opposite faces) or "berkovich" '
                "(three faces, 65.27 degrees from the axis to a face), "
                "tip down at tip, axis z",
                choices=("", "vickers", "berkovich"),
            ),
            "tip": Key("vec3", [0.0, 0.0, 0.0], unit="length", doc="the indenter's tip"),
            "size": Key(
                "float",
                0.0,
                unit="length",
                doc="the indenter's height above its tip",
                check=non_negative("size"),
            ),
            "side": Key(
                "str",
                "outside",
                doc='where the body is: "outside" or "inside" a closed '
                'surface, or on the "front" (the side its triangles\' '
                'normals, counter-clockwise, point to) or "back" of '
                "any surface",
                choices=("outside", "inside", "front", "back"),
            ),
        },
        "surface",
        common,
    )
    mortar = {
        **common,
        "body_a": Key("str", REQUIRED, doc="contactor body (its nodes get the constraint rows)"),
        "face_a": Key("str", REQUIRED, doc="contactor face tag", dims=(3,)),
        "body_b": Key("str", REQUIRED, doc="target body"),
        "face_b": Key(
            "str",
            REQUIRED,
            doc="target face tag (its triangles' outward normals are " "the contact normals)",
            dims=(3,),
        ),
        **_window(),
        "tolerance": _TOLERANCE,
    }
    return {
        "rigid_plane": plane,
        "rigid_sphere": sphere,
        "rigid_cylinder": cylinder,
        "rigid_surface": surface,
        "node_to_surface": mortar,
    }


#: The 3D contact kinds whose target is a rigid obstacle (node_b = -1; they take `motion`).
RIGID_KINDS_3D = ("rigid_plane", "rigid_sphere", "rigid_cylinder", "rigid_surface")

#: A generator or kind of one dimension and what plays its part in the other, for messages.
COUNTERPARTS = {
    "sphere": "quarter_cylinder",
    "roller": "half_cylinder",
    "box": "block",
    "punch": "block",
    "shell": "quarter_annulus",
    "quarter_cylinder": "sphere",
    "half_cylinder": "roller",
    "disc": "roller",
    "block": "box",
    "quarter_annulus": "shell",
    "rigid_plane": "rigid_line",
    "rigid_sphere": "rigid_circle",
    "rigid_cylinder": "rigid_circle",
    "rigid_surface": "rigid_polyline",
    "node_to_surface": "node_to_segment",
    "rigid_line": "rigid_plane",
    "rigid_circle": "rigid_sphere",
    "rigid_polyline": "rigid_surface",
    "node_to_segment": "node_to_surface",
}
