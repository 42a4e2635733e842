"""Bodies in space (``[analysis] dimension = 3``): linear tetrahedra, faces in place of edges,
contact between a face and a rigid plane, sphere, cylinder or triangulated surface, or between
the faces of two bodies; the model and result of docs/engine_api.md's "3D models" section.

One module per concept, as the 2D package has them:

``schema``           the 3D keys of a case (generators, contact kinds), read by slipstep.schema
``mesh``             the tetrahedron mesh of one body (TetMesh), its checks and face tags
``generators``       gmsh meshes of the shipped scenes: sphere, roller, box, punch, shell
``mesh_files``       .msh / .xdmf tetrahedra, and triangulated surfaces (.msh, .stl)
``surfaces``         triangulated surfaces: areas, normals, closest points, closedness
``indenters``        Vickers and Berkovich pyramids as closed surfaces
``supports``, ``loads``   fixed DOFs and symmetry planes; face loads, point loads, [load] P
``contact_geometry`` candidate pairs: rigid obstacles, node to node, their tangent bases
``mortar``           node-to-surface rows, mortar-weighted on triangles
``build``            case + meshes -> the 3D Scene and its engine model
``contact_measures``, ``summary``, ``output``, ``figures``   what a 3D result says and writes
"""
