"""Case + meshes -> the 2D :class:`slipstep.scene.Scene` (a plane or axisymmetric section of
triangles): mesh a body, merge them, and build the engine's model from the supports
(:mod:`slipstep.loads.supports`), the loads (:mod:`slipstep.loads.vectors`), the contact pairs
(:mod:`slipstep.contact.edges`) and the options (:mod:`slipstep.options`), checking the scene on
the way (:mod:`slipstep.validation.scene`).

Everything here is set up once, vectorised where it matters; the event loop itself is the
engine's.
"""

from __future__ import annotations

from ..mesh import triangle_generators as generators
from ..case import Case
from ..contact.edges import contact_areas, pair_rows
from ..contact.pairs import contact_pairs
from ..errors import CaseError
from ..mesh.base import Mesh, MeshError
from ..mesh.triangle_files import read_mesh
from ..loads.vectors import load_force, load_vector
from ..options import solver_options
from ..measures.references import effective_modulus, hertz_line, hertz_sphere
from ..scene import Scene
from .model import engine_load_path, engine_model
from ..schema import block_divisions
from ..loads.supports import supports
from ..validation.scene import (
    check_duplicate_nodes,
    check_pairs_not_held,
    check_radii,
    check_stick_on_half_held,
)


def mesh_body(case: Case, index: int) -> Mesh:
    """Mesh one body from its [body.mesh] table."""
    body = case.record.body[index]
    spec = body.mesh
    where = f"body {body.name!r}"
    if body.generator == "given":
        raise CaseError(
            f'{case.source}: body.{body.name}.mesh.generator = "given": its mesh comes '
            f"from Python (slipstep.mesh.from_arrays or from_meshio), not from mesh_body"
        )
    try:
        if spec.get("file"):
            path = case.base_dir / spec["file"]
            edge_file = case.base_dir / spec["edge_file"] if spec["edge_file"] else None
            return read_mesh(path, edge_file, spec["scale"])
        if spec["generator"] in ("quarter_cylinder", "half_cylinder", "disc"):
            make = getattr(generators, spec["generator"])
            return make(
                spec["R"], spec["h_contact"], spec["contact_zone"], spec["h_max"], spec["growth"]
            )
        if spec["generator"] == "quarter_annulus":
            return generators.quarter_annulus(spec["a"], spec["b"], spec["h"], spec["h_outer"])
        if spec["h_contact"] > 0:  # the graded block (gmsh); else the structured one
            return generators.graded_block(
                spec["width"],
                spec["height"],
                spec["h_contact"],
                spec["contact_zone"],
                spec["h_max"],
                spec["growth"],
                spec["focus"],
                spec["x0"],
                spec["y0"],
                spec["uniform_edges"],
            )
        nx, ny = block_divisions(spec)
        if spec["refine_box"] is not None:  # the structured grid inside it, coarse outside
            return generators.refined_block(
                spec["width"],
                spec["height"],
                nx,
                ny,
                spec["refine_box"],
                spec["h_max"],
                spec["growth"],
                spec["x0"],
                spec["y0"],
            )
        return generators.block(spec["width"], spec["height"], nx, ny, spec["x0"], spec["y0"])
    except MeshError as exc:
        raise CaseError(f"{case.source}: {where}: {exc}") from None


def build_section_scene(case: Case, body_meshes: dict, given: tuple, idealisation) -> Scene:
    """The 2D scene of a case whose bodies are meshed (``given``: the bodies whose mesh came
    from Python; ``idealisation``: the scene's, :class:`slipstep.idealisation.section.Section`)."""
    scene = Scene.of_bodies(case, body_meshes, given, idealisation)
    check_radii(scene)
    pairs = contact_pairs(scene, pair_rows, "length", foot_width=3)
    check_duplicate_nodes(scene, pairs.to_engine())
    path = case.path
    fixed = supports(scene)
    load = load_vector(scene) if not path.staged else load_force(scene, path.head)
    options = solver_options(case)
    scene.pair_area = contact_areas(scene, pairs)
    patterns, stages = engine_load_path(scene, path)
    analysis = case.record.analysis
    model = engine_model(
        scene,
        pairs=pairs,
        fixed_dofs=fixed,
        load=load,
        options=options,
        patterns=patterns,
        stages=stages,
        triangles=scene.triangles,
        plane=analysis.plane,
        thickness=float(analysis.thickness),  # the engine ignores it for rings
    )
    scene.use_model(model)
    check_pairs_not_held(scene)
    check_stick_on_half_held(scene)
    scene.reference = hertz_reference(scene)
    return scene


def hertz_reference(scene: Scene) -> dict:
    """Hertz contact on a rigid flat (§5.1 of the paper) for a case with ``[load] P`` and a
    rigid_line contact on that body: a cylinder in plane strain or stress
    (:func:`slipstep.measures.references.hertz_line`; a and p0 grow as P^(1/2), ``load_exponent``), a
    sphere in axisymmetry (:func:`slipstep.measures.references.hertz_sphere`; a and p0 as P^(1/3), the
    approach delta as P^(2/3)).  ``contact`` says which ("line" or "sphere")."""
    case = scene.case.record
    load = case.load
    if load is None:
        return {}
    if not any(c.kind == "rigid_line" and c.body == load.body for c in case.contact):
        return {}
    body = case.hertz_body
    E, nu = body.material.E, body.material.nu
    P, R = load.P, body.mesh["R"]
    plane = case.analysis.plane
    E_star = effective_modulus(E, nu, plane)
    if plane == "axisymmetric":
        a, p0, delta = hertz_sphere(P, R, E, nu)
        return {
            "contact": "sphere",
            "a_hertz": a,
            "p0_hertz": p0,
            "delta_hertz": delta,
            "P": P,
            "R": R,
            "E_star": E_star,
            "load_exponent": 1.0 / 3.0,
        }
    a, p0 = hertz_line(P, R, E, nu, plane)
    return {
        "contact": "line",
        "a_hertz": a,
        "p0_hertz": p0,
        "P": P,
        "R": R,
        "E_star": E_star,
        "load_exponent": 0.5,
    }
