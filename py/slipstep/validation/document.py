"""The case document against the schema: types, values and defaults of every key, and what
the keys say of each other (bodies and edges named, a mesh's own consistency, a boundary
condition that does something, unique names, the load path).  Returns the document with every
default filled in."""

from __future__ import annotations

import copy
import math

from ..case_record import CaseRecord
from ..errors import CaseError
from ..loads.path import load_path
from ..overrides import element_prefix
from ..schema import (
    ANALYSIS_KEYS,
    ARRAYS,
    BC_KEYS,
    BODY_KEYS,
    CONTACT_VARIANTS,
    FILE_MESH_KEYS,
    LOAD_KEYS,
    MATERIAL_KEYS,
    MESH_VARIANTS,
    POINT_LOAD_KEYS,
    REQUIRED,
    STAGE_KEYS,
    TABLES,
    Key,
    block_divisions,
    check_snapshot_times,
    contact_tags,
    generator_dimension,
    generator_tags,
    kind_dimension,
)
from ..schema.sizes import SIDES
from ..toml_writing import toml_text
from . import solid as space
from .terms import terms_of


_TYPE_HELP = {
    "float": "a number",
    "int": "an integer",
    "str": "a string in quotes",
    "bool": "true or false",
    "vec2": "two numbers, e.g. [0.0, 1.0]",
    "vec3": "three numbers, e.g. [0.0, 0.0, 1.0]",
    "box": "four numbers [x0, y0, x1, y1], e.g. [0.0, -15.0, 15.0, 0.0]",
    "axes": 'a list of "x"/"y", e.g. ["x", "y"]',
    "snapshots": '"auto", "events" or a list of load fractions',
    "xy": "an inline table of numbers x and/or y, e.g. {x = 0.0, y = -0.1}",
    "factors": "an inline table of load names and numbers, e.g. {load = 1.0}",
    "points": "a list of [x, y] points, e.g. [[0.0, 1.0], [10.0, 1.0]]",
}


#: The keys of a block mesh that shape only the graded block (h_contact > 0), and those that
#: shape the refined block (refine_box) too: a structured block refuses them when given.
GRADED_ONLY = ("contact_zone", "focus", "uniform_edges")
GRADED_OR_REFINED = ("h_max", "growth")
#: The least yield strain Sy/E a material is given with: below it E and Sy are in different
#: units (Validator.yield_strain).
LEAST_YIELD_STRAIN = 1e-5
#: The magnitudes the engine takes E, Sy and H in (rust/src/material.rs, MAGNITUDES); beyond
#: them it refuses the value with its own message, which names that fix.
ENGINE_MAGNITUDES = (1e-50, 1e50)


def inert_keys(data: dict) -> dict[str, tuple]:
    """The keys of a validated document that the validator refuses when they are given with
    the value they hold (their defaults, filled in all the same): the keys its other keys make
    inert, and a displacement's empty default {}.  Per table path ("analysis", "bc.<i>",
    "body.<i>.mesh"), the keys; a document written back without them validates to the same
    data."""
    out = space.other_dimension_keys(data)
    if data["analysis"]["plane"] == "axisymmetric":  # (a 3D case keeps the default, "strain")
        out["analysis"] = ("thickness",)
    for i, bc in enumerate(data["bc"]):
        if not bc["displacement"]:
            out[f"bc.{i}"] = out.get(f"bc.{i}", ()) + ("displacement",)
    for i, body in enumerate(data["body"]):
        mesh = body["mesh"]
        if mesh.get("generator") == "block" and mesh["h_contact"] == 0:
            refined = mesh["refine_box"] is not None
            out[f"body.{i}.mesh"] = GRADED_ONLY + (() if refined else GRADED_OR_REFINED)
    return out


