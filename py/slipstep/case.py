"""The scene description: load a case TOML file, apply ``--set`` overrides, validate.

A case is a TOML file (schema in ``cases/README.md``; the same schema is declared below in
``SCHEMA`` and every key there is checked).  ``load_case`` returns a :class:`Case` whose
``data`` is the validated document with every default filled in, so the rest of the package
reads plain dicts and never guesses.

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

import copy
import math
import tomllib
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any, Callable

from .errors import InputError


class CaseError(InputError):
    """A problem in a case file or an override; the message is one line and names the fix."""


# --------------------------------------------------------------------------- the schema
REQUIRED = object()  # marker: the key has no default


@dataclass(frozen=True)
class Key:
    """One key of a table: its type, default, unit, meaning and an optional value check.

    ``type`` is one of ``"float"``, ``"int"``, ``"str"``, ``"bool"``, ``"vec2"`` (two floats),
    ``"box"`` (four floats [x0, y0, x1, y1]),
    ``"axes"`` (a list of ``"x"``/``"y"``), ``"snapshots"`` (``"events"`` or a list of path
    times), ``"xy"`` (an inline table of floats x and/or y), ``"factors"`` (an inline table of
    floats by load name).  ``check(value)`` returns ``None`` or the reason the value is not
    allowed.
    """

    type: str
    default: Any = REQUIRED
    unit: str = ""
    doc: str = ""
    check: Callable[[Any], str | None] | None = None
    choices: tuple = ()


def _positive(what: str) -> Callable[[Any], str | None]:
    return lambda v: None if v > 0 else f"{what} must be > 0"


def _non_negative(what: str) -> Callable[[Any], str | None]:
    return lambda v: None if v >= 0 else f"{what} must be >= 0"


def _fraction_below_one(what: str) -> Callable[[Any], str | None]:
    return lambda v: None if 0 <= v < 1 else f"{what} must lie in [0, 1) (0 = the exact event procedure)"


def _check_nu(nu: float) -> str | None:
    if -1.0 < nu < 0.5:
        return None
    return "Poisson's ratio must satisfy -1 < nu < 0.5 (use 0.499 for near-incompressible)"


def _check_unit_free_vector(v) -> str | None:
    return None if math.hypot(*v) > 0 else "the normal must be a non-zero vector"


def _check_snapshots_form(v) -> str | None:
    """The form only; the range (0, n_stages] is checked once the stages are known."""
    if isinstance(v, str):
        return None if v == "events" else 'use "events" or a list of load fractions in (0, 1]'
    if not v:
        return 'the list is empty: use "events" or e.g. [0.25, 0.5, 1.0]'
    return None


def _check_snapshot_times(v: list, n_stages: int) -> str | None:
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
    "units": Key("str", "consistent units (e.g. mm, N, MPa)",
                 doc="a note only: slipstep uses whatever consistent units the numbers are in"),
}

ANALYSIS_KEYS = {
    "plane": Key("str", "strain", doc='2D idealisation: "strain", "stress" or "axisymmetric" '
                                      "(rings about the axis x = 0: x = r >= 0, y = z; forces "
                                      "are totals over the full ring)",
                 choices=("strain", "stress", "axisymmetric")),
    "thickness": Key("float", 1.0, unit="length", doc="out-of-plane thickness t (plane strain "
                                                      "and plane stress only)",
                     check=_positive("the thickness")),
}

LOAD_KEYS = {
    "P": Key("float", REQUIRED, unit="force/length",
             doc="Hertz convenience: total compressive line load on the FULL cylinder per unit "
                 "thickness; the quarter model gets pressure q = P/(2R) on its cut edge `top`. "
                 'With plane = "axisymmetric" the quarter section is a hemisphere and P the '
                 "total force [force] on the sphere: q = P/(pi R^2) on the cut",
             check=_positive("the load P")),
    "body": Key("str", "", doc="the quarter_cylinder body it acts on (default: the only one)"),
}

OUTPUT_KEYS = {
    "snapshots": Key("snapshots", "events",
                     doc='"events" (a snapshot after every event) or a list of path times in '
                         "(0, n_stages] (= load fractions in (0, 1] without [[stage]]; every "
                         "stage end is always added)", check=_check_snapshots_form),
    "figures": Key("bool", True, doc="write PNG figures"),
    "xdmf": Key("bool", True, doc="write the XDMF/HDF5 time series of u and stresses"),
}

SOLVER_KEYS = {
    "tie_tol": Key("float", 1e-9, doc="relative tie tolerance: events with S <= S_min(1+tie_tol) "
                                      "are applied together", check=_non_negative("tie_tol")),
    "group_tol": Key("float", 0.03, doc="grouped plastic increments, the speed-accuracy knob "
                                        "(0 = exact, event by event): an increment runs on past "
                                        "the first yield by group_tol of the load; elements "
                                        "yielding inside get the exact elastic-plastic split; < 1",
                      check=_fraction_below_one("group_tol")),
    "max_events": Key("int", 0, doc="stop after this many events (0 = automatic bound)",
                      check=_non_negative("max_events")),
    "equilibrium_tol": Key("float", 1e-9, doc="relative equilibrium residual that is accepted",
                           check=_positive("equilibrium_tol")),
    "drift_control": Key("bool", True, doc="plasticity: bound the stress increment of plastic "
                                           "elements and return to the yield surface after each "
                                           "increment (false = the paper exactly)"),
    "max_stress_step": Key("float", 0.05, doc="plasticity, with drift_control: largest von Mises "
                                              "stress increment of a plastic element, x Sy",
                           check=_positive("max_stress_step")),
    "tangent_turn": Key("float", 0.05, doc="plasticity: a plastic element's tangent in the "
                                           "stiffness is renewed when its flow direction has "
                                           "turned by more than this angle (radians; 0 = at "
                                           "every increment, as the paper)",
                        check=_non_negative("tangent_turn")),
    "stop_at_first_yield": Key("bool", False, doc="plasticity: end the run right after the "
                                                  "first yield event"),
}

BODY_KEYS = {
    "name": Key("str", REQUIRED, doc="unique body name, used by [[bc]] and [[contact]]"),
    # "mesh" and "material" are sub-tables, declared below
}

MATERIAL_KEYS = {
    "E": Key("float", REQUIRED, unit="stress", doc="Young's modulus",
             check=_positive("Young's modulus E")),
    "nu": Key("float", REQUIRED, doc="Poisson's ratio", check=_check_nu),
    "Sy": Key("float", None, unit="stress", doc="yield stress (optional; plasticity)",
              check=_positive("the yield stress Sy")),
    "H": Key("float", None, unit="stress", doc="plastic (hardening) modulus H' (optional; 0 = perfectly plastic)",
             check=_non_negative("the hardening modulus H")),
}

QUARTER_CYLINDER_KEYS = {
    "generator": Key("str", REQUIRED, doc='"quarter_cylinder" (x >= 0), "half_cylinder" (the quarter mirrored: tags arc, top) or "disc" (the whole circle: tags lower_arc, upper_arc, circle)'),
    "R": Key("float", REQUIRED, unit="length", doc="cylinder radius; centre at (0, R), bottom "
                                                    "point at (0, 0)", check=_positive("R")),
    "h_contact": Key("float", REQUIRED, unit="length",
                     doc="element size within contact_zone of the bottom point (0, 0)",
                     check=_positive("h_contact")),
    "contact_zone": Key("float", REQUIRED, unit="length",
                        doc="radius of the fine zone around (0, 0)",
                        check=_positive("contact_zone")),
    "h_max": Key("float", REQUIRED, unit="length", doc="largest element size",
                 check=_positive("h_max")),
    "growth": Key("float", 0.1, doc="size growth per unit distance outside the zone "
                                    "(h = h_contact + growth * (d - contact_zone))",
                  check=_positive("growth")),
}

BLOCK_KEYS = {
    "generator": Key("str", REQUIRED, doc='"block"'),
    "x0": Key("float", 0.0, unit="length", doc="lower-left corner x"),
    "y0": Key("float", 0.0, unit="length", doc="lower-left corner y"),
    "width": Key("float", REQUIRED, unit="length", doc="size in x", check=_positive("width")),
    "height": Key("float", REQUIRED, unit="length", doc="size in y", check=_positive("height")),
    "nx": Key("int", 0, doc="divisions in x (0: from h)", check=_non_negative("nx")),
    "ny": Key("int", 0, doc="divisions in y (0: from h)", check=_non_negative("ny")),
    "h": Key("float", 0.0, unit="length",
             doc="target element size when nx/ny are 0 (n = round(size/h))",
             check=_non_negative("h")),
    # the graded block (gmsh), when h_contact > 0; nx, ny and h are then not used
    "h_contact": Key("float", 0.0, unit="length",
                     doc="graded block (gmsh): element size within contact_zone of focus "
                         "(0 = the structured block of nx/ny or h)",
                     check=_non_negative("h_contact")),
    "contact_zone": Key("float", 0.0, unit="length",
                        doc="graded block: radius of the fine zone around focus",
                        check=_positive("contact_zone")),
    "h_max": Key("float", 0.0, unit="length", doc="graded or refined block: largest element "
                                                  "size", check=_positive("h_max")),
    "growth": Key("float", 0.1, doc="graded or refined block: size growth per unit distance "
                                    "outside the fine zone (graded: h = h_contact + growth * (d "
                                    "- contact_zone); refined: h + growth * d from the box)",
                  check=_positive("growth")),
    "focus": Key("vec2", None, unit="length",
                 doc="graded block: the point [x, y] it is fine around, inside or on the "
                     "boundary (default: the middle of the top edge)"),
    "uniform_edges": Key("bool", False,
                         doc="graded block with focus on the boundary: divide the side from "
                             "focus to a corner within contact_zone uniformly at h_contact, so "
                             "a structured body's nodes can match it (node_to_node)"),
    # the refined block: the structured one (nx/ny or h) kept inside refine_box, gmsh outside
    "refine_box": Key("box", None, unit="length",
                      doc="structured block: keep its grid (nx/ny or h) only inside this box "
                          "[x0, y0, x1, y1] (rounded out to grid lines) and coarsen the rest "
                          "up to h_max (gmsh)"),
}

QUARTER_ANNULUS_KEYS = {
    "generator": Key("str", REQUIRED, doc='"quarter_annulus"'),
    "a": Key("float", REQUIRED, unit="length", doc="inner radius (the bore); centre (0, 0)",
             check=_positive("the inner radius a")),
    "b": Key("float", REQUIRED, unit="length", doc="outer radius, > a",
             check=_positive("the outer radius b")),
    "h": Key("float", REQUIRED, unit="length", doc="element size at the bore r = a",
             check=_positive("h")),
    "h_outer": Key("float", 0.0, unit="length",
                   doc="element size at r = b, linear in r in between (0: uniform h)",
                   check=_non_negative("h_outer")),
}

FILE_MESH_KEYS = {
    "file": Key("str", REQUIRED, doc="triangle mesh .msh (gmsh physical names = edge tags) or "
                                     ".xdmf (meshio; line cells tagged by an integer cell "
                                     "array); relative to the case file"),
    "edge_file": Key("str", "", doc=".xdmf holding the tagged line cells when they are kept "
                                    "apart from the triangles (dolfinx style)"),
    "scale": Key("float", 1.0, doc="multiply the coordinates by this", check=_positive("scale")),
}

GIVEN_MESH_KEYS = {
    "generator": Key("str", REQUIRED, doc='"given": the mesh comes from Python, '
                                          "slipstep.run(case, meshes={body: mesh}) (a "
                                          "slipstep.mesh.Mesh: from_arrays, from_meshio)"),
}

MESH_VARIANTS = {"quarter_cylinder": QUARTER_CYLINDER_KEYS,
                 "half_cylinder": QUARTER_CYLINDER_KEYS, "disc": QUARTER_CYLINDER_KEYS,
                 "block": BLOCK_KEYS,
                 "quarter_annulus": QUARTER_ANNULUS_KEYS, "given": GIVEN_MESH_KEYS}

def block_divisions(mesh: dict) -> tuple[int, int]:
    """The structured block's cells (nx, ny): as given, or round(size / h)."""
    return (mesh["nx"] or max(1, round(mesh["width"] / mesh["h"])),
            mesh["ny"] or max(1, round(mesh["height"] / mesh["h"])))


