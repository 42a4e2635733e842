# %% [markdown]
# # A result in ParaView, with the path time on the time slider
#
# slipstep writes `results.xdmf` with the path time t as its XDMF time (stage k spans
# t in [k-1, k]; one stage: t = the load fraction), one time step per distinct t (the state
# after every event at that t; events.csv lists each event), so ParaView's time slider walks
# the load path.  Run this with ParaView's Python (Debian: `apt-get install python3-paraview`),
# not slipstep's:
#
#     pvpython --force-offscreen-rendering examples/paraview_time.py \
#         results/hertz_load_unload/results.xdmf
#
# It opens the file with ParaView's Xdmf3 reader, sets the animation to the data's time steps,
# and prints (as one JSON line) the time steps and, at each, the largest displacement
# magnitude, von Mises stress and contact pressure that ParaView reads (a step where ParaView
# finds no data is listed under "empty").  In the ParaView GUI: File > Open, "Xdmf3 Reader S",
# Apply, colour by von_mises (cells), nodal_stress or contact_pressure (points), and the time
# slider shows t.  (Pictures from pvpython need a display: Debian's ParaView renders through X.)

# %%
import json
import os
import sys

import numpy as np
from paraview import servermanager
from paraview.simple import GetAnimationScene, Xdmf3ReaderS
from vtkmodules.util.numpy_support import vtk_to_numpy


def first_block(data):
    """The dataset itself, or the first block of a multiblock one."""
    if data.IsA("vtkMultiBlockDataSet"):
        it = data.NewIterator()
        it.InitTraversal()
        return it.GetCurrentDataObject()
    return data


def largest(array) -> float:
    """The largest magnitude of a VTK data array's tuples."""
    values = vtk_to_numpy(array).reshape(array.GetNumberOfTuples(), -1)
    return float(np.linalg.norm(values, axis=1).max(initial=0.0))


# %%
# The result to open: the command line's argument as a script; in a notebook (a kernel with
# ParaView's Python, whose argv is the kernel's own) the path set here. An absolute path:
# ParaView's reader joins a bare file name's folder ("") and the .h5's name without a separator.
RESULT = "results/hertz_load_unload/results.xdmf"
as_script = len(sys.argv) == 2 and sys.argv[1].endswith(".xdmf")
path = os.path.abspath(sys.argv[1] if as_script else RESULT)
reader = Xdmf3ReaderS(FileName=[path])
reader.UpdatePipelineInformation()
scene = GetAnimationScene()
scene.UpdateAnimationUsingDataTimeSteps()  # the slider's steps are the data's times: t
times = [float(t) for t in scene.TimeKeeper.TimestepValues]

# %%
steps, empty = [], []
for t in times:
    scene.AnimationTime = t
    reader.UpdatePipeline(t)
    data = first_block(servermanager.Fetch(reader))
    point, cell = (None, None) if data is None else (data.GetPointData(), data.GetCellData())
    if point is None or point.GetArray("u") is None:
        empty.append(t)
        continue
    step = {
        "t": t,
        "max_u": largest(point.GetArray("u")),
        "max_von_mises": largest(cell.GetArray("von_mises")),
    }
    if point.GetArray("contact_pressure") is not None:
        step["max_contact_pressure"] = largest(point.GetArray("contact_pressure"))
    steps.append(step)

# %%
print(json.dumps({"file": path, "times": times, "steps": steps, "empty": empty}))
