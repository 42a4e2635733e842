"""Case + meshes -> :class:`slipstep.scene.Scene` and its engine model.

:func:`build_scene` chooses the scene's idealisation (:func:`slipstep.idealisation.of_case`:
a 2D section or a 3D solid), meshes the bodies with it and lets it build the scene
(:mod:`slipstep.builders.section`: 2D bodies, plane or axisymmetric sections of triangles;
:mod:`slipstep.builders.solid`: 3D bodies, solids of tetrahedra).
"""

from __future__ import annotations

from .case import Case
from .errors import CaseError, InputError
from .idealisation import of_case
from .mesh.base import Mesh
from .scene import Scene
from .validation.scene import check_file_mesh_tags

__all__ = ["build_scene"]


def build_scene(case: Case, meshes: dict[str, Mesh] | None = None) -> Scene:
    """Mesh every body (except those whose mesh ``meshes`` gives, by body name), merge them,
    and build the engine model, as the case's idealisation does it (2D:
    :func:`slipstep.builders.section.build_section_scene`, 3D:
    :func:`slipstep.builders.solid.build_solid_scene`)."""
    bodies = [b.name for b in case.record.body]
    given = dict(meshes or {})
    unknown = sorted(set(given) - set(bodies))
    if unknown:
        raise InputError(
            f"build_scene: meshes given for {', '.join(map(repr, unknown))}, "
            f"which the case has no body of (its bodies: {', '.join(bodies)})"
        )
    idealisation = of_case(case)
    wrong = [name for name in given if given[name].dimension != idealisation.dimension]
    if wrong:
        raise InputError(
            f"build_scene: the mesh given for {wrong[0]!r} is "
            f"{given[wrong[0]].dimension}D, the case {case.dimension}D "
            f"(analysis.dimension): give a {case.dimension}D mesh"
        )
    missing = [b.name for b in case.record.body if b.generator == "given" and b.name not in given]
    if missing:
        raise given_mesh_missing(case, missing[0], idealisation.given_mesh_from)
    body_meshes = {
        name: given[name] if name in given else idealisation.mesh_body(case, i)
        for i, name in enumerate(bodies)
    }
    check_file_mesh_tags(case, body_meshes, idealisation.boundary)
    return idealisation.build(case, body_meshes, tuple(name for name in bodies if name in given))


def given_mesh_missing(case: Case, body: str, how: str) -> CaseError:
    """The error of a body whose ``generator = "given"`` mesh was not passed from Python
    (``how``: the functions that make one)."""
    return CaseError(
        f'{case.source}: body.{body}.mesh.generator = "given": pass its mesh from '
        f'Python, slipstep.run(case, meshes={{"{body}": mesh}}) ({how})'
    )
