"""The case schema: every table and key a case file may hold, with its type, default, unit,
meaning and value check (:class:`Key`).  ``cases/README.md`` documents the same keys, and
``slipstep keys`` prints them from here; :mod:`slipstep.validation` checks a document against
them and :mod:`slipstep.overrides` addresses them with ``--set``.
"""

from __future__ import annotations

import math
from typing import Any, Callable

from ..key import REQUIRED, Key, check_unit_free_vector, non_negative, positive
from .sizes import divisions, graded_keys
from .solid import MESH_VARIANTS_3D, RIGID_KINDS_3D, contact_variants_3d, generator_faces
from ..toml_writing import toml_text

# Key and REQUIRED are read through here by the rest of the package (declared in .key)


def _check_nu(nu: float) -> str | None:
    if -1.0 < nu < 0.5:
        return None
    return "Poisson's ratio must satisfy -1 < nu < 0.5 (use 0.499 for near-incompressible)"


def _check_snapshots_form(v) -> str | None:
    """The form only; the range (0, n_stages] is checked once the stages are known."""
    if isinstance(v, str):
        return (
            None
            if v in ("auto", "events")
            else 'use "auto", "events" or a list of load fractions in (0, 1]'
        )
    if not v:
        return 'the list is empty: use "auto", "events" or e.g. [0.25, 0.5, 1.0]'
    return None


def check_snapshot_times(v: list, n_stages: int) -> str | None:
    """Times in (0, n_stages], strictly increasing (worded as load fractions for one stage)."""
    what = "load fraction" if n_stages == 1 else "snapshot time"
    where = "" if n_stages == 1 else " (stage k runs over path time t in [k-1, k])"
    if any(not (0.0 < f <= n_stages) for f in v):
        return f"every {what} must lie in (0, {n_stages}]{where}"
    if any(b <= a for a, b in zip(v, v[1:])):
        return f"the {what}s must be strictly increasing"
    return None


CASE_KEYS = {
    "name": Key("str", "unnamed", doc="short name, used in file names and figure titles"),
    "description": Key("str", "", doc="free text"),
    "units": Key(
        "str",
        "consistent units (e.g. mm, N, MPa)",
        doc="a note only: slipstep uses whatever consistent units the numbers are in",
    ),
}

ANALYSIS_KEYS = {
    "dimension": Key(
        "int",
        2,
        doc="2: a plane section or rings about an axis (linear "
        "triangles, see plane); 3: bodies in space (linear "
        "tetrahedra, x, y, z; no plane, no thickness)",
        choices=(2, 3),
    ),
    "plane": Key(
        "str",
        "strain",
        doc='2D idealisation: "strain", "stress" or "axisymmetric" '
        "(rings about the axis x = 0: x = r >= 0, y = z; forces "
        "are totals over the full ring)",
        choices=("strain", "stress", "axisymmetric"),
        dims=(2,),
    ),
    "thickness": Key(
        "float",
        1.0,
        unit="length",
        doc="out-of-plane thickness t (plane strain " "and plane stress only)",
        check=positive("the thickness"),
        dims=(2,),
    ),
}

LOAD_KEYS = {
    "P": Key(
        "float",
        REQUIRED,
        unit="force/length",
        doc="Hertz convenience: total compressive line load on the FULL cylinder per unit "
        "thickness; the quarter model gets pressure q = P/(2R) on its cut edge `top`. "
        'With plane = "axisymmetric" the quarter section is a hemisphere and P the '
        "total force [force] on the sphere: q = P/(pi R^2) on the cut. In 3D "
        "(dimension = 3) P is the total force on a `sphere` body, whose part (eighth, "
        "quarter or half) carries its share: q = P/(pi R^2) on its cut face `top`",
        check=positive("the load P"),
    ),
    "body": Key(
        "str",
        "",
        doc="the quarter_cylinder (3D: sphere) body it acts on (default: " "the only one)",
    ),
}

