"""The 2D idealisation: bodies as sections of linear triangles (plane strain, plane stress or
axisymmetric, ``[analysis] plane``), two displacement components per node, contact and
supports on edges, four stress components per element (x, y, z, xy)."""

from __future__ import annotations

import numpy as np

from ..builders.section import build_section_scene, mesh_body
from ..figures import section as figures
from ..measures.contact_edges import contact_profile
from ..output import summary, writers
from ..output.fields import von_mises
from ..output.result import section_fields
from .base import Idealisation


class Section(Idealisation):
    """A section of triangles: :class:`Plane` or :class:`Axisymmetric`."""

    dimension = 2
    boundary = "edge"
    stress_width = 4
    cell_type = "triangle"
    given_mesh_from = "slipstep.mesh.from_arrays or from_meshio"

    def elements(self, scene) -> np.ndarray:
        return scene.triangles

    def mesh_body(self, case, index: int):
        return mesh_body(case, index)

    def build(self, case, body_meshes: dict, given: tuple):
        return build_section_scene(case, body_meshes, given, self)

    def von_mises(self, stress: np.ndarray) -> np.ndarray:
        return von_mises(np.asarray(stress).reshape(-1, 4))

    def fields(self, scene, snap: dict) -> dict:
        return section_fields(scene, snap)

    def profile(self, scene, snap: dict) -> dict:
        return contact_profile(scene, snap)

    def contact_numbers(self, scene, result) -> dict:
        """The contact part of summary.json (:func:`slipstep.output.summary.section_contact_numbers`)."""
        return summary.section_contact_numbers(scene, result)

    def xdmf_step(self, scene, snap: dict) -> tuple[dict, dict]:
        return writers.xdmf_step(scene, snap)

    def write_profile_csv(self, path, scene, snap: dict) -> None:
        writers.write_profile_csv_2d(path, scene, snap)

    def chosen_figures(self, scene, result) -> list:
        return figures.chosen(scene, result)

    def figures(self, scene, result, summary: dict) -> dict:
        return figures.figures(scene, result, summary)

    def write_figures(self, folder, scene, result, summary: dict) -> list:
        return figures.write_figures(folder, scene, result, summary)


class Plane(Section):
    """A plane strain or plane stress section: forces in x and y, moments about z."""

    force_components = (0, 1)
    moment_components = (2,)
    component_names = "xyz"


class Axisymmetric(Section):
    """An axisymmetric section (x = r, y = z): a ring force has no radial resultant and no
    moment; components are called r and z."""

    force_components = (1,)
    moment_components = ()
    component_names = "rz"
