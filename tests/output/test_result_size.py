"""The size of a run's results (issue 38: `slipstep run mindlin_sphere_3d` wrote 3.4 GB, a
snapshot after each of its 667 events).  ``[output] snapshots = "auto"``, the default, keeps
in 3D the stage ends and evenly spaced path times within a budget
(:mod:`slipstep.output.snapshots`); `slipstep check` predicts results.h5's size.

- the times of "auto": per stage n evenly spaced, n = min(10, budget // (stages x step)) but at
  least 1, exact as fractions i/n (closed form);
- the prediction is the size results.h5 has: the arrays of one time step are counted exactly
  from the writer; HDF5 adds its own metadata (a few kB a dataset: the tolerance below is 2 %
  of the file plus 64 kB);
- the default results of every shipped 3D case together stay under 500 MB (the issue's bound),
  from the prediction for each case's own mesh."""

from __future__ import annotations

import math

import pytest
from conftest import CASES, MINIMAL, needs_gmsh, shipped_cases

import slipstep
from slipstep.output import snapshots as snapshot_plan
from slipstep.build import build_scene
from slipstep.case import Case, load_case


@pytest.mark.parametrize(
    "n_stages, step, per_stage",
    [
        (1, 1e6, 10),  # small steps: the most per stage
        (2, 7.3e6, 6),  # the Mindlin sphere: 100 MB // (2 x 7.3 MB) = 6
        (2, 46e6, 1),  # 138k DOFs: the stage ends alone
        (3, 400e6, 1),  # larger than the budget: still each stage end
    ],
)
def test_auto_keeps_evenly_spaced_times_within_the_budget(n_stages, step, per_stage):
    times = snapshot_plan.auto_times(n_stages, step)
    assert len(times) == n_stages * per_stage
    want = [k + i / per_stage for k in range(n_stages) for i in range(1, per_stage + 1)]
    assert all(math.isclose(a, b, abs_tol=1e-12) for a, b in zip(times, want))
    assert per_stage == 1 or len(times) * step <= snapshot_plan.AUTO_BYTES


def test_auto_is_every_event_in_2d():
    case = Case.from_toml(MINIMAL)  # no [output]: the defaults
    assert case.data["output"]["snapshots"] == "auto"
    assert snapshot_plan.requested(case) == "events"


@needs_gmsh
def test_the_predicted_size_is_the_size_of_results_h5(tmp_path):
    """A coarse 3D run with the default snapshots: results.h5 holds the mesh and one step per
    snapshot time, the prediction's count and bytes."""
    r = slipstep.run(
        CASES / "boussinesq_punch_3d.toml",
        progress=False,
        out=tmp_path,
        overrides=["mesh.h_contact=0.3", "mesh.growth=0.5", "output.snapshots=\"auto\""],
        figures=False,
    )
    scene = r.scene
    per_step = snapshot_plan.step_bytes(scene)
    n = len(snapshot_plan.requested(r.case, per_step))
    assert n == 10 and len(set(r.times)) == n  # the stage end is one of the ten
    predicted = snapshot_plan.mesh_bytes(scene) + n * per_step
    actual = (tmp_path / "results.h5").stat().st_size
    assert abs(actual - predicted) <= 0.02 * actual + 64e3, (actual, predicted)
    text = snapshot_plan.predicted_text(scene)
    assert text.startswith(f"results.h5: ~{predicted * 1e-6:.1f} MB ({n} snapshots")


@needs_gmsh
def test_the_default_results_of_the_shipped_3d_cases_stay_under_500_mb():
    sizes = {}
    for path in shipped_cases(3):
        scene = build_scene(load_case(path))
        per_step = snapshot_plan.step_bytes(scene)
        asked = snapshot_plan.requested(scene.case, per_step)
        assert asked != "events", f"{path.name} keeps every event by default"
        n = len(set(asked) | set(range(1, scene.case.path.n_stages + 1)))
        sizes[path.name] = snapshot_plan.mesh_bytes(scene) + n * per_step
    assert sum(sizes.values()) < 500e6, sizes