OUTPUT_KEYS = {
    "snapshots": Key(
        "snapshots",
        "auto",
        doc='"auto" (sized for the scene: in 2D "events"; in 3D the stage ends and '
        "evenly spaced path times, at most 10 per stage, as many as keep "
        'results.h5 within 100 MB), "events" (a snapshot after every event: '
        "the full-field history) or a list of path times in (0, n_stages] (= "
        "load fractions in (0, 1] without [[stage]]; every stage end is always "
        "added)",
        check=_check_snapshots_form,
    ),
    "figures": Key("bool", True, doc="write PNG figures"),
    "xdmf": Key("bool", True, doc="write the XDMF/HDF5 time series of u and stresses"),
}


def _within(spec: dict) -> Callable[[Any], str | None]:
    """The check of an engine option's range (``min``/``max``: None or (value, inclusive))."""
    lo, hi = spec["min"], spec["max"]

    def check(v) -> str | None:
        if lo is not None and not (v > lo[0] or (lo[1] and v == lo[0])):
            return f"must be {'>=' if lo[1] else '>'} {lo[0]:g}"
        if hi is not None and not (v < hi[0] or (hi[1] and v == hi[0])):
            return f"must be {'<=' if hi[1] else '<'} {hi[0]:g}"
        return None

    return check


def _solver_keys() -> dict:
    """[solver]: the engine's options as the engine declares them (rust/src/options.rs, through
    ``slipstep._engine.option_specs()``): key, kind, default, allowed range and meaning live
    there once; a case's [solver] table reaches the engine key by key, unchanged."""
    from .._engine import option_specs

    kinds = {"real": "float", "count": "int", "flag": "bool", "choice": "str"}
    return {
        s["key"]: Key(
            kinds[s["kind"]],
            s["default"],
            doc=s["doc"],
            check=_within(s) if s["kind"] in ("real", "count") else None,
            choices=tuple(s.get("choices", ())),
        )
        for s in option_specs()
    }


SOLVER_KEYS = _solver_keys()

BODY_KEYS = {
    "name": Key("str", REQUIRED, doc="unique body name, used by [[bc]] and [[contact]]"),
    # "mesh" and "material" are sub-tables, declared below
}

MATERIAL_KEYS = {
    "E": Key(
        "float", REQUIRED, unit="stress", doc="Young's modulus", check=positive("Young's modulus E")
    ),
    "nu": Key("float", REQUIRED, doc="Poisson's ratio", check=_check_nu),
    "Sy": Key(
        "float",
        None,
        unit="stress",
        doc="yield stress (optional; plasticity)",
        check=positive("the yield stress Sy"),
    ),
    "H": Key(
        "float",
        None,
        unit="stress",
        doc="plastic (hardening) modulus H' (optional; 0 = perfectly plastic)",
        check=non_negative("the hardening modulus H"),
    ),
}

QUARTER_CYLINDER_KEYS = {
    "generator": Key(
        "str",
        REQUIRED,
        doc='"quarter_cylinder" (x >= 0), "half_cylinder" (the quarter mirrored: tags arc, top) or "disc" (the whole circle: tags lower_arc, upper_arc, circle)',
    ),
    "R": Key(
        "float",
        REQUIRED,
        unit="length",
        doc="cylinder radius; centre at (0, R), bottom " "point at (0, 0)",
        check=positive("R"),
    ),
    **graded_keys("the bottom point (0, 0)"),
}

BLOCK_KEYS = {
    "generator": Key("str", REQUIRED, doc='"block"'),
    "x0": Key("float", 0.0, unit="length", doc="lower-left corner x"),
    "y0": Key("float", 0.0, unit="length", doc="lower-left corner y"),
    "width": Key("float", REQUIRED, unit="length", doc="size in x", check=positive("width")),
    "height": Key("float", REQUIRED, unit="length", doc="size in y", check=positive("height")),
    "nx": Key("int", 0, doc="divisions in x (0: from h)", check=non_negative("nx")),
    "ny": Key("int", 0, doc="divisions in y (0: from h)", check=non_negative("ny")),
    "h": Key(
        "float",
        0.0,
        unit="length",
        doc="target element size when nx/ny are 0 (n = round(size/h))",
        check=non_negative("h"),
    ),
    # the graded block (gmsh), when h_contact > 0; nx, ny and h are then not used
    **graded_keys("focus", "block", refined="h + growth * d from the box"),
    "focus": Key(
        "vec2",
        None,
        unit="length",
        doc="graded block: the point [x, y] it is fine around, inside or on the "
        "boundary (default: the middle of the top edge)",
    ),
    "uniform_edges": Key(
        "bool",
        False,
        doc="graded block with focus on the boundary: divide the side from "
        "focus to a corner within contact_zone uniformly at h_contact, so "
        "a structured body's nodes can match it (node_to_node)",
    ),
    # the refined block: the structured one (nx/ny or h) kept inside refine_box, gmsh outside
    "refine_box": Key(
        "box",
        None,
        unit="length",
        doc="structured block: keep its grid (nx/ny or h) only inside this box "
        "[x0, y0, x1, y1] (rounded out to grid lines) and coarsen the rest "
        "up to h_max (gmsh)",
    ),
}

