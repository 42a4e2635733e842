"""The scene builders of each dimension: ``solid`` builds a 3D scene (tetrahedra) for
:func:`slipstep.build.build_scene`, which builds a 2D one itself."""
