"""The scene: a case built into the engine's model (:class:`slipstep.engine_model.EngineModel`,
``engine_model``; ``model`` is the dict of it the engine reads, docs/engine_api.md) and what the
outputs need besides it: which body each node belongs to, each candidate pair's node position,
tributary length and contact area (contact pressure = lambda_n / area), the Hertz reference
when it applies, and the load path (named loads, stages, factors, supports and prescribed
displacements).  :func:`slipstep.build.build_scene` makes one.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .case import Case
from .engine_model import EngineModel
from .mesh.base import Mesh


@dataclass(kw_only=True)
class Scene:
    """The assembled problem: global mesh, the engine model, and per-pair bookkeeping."""

    case: Case
    bodies: list[str]
    meshes: dict[str, Mesh]
    offsets: dict[str, int]  # first global node id of each body
    nodes: np.ndarray  # (N, 2); 3D: (N, 3)
    # (M, 3); 3D: (0, 3), the elements are ``tetrahedra``
    triangles: np.ndarray = field(default_factory=lambda: np.zeros((0, 3), dtype=np.int64))
    element_body: np.ndarray  # (M,) index into bodies
    # how the bodies are modelled, chosen once by build_scene (slipstep.idealisation): a 2D
    # Section or a 3D Solid, which the outputs ask instead of testing the dimension
    idealisation: object
    # the engine's model, and the dict of it the engine reads (a caller may edit the dict
    # before solving: the runner hands it to the engine); set together by ``use_model``
    engine_model: EngineModel | None = None
    model: dict = field(default_factory=dict)
    pair_xy: np.ndarray = field(
        default_factory=lambda: np.zeros((0, 2))
    )  # (P, 2) node a; 3D (P, 3)
    pair_length: np.ndarray = field(default_factory=lambda: np.zeros(0))  # (P,) tributary length
    pair_contact: np.ndarray = field(
        default_factory=lambda: np.zeros(0, dtype=np.int64)
    )  # [[contact]]
    # (P,) the area its contact force acts on: L t, or its ring 2 pi int N_a r ds (contact_areas)
    pair_area: np.ndarray = field(default_factory=lambda: np.zeros(0))
    # node-to-segment rows: node a's closest target point (end nodes l1, l2 and parameter eta)
    # and its own initial gap, where the outputs measure gap and RTD; (-1, -1, 0) and nan else
    pair_foot: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    pair_point_gap: np.ndarray = field(default_factory=lambda: np.zeros(0))
    # per [[contact]]: True when some nodes of its candidate edge are not candidates (window,
    # no partner), so contact reaching the outermost candidate may be cut short
    contact_truncated: list = field(default_factory=list)
    reference: dict = field(default_factory=dict)  # Hertz a, p0 when the case is Hertz-like
    # the load path (docs: cases/README.md, [[stage]]); see build_scene
    load_names: list = field(default_factory=lambda: ["load"])  # factor order, "load" first
    stage_names: list = field(default_factory=lambda: ["stage 1"])
    n_stages: int = 1
    support_dofs: dict = field(default_factory=dict)  # bc name -> (k,) DOFs it holds
    prescribed: dict = field(default_factory=dict)  # load name -> {"dofs", "values"}
    motions: dict = field(default_factory=dict)  # load name -> {"contact", "motion"}
    factors: np.ndarray = field(default_factory=lambda: np.array([[0.0], [1.0]]))
    given_meshes: tuple = ()  # the bodies whose mesh came from Python (build_scene's meshes)
    # 3D scenes (slipstep.builders.solid): the elements, and each pair's tangent basis (t1, t2)
    tetrahedra: np.ndarray = field(default_factory=lambda: np.zeros((0, 4), dtype=np.int64))
    pair_tangent: np.ndarray = field(default_factory=lambda: np.zeros((0, 2, 3)))

    @classmethod
    def of_bodies(cls, case: Case, meshes: dict[str, Mesh], given: tuple, idealisation) -> Scene:
        """The scene of a case's meshed bodies in one node numbering (:func:`merged_bodies`),
        before its contact pairs and engine model: triangles in 2D, tetrahedra in 3D, as the
        ``idealisation`` has them (``given``: the bodies whose mesh came from Python)."""
        bodies = [b.name for b in case.record.body]
        offsets, nodes, elements, element_body = merged_bodies(bodies, meshes)
        cells = {idealisation.cells_field: elements}
        return cls(
            case=case,
            bodies=bodies,
            meshes=meshes,
            offsets=offsets,
            nodes=nodes,
            element_body=element_body,
            idealisation=idealisation,
            pair_xy=np.zeros((0, nodes.shape[1])),
            given_meshes=tuple(given),
            **cells,
        )

    def use_model(self, model: EngineModel) -> None:
        """Take ``model`` as the scene's engine model, and its dict as ``model``."""
        self.engine_model, self.model = model, model.to_engine()

    @property
    def dimension(self) -> int:
        """2 (triangles, two DOFs per node) or 3 (tetrahedra, three)."""
        return self.idealisation.dimension

    @property
    def n_dofs(self) -> int:
        return self.dimension * len(self.nodes)

    @property
    def elements(self) -> np.ndarray:
        """The element connectivity: (M, 3) triangles, or (M, 4) tetrahedra in 3D."""
        return self.idealisation.elements(self)

    def global_edge(self, body: str, tag: str) -> np.ndarray:
        """Segments of a body's edge tag in global node numbers (body on the left)."""
        return self.meshes[body].edges[tag] + self.offsets[body]

    def global_boundary(self, body: str, tag: str) -> np.ndarray:
        """A body's boundary tag in global node numbers: edge segments (body on the left), or
        in 3D face triangles (outward)."""
        return self.meshes[body].tags[tag] + self.offsets[body]


def merged_bodies(
    bodies: list[str], meshes: dict
) -> tuple[dict, np.ndarray, np.ndarray, np.ndarray]:
    """The bodies' meshes in one global numbering, body after body: (first node of each body,
    nodes, elements (triangles, or tetrahedra in 3D) in global node ids, the body index of
    each element)."""
    offsets, start = {}, 0
    for name in bodies:
        offsets[name] = start
        start += meshes[name].n_nodes
    nodes = np.concatenate([meshes[b].nodes for b in bodies])
    elements = np.concatenate([meshes[b].elements + offsets[b] for b in bodies])
    element_body = np.concatenate(
        [np.full(meshes[b].n_elements, i, dtype=np.int64) for i, b in enumerate(bodies)]
    )
    return offsets, nodes, elements, element_body