#: Edge tags that the generators create (file meshes bring their own).
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
    "edge": Key("str", "", doc="edge tag of that body (or give `nodes`)"),
    "nodes": Key("str", "", doc="node-set name of that body (supports `fix` and "
                                "`displacement` only)"),
    "fix": Key("axes", [], doc='components held at zero: ["x"], ["y"] or ["x", "y"]'),
    "symmetry": Key("bool", False, doc="hold the normal component (edge must be parallel to an axis)"),
    "pressure": Key("float", 0.0, unit="stress",
                    doc="uniform pressure q, acting against the outward normal"),
    "traction": Key("vec2", [0.0, 0.0], unit="stress", doc="uniform traction [tx, ty]"),
    "displacement": Key("xy", {}, unit="length",
                        doc="prescribed displacement components at factor 1, e.g. {y = -0.1} "
                            "(a load, eliminated exactly like a support)"),
}

POINT_LOAD_KEYS = {
    "name": Key("str", "", doc="optional name"),
    "body": Key("str", "", doc="restrict the node search to this body (default: all bodies)"),
    "at": Key("vec2", REQUIRED, unit="length", doc="the load goes to the node nearest this point"),
    "force": Key("vec2", REQUIRED, unit="force/length",
                 doc='[Fx, Fy] per unit thickness (plane = "axisymmetric": the total over the '
                     "node's ring [force])"),
}

_CONTACT_COMMON = {
    "kind": Key("str", REQUIRED, doc='the contact kind: "rigid_line", "rigid_circle", '
                                     '"rigid_polyline" (a deformable body against a rigid '
                                     'obstacle) or a deformable pair ("node_to_node", ...)'),
    "name": Key("str", "", doc="optional name"),
    "mu": Key("float", 0.0, doc="Coulomb friction coefficient", check=_non_negative("mu")),
}

