"""The interface of a scene's idealisation (:mod:`slipstep.idealisation`): what differs between
a 2D section and a 3D solid, from meshing the bodies to drawing the result.  Each method
forwards to its implementation's module; printing one names it."""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np


class Idealisation(ABC):
    """How a scene's bodies are modelled; ``scene.idealisation``."""

    #: coordinates and displacement components per node
    dimension: int
    #: the boundary a [[bc]] or [[contact]] names: "edge" (2D) or "face" (3D)
    boundary: str
    #: stress components per element in the engine's result
    stress_width: int
    #: the meshio cell type of the elements
    cell_type: str
    #: the functions that make a mesh given from Python
    given_mesh_from: str
    #: the components a resultant force and moment have, and the names of components
    force_components: tuple[int, ...]
    moment_components: tuple[int, ...]
    component_names: str

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
