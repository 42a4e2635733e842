"""The 3D idealisation: bodies as solids of linear tetrahedra, three displacement components
per node, contact and supports on faces, six stress components per element (Voigt: xx, yy,
zz, yz, xz, xy)."""

from __future__ import annotations

import numpy as np

from ..builders.solid import build_solid_scene, mesh_body_3d
from ..figures import solid as figures
from ..loads.faces import face_load, sphere_load_pressure
from ..mesh.tetrahedra import triangle_normals
from ..measures.contact_faces import mirror_planes, mirror_planes_of, pair_forces
from ..output import summary, writers
from ..output.fields import STRESS_NAMES_3D, von_mises_3d
from ..output.result import solid_fields, solid_profile
from ..validation.pairs import on_triangles, unit_face_normals
from ..validation.terms import SolidTerms
from .base import Idealisation


class Solid(SolidTerms, Idealisation):
    """A solid of tetrahedra."""

    stress_width = 6
    stress_names = STRESS_NAMES_3D
    cell_type = "tetra"
    cells_field = "tetrahedra"
    xdmf_topology = ("Tetrahedron", "Triangle")
    given_mesh_from = "slipstep.from_tetrahedra"
    force_components = (0, 1, 2)
    moment_components = (0, 1, 2)
    component_names = "xyz"
    engine_moment_axes = (0, 1, 2)

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

    def stage_contact_numbers(self, scene, result, snap: dict) -> dict:
        return summary.solid_stage_contact(scene, snap)

    def pair_forces(self, scene, snap: dict) -> np.ndarray:
        return pair_forces(scene, snap)

    def mirror_planes(self, scene, index: int) -> list[tuple[int, float]]:
        """The body's ``symmetry`` faces the contact's candidates lie on one side of."""
        return mirror_planes(scene, index)

    def mirror_planes_of(self, scene, bodies, points) -> list[tuple[int, float]]:
        return mirror_planes_of(scene, bodies, points)

    def boundary_load(self, scene, cells: np.ndarray, pressure: float, traction) -> np.ndarray:
        return face_load(scene.nodes, cells, len(scene.nodes), pressure, traction)

    def cut_pressure(self, scene) -> float:
        return sphere_load_pressure(scene)

    def facet_normals(self, nodes: np.ndarray, cells) -> np.ndarray:
        return triangle_normals(nodes, cells)[0]

    def surface_normals(self, nodes: np.ndarray, cells, ids) -> np.ndarray:
        """The unit area-weighted normal of the triangles at each node."""
        return unit_face_normals(nodes, cells, ids)

    def on_boundary(self, nodes: np.ndarray, points, cells, tol: float) -> np.ndarray:
        return on_triangles(nodes, points, cells, tol)

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