RIGID_LINE_KEYS = {
    **_CONTACT_COMMON,
    "body": Key("str", REQUIRED, doc="the deformable body"),
    "edge": Key("str", REQUIRED, doc="its candidate edge tag"),
    "point": Key("vec2", [0.0, 0.0], unit="length", doc="a point of the rigid line"),
    "normal": Key("vec2", [0.0, 1.0], doc="normal of the line pointing to the body side",
                  check=_check_unit_free_vector),
    "x_min": Key("float", -math.inf, unit="length", doc="candidates: nodes with x >= x_min"),
    "x_max": Key("float", math.inf, unit="length", doc="candidates: nodes with x <= x_max"),
    "y_min": Key("float", -math.inf, unit="length", doc="candidates: nodes with y >= y_min"),
    "y_max": Key("float", math.inf, unit="length", doc="candidates: nodes with y <= y_max"),
    "tolerance": Key("float", 1e-9, unit="length",
                     doc="gaps in [-tolerance, 0) count as 0; below -tolerance is an error",
                     check=_non_negative("tolerance")),
    "motion": Key("vec2", None, unit="length",
                  doc="translation [dx, dy] of the rigid line at factor 1 (a load)"),
}

def _check_polyline(points) -> str | None:
    """At least two points, no zero-length segment, no segment folding back onto the last."""
    if len(points) < 2:
        return f"a polyline needs at least 2 points, got {len(points)}"
    for k in range(len(points) - 1):
        if points[k] == points[k + 1]:
            return (f"points {k} and {k + 1} are both {toml_text(points[k])}: a zero-length segment; "
                    f"remove one of them")
        dx, dy = points[k + 1][0] - points[k][0], points[k + 1][1] - points[k][1]
        if not 0.0 < dx * dx + dy * dy < math.inf:  # its squared length under- or overflows
            return (f"the segment from point {k} to point {k + 1} is too short or too long to "
                    f"compute with: rescale the coordinates")
    for k in range(len(points) - 2):
        (x0, y0), (x1, y1), (x2, y2) = points[k:k + 3]
        d, e = (x1 - x0, y1 - y0), (x2 - x1, y2 - y1)
        if d[0] * e[1] - d[1] * e[0] == 0.0 and d[0] * e[0] + d[1] * e[1] < 0.0:
            return (f"the segments before and after point {k + 1} fold back onto each other "
                    f"(the normal at that vertex is undefined): remove point {k + 1}")
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
        "motion": Key("vec2", None, unit="length",
                      doc=f"translation [dx, dy] of the {what} at factor 1 (a load)"),
    }


RIGID_CIRCLE_KEYS = _rigid_obstacle_keys({
    "centre": Key("vec2", REQUIRED, unit="length", doc="centre [x, y] of the rigid circle"),
    "radius": Key("float", REQUIRED, unit="length", doc="radius of the rigid circle",
                  check=_positive("the radius")),
    "side": Key("str", "outside", doc='where the body is: "outside" the circle (a rigid '
                                      'cylinder pressed into it) or "inside" (in a circular '
                                      'hole or cup)', choices=("outside", "inside")),
}, "circle")

RIGID_POLYLINE_KEYS = _rigid_obstacle_keys({
    "points": Key("points", REQUIRED, unit="length",
                  doc="vertices [[x, y], ...] of the rigid polyline, at least 2, no two "
                      "consecutive ones equal", check=_check_polyline),
    "side": Key("str", REQUIRED, doc='the side the body lies on, walking the polyline from its '
                                     'first point to its last: "left" or "right"',
                choices=("left", "right")),
}, "polyline")

#: The contact kinds whose target is a rigid obstacle (node_b = -1; they take `motion`).
RIGID_KINDS = ("rigid_line", "rigid_circle", "rigid_polyline")

NODE_TO_NODE_KEYS = {
    **_CONTACT_COMMON,
    "body_a": Key("str", REQUIRED, doc="contactor body"),
    "edge_a": Key("str", REQUIRED, doc="contactor edge tag"),
    "body_b": Key("str", REQUIRED, doc="target body"),
    "edge_b": Key("str", REQUIRED, doc="target edge tag"),
    "tolerance": Key("float", 1e-6, unit="length",
                     doc="pair node a with the nearest node b within this distance",
                     check=_positive("tolerance")),
    "normal": Key("vec2", None, doc="fixed normal for every pair (default: outward normal of "
                                    "edge_b averaged at node b)", check=_check_unit_free_vector),
}

NODE_TO_SEGMENT_KEYS = {
    **_CONTACT_COMMON,
    "body_a": Key("str", REQUIRED, doc="contactor body (its nodes get the constraint rows)"),
    "edge_a": Key("str", REQUIRED, doc="contactor edge tag"),
    "body_b": Key("str", REQUIRED, doc="target body"),
    "edge_b": Key("str", REQUIRED, doc="target edge tag (a polyline: its segments' outward "
                                       "normals are the contact normals)"),
    "x_min": Key("float", -math.inf, unit="length", doc="candidates: contactor nodes with x >= x_min"),
    "x_max": Key("float", math.inf, unit="length", doc="candidates: contactor nodes with x <= x_max"),
    "y_min": Key("float", -math.inf, unit="length", doc="candidates: contactor nodes with y >= y_min"),
    "y_max": Key("float", math.inf, unit="length", doc="candidates: contactor nodes with y <= y_max"),
    "tolerance": Key("float", 1e-9, unit="length",
                     doc="initial gaps in [-tolerance, 0) count as 0 (touching); below "
                         "-tolerance is an initial penetration (an error)",
                     check=_non_negative("tolerance")),
}

CONTACT_VARIANTS = {"rigid_line": RIGID_LINE_KEYS, "rigid_circle": RIGID_CIRCLE_KEYS,
                    "rigid_polyline": RIGID_POLYLINE_KEYS, "node_to_node": NODE_TO_NODE_KEYS,
                    "node_to_segment": NODE_TO_SEGMENT_KEYS}

STAGE_KEYS = {
    "name": Key("str", "", doc='optional name (default "stage <k>", 1-based)'),
    "factors": Key("factors", REQUIRED,
                   doc="the factor each named load reaches at the end of the stage, e.g. "
                       "{load = 1.0}; loads not named keep their factor"),
}

#: Top-level tables and arrays of tables.
TABLES = {"case": CASE_KEYS, "analysis": ANALYSIS_KEYS, "load": LOAD_KEYS,
          "output": OUTPUT_KEYS, "solver": SOLVER_KEYS}
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
    "contact": _union(RIGID_LINE_KEYS, RIGID_CIRCLE_KEYS, RIGID_POLYLINE_KEYS,
                      NODE_TO_NODE_KEYS, NODE_TO_SEGMENT_KEYS),
    "stage": STAGE_KEYS,
}
BODY_SUBTABLES = {"mesh": _union(QUARTER_CYLINDER_KEYS, BLOCK_KEYS, QUARTER_ANNULUS_KEYS,
                                  FILE_MESH_KEYS),
                  "material": MATERIAL_KEYS}


