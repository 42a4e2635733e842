"""Body meshes: one interface, :class:`Mesh` (:mod:`.base`), and its two implementations.

``base``                    the :class:`Mesh` interface and :class:`MeshError`
``triangles``               :class:`TriangleMesh`: linear triangles (a plane or axisymmetric
                            section), its checks, edge tags, a mesh from arrays
``tetrahedra``              :class:`TetMesh`: linear tetrahedra (a solid), its checks, face tags
``triangle_generators``     gmsh and structured meshes of the shipped 2D bodies
``tetrahedron_generators``  gmsh and structured meshes of the shipped 3D bodies
``triangle_files``          ``.msh`` / ``.xdmf`` triangles, meshio, the ``.msh`` writer
``tetrahedron_files``       ``.msh`` / ``.xdmf`` tetrahedra, triangulated surfaces
``gmsh_api``                the gmsh session the generators and readers share
``cache``                   the cache of generated meshes
"""

from .base import Mesh, MeshError
from .tetrahedra import TetMesh, from_tetrahedra
from .triangle_files import from_meshio
from .triangles import TriangleMesh, from_arrays

__all__ = [
    "Mesh",
    "MeshError",
    "TetMesh",
    "TriangleMesh",
    "from_arrays",
    "from_meshio",
    "from_tetrahedra",
]