QUARTER_ANNULUS_KEYS = {
    "generator": Key("str", REQUIRED, doc='"quarter_annulus"'),
    "a": Key(
        "float",
        REQUIRED,
        unit="length",
        doc="inner radius (the bore); centre (0, 0)",
        check=positive("the inner radius a"),
    ),
    "b": Key(
        "float",
        REQUIRED,
        unit="length",
        doc="outer radius, > a",
        check=positive("the outer radius b"),
    ),
    "h": Key(
        "float", REQUIRED, unit="length", doc="element size at the bore r = a", check=positive("h")
    ),
    "h_outer": Key(
        "float",
        0.0,
        unit="length",
        doc="element size at r = b, linear in r in between (0: uniform h)",
        check=non_negative("h_outer"),
    ),
}

FILE_MESH_KEYS = {
    "file": Key(
        "str",
        REQUIRED,
        doc="triangle mesh .msh (gmsh physical names = edge tags) or "
        ".xdmf (meshio; line cells tagged by an integer cell "
        "array); in 3D a tetrahedron mesh, its physical surfaces "
        "(.msh) or tagged triangle cells (.xdmf) the face tags; "
        "relative to the case file",
    ),
    "edge_file": Key(
        "str",
        "",
        doc=".xdmf holding the tagged line cells when they are kept "
        "apart from the triangles (dolfinx style)",
        dims=(2,),
    ),
    "face_file": Key(
        "str",
        "",
        doc=".xdmf holding the tagged triangle cells (faces) when they "
        "are kept apart from the tetrahedra (dolfinx style)",
        dims=(3,),
    ),
    "scale": Key("float", 1.0, doc="multiply the coordinates by this", check=positive("scale")),
}

GIVEN_MESH_KEYS = {
    "generator": Key(
        "str",
        REQUIRED,
        doc='"given": the mesh comes from Python, '
        "slipstep.run(case, meshes={body: mesh}) (a "
        "slipstep.mesh.Mesh: from_arrays, from_meshio)",
    ),
}

MESH_VARIANTS = {
    "quarter_cylinder": QUARTER_CYLINDER_KEYS,
    "half_cylinder": QUARTER_CYLINDER_KEYS,
    "disc": QUARTER_CYLINDER_KEYS,
    "block": BLOCK_KEYS,
    "quarter_annulus": QUARTER_ANNULUS_KEYS,
    "given": GIVEN_MESH_KEYS,
    **MESH_VARIANTS_3D,
}


def generator_dimension(generator: str) -> int | None:
    """The case dimension a generator meshes for (None: "given", either)."""
    if generator == "given":
        return None
    return 3 if generator in MESH_VARIANTS_3D else 2


def block_divisions(mesh: dict) -> tuple[int, int]:
    """The structured block's cells (nx, ny): as given, or round(size / h)."""
    return divisions(mesh)


def generator_tags(mesh: dict) -> tuple[str, ...] | None:
    """The edge tags (3D: face tags) a validated [body.mesh] table's generator creates; None
    for a file or "given" mesh (known once it is read)."""
    gen = mesh.get("generator")
    if gen in MESH_VARIANTS_3D:
        return generator_faces(mesh)
    return GENERATOR_EDGES.get(gen)


#: Edge tags that the 2D generators create (file meshes bring their own).
GENERATOR_EDGES = {
    "quarter_cylinder": ("arc", "symmetry", "top"),
    "half_cylinder": ("arc", "top"),
    "disc": ("lower_arc", "upper_arc", "circle"),
    "block": ("bottom", "right", "top", "left"),
    "quarter_annulus": ("inner", "outer", "x_axis", "y_axis"),
}