# --------------------------------------------------------------------------- the case object
@dataclass
class Case:
    """A validated case: ``data`` holds every table with defaults filled in.

    ``source`` is how messages name the file; ``base_dir`` resolves relative mesh paths.
    """

    data: dict
    source: str
    base_dir: Path

    @property
    def name(self) -> str:
        return self.data["case"]["name"]

    def body(self, name: str) -> dict:
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
        return load_path(self.data, self.source)

    @property
    def units(self) -> dict[str, str]:
        """``[case] units`` read as "length, force, stress" (e.g. "mm, N, MPa"): {"length":
        "mm", "force": "N", "stress": "MPa"}; {} when the note is not three such words."""
        words = [w.strip() for w in self.data["case"]["units"].split(",")]
        if len(words) != 3 or not all(w and " " not in w and len(w) <= 8 for w in words):
            return {}
        return dict(zip(("length", "force", "stress"), words))

    @classmethod
    def from_toml(cls, text: str, source: str = "<case>", base_dir: Path | str = ".",
                  overrides=()) -> "Case":
        """A case from TOML text (:func:`parse_case`)."""
        return parse_case(text, source, base_dir, overrides)

    @classmethod
    def from_dict(cls, data: dict, source: str = "<dict>", base_dir: Path | str = ".",
                  overrides=()) -> "Case":
        """A case from a dict shaped like the TOML document (``{"case": {...}, "body":
        [{...}], ...}``, keys as in cases/README.md), validated like a file: tuples and numpy
        arrays count as lists, numpy numbers as numbers, a None value as an absent key."""
        if not isinstance(data, dict):
            raise CaseError(f"{source}: a case is a dict of tables, not {type(data).__name__}")
        raw = _toml_like(data)
        for item in overrides:
            apply_override(raw, item, source)
        return cls(data=_Validator(source).case(raw), source=source, base_dir=Path(base_dir))


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
        raise CaseError(f"{source}: not a UTF-8 text file (byte {exc.start}): a case is a TOML "
                        f"text file") from None
    return parse_case(text, source=source, base_dir=path.resolve().parent, overrides=overrides)


def parse_case(text: str, source: str = "<case>", base_dir: Path | str = ".",
               overrides=()) -> Case:
    """Like :func:`load_case`, from TOML text."""
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise CaseError(f"{source}: invalid TOML: {exc}") from None
    for item in overrides:
        apply_override(raw, item, source)
    data = _Validator(source).case(raw)
    return Case(data=data, source=source, base_dir=Path(base_dir))


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


# --------------------------------------------------------------------------- overrides
def parse_override(item: str) -> tuple[str, Any]:
    """Split ``"key=value"``; the value is a TOML literal (``0.35``, ``[0, 1]``, ``"strain"``,
    ``true``); a bare word that is no TOML literal is taken as a string (``plane=stress``)."""
    key, sep, text = item.partition("=")
    key, text = key.strip(), text.strip()
    if not sep or not key:
        raise CaseError(f"--set {item}: expected KEY=VALUE, e.g. --set contact.mu=0.35")
    try:
        value = tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        if text and all(c.isalnum() or c in "_-./" for c in text):
            value = text
        else:
            raise CaseError(f"--set {item}: {text!r} is not a TOML value "
                            f'(numbers as 0.35, strings as "text", lists as [0, 1])') from None
    return key, value


def apply_override(raw: dict, item: str, source: str = "<case>") -> None:
    """Apply one ``--set key=value`` to the raw TOML document, in place."""
    key, value = parse_override(item)
    where = f"--set {item}"
    parts = key.split(".")
    head, rest = parts[0], parts[1:]

    if head in ("mesh", "material"):  # shorthand for the single body
        bodies = raw.get("body", [])
        if len(bodies) != 1:
            raise CaseError(f"{where}: '{head}.*' is short for body.<name>.{head}.* only in a "
                            f"case with one body; this one has {len(bodies)}: use "
                            f"body.<name>.{key}")
        head, rest = "body", ["0", head, *rest]

    if head in TABLES:
        table = raw.setdefault(head, {})
        if not isinstance(table, dict):
            raise CaseError(f"{where}: {head} must be a table, written [{head}]")
        _set_in_table(table, TABLES[head], rest, value, where, f"[{head}]")
        return
    if head in ARRAYS:
        elements = raw.get(head, [])
        if not isinstance(elements, list) or any(not isinstance(e, dict) for e in elements):
            raise CaseError(f"{where}: {head} must be an array of tables, written [[{head}]]")
        index, rest = _array_index(elements, head, rest, where)
        element = elements[index]
        if head == "body" and rest and rest[0] in BODY_SUBTABLES:
            sub = rest[0]
            table = element.setdefault(sub, {})
            if not isinstance(table, dict):
                raise CaseError(f"{where}: {sub} must be a table, written [body.{sub}]")
            keys = BODY_SUBTABLES[sub]
            if sub == "mesh":  # the keys of this mesh's form, if it has a known one
                form = "file" if "file" in table else table.get("generator")
                keys = FILE_MESH_KEYS if form == "file" else MESH_VARIANTS.get(form if isinstance(form, str) else "", keys)
            _set_in_table(table, keys, rest[1:], value, where, f"[body.{sub}]")
            return
        keys = ARRAY_KEYS[head]
        if head == "contact":  # the keys of this contact's kind, if it has a known one
            kind = element.get("kind")
            keys = CONTACT_VARIANTS.get(kind if isinstance(kind, str) else "", keys)
            if kind in ("node_to_node", "node_to_segment") and rest == ["motion"]:  # refused by the validator,
                keys = {**keys, "motion": RIGID_LINE_KEYS["motion"]}  # with the reason
        _set_in_table(element, keys, rest, value, where, f"[[{head}]]",
                      extra=tuple(BODY_SUBTABLES) if head == "body" else ())
        return
    valid = ", ".join([*TABLES, *ARRAYS, "mesh", "material"])
    raise CaseError(f"{where}: unknown key '{head}'; valid first parts are {valid}")


def _array_index(elements: list, head: str, rest: list[str], where: str) -> tuple[int, list]:
    """Pick the element of an array of tables that an override addresses."""
    if not elements:
        raise CaseError(f"{where}: the case has no [[{head}]] entry to change")
    if rest:
        first = rest[0]
        if first.isdigit():
            i = int(first)
            if i >= len(elements):
                raise CaseError(f"{where}: [[{head}]] has {len(elements)} entries: "
                                f"use an index 0..{len(elements) - 1}")
            return i, rest[1:]
        names = [e.get("name") for e in elements]
        if first in names:
            return names.index(first), rest[1:]
    if len(elements) == 1:
        return 0, rest
    names = [str(e["name"]) for e in elements if "name" in e]
    hint = f" or a name ({', '.join(names)})" if names else ""
    raise CaseError(f"{where}: the case has {len(elements)} [[{head}]] entries: say which, "
                    f"e.g. {head}.0.{'.'.join(rest) or 'KEY'} (an index{hint})")


def _set_in_table(table: dict, keys: dict, rest: list[str], value, where: str, label: str,
                  extra: tuple = ()) -> None:
    """Set ``rest`` = [key] in ``table``, or [key, entry] of an inline-table key
    (``factors.load``, ``displacement.y``); entries are checked by the validator."""
    valid = ", ".join([*keys, *extra])
    inline = len(rest) == 2 and rest[0] in keys and keys[rest[0]].type in ("xy", "factors")
    if not inline and (len(rest) != 1 or rest[0] not in keys):
        name = ".".join(rest) or "(nothing)"
        raise CaseError(f"{where}: unknown key '{name}' in {label}; valid keys: {valid}")
    if not inline:
        table[rest[0]] = value
        return
    sub = table.setdefault(rest[0], {})
    if not isinstance(sub, dict):
        raise CaseError(f"{where}: {rest[0]} must be an inline table, e.g. "
                        f"{rest[0]} = {{{rest[1]} = 1.0}}")
    sub[rest[1]] = value