class Validator:
    """Walks the raw document, checks types and values, fills defaults."""

    def __init__(self, source: str):
        self.source = source
        # the terms of the case's [analysis] dimension, read first by :meth:`case`
        self.terms = terms_of(ANALYSIS_KEYS["dimension"].default)

    def fail(self, key: str, message: str) -> CaseError:
        return CaseError(f"{self.source}: {key} {message}")

    # ---- one table against its key declarations
    def table(self, raw, keys: dict, label: str, prefix: str, skip=()) -> dict:
        if not isinstance(raw, dict):
            raise CaseError(f"{self.source}: {label} must be a table")
        unknown = [k for k in raw if k not in keys and k not in skip]
        if unknown:
            valid = ", ".join([*keys, *skip])
            raise CaseError(
                f"{self.source}: unknown key {prefix}{unknown[0]} in {label}; "
                f"valid keys: {valid}"
            )
        for name in raw:
            if name in keys and self.terms.dimension not in keys[name].dims:
                raise self.fail(prefix + name, self.terms.wrong_dimension(prefix + name, raw[name]))
        out = {}
        for name, spec in keys.items():
            full = prefix + name
            if name not in raw:
                if spec.default is REQUIRED or self.terms.dimension in spec.required_in:
                    raise self.fail(
                        full,
                        f"is missing: {spec.doc}"
                        + (f" [{spec.unit}]" if spec.unit else "")
                        + f"; add `{name} = ...` to {label}",
                    )
                out[name] = copy.deepcopy(spec.default)
                if spec.type == "vec" and isinstance(spec.default, list):  # zeros, one a component
                    out[name] = [0.0] * self.terms.dimension
                continue
            out[name] = self.value(raw[name], spec, full)
        return out

    def value(self, v, spec: Key, full: str):
        shown = toml_text(v)  # as written, before int -> float
        t = spec.type
        if t == "vec":  # one component per dimension of the case
            space.check_vector_length(self, v, full)
            t = self.terms.vector_type
        bad = self.fail(full, f"= {shown} is not allowed: expected {_TYPE_HELP[t]}")
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
        elif t in ("vec2", "vec3", "box"):
            size, count = {"vec2": (2, "two"), "vec3": (3, "three"), "box": (4, "four")}[t]
            if (
                not isinstance(v, list)
                or len(v) != size
                or any(isinstance(c, bool) or not isinstance(c, (int, float)) for c in v)
            ):
                raise bad
            v = [float(c) for c in v]
            if not all(math.isfinite(c) for c in v):
                raise self.fail(
                    full, f"= {shown} is not allowed: expected {count} finite " f"numbers"
                )
        elif t == "axes":
            if isinstance(v, list) and "z" in v and "z" not in self.terms.axes:
                raise self.fail(
                    full,
                    f"= {shown} is not allowed in a 2D case: z is the third "
                    f"component (set analysis.dimension = 3, or hold x and y)",
                )
            if (
                not isinstance(v, list)
                or any(c not in self.terms.axes for c in v)
                or len(set(v)) != len(v)
            ):
                raise bad
        elif t == "snapshots":
            if isinstance(v, list):
                if any(isinstance(c, bool) or not isinstance(c, (int, float)) for c in v):
                    raise bad
                v = [float(c) for c in v]
            elif not isinstance(v, str):
                raise bad
        elif t == "points":
            if not isinstance(v, list) or any(
                not isinstance(p, list)
                or len(p) != 2
                or any(isinstance(c, bool) or not isinstance(c, (int, float)) for c in p)
                for p in v
            ):
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
            axes = self.terms.axes
            other = [k for k in v if k not in axes]
            if other and other[0] == "z":
                raise self.fail(
                    f"{full}.z",
                    "is not allowed in a 2D case: z is the third "
                    "component (set analysis.dimension = 3, or prescribe x and y)",
                )
            if other:
                names = f"{', '.join(axes[:-1])} and {axes[-1]}"
                raise self.fail(
                    f"{full}.{other[0]}",
                    f"is not allowed: a displacement has "
                    f"components {names} only, e.g. displacement = "
                    "{x = 0.0, y = -0.1}",
                )
            if not v:
                raise self.fail(
                    full, "= {} is not allowed: give x and/or y, e.g. " "displacement = {y = -0.1}"
                )
        what = "the displacement component" if t == "xy" else "the factor that load reaches"
        out = {}
        for k, c in v.items():
            if isinstance(c, bool) or not isinstance(c, (int, float)):
                raise self.fail(
                    f"{full}.{k}",
                    f"= {toml_text(c)} is not allowed: expected a number " f"({what})",
                )
            if not math.isfinite(c):
                raise self.fail(
                    f"{full}.{k}", f"= {toml_text(c)} is not allowed: expected a finite " f"number"
                )
            out[k] = float(c)
        return out

    # ---- arrays of tables
    def array(self, raw: dict, array: str) -> list:
        elements = raw.get(array, [])
        if not isinstance(elements, list) or any(not isinstance(e, dict) for e in elements):
            raise CaseError(
                f"{self.source}: {array} must be an array of tables, " f"written [[{array}]]"
            )
        return elements

    # ---- the whole document
    def case(self, raw: dict) -> dict:
        known = [*TABLES, *ARRAYS]
        for k in raw:
            if k not in known:
                raise CaseError(
                    f"{self.source}: unknown key {k}; valid top-level tables: "
                    f"{', '.join(known)}"
                )
        self.terms = terms_of(self.case_dimension(raw.get("analysis", {})))
        data = {}
        for name, keys in TABLES.items():
            if name == "load":
                continue
            data[name] = self.table(raw.get(name, {}), keys, f"[{name}]", f"{name}.")
        data["load"] = (
            self.table(raw["load"], LOAD_KEYS, "[load]", "load.") if "load" in raw else None
        )
        self.axisymmetric_thickness(data, raw)

        bodies = self.array(raw, "body")
        if not bodies:
            raise CaseError(
                f"{self.source}: no [[body]]: a case needs at least one body "
                f"with a mesh and a material"
            )
        data["body"] = [
            self.body(b, element_prefix("body", bodies, i), len(bodies))
            for i, b in enumerate(bodies)
        ]
        names = [b["name"] for b in data["body"]]
        for n in names:
            if names.count(n) > 1:
                raise CaseError(
                    f"{self.source}: body.name = {toml_text(n)} is used twice: body "
                    f"names must be unique"
                )
        edges = {b["name"]: b["mesh"]["edges"] for b in data["body"]}  # 3D: the face tags

        data["bc"] = [
            self.bc(e, element_prefix("bc", raw.get("bc", []), i), edges)
            for i, e in enumerate(self.array(raw, "bc"))
        ]
        pls = self.array(raw, "point_load")
        data["point_load"] = []
        for i, e in enumerate(pls):
            prefix = element_prefix("point_load", pls, i)
            pl = self.table(e, POINT_LOAD_KEYS, "[[point_load]]", prefix)
            if pl["body"]:
                self.need_body(pl["body"], prefix + "body", edges)
            data["point_load"].append(pl)
        contacts = self.array(raw, "contact")
        data["contact"] = [
            self.contact(c, element_prefix("contact", contacts, i), edges)
            for i, c in enumerate(contacts)
        ]
        self.load(data, edges)
        stages = self.array(raw, "stage")
        if "stage" in raw and not stages:
            raise self.fail(
                "stage",
                "= [] is not allowed: an empty load path; give one or more "
                "[[stage]] tables with factors = {...}, or remove the key "
                "(one stage with every load at factor 1)",
            )
        data["stage"] = [
            self.table(s, STAGE_KEYS, "[[stage]]", element_prefix("stage", stages, i))
            for i, s in enumerate(stages)
        ]
        self.stage_names(data["stage"])
        path = load_path(CaseRecord.of(data), self.source)  # checks loads, names and factors
        n_stages = path.n_stages
        snaps = data["output"]["snapshots"]
        reason = check_snapshot_times(snaps, n_stages) if isinstance(snaps, list) else None
        if reason:
            raise self.fail("output.snapshots", f"= {toml_text(snaps)} is not allowed: {reason}")
        return data

    def case_dimension(self, analysis) -> int:
        """``[analysis] dimension`` alone, checked (2 when absent or not a table: the table's
        own check says why)."""
        if not isinstance(analysis, dict) or "dimension" not in analysis:
            return 2
        return self.value(analysis["dimension"], ANALYSIS_KEYS["dimension"], "analysis.dimension")

    def axisymmetric_thickness(self, data: dict, raw: dict) -> None:
        """``thickness`` does not apply to rings (every force is a total over the ring)."""
        given = raw.get("analysis", {})
        if data["analysis"]["plane"] == "axisymmetric" and "thickness" in given:
            raise self.fail(
                "analysis.thickness",
                f"= {toml_text(given['thickness'])} is not allowed "
                f'with plane = "axisymmetric": forces are '
                f"totals over the full ring (2 pi r), there is "
                f"no thickness; remove analysis.thickness",
            )

    def stage_names(self, stages: list) -> None:
        """Stage names must be unique (--set and the outputs address stages by name)."""
        names = [s["name"] for s in stages]
        for k, n in enumerate(names):
            if n and n in names[:k]:  # by index: --set finds the first of a shared name
                raise self.fail(
                    f"stage.{k}.name",
                    f"= {toml_text(n)} is used twice (also by stage."
                    f"{names.index(n)}): stage names must be "
                    f"unique; rename one",
                )

    def body(self, raw: dict, prefix: str, n_bodies: int) -> dict:
        body = self.table(raw, BODY_KEYS, "[[body]]", prefix, skip=("mesh", "material"))
        sub = "" if n_bodies == 1 else prefix  # messages: material.nu for a single body
        if "material" not in raw:
            raise self.fail(
                f"{sub}material", "is missing: add a [body.material] table with " "E and nu"
            )
        body["material"] = self.table(
            raw["material"], MATERIAL_KEYS, "[body.material]", f"{sub}material."
        )
        self.yield_strain(body["material"], f"{sub}material.")
        if "mesh" not in raw:
            choices = " or ".join(
                toml_text(g)
                for g in MESH_VARIANTS
                if generator_dimension(g) == self.terms.dimension
            )
            raise self.fail(
                f"{sub}mesh",
                f"is missing: add a [body.mesh] table with generator = "
                f'{choices}, or file = "..."',
            )
        body["mesh"] = self.mesh(raw["mesh"], f"{sub}mesh.")
        return body

    def yield_strain(self, material: dict, prefix: str) -> None:
        """A yield stress no material has beside its E: Sy/E below :data:`LEAST_YIELD_STRAIN`
        (lead's and annealed copper's are ~3e-4) is E and Sy in different units (E in Pa, Sy in
        MPa gives 1e-9).  A large Sy stays allowed: it keeps a body elastic.  Values beyond the
        engine's magnitudes are left to its own message."""
        low, high = ENGINE_MAGNITUDES
        if material["Sy"] is None or not all(low <= material[k] <= high for k in ("E", "Sy")):
            return
        if material["Sy"] < LEAST_YIELD_STRAIN * material["E"]:
            raise self.fail(
                prefix + "Sy",
                f"= {material['Sy']:g} is not allowed: it is "
                f"{material['Sy'] / material['E']:.3g} of E = "
                f"{material['E']:g}, a yield strain Sy/E below "
                f"{LEAST_YIELD_STRAIN:g} that no material has: give E "
                f"and Sy in the same units (e.g. both in MPa)",
            )

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
            choices = " or ".join(
                toml_text(g)
                for g in MESH_VARIANTS
                if generator_dimension(g) in (None, self.terms.dimension)
            )
            what = "is missing" if gen is None else f"= {toml_text(gen)} is not allowed"
            raise self.fail(
                prefix + "generator", f"{what}: use {choices}, or give " f'file = "mesh.msh"'
            )
        if generator_dimension(gen) not in (None, self.terms.dimension):
            raise self.fail(prefix + "generator", self.terms.wrong_variant("generator", gen))
        mesh = self.table(raw, MESH_VARIANTS[gen], "[body.mesh]", prefix)
        check = {
            "quarter_cylinder": self.cylinder_mesh,
            "half_cylinder": self.cylinder_mesh,
            "disc": self.cylinder_mesh,
            "quarter_annulus": self.annulus_mesh,
        }
        if gen == "block":
            self.block_mesh(mesh, raw, prefix)
        elif gen in check:
            check[gen](mesh, prefix)
        elif generator_dimension(gen) == 3:
            space.check_mesh(self, mesh, raw, prefix)
        mesh["edges"] = generator_tags(mesh)  # None ("given"): known with the mesh
        return mesh

    def cylinder_mesh(self, mesh: dict, prefix: str) -> None:
        """quarter_cylinder / half_cylinder / disc: h_contact <= h_max, contact_zone < R."""
        if mesh["h_contact"] > mesh["h_max"]:
            raise self.fail(
                prefix + "h_contact",
                f"= {toml_text(mesh['h_contact'])} is not "
                f"allowed: it must not exceed h_max = {toml_text(mesh['h_max'])}",
            )
        if mesh["contact_zone"] >= mesh["R"]:
            raise self.fail(
                prefix + "contact_zone",
                f"= {toml_text(mesh['contact_zone'])} is not"
                f" allowed: it must be smaller than R = {toml_text(mesh['R'])}",
            )

    def annulus_mesh(self, mesh: dict, prefix: str) -> None:
        """quarter_annulus: b > a, element sizes within the wall."""
        if mesh["b"] <= mesh["a"]:
            raise self.fail(
                prefix + "b",
                f"= {toml_text(mesh['b'])} is not allowed: the outer "
                f"radius must exceed the inner radius a = {toml_text(mesh['a'])}",
            )
        for key in ("h", "h_outer"):
            if mesh[key] > mesh["b"] - mesh["a"]:
                raise self.fail(
                    prefix + key,
                    f"= {toml_text(mesh[key])} is not allowed: it must "
                    f"not exceed the wall thickness b - a = "
                    f"{toml_text(mesh['b'] - mesh['a'])}",
                )

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
        self.structured_sizes(mesh, prefix)
        refined = mesh["refine_box"] is not None
        for key in GRADED_ONLY + GRADED_OR_REFINED:
            if key not in raw or (refined and key in GRADED_OR_REFINED):
                continue
            shown = f"= {toml_text(mesh[key])} is not allowed"
            if refined:
                raise self.fail(
                    prefix + key,
                    f"{shown} with refine_box: it shapes the graded "
                    f"block (h_contact > 0), fine around focus; drop {key}",
                )
            if key in GRADED_OR_REFINED:
                raise self.fail(
                    prefix + key,
                    f"{shown} without h_contact or refine_box: it "
                    f"shapes the graded block (h_contact > 0) or the refined one "
                    f"(refine_box); add one of them or drop {key}",
                )
            raise self.fail(
                prefix + key,
                f"{shown} without h_contact: it shapes the graded "
                f"block (h_contact > 0); add h_contact or drop {key}",
            )
        if refined:
            self.refine_box(mesh, prefix)

    def structured_sizes(self, mesh: dict, prefix: str) -> None:
        """A structured block or box: the divisions along each of its sides
        (:data:`slipstep.schema.sizes.SIDES`), or h."""
        for n, size in SIDES[mesh["generator"]]:
            if mesh[n] == 0 and mesh["h"] == 0:
                raise self.fail(
                    prefix + n,
                    f"is missing: give {n} (divisions along "
                    f"{size}) or h (element size), or h_contact (a graded "
                    f"gmsh mesh)",
                )

    def refine_box(self, mesh: dict, prefix: str) -> None:
        """The refined block: a box [x0, y0, x1, y1] inside the block, h_max >= the grid
        spacing."""
        bx0, by0, bx1, by1 = mesh["refine_box"]
        x0, y0, x1, y1 = (
            mesh["x0"],
            mesh["y0"],
            mesh["x0"] + mesh["width"],
            mesh["y0"] + mesh["height"],
        )
        shown = f"= {toml_text(mesh['refine_box'])} is not allowed"
        if not (bx0 < bx1 and by0 < by1):
            raise self.fail(
                prefix + "refine_box",
                f"{shown}: write it [x0, y0, x1, y1] with " f"x0 < x1 and y0 < y1",
            )
        tol = 1e-9 * max(mesh["width"], mesh["height"])  # as mesh.refined_block
        if not (x0 - tol <= bx0 and bx1 <= x1 + tol and y0 - tol <= by0 and by1 <= y1 + tol):
            raise self.fail(
                prefix + "refine_box",
                f"{shown}: it reaches outside the block "
                f"[{toml_text(x0)}, {toml_text(x1)}] x [{toml_text(y0)}, {toml_text(y1)}]; keep it "
                f"inside",
            )
        if mesh["h_max"] == 0:
            raise self.fail(
                prefix + "h_max",
                "is missing: the refined block (refine_box) "
                "needs the largest element size [length]; add `h_max = ...` to "
                "[body.mesh]",
            )
        nx, ny = block_divisions(mesh)
        spacing = min(mesh["width"] / nx, mesh["height"] / ny)
        if mesh["h_max"] < spacing:
            raise self.fail(
                prefix + "h_max",
                f"= {toml_text(mesh['h_max'])} is not allowed: it "
                f"must not be smaller than the grid spacing {spacing:g} that the "
                f"refined block grows from",
            )

    def graded_block_mesh(self, mesh: dict, prefix: str) -> None:
        """h_contact around focus: contact_zone and h_max given, no structured keys."""
        hc = toml_text(mesh["h_contact"])
        for key in ("nx", "ny", "h"):
            if mesh[key] > 0:
                raise self.fail(
                    prefix + key,
                    f"= {toml_text(mesh[key])} is not allowed "
                    f"together with h_contact = {hc}: nx/ny/h make the "
                    f"structured block, h_contact the graded one; drop "
                    f"{key} (or h_contact)",
                )
        if mesh["refine_box"] is not None:
            raise self.fail(
                prefix + "refine_box",
                f"= {toml_text(mesh['refine_box'])} is not "
                f"allowed together with h_contact = {hc}: refine_box keeps the "
                f"structured block (nx/ny or h) inside it, h_contact grades around "
                f"focus; drop refine_box (or h_contact)",
            )
        for key, what in (
            ("contact_zone", "the radius of the fine zone around focus"),
            ("h_max", "the largest element size"),
        ):
            if mesh[key] == 0:
                raise self.fail(
                    prefix + key,
                    f"is missing: the graded block "
                    f"(h_contact = {hc}) needs {what} [length]; add "
                    f"`{key} = ...` to [body.mesh]",
                )
        if mesh["h_contact"] > mesh["h_max"]:
            raise self.fail(
                prefix + "h_contact",
                f"= {hc} is not allowed: it must not " f"exceed h_max = {toml_text(mesh['h_max'])}",
            )
        if mesh["focus"] is not None:
            (fx, fy), x0, y0 = mesh["focus"], mesh["x0"], mesh["y0"]
            x1, y1 = x0 + mesh["width"], y0 + mesh["height"]
            tol = 1e-9 * max(mesh["width"], mesh["height"])  # as mesh.graded_block
            if not (x0 - tol <= fx <= x1 + tol and y0 - tol <= fy <= y1 + tol):
                raise self.fail(
                    prefix + "focus",
                    f"= {toml_text(mesh['focus'])} is not "
                    f"allowed: it lies outside the block [{toml_text(x0)}, "
                    f"{toml_text(x1)}] x [{toml_text(y0)}, {toml_text(y1)}]; move it "
                    f"inside or onto the boundary",
                )

    def need_body(self, name: str, key: str, edges: dict) -> None:
        if name not in edges:
            raise self.fail(
                key,
                f"= {toml_text(name)} is not allowed: no body has that name "
                f"(bodies: {', '.join(edges)})",
            )

    def need_edge(self, body: str, tag: str, key: str, edges: dict) -> None:
        """A body's edge tag (3D: face tag) must exist (when its generator tells them)."""
        known = edges[body]
        what = self.terms.boundary
        if known is not None and tag not in known:
            raise self.fail(
                key,
                f"= {toml_text(tag)} is not allowed: body {toml_text(body)} has no "
                f"{what} with that tag (its {what}s: {', '.join(known)})",
            )

    def bc(self, raw: dict, prefix: str, edges: dict) -> dict:
        bc = self.table(raw, BC_KEYS, "[[bc]]", prefix)
        self.need_body(bc["body"], prefix + "body", edges)
        surface = self.terms.boundary
        if bool(bc[surface]) == bool(bc["nodes"]):
            raise self.fail(
                prefix + surface,
                f"is missing: give exactly one of {surface} (an "
                f"{surface} tag) or nodes (a node set)",
            )
        if bc[surface]:
            self.need_edge(bc["body"], bc[surface], prefix + surface, edges)
        loads = bc["pressure"] != 0.0 or any(c != 0.0 for c in bc["traction"])
        if not (bc["fix"] or bc["symmetry"] or loads or bc["displacement"]):
            raise CaseError(
                f"{self.source}: {prefix[:-1]} does nothing: give fix, symmetry, "
                f"pressure, traction or displacement"
            )
        if bc["nodes"] and (loads or bc["symmetry"]):
            raise self.fail(
                prefix + "nodes",
                f"supports fix and displacement only: put "
                f"pressure, traction and symmetry on an {surface}",
            )
        for c in bc["displacement"]:
            if c in bc["fix"]:
                raise self.fail(
                    f"{prefix}displacement.{c}",
                    f"is not allowed: fix also holds "
                    f"{c} (at zero): a component is fixed or prescribed, not both; "
                    f'remove "{c}" from fix or {c} from displacement',
                )
        return bc

    def contact(self, raw: dict, prefix: str, edges: dict) -> dict:
        kind = raw.get("kind")
        if not isinstance(kind, str) or kind not in CONTACT_VARIANTS:
            choices = " or ".join(toml_text(k) for k in CONTACT_VARIANTS)
            what = "is missing" if kind is None else f"= {toml_text(kind)} is not allowed"
            raise self.fail(prefix + "kind", f"{what}: use {choices}")
        if kind_dimension(kind) not in (None, self.terms.dimension):
            raise self.fail(prefix + "kind", self.terms.wrong_variant("kind", kind))
        if kind in ("node_to_node", "node_to_segment", "node_to_surface") and "motion" in raw:
            raise self.fail(
                prefix + "motion",
                "is not allowed: motion on a deformable-pair "
                f'contact (kind "{kind}"): motion moves a rigid obstacle; '
                "prescribe a displacement [[bc]] on one of the bodies instead",
            )
        c = self.table(raw, CONTACT_VARIANTS[kind], f'[[contact]] of kind "{kind}"', prefix)
        for key, body, tag in contact_tags(c):
            body_key = "body" if key in ("edge", "face") else f"body_{key[-1]}"
            self.need_body(body, prefix + body_key, edges)
            self.need_edge(body, tag, prefix + key, edges)
        if kind == "rigid_surface":
            space.check_rigid_surface(self, c, prefix)
        return c

    def load(self, data: dict, edges: dict) -> None:
        """`[load] P` needs a quarter_cylinder body (3D: a sphere) to act on."""
        load = data["load"]
        if load is None:
            return
        generator = self.terms.hertz_generator
        cylinders = [b["name"] for b in data["body"] if b["mesh"].get("generator") == generator]
        if load["body"]:
            self.need_body(load["body"], "load.body", edges)
            if load["body"] not in cylinders:
                raise self.fail(
                    "load.body",
                    f"= {toml_text(load['body'])} is not allowed: [load] P "
                    f"acts on a {generator} body",
                )
        elif len(cylinders) == 1:
            load["body"] = cylinders[0]
        else:
            raise self.fail(
                "load.P",
                f"is not allowed here: [load] P is the Hertz convenience "
                f"for one {generator} body (give load.body, or use "
                f"[[bc]] pressure)",
            )
