"""Input validation, one module per concern; each problem is one line naming the place (case
key, body, node) and the fix.

``document``  the case document against the schema (:mod:`slipstep.schema`): types, values,
              defaults, cross-references between keys, the load path.
``scene``     the built scene, where the case alone cannot tell: file mesh tags, radii in
              axisymmetry, duplicate nodes, pairs held by supports.
``pairs``     the contact pairs' geometry: facing, matching meshes, initial penetration.
The engine checks its model again (``rust/src/model.rs``): the last guard for models built in
Python without a case file.
"""