# --------------------------------------------------------------------------- validation
def toml_text(value) -> str:
    """A value as TOML would spell it, for messages."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, list):
        return "[" + ", ".join(toml_text(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{...}"
    return repr(value)


_TYPE_HELP = {
    "float": "a number", "int": "an integer", "str": "a string in quotes",
    "bool": "true or false", "vec2": "two numbers, e.g. [0.0, 1.0]",
    "box": "four numbers [x0, y0, x1, y1], e.g. [0.0, -15.0, 15.0, 0.0]",
    "axes": 'a list of "x"/"y", e.g. ["x", "y"]',
    "snapshots": '"events" or a list of load fractions',
    "xy": "an inline table of numbers x and/or y, e.g. {x = 0.0, y = -0.1}",
    "factors": "an inline table of load names and numbers, e.g. {load = 1.0}",
    "points": "a list of [x, y] points, e.g. [[0.0, 1.0], [10.0, 1.0]]",
}


class _Validator:
    """Walks the raw document, checks types and values, fills defaults."""

    def __init__(self, source: str):
        self.source = source

    def fail(self, key: str, message: str) -> CaseError:
        return CaseError(f"{self.source}: {key} {message}")

    # ---- one table against its key declarations
    def table(self, raw, keys: dict, label: str, prefix: str, skip=()) -> dict:
        if not isinstance(raw, dict):
            raise CaseError(f"{self.source}: {label} must be a table")
        unknown = [k for k in raw if k not in keys and k not in skip]
        if unknown:
            valid = ", ".join([*keys, *skip])
            raise CaseError(f"{self.source}: unknown key {prefix}{unknown[0]} in {label}; "
                            f"valid keys: {valid}")
        out = {}
        for name, spec in keys.items():
            full = prefix + name
            if name not in raw:
                if spec.default is REQUIRED:
                    raise self.fail(full, f"is missing: {spec.doc}" +
                                    (f" [{spec.unit}]" if spec.unit else "") +
                                    f"; add `{name} = ...` to {label}")
                out[name] = copy.deepcopy(spec.default)
                continue
            out[name] = self.value(raw[name], spec, full)
        return out

    def value(self, v, spec: Key, full: str):
        shown = toml_text(v)  # as written, before int -> float
        bad = self.fail(full, f"= {shown} is not allowed: expected {_TYPE_HELP[spec.type]}")
        t = spec.type
        if t == "float":
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise bad
            v = float(v)
            if math.isnan(v):
                raise bad
            if math.isinf(v) and not (isinstance(spec.default, float) and math.isinf(spec.default)):
                raise self.fail(full, f"= {shown} is not allowed: expected a finite number")
        elif t == "int":
            if isinstance(v, bool) or not isinstance(v, int):
                raise bad
        elif t == "str":
            if not isinstance(v, str):
                raise bad
        elif t == "bool":
            if not isinstance(v, bool):
                raise bad
        elif t in ("vec2", "box"):
            size, count = (2, "two") if t == "vec2" else (4, "four")
            if (not isinstance(v, list) or len(v) != size or
                    any(isinstance(c, bool) or not isinstance(c, (int, float)) for c in v)):
                raise bad
            v = [float(c) for c in v]
            if not all(math.isfinite(c) for c in v):
                raise self.fail(full, f"= {shown} is not allowed: expected {count} finite "
                                      f"numbers")
        elif t == "axes":
            if not isinstance(v, list) or any(c not in ("x", "y") for c in v) or len(set(v)) != len(v):
                raise bad
        elif t == "snapshots":
            if isinstance(v, list):
                if any(isinstance(c, bool) or not isinstance(c, (int, float)) for c in v):
                    raise bad
                v = [float(c) for c in v]
            elif not isinstance(v, str):
                raise bad
        elif t == "points":
            if (not isinstance(v, list) or
                    any(not isinstance(p, list) or len(p) != 2 or
                        any(isinstance(c, bool) or not isinstance(c, (int, float)) for c in p)
                        for p in v)):
                raise bad
            v = [[float(c) for c in p] for p in v]
            if not all(math.isfinite(c) for p in v for c in p):
                raise self.fail(full, f"= {shown} is not allowed: expected finite numbers")
        elif t in ("xy", "factors"):
            if not isinstance(v, dict):
                raise bad
            v = self.inline_numbers(v, t, full)
        if spec.choices and v not in spec.choices:
            choices = " or ".join(toml_text(c) for c in spec.choices)
            raise self.fail(full, f"= {shown} is not allowed: use {choices}")
        if spec.check is not None and v is not None:
            reason = spec.check(v)
            if reason:
                raise self.fail(full, f"= {shown} is not allowed: {reason}")
        return v

    def inline_numbers(self, v: dict, t: str, full: str) -> dict:
        """An inline table of finite numbers: x/y of a displacement, or load factors."""
        if t == "xy":
            other = [k for k in v if k not in ("x", "y")]
            if other:
                raise self.fail(f"{full}.{other[0]}", "is not allowed: a displacement has "
                                "components x and y only, e.g. displacement = {x = 0.0, y = -0.1}")
            if not v:
                raise self.fail(full, "= {} is not allowed: give x and/or y, e.g. "
                                      "displacement = {y = -0.1}")
        what = "the displacement component" if t == "xy" else "the factor that load reaches"
        out = {}
        for k, c in v.items():
            if isinstance(c, bool) or not isinstance(c, (int, float)):
                raise self.fail(f"{full}.{k}", f"= {toml_text(c)} is not allowed: expected a number "
                                               f"({what})")
            if not math.isfinite(c):
                raise self.fail(f"{full}.{k}", f"= {toml_text(c)} is not allowed: expected a finite "
                                               f"number")
            out[k] = float(c)
        return out

    # ---- arrays of tables
    @staticmethod
    def element_prefix(array: str, elements: list, i: int) -> str:
        """How --set addresses element i of an array (see the module docstring)."""
        if len(elements) == 1:
            return f"{array}."
        name = elements[i].get("name") if isinstance(elements[i], dict) else None
        return f"{array}.{name}." if isinstance(name, str) and name else f"{array}.{i}."

    def array(self, raw: dict, array: str) -> list:
        elements = raw.get(array, [])
        if not isinstance(elements, list) or any(not isinstance(e, dict) for e in elements):
            raise CaseError(f"{self.source}: {array} must be an array of tables, "
                            f"written [[{array}]]")
        return elements

    # ---- the whole document
    def case(self, raw: dict) -> dict:
        known = [*TABLES, *ARRAYS]
        for k in raw:
            if k not in known:
                raise CaseError(f"{self.source}: unknown key {k}; valid top-level tables: "
                                f"{', '.join(known)}")
        data = {}
        for name, keys in TABLES.items():
            if name == "load":
                continue
            data[name] = self.table(raw.get(name, {}), keys, f"[{name}]", f"{name}.")
        data["load"] = (self.table(raw["load"], LOAD_KEYS, "[load]", "load.")
                        if "load" in raw else None)
        self.axisymmetric_thickness(data, raw)

        bodies = self.array(raw, "body")
        if not bodies:
            raise CaseError(f"{self.source}: no [[body]]: a case needs at least one body "
                            f"with a mesh and a material")
        data["body"] = [self.body(b, self.element_prefix("body", bodies, i), len(bodies))
                        for i, b in enumerate(bodies)]
        names = [b["name"] for b in data["body"]]
        for n in names:
            if names.count(n) > 1:
                raise CaseError(f"{self.source}: body.name = {toml_text(n)} is used twice: body "
                                f"names must be unique")
        edges = {b["name"]: b["mesh"]["edges"] for b in data["body"]}

        data["bc"] = [self.bc(e, self.element_prefix("bc", raw.get("bc", []), i), edges)
                      for i, e in enumerate(self.array(raw, "bc"))]
        pls = self.array(raw, "point_load")
        data["point_load"] = []
        for i, e in enumerate(pls):
            prefix = self.element_prefix("point_load", pls, i)
            pl = self.table(e, POINT_LOAD_KEYS, "[[point_load]]", prefix)
            if pl["body"]:
                self.need_body(pl["body"], prefix + "body", edges)
            data["point_load"].append(pl)
        contacts = self.array(raw, "contact")
        data["contact"] = [self.contact(c, self.element_prefix("contact", contacts, i), edges)
                           for i, c in enumerate(contacts)]
        self.load(data, edges)
        stages = self.array(raw, "stage")
        if "stage" in raw and not stages:
            raise self.fail("stage", "= [] is not allowed: an empty load path; give one or more "
                                     "[[stage]] tables with factors = {...}, or remove the key "
                                     "(one stage with every load at factor 1)")
        data["stage"] = [self.table(s, STAGE_KEYS, "[[stage]]",
                                    self.element_prefix("stage", stages, i))
                         for i, s in enumerate(stages)]
        self.stage_names(data["stage"])
        n_stages = load_path(data, self.source).n_stages  # checks loads, names and factors
        snaps = data["output"]["snapshots"]
        reason = _check_snapshot_times(snaps, n_stages) if isinstance(snaps, list) else None
        if reason:
            raise self.fail("output.snapshots", f"= {toml_text(snaps)} is not allowed: {reason}")
        return data

    def axisymmetric_thickness(self, data: dict, raw: dict) -> None:
        """``thickness`` does not apply to rings (every force is a total over the ring)."""
        given = raw.get("analysis", {})
        if data["analysis"]["plane"] == "axisymmetric" and "thickness" in given:
            raise self.fail("analysis.thickness", f"= {toml_text(given['thickness'])} is not allowed "
                                                  f'with plane = "axisymmetric": forces are '
                                                  f"totals over the full ring (2 pi r), there is "
                                                  f"no thickness; remove analysis.thickness")

    def stage_names(self, stages: list) -> None:
        """Stage names must be unique (--set and the outputs address stages by name)."""
        names = [s["name"] for s in stages]
        for k, n in enumerate(names):
            if n and n in names[:k]:  # by index: --set finds the first of a shared name
                raise self.fail(f"stage.{k}.name", f"= {toml_text(n)} is used twice (also by stage."
                                                   f"{names.index(n)}): stage names must be "
                                                   f"unique; rename one")

    def body(self, raw: dict, prefix: str, n_bodies: int) -> dict:
        body = self.table(raw, BODY_KEYS, "[[body]]", prefix, skip=("mesh", "material"))
        sub = "" if n_bodies == 1 else prefix  # messages: material.nu for a single body
        if "material" not in raw:
            raise self.fail(f"{sub}material", "is missing: add a [body.material] table with "
                                              "E and nu")
        body["material"] = self.table(raw["material"], MATERIAL_KEYS, "[body.material]",
                                      f"{sub}material.")
        if "mesh" not in raw:
            raise self.fail(f"{sub}mesh", 'is missing: add a [body.mesh] table with generator = '
                                          '"quarter_cylinder", "half_cylinder", "disc", "block" or '
                                          '"quarter_annulus", '
                                          'or file = "..."')
        body["mesh"] = self.mesh(raw["mesh"], f"{sub}mesh.")
        return body

    def mesh(self, raw, prefix: str) -> dict:
        if not isinstance(raw, dict):
            raise CaseError(f"{self.source}: {prefix[:-1]} must be a table")
        if "file" in raw and "generator" in raw:
            raise self.fail(prefix + "file", "and generator are both given: keep one")
        if "file" in raw:
            mesh = self.table(raw, FILE_MESH_KEYS, "[body.mesh]", prefix)
            mesh["edges"] = None  # known once the file is read
            return mesh
        gen = raw.get("generator")
        if not isinstance(gen, str) or gen not in MESH_VARIANTS:
            choices = " or ".join(toml_text(g) for g in MESH_VARIANTS)
            what = "is missing" if gen is None else f"= {toml_text(gen)} is not allowed"
            raise self.fail(prefix + "generator", f"{what}: use {choices}, or give "
                                                  f'file = "mesh.msh"')
        mesh = self.table(raw, MESH_VARIANTS[gen], "[body.mesh]", prefix)
        check = {"quarter_cylinder": self.cylinder_mesh, "half_cylinder": self.cylinder_mesh,
                 "disc": self.cylinder_mesh, "quarter_annulus": self.annulus_mesh}
        if gen == "block":
            self.block_mesh(mesh, raw, prefix)
        elif gen in check:
            check[gen](mesh, prefix)
        mesh["edges"] = GENERATOR_EDGES.get(gen)  # None ("given"): known with the mesh
        return mesh

    def cylinder_mesh(self, mesh: dict, prefix: str) -> None:
        """quarter_cylinder / half_cylinder / disc: h_contact <= h_max, contact_zone < R."""
        if mesh["h_contact"] > mesh["h_max"]:
            raise self.fail(prefix + "h_contact", f"= {toml_text(mesh['h_contact'])} is not "
                            f"allowed: it must not exceed h_max = {toml_text(mesh['h_max'])}")
        if mesh["contact_zone"] >= mesh["R"]:
            raise self.fail(prefix + "contact_zone", f"= {toml_text(mesh['contact_zone'])} is not"
                            f" allowed: it must be smaller than R = {toml_text(mesh['R'])}")

    def annulus_mesh(self, mesh: dict, prefix: str) -> None:
        """quarter_annulus: b > a, element sizes within the wall."""
        if mesh["b"] <= mesh["a"]:
            raise self.fail(prefix + "b", f"= {toml_text(mesh['b'])} is not allowed: the outer "
                            f"radius must exceed the inner radius a = {toml_text(mesh['a'])}")
        for key in ("h", "h_outer"):
            if mesh[key] > mesh["b"] - mesh["a"]:
                raise self.fail(prefix + key, f"= {toml_text(mesh[key])} is not allowed: it must "
                                f"not exceed the wall thickness b - a = "
                                f"{toml_text(mesh['b'] - mesh['a'])}")

    def block_mesh(self, mesh: dict, raw: dict, prefix: str) -> None:
        """block: structured (nx/ny or h; refined with refine_box) or graded (h_contact around
        focus), not both."""
        if mesh["h_contact"] == 0:
            self.structured_block_mesh(mesh, raw, prefix)
        else:
            self.graded_block_mesh(mesh, prefix)

    def structured_block_mesh(self, mesh: dict, raw: dict, prefix: str) -> None:
        """nx/ny or h; the keys of the graded block would do nothing (h_max and growth shape
        the refined block too)."""
        for n, size in (("nx", "width"), ("ny", "height")):
            if mesh[n] == 0 and mesh["h"] == 0:
                raise self.fail(prefix + n, f"is missing: give {n} (divisions along "
                                f"{size}) or h (element size), or h_contact (a graded "
                                f"gmsh mesh)")
        refined = mesh["refine_box"] is not None
        for key in ("contact_zone", "focus", "uniform_edges", "h_max", "growth"):
            if key not in raw or (refined and key in ("h_max", "growth")):
                continue
            shown = f"= {toml_text(mesh[key])} is not allowed"
            if refined:
                raise self.fail(prefix + key, f"{shown} with refine_box: it shapes the graded "
                                f"block (h_contact > 0), fine around focus; drop {key}")
            if key in ("h_max", "growth"):
                raise self.fail(prefix + key, f"{shown} without h_contact or refine_box: it "
                                f"shapes the graded block (h_contact > 0) or the refined one "
                                f"(refine_box); add one of them or drop {key}")
            raise self.fail(prefix + key, f"{shown} without h_contact: it shapes the graded "
                            f"block (h_contact > 0); add h_contact or drop {key}")
        if refined:
            self.refine_box(mesh, prefix)

    def refine_box(self, mesh: dict, prefix: str) -> None:
        """The refined block: a box [x0, y0, x1, y1] inside the block, h_max >= the grid
        spacing."""
        bx0, by0, bx1, by1 = mesh["refine_box"]
        x0, y0, x1, y1 = mesh["x0"], mesh["y0"], mesh["x0"] + mesh["width"], \
            mesh["y0"] + mesh["height"]
        shown = f"= {toml_text(mesh['refine_box'])} is not allowed"
        if not (bx0 < bx1 and by0 < by1):
            raise self.fail(prefix + "refine_box", f"{shown}: write it [x0, y0, x1, y1] with "
                            f"x0 < x1 and y0 < y1")
        tol = 1e-9 * max(mesh["width"], mesh["height"])  # as mesh.refined_block
        if not (x0 - tol <= bx0 and bx1 <= x1 + tol and y0 - tol <= by0 and by1 <= y1 + tol):
            raise self.fail(prefix + "refine_box", f"{shown}: it reaches outside the block "
                            f"[{toml_text(x0)}, {toml_text(x1)}] x [{toml_text(y0)}, {toml_text(y1)}]; keep it "
                            f"inside")
        if mesh["h_max"] == 0:
            raise self.fail(prefix + "h_max", "is missing: the refined block (refine_box) "
                            "needs the largest element size [length]; add `h_max = ...` to "
                            "[body.mesh]")
        nx, ny = block_divisions(mesh)
        spacing = min(mesh["width"] / nx, mesh["height"] / ny)
        if mesh["h_max"] < spacing:
            raise self.fail(prefix + "h_max", f"= {toml_text(mesh['h_max'])} is not allowed: it "
                            f"must not be smaller than the grid spacing {spacing:g} that the "
                            f"refined block grows from")

    def graded_block_mesh(self, mesh: dict, prefix: str) -> None:
        """h_contact around focus: contact_zone and h_max given, no structured keys."""
        hc = toml_text(mesh["h_contact"])
        for key in ("nx", "ny", "h"):
            if mesh[key] > 0:
                raise self.fail(prefix + key, f"= {toml_text(mesh[key])} is not allowed "
                                f"together with h_contact = {hc}: nx/ny/h make the "
                                f"structured block, h_contact the graded one; drop "
                                f"{key} (or h_contact)")
        if mesh["refine_box"] is not None:
            raise self.fail(prefix + "refine_box", f"= {toml_text(mesh['refine_box'])} is not "
                            f"allowed together with h_contact = {hc}: refine_box keeps the "
                            f"structured block (nx/ny or h) inside it, h_contact grades around "
                            f"focus; drop refine_box (or h_contact)")
        for key, what in (("contact_zone", "the radius of the fine zone around focus"),
                          ("h_max", "the largest element size")):
            if mesh[key] == 0:
                raise self.fail(prefix + key, f"is missing: the graded block "
                                f"(h_contact = {hc}) needs {what} [length]; add "
                                f"`{key} = ...` to [body.mesh]")
        if mesh["h_contact"] > mesh["h_max"]:
            raise self.fail(prefix + "h_contact", f"= {hc} is not allowed: it must not "
                            f"exceed h_max = {toml_text(mesh['h_max'])}")
        if mesh["focus"] is not None:
            (fx, fy), x0, y0 = mesh["focus"], mesh["x0"], mesh["y0"]
            x1, y1 = x0 + mesh["width"], y0 + mesh["height"]
            tol = 1e-9 * max(mesh["width"], mesh["height"])  # as mesh.graded_block
            if not (x0 - tol <= fx <= x1 + tol and y0 - tol <= fy <= y1 + tol):
                raise self.fail(prefix + "focus", f"= {toml_text(mesh['focus'])} is not "
                                f"allowed: it lies outside the block [{toml_text(x0)}, "
                                f"{toml_text(x1)}] x [{toml_text(y0)}, {toml_text(y1)}]; move it "
                                f"inside or onto the boundary")

    def need_body(self, name: str, key: str, edges: dict) -> None:
        if name not in edges:
            raise self.fail(key, f"= {toml_text(name)} is not allowed: no body has that name "
                                 f"(bodies: {', '.join(edges)})")

    def need_edge(self, body: str, tag: str, key: str, edges: dict) -> None:
        known = edges[body]
        if known is not None and tag not in known:
            raise self.fail(key, f"= {toml_text(tag)} is not allowed: body {toml_text(body)} has no edge "
                                 f"with that tag (its edges: {', '.join(known)})")

    def bc(self, raw: dict, prefix: str, edges: dict) -> dict:
        bc = self.table(raw, BC_KEYS, "[[bc]]", prefix)
        self.need_body(bc["body"], prefix + "body", edges)
        if bool(bc["edge"]) == bool(bc["nodes"]):
            raise self.fail(prefix + "edge", "is missing: give exactly one of edge (an edge tag)"
                                             " or nodes (a node set)")
        if bc["edge"]:
            self.need_edge(bc["body"], bc["edge"], prefix + "edge", edges)
        loads = bc["pressure"] != 0.0 or bc["traction"] != [0.0, 0.0]
        if not (bc["fix"] or bc["symmetry"] or loads or bc["displacement"]):
            raise CaseError(f"{self.source}: {prefix[:-1]} does nothing: give fix, symmetry, "
                            f"pressure, traction or displacement")
        if bc["nodes"] and (loads or bc["symmetry"]):
            raise self.fail(prefix + "nodes", "supports fix and displacement only: put "
                                              "pressure, traction and symmetry on an edge")
        for c in bc["displacement"]:
            if c in bc["fix"]:
                raise self.fail(f"{prefix}displacement.{c}", f"is not allowed: fix also holds "
                                f"{c} (at zero): a component is fixed or prescribed, not both; "
                                f'remove "{c}" from fix or {c} from displacement')
        return bc

    def contact(self, raw: dict, prefix: str, edges: dict) -> dict:
        kind = raw.get("kind")
        if not isinstance(kind, str) or kind not in CONTACT_VARIANTS:
            choices = " or ".join(toml_text(k) for k in CONTACT_VARIANTS)
            what = "is missing" if kind is None else f"= {toml_text(kind)} is not allowed"
            raise self.fail(prefix + "kind", f"{what}: use {choices}")
        if kind in ("node_to_node", "node_to_segment") and "motion" in raw:
            raise self.fail(prefix + "motion", "is not allowed: motion on a deformable-pair "
                            f'contact (kind "{kind}"): motion moves a rigid obstacle; '
                            "prescribe a displacement [[bc]] on one of the bodies instead")
        c = self.table(raw, CONTACT_VARIANTS[kind], f'[[contact]] of kind "{kind}"', prefix)
        if kind in RIGID_KINDS:
            self.need_body(c["body"], prefix + "body", edges)
            self.need_edge(c["body"], c["edge"], prefix + "edge", edges)
        else:
            for side in "ab":
                self.need_body(c[f"body_{side}"], f"{prefix}body_{side}", edges)
                self.need_edge(c[f"body_{side}"], c[f"edge_{side}"], f"{prefix}edge_{side}",
                               edges)
        return c

    def load(self, data: dict, edges: dict) -> None:
        """`[load] P` needs a quarter_cylinder body to act on."""
        load = data["load"]
        if load is None:
            return
        cylinders = [b["name"] for b in data["body"]
                     if b["mesh"].get("generator") == "quarter_cylinder"]
        if load["body"]:
            self.need_body(load["body"], "load.body", edges)
            if load["body"] not in cylinders:
                raise self.fail("load.body", f"= {toml_text(load['body'])} is not allowed: [load] P "
                                             f"acts on a quarter_cylinder body")
        elif len(cylinders) == 1:
            load["body"] = cylinders[0]
        else:
            raise self.fail("load.P", "is not allowed here: [load] P is the Hertz convenience "
                                      "for one quarter_cylinder body (give load.body, or use "
                                      "[[bc]] pressure)")


# --------------------------------------------------------------------------- the load path
@dataclass(frozen=True)
class Load:
    """One load pattern at factor 1: ``[load]``, a ``[[bc]]`` with pressure, traction or
    displacement, a ``[[point_load]]``, or a ``[[contact]]`` with motion."""

    name: str        # its `name` ("load" for [load]); "" when unnamed
    key: str         # the element as --set spells it: "load", "bc", "bc.1", "bc.push"
    array: str       # "load", "bc", "point_load" or "contact"
    index: int       # its position in that array
    force: bool      # applies forces (P, pressure, traction, a point force)
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


def element_key(array: str, elements: list, i: int) -> str:
    """How --set addresses element i of an array: ``bc``, ``bc.push`` or ``bc.1``."""
    return _Validator.element_prefix(array, elements, i)[:-1]


def case_loads(data: dict) -> tuple:
    """Every load of a validated document, in order: [load], bc, point_load, contact."""
    out = [Load("load", "load", "load", 0, True, False)] if data["load"] is not None else []
    for i, bc in enumerate(data["bc"]):
        force = bc["pressure"] != 0.0 or bc["traction"] != [0.0, 0.0]
        if force or bc["displacement"]:
            out.append(Load(bc["name"], element_key("bc", data["bc"], i), "bc", i, force,
                            bool(bc["displacement"])))
    for i, pl in enumerate(data["point_load"]):
        out.append(Load(pl["name"], element_key("point_load", data["point_load"], i),
                        "point_load", i, True, False))
    for i, c in enumerate(data["contact"]):
        if c.get("motion") is not None:
            out.append(Load(c["name"], element_key("contact", data["contact"], i), "contact", i,
                            False, True))
    return tuple(out)


def load_path(data: dict, source: str = "<case>") -> LoadPath:
    """The load path of a validated document; CaseError for unnamed or duplicate loads, a
    displacement/motion load named "load", unknown names in factors, a stage that changes
    nothing."""
    loads = case_loads(data)
    stages = data.get("stage", [])
    if not stages:
        patterns = tuple(x for x in loads if x.kinematic)
        _check_load_names(patterns, source)
        n = 1 + len(patterns)
        return LoadPath(loads, None, patterns, ("load", *(x.label for x in patterns)),
                        ("stage 1",), ((0.0,) * n, (1.0,) * n), False)
    for x in loads:
        if not x.name:
            raise CaseError(f"{source}: {x.key} is a load without a name: with [[stage]] every "
                            f'load needs one; add name = "..." to it (stages name loads in '
                            f"factors)")
    _check_load_names(loads, source)
    head = next((x for x in loads if x.name == "load"), None)
    patterns = tuple(x for x in loads if x is not head)
    names = ("load", *(x.name for x in patterns))
    rows = _factor_rows(stages, names, head is not None, source)
    stage_names = tuple(s["name"] or f"stage {k + 1}" for k, s in enumerate(stages))
    return LoadPath(loads, head, patterns, names, stage_names, rows, True)


def _check_load_names(loads, source: str) -> None:
    """Unique names; "load" only for a force load (it is the engine's `load` vector)."""
    seen = {}
    for x in loads:
        if x.label == "load" and x.kinematic:
            raise CaseError(f'{source}: {x.key}.name = "load" is not allowed: "load" names the '
                            f"force pattern ([load], or a force [[bc]]/[[point_load]] named so); "
                            f'a displacement or motion load needs another name, e.g. "push"')
        if x.label in seen:  # by index: --set finds the first of a shared name
            raise CaseError(f"{source}: {x.array}.{x.index}.name = {toml_text(x.label)} is used twice "
                            f"(also by {seen[x.label]}): load names must be unique; rename one")
        seen[x.label] = x.place


def _factor_rows(stages: list, names: tuple, has_load: bool, source: str) -> tuple:
    """Factors at t = 0, 1, ..., n_stages: all 0 at first; a stage sets the loads it names,
    the others keep theirs."""
    valid = [n for n in names if n != "load" or has_load]
    current, rows = [0.0] * len(names), [(0.0,) * len(names)]
    for k, stage in enumerate(stages):
        key = element_key("stage", stages, k) + ".factors"
        for name, value in stage["factors"].items():
            if name not in valid:
                raise CaseError(f"{source}: {key}.{name} = {toml_text(value)} is not allowed: no load "
                                f"is named {toml_text(name)} (loads: {', '.join(valid) or 'none'}); "
                                f'a load is named by its name key ([load] is "load")')
            current[names.index(name)] = value
        if tuple(current) == rows[-1]:
            raise CaseError(f"{source}: {key} changes nothing: every factor equals its value at "
                            f"the end of the previous stage (all start at 0); give a factor that "
                            f"changes, or remove the stage")
        rows.append(tuple(current))
    return tuple(rows)
