"""Loads and supports of a scene.

``path``      the load path of a case: named loads, stages and their factors
``vectors``   the engine's load vector and prescribed motions, in any dimension
``faces``     3D face loads: pressure and traction on face triangles, a sphere's cut pressure
``supports``  fixed DOFs, symmetry planes, the support groups whose reactions are recorded
"""
