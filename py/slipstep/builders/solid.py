"""Case + meshes -> the 3D :class:`slipstep.scene.Scene` (a solid of tetrahedra) and its engine
model (docs/engine_api.md, "3D models"): every body a tetrahedron mesh
(:mod:`slipstep.mesh.tetrahedron_generators`, :mod:`slipstep.mesh.tetrahedron_files`), merged
into one node numbering, with the supports and loads of :mod:`slipstep.loads` (three components
per node) and the pairs of :mod:`slipstep.contact.faces`."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..errors import CaseError
from ..loads.vectors import load_force, load_vector
from ..mesh.base import MeshError
from ..options import solver_options
from ..measures.references import effective_modulus, hertz_sphere
from ..scene import Scene
from .model import engine_load_path, engine_model
from ..output.snapshots import requested, step_bytes
from ..loads.supports import supports
from ..validation.scene import check_duplicate_nodes, check_pairs_not_held
from ..mesh import tetrahedron_generators as generators
from ..contact.faces import align_to_supports, pair_rows, tangent_basis
from ..contact.pairs import contact_pairs
from ..mesh.tetrahedra import TetMesh
from ..mesh.tetrahedron_files import read_tet_mesh
from ..schema.solid import box_divisions


def mesh_body_3d(case, index: int) -> TetMesh:
    """Mesh one body of a 3D case from its [body.mesh] table (not a "given" one: its mesh
    comes from Python, :func:`slipstep.build.build_scene`)."""
    body = case.record.body[index]
    try:
        return _meshed(case, body.mesh)
    except MeshError as exc:
        raise CaseError(f"{case.source}: body {body.name!r}: {exc}") from None


def _meshed(case, spec) -> TetMesh:
    if spec.get("file"):
        face_file = case.base_dir / spec["face_file"] if spec["face_file"] else None
        return read_tet_mesh(case.base_dir / spec["file"], face_file, spec["scale"])
    gen = spec["generator"]
    if gen == "shell":
        return generators.shell(spec["a"], spec["b"], spec["h"], spec["h_outer"])
    graded = {k: spec[k] for k in ("h_contact", "contact_zone", "h_max", "growth")}
    if gen == "sphere":
        return generators.sphere(spec["R"], **graded, portion=spec["portion"])
    if gen == "roller":
        return generators.roller(spec["R"], spec["length"], **graded, portion=spec["portion"])
    if gen == "punch":
        return generators.punch(
            spec["a"], spec["height"], **graded, shape=spec["shape"], portion=spec["portion"]
        )
    corner = (spec["x0"], spec["y0"], spec["z0"])
    if spec["h_contact"] > 0:
        return generators.graded_box(
            spec["width"],
            spec["depth"],
            spec["height"],
            **graded,
            focus=spec["focus"],
            corner=corner,
        )
    return generators.box(
        spec["width"], spec["depth"], spec["height"], *box_divisions(spec), corner=corner
    )


def build_solid_scene(case, body_meshes: dict[str, TetMesh], given: tuple, idealisation) -> Scene:
    """The 3D scene of a case whose bodies are meshed (``given``: the bodies whose mesh came
    from Python; ``idealisation``: the scene's, :class:`slipstep.idealisation.solid.Solid`)."""
    scene = Scene.of_bodies(case, body_meshes, given, idealisation)
    pairs = contact_pairs(scene, pair_rows, "area", 6, tangent_basis)
    scene.pair_length = np.full(len(scene.pair_area), np.nan)  # 2D only
    check_duplicate_nodes(scene, pairs.to_engine())
    path = case.path
    fixed = supports(scene)
    held = np.zeros((len(scene.nodes), 3), dtype=bool)
    held.reshape(-1)[np.asarray(fixed, dtype=np.int64)] = True
    pairs = replace(
        pairs, tangent=align_to_supports(pairs.normal, pairs.tangent, held[pairs.node_a])
    )
    scene.pair_tangent = pairs.tangent
    load = load_vector(scene) if not path.staged else load_force(scene, path.head)
    patterns, stages = engine_load_path(scene, path)
    model = engine_model(
        scene,
        pairs=pairs,
        fixed_dofs=fixed,
        load=load,
        options={},  # below: they need the model
        patterns=patterns,
        stages=stages,
        dimension=3,
        tetrahedra=scene.tetrahedra,
    )
    scene.use_model(model)
    check_pairs_not_held(scene)
    scene.reference = hertz_sphere_reference(scene)
    # "auto" snapshots are sized by the scene's time step in results.h5 (slipstep.output.snapshots)
    options = solver_options(case, requested(case, step_bytes(scene)))
    scene.use_model(replace(model, options=options))
    return scene


def hertz_sphere_reference(scene) -> dict:
    """Hertz's sphere on a rigid flat (Johnson §4.2) for a 3D case with ``[load] P`` on a sphere
    and a ``rigid_plane`` contact on it: a, p0 (as P^(1/3)) and the approach delta (P^(2/3))
    of the full sphere under P, with E* = E/(1 - nu^2)."""
    case = scene.case.record
    load = case.load
    if load is None or not any(
        c.kind == "rigid_plane" and c.body == load.body for c in case.contact
    ):
        return {}
    material, R = case.hertz_body.material, case.hertz_body.mesh["R"]
    E, nu, P = material.E, material.nu, load.P
    a, p0, delta = hertz_sphere(P, R, E, nu)
    return {
        "contact": "sphere",
        "a_hertz": a,
        "p0_hertz": p0,
        "delta_hertz": delta,
        "P": P,
        "R": R,
        "E_star": effective_modulus(E, nu, "strain"),
        "load_exponent": 1.0 / 3.0,
    }
