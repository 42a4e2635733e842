"""The 3D idealisation: bodies as solids of linear tetrahedra, three displacement components
per node, contact and supports on faces, six stress components per element (Voigt: xx, yy,
zz, yz, xz, xy)."""

from __future__ import annotations

import numpy as np

from ..builders.solid import build_solid_scene, mesh_body_3d
from ..figures import solid as figures
from ..output import summary, writers
from ..output.fields import von_mises_3d
from ..output.result import solid_fields, solid_profile
from .base import Idealisation


class Solid(Idealisation):
    """A solid of tetrahedra."""

    dimension = 3
    boundary = "face"
    stress_width = 6
    cell_type = "tetra"
    given_mesh_from = "slipstep.from_tetrahedra"
    force_components = (0, 1, 2)
    moment_components = (0, 1, 2)
    component_names = "xyz"

    def elements(self, scene) -> np.ndarray:
        return scene.tetrahedra

    def mesh_body(self, case, index: int):
        return mesh_body_3d(case, index)

    def build(self, case, body_meshes: dict, given: tuple):
        return build_solid_scene(case, body_meshes, given, self)

    def von_mises(self, stress: np.ndarray) -> np.ndarray:
        return von_mises_3d(stress)

    def fields(self, scene, snap: dict) -> dict:
        return solid_fields(scene, snap)

    def profile(self, scene, snap: dict) -> dict:
        return solid_profile(scene, snap)

    def contact_numbers(self, scene, result) -> dict:
        """The contact part of summary.json (:func:`slipstep.output.summary.solid_contact_numbers`)."""
        return summary.solid_contact_numbers(scene, result)

    def xdmf_step(self, scene, snap: dict) -> tuple[dict, dict]:
        return writers.xdmf_step_3d(scene, snap)

    def write_profile_csv(self, path, scene, snap: dict) -> None:
        writers.write_profile_csv_3d(path, scene, snap)

    def chosen_figures(self, scene, result) -> list:
        return figures.chosen(scene, result)

    def figures(self, scene, result, summary: dict) -> dict:
        return figures.figures_3d(scene, result, summary)

    def write_figures(self, folder, scene, result, summary: dict) -> list:
        return figures.write_figures_3d(folder, scene, result, summary)
