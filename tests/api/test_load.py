"""A result folder read back (issue 38: "a saved result folder cannot be loaded back"):
``slipstep.load(path)`` gives the Result of the run that wrote it, from its files alone.

Round trip, exact: the files hold float64 (results.h5) and repr()-written floats (events.csv,
summary.json), so every array of the loaded Result equals the run's bit for bit: the times (one
per time step of results.xdmf: the run's distinct times), the events, the fields and the
contact profile at each time, the summary (as JSON holds it: NaN as null).  In 2D an
elastoplastic load-unload (two stages, plastic fields, reactions), in 3D the Vickers block (the
same, in space).  A folder that is none, or whose mesh case.toml no longer makes, is one clear
error.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from conftest import CASES, needs_gmsh

import slipstep
from slipstep import InputError, Result
from slipstep.output.writers import json_safe


@pytest.fixture(scope="module", params=["2d", "3d"])
def saved(request, tmp_path_factory):
    out = tmp_path_factory.mktemp("saved") / request.param
    if request.param == "2d":
        r = slipstep.run(
            "hertz_load_unload",
            out=out,
            progress=False,
            overrides=["mesh.h_contact=0.2", "output.snapshots=[0.5, 1.0, 1.5, 2.0]"],
        )
    else:
        pytest.importorskip("gmsh")
        r = slipstep.run(
            CASES / "vickers_indentation_3d.toml",
            out=out,
            progress=False,
            overrides=["output.snapshots=[0.5, 1.0, 1.5, 2.0]"],
        )
    return r, out


def _equal(a, b, where: str) -> None:
    assert set(a) == set(b), where
    for key in a:
        x, y = np.asarray(a[key]), np.asarray(b[key])
        assert x.dtype.kind == y.dtype.kind and np.array_equal(x, y), f"{where}: {key}"


@needs_gmsh
def test_the_loaded_result_is_the_run_s(saved):
    run, out = saved
    back = slipstep.load(out)
    assert isinstance(back, Result) and back.out == out and back.case.name == run.case.name
    assert np.array_equal(back.times, np.unique(run.times))
    assert back.events.dtype == run.events.dtype and np.array_equal(back.events, run.events)
    assert back.summary == json.loads(json.dumps(json_safe(run.summary)))
    assert back.stop == run.summary["stop"] and back.completed
    for t in back.times:
        _equal(back.fields(t), run.fields(t), f"fields at t = {t}")
        _equal(back.profile(t), run.profile(t), f"profile at t = {t}")
    assert np.array_equal(back.nodes, run.nodes) and np.array_equal(back.elements, run.elements)
    assert set(back.figures()) == set(run.figures())


def test_a_folder_without_results_is_one_clear_error(tmp_path):
    with pytest.raises(InputError, match=r"no case\.toml, so not a slipstep result folder"):
        slipstep.load(tmp_path)


def test_a_mesh_that_changed_since_the_run_is_one_clear_error(tmp_path):
    slipstep.run(
        "hertz_cylinder",
        out=tmp_path,
        progress=False,
        overrides=["mesh.h_contact=0.2", "output.snapshots=[1.0]", "output.figures=false"],
    )
    text = (tmp_path / "case.toml").read_text()
    assert "h_contact = 0.2\n" in text
    (tmp_path / "case.toml").write_text(text.replace("h_contact = 0.2\n", "h_contact = 0.25\n"))
    with pytest.raises(InputError, match="the mesh case.toml makes now is not the one"):
        slipstep.load(tmp_path)
