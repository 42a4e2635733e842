"""A result, and the files of a result folder.

``result``         :class:`Result`, the object slipstep.run returns
``fields``         stress names, von Mises, tensors, nodal averages, the plastic state (2D, 3D)
``history``        the event history: times, load factors, snapshots, event positions
``summary``        summary.json and the one-line summary
``writers``        events.csv, contact_profile.csv, results.xdmf / results.h5
``snapshot``       one engine snapshot read in the scene's shapes (``Snapshot``)
``snapshots``      which snapshots are written and their size
``results``        the result folder written at once; ``saved``: a folder read back
``resolved_case``  case.resolved.toml, the case with every default filled in
"""