BC_KEYS = {
    "name": Key("str", "", doc="optional name, to address it as bc.<name>.* in --set"),
    "body": Key("str", REQUIRED, doc="body name"),
    "edge": Key("str", "", doc="edge tag of that body (or give `nodes`)", dims=(2,)),
    "face": Key("str", "", doc="face tag of that body (3D; or give `nodes`)", dims=(3,)),
    "nodes": Key(
        "str", "", doc="node-set name of that body (supports `fix` and " "`displacement` only)"
    ),
    "fix": Key(
        "axes", [], doc='components held at zero: ["x"], ["y"] or ["x", "y"] (3D: ' 'also "z")'
    ),
    "symmetry": Key(
        "bool",
        False,
        doc="hold the normal component (the edge must be parallel "
        "to an axis; in 3D the face a plane parallel to a "
        "coordinate plane)",
    ),
    "pressure": Key(
        "float", 0.0, unit="stress", doc="uniform pressure q, acting against the outward normal"
    ),
    "traction": Key(
        "vec", [0.0, 0.0], unit="stress", doc="uniform traction [tx, ty] (3D: [tx, ty, tz])"
    ),
    "displacement": Key(
        "xy",
        {},
        unit="length",
        doc="prescribed displacement components at factor 1, e.g. {y = -0.1} "
        "(a load, eliminated exactly like a support; 3D: z too)",
    ),
}

POINT_LOAD_KEYS = {
    "name": Key("str", "", doc="optional name"),
    "body": Key("str", "", doc="restrict the node search to this body (default: all bodies)"),
    "at": Key(
        "vec",
        REQUIRED,
        unit="length",
        doc="the load goes to the node nearest this " "point ([x, y]; 3D: [x, y, z])",
    ),
    "force": Key(
        "vec",
        REQUIRED,
        unit="force/length",
        doc='[Fx, Fy] per unit thickness (plane = "axisymmetric": the total over the '
        "node's ring [force]; 3D: [Fx, Fy, Fz], a force [force])",
    ),
}

_CONTACT_COMMON = {
    "kind": Key(
        "str",
        REQUIRED,
        doc='the contact kind: "rigid_line", "rigid_circle", '
        '"rigid_polyline" (a deformable body against a rigid '
        'obstacle) or a deformable pair ("node_to_node", ...); in '
        '3D "rigid_plane", "rigid_sphere", "rigid_cylinder", '
        '"rigid_surface", "node_to_node" or "node_to_surface"',
    ),
    "name": Key("str", "", doc="optional name"),
    "mu": Key("float", 0.0, doc="Coulomb friction coefficient", check=non_negative("mu")),
}

RIGID_LINE_KEYS = {
    **_CONTACT_COMMON,
    "body": Key("str", REQUIRED, doc="the deformable body"),
    "edge": Key("str", REQUIRED, doc="its candidate edge tag"),
    "point": Key("vec2", [0.0, 0.0], unit="length", doc="a point of the rigid line"),
    "normal": Key(
        "vec2",
        [0.0, 1.0],
        doc="normal of the line pointing to the body side",
        check=check_unit_free_vector,
    ),
    "x_min": Key("float", -math.inf, unit="length", doc="candidates: nodes with x >= x_min"),
    "x_max": Key("float", math.inf, unit="length", doc="candidates: nodes with x <= x_max"),
    "y_min": Key("float", -math.inf, unit="length", doc="candidates: nodes with y >= y_min"),
    "y_max": Key("float", math.inf, unit="length", doc="candidates: nodes with y <= y_max"),
    "tolerance": Key(
        "float",
        1e-9,
        unit="length",
        doc="gaps in [-tolerance, 0) count as 0; below -tolerance is an error",
        check=non_negative("tolerance"),
    ),
    "motion": Key(
        "vec2",
        None,
        unit="length",
        doc="translation [dx, dy] of the rigid line at factor 1 (a load)",
    ),
}


