"""A result folder read back (``slipstep.load(path)``): the :class:`~slipstep.output.result.Result` of
the run that wrote it, from its files alone.

- the scene: ``case.toml`` (the resolved case) built again, its meshes from the same
  generators, mesh files or the cache (a body whose mesh came from Python is given again:
  ``meshes=``); its nodes must be those results.h5 holds;
- the summary: ``summary.json``; the events: ``events.csv``;
- the snapshots: one per time step of results.xdmf (the state after every event at that time,
  as the file keeps it): u, reaction, the stresses and plastic state from its fields, the
  place on the path and the per-pair arrays from the record beside them
  (:func:`slipstep.output.writers.snapshot_record`).  A folder written with ``output.xdmf = false``
  has no snapshots.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np

from ..build import build_scene
from ..case import load_case
from ..errors import InputError
from .fields import is_elastoplastic
from .writers import RECORD_GROUP
from .result import Result

#: The files a result folder must hold.
REQUIRED = ("case.toml", "summary.json", "events.csv")


def load(path: str | Path, meshes: dict | None = None) -> Result:
    """The Result of the run whose files are in ``path`` (module doc); ``meshes``: the bodies'
    meshes that came from Python, by body name, as for :func:`slipstep.run`."""
    folder = Path(path)
    for name in REQUIRED:
        if not (folder / name).is_file():
            raise InputError(
                f"{folder}: no {name}, so not a slipstep result folder (`slipstep "
                f"run CASE --out DIR` or `Result.write(DIR)` writes one)"
            )
    scene = build_scene(load_case(folder / "case.toml"), meshes)
    summary = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
    raw = {
        "events": read_events(folder / "events.csv"),
        "snapshots": read_snapshots(folder, scene),
        "stop": dict(summary["stop"]),
        "n_stages": summary["n_stages"],
        "stage_names": summary["stage_names"],
    }
    return Result(scene, raw, summary, out=folder)


def read_events(path: Path) -> dict:
    """events.csv as the engine's ``events`` (stage 0-based, as the engine counts)."""
    with open(path, newline="", encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    return {
        "step": np.array([int(r["step"]) for r in rows], dtype=np.int64),
        "load_fraction": np.array([float(r["load_fraction"]) for r in rows]),
        "kind": [r["kind"] for r in rows],
        "entity": np.array([int(r["entity"]) for r in rows], dtype=np.int64),
        "t": np.array([float(r["t"]) for r in rows]),
        "stage": np.array([int(r["stage"]) - 1 for r in rows], dtype=np.int64),
    }


def read_snapshots(folder: Path, scene) -> list[dict]:
    """The snapshots of results.xdmf + results.h5 (none without them)."""
    if not (folder / "results.xdmf").is_file():
        return []
    import h5py
    import meshio

    reader = meshio.xdmf.TimeSeriesReader(folder / "results.xdmf")
    points, _ = reader.read_points_cells()
    d = scene.dimension
    if points.shape[0] != len(scene.nodes) or not np.array_equal(points[:, :d], scene.nodes):
        raise InputError(
            f"{folder}: the mesh case.toml makes now is not the one results.h5 "
            f"holds (the generator, the mesh files or gmsh changed since the run): "
            f"load the folder where it was run, or run the case again"
        )
    with h5py.File(folder / "results.h5", "r") as h5:
        record = {key: np.asarray(v) for key, v in h5[RECORD_GROUP].items()}
    names = scene.idealisation.stress_names
    out = []
    for k in range(reader.num_steps):
        _, point_data, cell_data = reader.read_data(k)
        snap = {
            "t": float(record["t"][k]),
            "stage": int(record["stage"][k]),
            "load_fraction": float(record["load_fraction"][k]),
            "u": point_data["u"][:, :d].reshape(-1),
            "stress": np.column_stack([cell_data[n][0] for n in names]).reshape(-1),
        }
        if "reaction" in point_data:
            snap["reaction"] = point_data["reaction"][:, :d].reshape(-1)
        if is_elastoplastic(scene):
            snap["plastic_strain"] = cell_data["plastic_strain"][0]
            snap["plastic"] = cell_data["plastic"][0].astype(np.int8)
        for key in ("lambda_n", "lambda_t", "status", "gap", "rtd"):
            snap[key] = record[key][k]
        out.append(snap)
    return out
