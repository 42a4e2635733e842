"""The figures of a result (matplotlib).

``frame``    the shared frame: a new figure, labels, titles, status colours, saving
``section``  2D figures: deformed mesh, contact profiles, growth, von Mises
``solid``    3D figures: contact maps on faces, profiles, von Mises on a cut
``loads``    the load figures any scene has: force-displacement, resultants per stage
"""