def _check_polyline(points) -> str | None:
    """At least two points, no zero-length segment, no segment folding back onto the last."""
    if len(points) < 2:
        return f"a polyline needs at least 2 points, got {len(points)}"
    for k in range(len(points) - 1):
        if points[k] == points[k + 1]:
            return (
                f"points {k} and {k + 1} are both {toml_text(points[k])}: a zero-length segment; "
                f"remove one of them"
            )
        dx, dy = points[k + 1][0] - points[k][0], points[k + 1][1] - points[k][1]
        if not 0.0 < dx * dx + dy * dy < math.inf:  # its squared length under- or overflows
            return (
                f"the segment from point {k} to point {k + 1} is too short or too long to "
                f"compute with: rescale the coordinates"
            )
    for k in range(len(points) - 2):
        (x0, y0), (x1, y1), (x2, y2) = points[k : k + 3]
        d, e = (x1 - x0, y1 - y0), (x2 - x1, y2 - y1)
        if d[0] * e[1] - d[1] * e[0] == 0.0 and d[0] * e[0] + d[1] * e[1] < 0.0:
            return (
                f"the segments before and after point {k + 1} fold back onto each other "
                f"(the normal at that vertex is undefined): remove point {k + 1}"
            )
    return None


def _rigid_obstacle_keys(shape: dict, what: str) -> dict:
    """The keys of a rigid obstacle of any shape: body, edge, the ``shape`` keys, the candidate
    window, tolerance and motion (as for the rigid line)."""
    return {
        **_CONTACT_COMMON,
        "body": RIGID_LINE_KEYS["body"],
        "edge": RIGID_LINE_KEYS["edge"],
        **shape,
        **{k: RIGID_LINE_KEYS[k] for k in ("x_min", "x_max", "y_min", "y_max", "tolerance")},
        "motion": Key(
            "vec2",
            None,
            unit="length",
            doc=f"translation [dx, dy] of the {what} at factor 1 (a load)",
        ),
    }


RIGID_CIRCLE_KEYS = _rigid_obstacle_keys(
    {
        "centre": Key("vec2", REQUIRED, unit="length", doc="centre [x, y] of the rigid circle"),
        "radius": Key(
            "float",
            REQUIRED,
            unit="length",
            doc="radius of the rigid circle",
            check=positive("the radius"),
        ),
        "side": Key(
            "str",
            "outside",
            doc='where the body is: "outside" the circle (a rigid '
            'cylinder pressed into it) or "inside" (in a circular '
            'hole or cup)',
            choices=("outside", "inside"),
        ),
    },
    "circle",
)

RIGID_POLYLINE_KEYS = _rigid_obstacle_keys(
    {
        "points": Key(
            "points",
            REQUIRED,
            unit="length",
            doc="vertices [[x, y], ...] of the rigid polyline, at least 2, no two "
            "consecutive ones equal",
            check=_check_polyline,
        ),
        "side": Key(
            "str",
            REQUIRED,
            doc='the side the body lies on, walking the polyline from its '
            'first point to its last: "left" or "right"',
            choices=("left", "right"),
        ),
    },
    "polyline",
)

#: The contact kinds whose target is a rigid obstacle (node_b = -1; they take `motion`).
RIGID_KINDS = ("rigid_line", "rigid_circle", "rigid_polyline")

NODE_TO_NODE_KEYS = {
    **_CONTACT_COMMON,
    "body_a": Key("str", REQUIRED, doc="contactor body"),
    "edge_a": Key("str", "", doc="contactor edge tag", dims=(2,), required_in=(2,)),
    "face_a": Key("str", "", doc="contactor face tag (3D)", dims=(3,), required_in=(3,)),
    "body_b": Key("str", REQUIRED, doc="target body"),
    "edge_b": Key("str", "", doc="target edge tag", dims=(2,), required_in=(2,)),
    "face_b": Key("str", "", doc="target face tag (3D)", dims=(3,), required_in=(3,)),
    "tolerance": Key(
        "float",
        1e-6,
        unit="length",
        doc="pair node a with the nearest node b within this distance",
        check=positive("tolerance"),
    ),
    "normal": Key(
        "vec",
        None,
        doc="fixed normal for every pair (default: outward normal of "
        "edge_b (face_b) averaged at node b)",
        check=check_unit_free_vector,
    ),
}

