"""A scene's engine model (:class:`slipstep.engine_model.EngineModel`) from the parts every
idealisation has alike: the nodes, each element's material, the names, the supports' groups and
the load path's patterns and stages; the builders (:mod:`slipstep.builders.section`,
:mod:`slipstep.builders.solid`) give the rest: their mesh's fields, the pairs, supports, load and
options."""

from __future__ import annotations

import numpy as np

from ..case import Case
from ..engine_model import ContactPairs, EngineMaterial, EngineModel, LoadPattern, Stage
from ..loads.path import LoadPath
from ..loads.supports import engine_support_groups
from ..loads.vectors import set_load_path
from ..scene import Scene


def engine_model(
    scene: Scene,
    *,
    pairs: ContactPairs,
    fixed_dofs: np.ndarray,
    load: np.ndarray,
    options: dict,
    patterns: tuple[LoadPattern, ...] | None,
    stages: tuple[Stage, ...] | None,
    **mesh,
) -> EngineModel:
    """The scene's engine model; ``mesh``: the fields of its dimension (2D: triangles, plane,
    thickness; 3D: dimension, tetrahedra)."""
    groups = engine_support_groups(scene)  # the reactions recorded at every increment, per [[bc]]
    return EngineModel(
        nodes=scene.nodes,
        element_material=scene.element_body.copy(),
        materials=materials(scene.case),
        fixed_dofs=fixed_dofs,
        load=load,
        pairs=pairs,
        options=options,
        # names for the engine's messages (docs/engine_api.md)
        body_names=tuple(scene.bodies),
        element_body=scene.element_body,
        contact_names=contact_names(scene.case),
        support_names=tuple(groups["support_names"]),
        support_dofs=tuple(groups["support_dofs"]),
        patterns=patterns,
        stages=stages,
        **mesh,
    )


def materials(case: Case) -> tuple[EngineMaterial, ...]:
    """The engine's material of each body, in body order (``Sy``, ``H`` only when plastic)."""
    out = []
    for b in case.record.body:
        m = b.material
        if m.Sy is None:
            out.append(EngineMaterial(E=m.E, nu=m.nu))
        else:
            H = m.H if m.H is not None else 0.0
            out.append(EngineMaterial(E=m.E, nu=m.nu, Sy=m.Sy, H=H))
    return tuple(out)


def contact_names(case: Case) -> tuple[str, ...]:
    """The name of each [[contact]]: its ``name``, else ``contact <i>`` (0-based)."""
    return tuple(c.name or f"contact {i}" for i, c in enumerate(case.record.contact))


def engine_load_path(
    scene: Scene, path: LoadPath
) -> tuple[tuple[LoadPattern, ...] | None, tuple[Stage, ...] | None]:
    """The engine's patterns and stages of the load path (None: the case needs none), with the
    scene's load-path attributes set (:func:`slipstep.loads.vectors.set_load_path`, which
    writes the engine's entries into ``scene.model``: an empty one here, read back)."""
    scene.model = {}
    set_load_path(scene, path)
    written = scene.model
    patterns = written.get("patterns")
    stages = written.get("stages")
    return (
        None if patterns is None else tuple(LoadPattern(**p) for p in patterns),
        None if stages is None else tuple(Stage(**s) for s in stages),
    )
