"""Loads: the consistent nodal forces of pressures, tractions, the Hertz load and point loads
(weighted by the section, :mod:`slipstep.section`; on the faces of a 3D body,
:func:`slipstep.loads.faces.face_load`), and the engine's load patterns and stages along the
load path (:mod:`slipstep.loads.path`)."""

from __future__ import annotations

import math

import numpy as np

from ..mesh import triangles as meshing
from ..case import Case
from .path import Load, LoadPath, case_loads
from ..scene import Scene
from ..section import boundary_shares, is_axisymmetric


def edge_load(
    nodes: np.ndarray,
    segments: np.ndarray,
    n_nodes: int,
    thickness: float,
    pressure: float = 0.0,
    traction=(0.0, 0.0),
    plane: str = "strain",
) -> np.ndarray:
    """Consistent nodal loads of a uniform pressure and/or traction on linear edge segments.

    Traction on a segment: t = traction - pressure * n (n outward); each end node gets t times
    its :func:`boundary_shares` (half of t L thickness in the plane; in axisymmetry the ring
    load 2 pi int N_i r t ds).  Returns a (2 n_nodes,) vector.
    """
    f = np.zeros(2 * n_nodes)
    if len(segments) == 0:
        return f
    t = np.asarray(traction, dtype=np.float64)[None, :] - pressure * meshing.outward_normals(
        nodes, segments
    )
    share = boundary_shares(nodes, segments, plane, thickness)
    for end in (0, 1):
        force = t * share[:, end, None]
        for c in (0, 1):
            np.add.at(f, 2 * segments[:, end] + c, force[:, c])
    return f


def load_vector(scene: Scene) -> np.ndarray:
    """The summed nodal force at load fraction 1 of a case without [[stage]] (``[[bc]]``
    pressure/traction, ``[load] P``, ``[[point_load]]``, in this order), thickness included."""
    rank = {"bc": 0, "load": 1, "point_load": 2}
    f = np.zeros(scene.n_dofs)
    for load in sorted(
        (x for x in case_loads(scene.case.record) if x.force), key=lambda x: rank[x.array]
    ):
        f += load_force(scene, load)
    return f


def load_force(scene: Scene, load: Load | None) -> np.ndarray:
    """The nodal force of one load at factor 1, thickness included (ring totals in
    axisymmetry; forces in 3D; zeros for None or a load without force)."""
    case, d = scene.case.record, scene.dimension
    f = np.zeros(scene.n_dofs)
    if load is None or not load.force:
        return f
    if load.array == "load":
        return boundary_load(scene, case.load.body, "top", scene.idealisation.cut_pressure(scene))
    if load.array == "bc":
        bc = case.bc[load.index]
        return boundary_load(scene, bc.body, bc.boundary_tag, bc.pressure, bc.traction)
    pl = case.point_load[load.index]
    candidates = [pl.body] if pl.body else scene.bodies
    ids = np.concatenate(
        [np.arange(scene.meshes[b].n_nodes) + scene.offsets[b] for b in candidates]
    )
    node = ids[np.argmin(np.linalg.norm(scene.nodes[ids] - np.asarray(pl.at), axis=1))]
    weight = scene.idealisation.point_force_scale(scene.case)
    f[d * node : d * node + d] += np.asarray(pl.force) * weight
    return f


def boundary_load(
    scene: Scene, body: str, tag: str, pressure: float = 0.0, traction=None
) -> np.ndarray:
    """The consistent nodal forces of a uniform pressure and traction on a body's edge tag
    (:func:`section_boundary_load`), or in 3D on its face tag
    (:func:`slipstep.loads.faces.face_load`): the scene's idealisation's."""
    cells = scene.global_boundary(body, tag)
    traction = np.zeros(scene.dimension) if traction is None else traction
    return scene.idealisation.boundary_load(scene, cells, pressure, traction)


def section_boundary_load(
    scene: Scene, segments: np.ndarray, pressure: float, traction
) -> np.ndarray:
    """:func:`edge_load` on a 2D scene's edge segments, with its thickness and plane."""
    analysis = scene.case.record.analysis
    return edge_load(
        scene.nodes,
        segments,
        len(scene.nodes),
        analysis.thickness,
        pressure,
        traction,
        plane=analysis.plane,
    )


def set_load_path(scene: Scene, path: LoadPath) -> None:
    """The engine's ``patterns`` and ``stages`` (only when the case needs them: a case without
    [[stage]], displacement and motion keeps the model it always had) and the scene's load-path
    attributes."""
    scene.load_names = list(path.names)
    scene.stage_names = list(path.stage_names)
    scene.n_stages = path.n_stages
    scene.factors = np.array(path.factors, dtype=np.float64)
    contacts = scene.case.record.contact
    scene.motions = {
        x.label: {"contact": x.index, "motion": list(contacts[x.index].motion_load)}
        for x in path.loads
        if x.array == "contact"
    }
    if path.patterns:
        scene.model["patterns"] = [load_pattern(scene, x, path.staged) for x in path.patterns]
    if path.staged:
        scene.model["stages"] = [
            {"name": s.name, "factors": np.array(row, dtype=np.float64)}
            for s, row in zip(scene.case.record.stage, path.factors[1:])
        ]


def load_pattern(scene: Scene, load: Load, with_force: bool) -> dict:
    """One entry of the engine's ``patterns`` (its force only ``with_force``: without
    [[stage]] forces are summed into ``load``)."""
    out = {"name": load.label}
    if with_force and load.force:
        out["force"] = load_force(scene, load)
    if load.label in scene.prescribed:
        out["displacement_dofs"] = scene.prescribed[load.label]["dofs"]
        out["displacement_values"] = scene.prescribed[load.label]["values"]
    if load.label in scene.motions:
        out["motion_contacts"] = np.array([load.index], dtype=np.int64)
        out["motion"] = np.array([scene.motions[load.label]["motion"]], dtype=np.float64)
    return out


def hertz_cut_pressure(case: Case) -> float:
    """q = P / (2R): the quarter model carries half the total load P across its cut of
    length R (the other half is carried by the mirrored quarter).  In axisymmetry the quarter
    section is a hemisphere whose cut is the disc of radius R: q = P / (pi R^2) (a 3D sphere's
    cut: :func:`slipstep.loads.faces.sphere_cut_pressure`)."""
    load = case.record.load
    R = case.record.hertz_body.mesh["R"]
    if is_axisymmetric(case):
        return load.P / (math.pi * R**2)
    return load.P / (2.0 * R)
