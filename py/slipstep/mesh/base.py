"""The interface every body mesh has, whatever its elements: :class:`Mesh`, implemented by
:class:`slipstep.mesh.triangles.TriangleMesh` (linear triangles, a 2D section: plane or
axisymmetric) and :class:`slipstep.mesh.tetrahedra.TetMesh` (linear tetrahedra, a 3D solid);
and :class:`MeshError`, the error of a mesh that cannot be used.
"""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np

from ..errors import InputError


class MeshError(InputError):
    """A mesh that cannot be used; one-line message naming the element/edge and the fix."""


class Mesh(ABC):
    """One body's mesh: ``nodes`` (N, dimension), ``elements`` (M, dimension + 1) node ids,
    the boundary ``tags`` that [[bc]] and [[contact]] name (tag -> (K, dimension) boundary
    segments or triangles, outward) and ``node_sets`` (name -> node ids; every tag is one).
    Printing one gives a summary: its element kind, sizes and tags."""

    #: 2 (triangles: two coordinates, two DOFs per node) or 3 (tetrahedra: three)
    dimension: int
    #: what its elements are, and what its boundary tags hold (for summaries and messages)
    element_name: str
    boundary_name: str
    nodes: np.ndarray
    node_sets: dict[str, np.ndarray]

    @property
    @abstractmethod
    def elements(self) -> np.ndarray:
        """The element connectivity, (M, dimension + 1)."""

    @property
    @abstractmethod
    def tags(self) -> dict[str, np.ndarray]:
        """The boundary tags [[bc]] and [[contact]] name."""

    @abstractmethod
    def measure(self) -> float:
        """The mesh's size: its area (triangles) or volume (tetrahedra)."""

    @property
    def n_nodes(self) -> int:
        return len(self.nodes)

    @property
    def n_elements(self) -> int:
        return len(self.elements)

    def _normalised(self, cells, tags: dict) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """For ``__post_init__``: the coordinates as float64; the connectivity and the tags
        (tag -> (K, dimension)) as contiguous int64 arrays, returned; every tag a node set too."""
        self.nodes = np.ascontiguousarray(self.nodes, dtype=np.float64)
        width = self.dimension
        tags = {k: np.asarray(v, dtype=np.int64).reshape(-1, width) for k, v in tags.items()}
        for tag, parts in tags.items():
            self.node_sets.setdefault(tag, np.unique(parts))
        self.node_sets = {k: np.asarray(v, dtype=np.int64) for k, v in self.node_sets.items()}
        return np.ascontiguousarray(cells, dtype=np.int64), tags

    def tag_nodes(self, tag: str) -> np.ndarray:
        """Sorted unique nodes of a boundary tag."""
        return np.unique(self.tags[tag])

    def __repr__(self) -> str:
        tags = ", ".join(f"{k} ({len(v)})" for k, v in self.tags.items()) or "none"
        return (
            f"{type(self).__name__}: {self.n_nodes} nodes, {self.n_elements} "
            f"{self.element_name}; {self.boundary_name} tags: {tags}"
        )
