"""The interface of a scene's idealisation (:mod:`slipstep.idealisation`): what differs between
a 2D section and a 3D solid, from meshing the bodies to drawing the result.  It extends the case
document's terms of its dimension (:mod:`slipstep.validation.terms`: the boundary's word, the
components of a vector...).  Each method forwards to its implementation's module; printing one
names it."""

from __future__ import annotations

from abc import abstractmethod

import numpy as np

from ..validation.terms import Terms


class Idealisation(Terms):
    """How a scene's bodies are modelled; ``scene.idealisation``."""

    #: stress components per element in the engine's result, and their names in the outputs
    stress_width: int
    stress_names: tuple[str, ...]
    #: the meshio cell type of the elements; the XDMF topologies of the elements and of the
    #: boundary facets (:mod:`slipstep.fenicsx.exchange`)
    cell_type: str
    xdmf_topology: tuple[str, str]
    #: the :class:`~slipstep.scene.Scene` field that holds its elements
    cells_field: str
    #: the functions that make a mesh given from Python
    given_mesh_from: str
    #: the components a resultant force and moment have, and the names of components
    force_components: tuple[int, ...]
    moment_components: tuple[int, ...]
    component_names: str
    #: the axes of the engine's contact moments (about z in 2D: one number per contact)
    engine_moment_axes: tuple[int, ...]

    def __repr__(self) -> str:
        return (
            f"{type(self).__name__}: {self.dimension}D, {self.cell_type} elements, "
            f"contact and supports on {self.boundary}s"
        )

    @abstractmethod
    def elements(self, scene) -> np.ndarray:
        """The scene's element connectivity."""

    @abstractmethod
    def mesh_body(self, case, index: int):
        """The mesh of body ``index`` from its [body.mesh] table."""

    @abstractmethod
    def build(self, case, body_meshes: dict, given: tuple):
        """The scene of a case whose bodies are meshed (``given``: those from Python)."""

    @abstractmethod
    def von_mises(self, stress: np.ndarray) -> np.ndarray:
        """The equivalent stress of the engine's stress rows."""

    @abstractmethod
    def fields(self, scene, snap: dict) -> dict:
        """:meth:`slipstep.output.result.Result.fields` of a snapshot."""

    @abstractmethod
    def profile(self, scene, snap: dict) -> dict:
        """:meth:`slipstep.output.result.Result.profile` of a snapshot."""

    @abstractmethod
    def contact_numbers(self, scene, result) -> dict:
        """The contact part of summary.json at the final snapshot (a scene with pairs)."""

    @abstractmethod
    def stage_contact_numbers(self, scene, result, snap: dict) -> dict:
        """The contact part of a summary.json stage record (a scene with pairs)."""

    @abstractmethod
    def pair_forces(self, scene, snap: dict) -> np.ndarray:
        """(P, 3) each contact pair's force on its contactor side in global axes."""

    def mirror_planes(self, scene, index: int) -> list[tuple[int, float]]:
        """The symmetry planes (axis, value) [[contact]] ``index``'s part is mirrored across
        into the whole: none, a section's numbers are the model's."""
        return []

    def mirror_planes_of(self, scene, bodies, points) -> list[tuple[int, float]]:
        """The symmetry planes a load or support on ``points`` of ``bodies`` is mirrored across
        into the whole: none, a section's numbers are the model's."""
        return []

    # ------------------------------------------------------------------ loads and boundaries
    @abstractmethod
    def boundary_load(self, scene, cells: np.ndarray, pressure: float, traction) -> np.ndarray:
        """The consistent nodal forces of a uniform pressure and traction on boundary ``cells``
        (global ids; edge segments or face triangles)."""

    @abstractmethod
    def cut_pressure(self, scene) -> float:
        """The pressure of ``[load] P`` (the Hertz convenience) on its body's cut ``top``."""

    def point_force_scale(self, case) -> float:
        """What a [[point_load]] force is multiplied by: 1 (a total force)."""
        return 1.0

    @abstractmethod
    def facet_normals(self, nodes: np.ndarray, cells) -> np.ndarray:
        """The outward unit normal of each boundary cell (edge segment or face triangle)."""

    @abstractmethod
    def surface_normals(self, nodes: np.ndarray, cells, ids) -> np.ndarray:
        """The outward normal of a boundary (its ``cells``) at each node of ``ids``."""

    @abstractmethod
    def on_boundary(self, nodes: np.ndarray, points, cells, tol: float) -> np.ndarray:
        """Whether each node of ``points`` lies on a boundary's ``cells``, off their corners."""

    @abstractmethod
    def xdmf_step(self, scene, snap: dict) -> tuple[dict, dict]:
        """The point and cell data of one results.xdmf time step."""

    @abstractmethod
    def write_profile_csv(self, path, scene, snap: dict) -> None:
        """contact_profile.csv of a snapshot."""

    @abstractmethod
    def chosen_figures(self, scene, result) -> list:
        """The (name, builder) of every figure the run has."""

    @abstractmethod
    def figures(self, scene, result, summary: dict) -> dict:
        """The run's figures by name."""

    @abstractmethod
    def write_figures(self, folder, scene, result, summary: dict) -> list:
        """The run's figures written as PNG files."""
