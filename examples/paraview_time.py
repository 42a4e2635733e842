# %% [markdown]
# # A result in ParaView, with the path time on the time slider
#
# slipstep writes `results.xdmf` with the path time t as its XDMF time (stage k spans
# t in [k-1, k]; one stage: t = the load fraction), so ParaView's time slider walks the load
# path.  Run this with ParaView's Python (Debian: `apt-get install python3-paraview`), not
# slipstep's:
#
#     pvpython --force-offscreen-rendering examples/paraview_time.py \
#         results/hertz_load_unload/results.xdmf
#
# It opens the file with ParaView's Xdmf3 reader, sets the animation to the data's time steps,
# and prints (as one JSON line) the time steps and, at each, the largest displacement
# magnitude and von Mises stress that ParaView reads.  In the ParaView GUI: File > Open,
# "Xdmf3 Reader S", Apply, colour by von_mises, and the time slider shows t.  (Pictures from
# pvpython need a display: Debian's ParaView renders through X.)

# %%
import json
import sys

from paraview import servermanager
from paraview.simple import GetAnimationScene, Xdmf3ReaderS


def first_block(data):
    """The dataset itself, or the first block of a multiblock one."""
    if data.IsA("vtkMultiBlockDataSet"):
        it = data.NewIterator()
        it.InitTraversal()
        return it.GetCurrentDataObject()
    return data


def largest(array) -> float:
    """The largest magnitude of a VTK data array's tuples."""
    n, k = array.GetNumberOfTuples(), array.GetNumberOfComponents()
    return max((sum(array.GetComponent(i, j) ** 2 for j in range(k)) ** 0.5 for i in range(n)),
               default=0.0)


# %%
path = sys.argv[1]
reader = Xdmf3ReaderS(FileName=[path])
reader.UpdatePipelineInformation()
scene = GetAnimationScene()
scene.UpdateAnimationUsingDataTimeSteps()  # the slider's steps are the data's times: t
times = [float(t) for t in scene.TimeKeeper.TimestepValues]

# %%
steps = []
for t in times:
    scene.AnimationTime = t
    reader.UpdatePipeline(t)
    data = first_block(servermanager.Fetch(reader))
    steps.append({"t": t, "max_u": largest(data.GetPointData().GetArray("u")),
                  "max_von_mises": largest(data.GetCellData().GetArray("von_mises"))})

# %%
print(json.dumps({"file": path, "times": times, "steps": steps}))
