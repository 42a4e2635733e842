"""Contact: the candidate pairs of every ``[[contact]]`` and the geometry they need.

``pairs``            every contact's rows gathered into the engine's ``pairs``; node-to-node
``edges``            2D: rigid lines, circles, polylines; rows on edges, tributary lengths, areas
``faces``            3D: rigid planes, spheres, cylinders, surfaces; rows on faces, tangent bases
``node_to_segment``  mortar rows of a node against a polyline (2D, also axisymmetric)
``node_to_surface``  mortar rows of a node against triangles (3D)
``surfaces``         triangulated surfaces: areas, normals, closest points, closedness
``indenters``        Vickers and Berkovich pyramids as closed surfaces
"""
