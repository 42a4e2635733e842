"""The scene builders of each idealisation (:func:`slipstep.build.build_scene` chooses one):
``section`` builds a 2D scene (triangles), ``solid`` a 3D one (tetrahedra)."""
