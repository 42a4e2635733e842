"""The 2D idealisation: bodies as sections of linear triangles (plane strain, plane stress or
axisymmetric, ``[analysis] plane``), two displacement components per node, contact and
supports on edges, four stress components per element (x, y, z, xy)."""

from __future__ import annotations

import numpy as np

from ..builders.section import build_section_scene, mesh_body
from ..figures import section as figures
from ..loads.vectors import hertz_cut_pressure, section_boundary_load
from ..measures.contact_edges import contact_profile, pair_forces
from ..mesh.triangles import node_normals, outward_normals
from ..output import summary, writers
from ..output.fields import STRESS_NAMES, von_mises
from ..output.result import section_fields
from ..validation.pairs import on_segments
from ..validation.terms import SectionTerms
from .base import Idealisation


class Section(SectionTerms, Idealisation):
    """A section of triangles: :class:`Plane` or :class:`Axisymmetric`."""

    stress_width = 4
    cell_type = "triangle"
    cells_field = "triangles"
    xdmf_topology = ("Triangle", "Polyline")
    given_mesh_from = "slipstep.mesh.from_arrays or from_meshio"
    engine_moment_axes = (2,)

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

    def stage_contact_numbers(self, scene, result, snap: dict) -> dict:
        return summary.section_stage_contact(scene, result, snap)

    def pair_forces(self, scene, snap: dict) -> np.ndarray:
        return pair_forces(scene, snap)

    def boundary_load(self, scene, cells: np.ndarray, pressure: float, traction) -> np.ndarray:
        return section_boundary_load(scene, cells, pressure, traction)

    def cut_pressure(self, scene) -> float:
        return hertz_cut_pressure(scene.case)

    def facet_normals(self, nodes: np.ndarray, cells) -> np.ndarray:
        return outward_normals(nodes, cells)

    def surface_normals(self, nodes: np.ndarray, cells, ids) -> np.ndarray:
        """The sum of the segments' unit normals at each node (zero where they cancel)."""
        return node_normals(nodes, cells, ids)

    def on_boundary(self, nodes: np.ndarray, points, cells, tol: float) -> np.ndarray:
        return on_segments(nodes, points, cells, tol)

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
    """A plane strain or plane stress section: forces in x and y, moments about z, both per
    unit thickness of the case's ``thickness``."""

    force_components = (0, 1)
    moment_components = (2,)
    component_names = "xyz"
    stress_names = STRESS_NAMES["strain"]

    def point_force_scale(self, case) -> float:
        """A [[point_load]] force is per unit thickness: times ``[analysis] thickness``."""
        return case.record.analysis.thickness


class Axisymmetric(Section):
    """An axisymmetric section (x = r, y = z): a ring force has no radial resultant and no
    moment; components are called r and z, stresses r, z, theta (hoop) and rz."""

    force_components = (1,)
    moment_components = ()
    component_names = "rz"
    stress_names = STRESS_NAMES["axisymmetric"]