NODE_TO_SEGMENT_KEYS = {
    **_CONTACT_COMMON,
    "body_a": Key("str", REQUIRED, doc="contactor body (its nodes get the constraint rows)"),
    "edge_a": Key("str", REQUIRED, doc="contactor edge tag"),
    "body_b": Key("str", REQUIRED, doc="target body"),
    "edge_b": Key(
        "str",
        REQUIRED,
        doc="target edge tag (a polyline: its segments' outward "
        "normals are the contact normals)",
    ),
    "x_min": Key(
        "float", -math.inf, unit="length", doc="candidates: contactor nodes with x >= x_min"
    ),
    "x_max": Key(
        "float", math.inf, unit="length", doc="candidates: contactor nodes with x <= x_max"
    ),
    "y_min": Key(
        "float", -math.inf, unit="length", doc="candidates: contactor nodes with y >= y_min"
    ),
    "y_max": Key(
        "float", math.inf, unit="length", doc="candidates: contactor nodes with y <= y_max"
    ),
    "tolerance": Key(
        "float",
        1e-9,
        unit="length",
        doc="initial gaps in [-tolerance, 0) count as 0 (touching); below "
        "-tolerance is an initial penetration (an error)",
        check=non_negative("tolerance"),
    ),
}

CONTACT_VARIANTS = {
    "rigid_line": RIGID_LINE_KEYS,
    "rigid_circle": RIGID_CIRCLE_KEYS,
    "rigid_polyline": RIGID_POLYLINE_KEYS,
    "node_to_node": NODE_TO_NODE_KEYS,
    "node_to_segment": NODE_TO_SEGMENT_KEYS,
    **contact_variants_3d(_CONTACT_COMMON),
}

#: Every contact kind whose target is a rigid obstacle, of either dimension.
RIGID_OBSTACLES = RIGID_KINDS + RIGID_KINDS_3D


def kind_dimension(kind: str) -> int | None:
    """The case dimension a contact kind belongs to (None: node_to_node, either)."""
    if kind == "node_to_node":
        return None
    return 3 if kind in RIGID_KINDS_3D or kind == "node_to_surface" else 2


def contact_tags(contact: dict) -> list[tuple[str, str, str]]:
    """(key, body, tag) of every surface a validated [[contact]] names, contactor first:
    ``edge``/``face`` of a rigid obstacle, ``edge_a``/``face_a`` and ``edge_b``/``face_b`` of a
    pair (the 3D key when it is given)."""
    if contact["kind"] in RIGID_OBSTACLES:
        key = "face" if contact.get("face") else "edge"
        return [(key, contact["body"], contact[key])]
    out = []
    for side in "ab":
        key = f"face_{side}" if contact.get(f"face_{side}") else f"edge_{side}"
        out.append((key, contact[f"body_{side}"], contact[key]))
    return out


STAGE_KEYS = {
    "name": Key("str", "", doc='optional name (default "stage <k>", 1-based)'),
    "factors": Key(
        "factors",
        REQUIRED,
        doc="the factor each named load reaches at the end of the stage, e.g. "
        "{load = 1.0}; loads not named keep their factor",
    ),
}

#: Top-level tables and arrays of tables.
TABLES = {
    "case": CASE_KEYS,
    "analysis": ANALYSIS_KEYS,
    "load": LOAD_KEYS,
    "output": OUTPUT_KEYS,
    "solver": SOLVER_KEYS,
}
ARRAYS = ("body", "bc", "point_load", "contact", "stage")


def _union(*tables: dict) -> dict:
    out: dict = {}
    for t in tables:
        out.update(t)
    return out


#: Every key an element of an array (or a body sub-table) may hold, for --set and unknown keys.
ARRAY_KEYS = {
    "body": BODY_KEYS,
    "bc": BC_KEYS,
    "point_load": POINT_LOAD_KEYS,
    "contact": _union(*CONTACT_VARIANTS.values()),
    "stage": STAGE_KEYS,
}
BODY_SUBTABLES = {
    "mesh": _union(
        QUARTER_CYLINDER_KEYS,
        BLOCK_KEYS,
        QUARTER_ANNULUS_KEYS,
        *MESH_VARIANTS_3D.values(),
        FILE_MESH_KEYS,
    ),
    "material": MATERIAL_KEYS,
}
