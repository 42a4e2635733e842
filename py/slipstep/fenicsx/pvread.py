"""Open XDMF files with ParaView's Xdmf3 reader and print what it sees, as JSON.

Run with ParaView's Python (Debian: ``apt-get install python3-paraview``)::

    pvpython --force-offscreen-rendering -m slipstep.fenicsx.pvread FILE.xdmf ...

(or ``pvpython .../pvread.py FILE.xdmf``).  Per file: the dataset type, number of points and
cells (summed over blocks), the point- and cell-data array names and the time steps.  Used by
tests/fenicsx/test_fenicsx_paraview.py; not imported by slipstep itself.
"""

import json
import sys


def describe(path):
    import os

    from paraview import servermanager as sm
    from paraview.simple import Xdmf3ReaderS

    # absolute: for a bare file name the reader looks for its .h5 as "NAME.xdmfNAME.h5"
    reader = Xdmf3ReaderS(FileName=[os.path.abspath(path)])
    reader.UpdatePipelineInformation()
    tv = reader.TimestepValues
    times = [float(tv)] if isinstance(tv, (int, float)) else [float(t) for t in (tv or [])]
    if times:  # a time series: look at its last step (before the first one it is empty)
        reader.UpdatePipeline(times[-1])
    else:
        reader.UpdatePipeline()
    data = sm.Fetch(reader)
    blocks = []
    if data.IsA("vtkMultiBlockDataSet"):
        it = data.NewIterator()
        it.InitTraversal()
        while not it.IsDoneWithTraversal():
            blocks.append(it.GetCurrentDataObject())
            it.GoToNextItem()
    else:
        blocks = [data]
    point, cell = set(), set()
    for b in blocks:
        for i in range(b.GetPointData().GetNumberOfArrays()):
            point.add(b.GetPointData().GetArrayName(i))
        for i in range(b.GetCellData().GetNumberOfArrays()):
            cell.add(b.GetCellData().GetArrayName(i))
    return {
        "type": data.GetClassName(),
        "blocks": len(blocks),
        "points": [b.GetNumberOfPoints() for b in blocks],
        "cells": [b.GetNumberOfCells() for b in blocks],
        "point_data": sorted(point),
        "cell_data": sorted(cell),
        "times": times,
    }


if __name__ == "__main__":
    print(json.dumps({p: describe(p) for p in sys.argv[1:]}))
