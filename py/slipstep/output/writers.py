"""The files of a run, one writer each: events.csv, contact_profile.csv, the XDMF/HDF5 time
series and summary.json (:mod:`slipstep.output.results` writes them all, with the figures, staged
and renamed into place).

Contact quantities per candidate pair (engine sign conventions, docs/engine_api.md):
pressure = lambda_n / area and tangential stress = lambda_t / area, with area = L t (L the
tributary length of node a on its edge, t the thickness; in axisymmetry node a's ring, see
slipstep.measures.contact_edges); the tangential direction is t = (-n_y, n_x), i.e. (-1, 0) for a flat with
normal (0, 1).  Axisymmetric runs name the coordinates r, z and the stresses sigma_r, sigma_z,
sigma_theta (hoop), tau_rz (:func:`slipstep.output.fields.coordinate_names`, ``stress_names``).
3D scenes (docs/engine_api.md, "3D models") write tetrahedra and their own contact columns:
:func:`xdmf_step_3d`, :func:`write_profile_csv_3d`.
"""

from __future__ import annotations

import contextlib
import csv
import json
import math
import os
from pathlib import Path

import numpy as np

from ..measures.contact_edges import contact_profile
from .fields import (
    coordinate_names,
    is_elastoplastic,
    nodal_stress,
    stress_names,
    stress_tensor,
    von_mises,
    yield_drift,
)
from .history import (
    ELEMENT_EVENTS,
    distinct_time_snapshots,
    event_positions,
    event_times,
    snapshot_time,
)
from ..measures.contact_faces import contact_profile_3d
from .fields import STRESS_NAMES_3D, nodal_stress_3d, stress_tensor_3d, von_mises_3d

STATUS_NAMES = ("open", "stick", "slip")


# --------------------------------------------------------------------------- writers
def write_events_csv(path: Path, scene, result) -> None:
    """One row per (event, entity): step, load_fraction (within its stage), kind, entity,
    entity_kind (``pair`` or ``element``), x, y (node a of the pair; the element centroid for
    the element events yield, unload, frozen_element; 3D: x, y, z), t (path time) and stage
    (1-based); x, y are called r, z in axisymmetry."""
    ev = result["events"]
    times, stages = event_times(result)
    where = event_positions(scene, result)
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(
            [
                "step",
                "load_fraction",
                "kind",
                "entity",
                "entity_kind",
                *coordinate_names(scene),
                "t",
                "stage",
            ]
        )
        for k in range(len(ev["step"])):
            kind, entity = ev["kind"][k], int(ev["entity"][k])
            w.writerow(
                [
                    int(ev["step"][k]),
                    repr(float(ev["load_fraction"][k])),
                    kind,
                    entity,
                    "element" if kind in ELEMENT_EVENTS else "pair",
                    *(repr(float(c)) for c in where[k]),
                    repr(float(times[k])),
                    int(stages[k]) + 1,
                ]
            )


def write_profile_csv(path: Path, scene, snapshot: dict) -> None:
    """contact_profile.csv of the scene's idealisation: :func:`write_profile_csv_2d`, or
    :func:`write_profile_csv_3d`."""
    scene.idealisation.write_profile_csv(path, scene, snapshot)


def write_profile_csv_2d(path: Path, scene, snapshot: dict) -> None:
    """contact_profile.csv: the candidate pairs at the final snapshot, sorted by x; s is the
    position along the pair's contact (slipstep.measures.contact_edges) and contact its [[contact]] name; x, y
    are called r, z in axisymmetry.  3D: :func:`write_profile_csv_3d`."""
    prof = contact_profile(scene, snapshot)
    names = scene.engine_model.contact_names
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(
            [
                *coordinate_names(scene),
                "pressure",
                "tangential_stress",
                "rtd",
                "status",
                "gap",
                "pair",
                "node_a",
                "s",
                "contact",
            ]
        )
        for i in range(len(prof["x"])):
            w.writerow(
                [
                    repr(float(prof["x"][i])),
                    repr(float(prof["y"][i])),
                    repr(float(prof["pressure"][i])),
                    repr(float(prof["tangential_stress"][i])),
                    repr(float(prof["rtd"][i])),
                    STATUS_NAMES[prof["status"][i]],
                    repr(float(prof["gap"][i])),
                    int(prof["pair"][i]),
                    int(prof["node_a"][i]),
                    repr(float(prof["s"][i])),
                    names[prof["contact"][i]],
                ]
            )


@contextlib.contextmanager
def _working_directory(path: Path):
    # meshio's TimeSeriesWriter creates its .h5 in the current directory, not beside the .xdmf
    old = os.getcwd()
    os.chdir(path)
    try:
        yield
    finally:
        os.chdir(old)


#: The columns of a 3D contact_profile.csv after x, y, z: (name, profile key, component).
PROFILE_3D = (
    ("pressure", "pressure", None),
    ("tangential_stress_1", "tau", 0),
    ("tangential_stress_2", "tau", 1),
    ("tangential_stress_x", "tangential_stress", 0),
    ("tangential_stress_y", "tangential_stress", 1),
    ("tangential_stress_z", "tangential_stress", 2),
    ("slip_1", "slip", 0),
    ("slip_2", "slip", 1),
    ("slip_x", "slip_xyz", 0),
    ("slip_y", "slip_xyz", 1),
    ("slip_z", "slip_xyz", 2),
    ("slip_direction_x", "slip_direction", 0),
    ("slip_direction_y", "slip_direction", 1),
    ("slip_direction_z", "slip_direction", 2),
    ("gap", "gap", None),
)


def write_profile_csv_3d(path: Path, scene, snapshot: dict) -> None:
    """contact_profile.csv of a 3D scene: the candidate pairs at the final snapshot, sorted by
    x, then y, then z: pressure, the tangential stress in the pair's (t1, t2) (``_1``, ``_2``)
    and in x, y, z, the slip (relative tangential displacement) likewise, the slip direction of
    a slipping pair (opposite to its friction force: the direction of its slip rate; 0
    otherwise), status, gap, pair, node_a and its [[contact]] name
    (:func:`slipstep.measures.contact_faces.contact_profile_3d`)."""
    prof = contact_profile_3d(scene, snapshot)
    names = scene.engine_model.contact_names
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(
            ["x", "y", "z", *(c[0] for c in PROFILE_3D), "status", "pair", "node_a", "contact"]
        )
        for i in range(len(prof["pair"])):
            values = [prof[key][i] if c is None else prof[key][i, c] for _, key, c in PROFILE_3D]
            w.writerow(
                [
                    *(repr(float(v)) for v in (*prof["x"][i], *values)),
                    STATUS_NAMES[prof["status"][i]],
                    int(prof["pair"][i]),
                    int(prof["node_a"][i]),
                    names[prof["contact"][i]],
                ]
            )


def write_xdmf(folder: Path, scene, result, name: str = "results") -> None:
    """``results.xdmf`` + ``results.h5``: a time series (time = path time t, the load fraction
    of a run without stages; one grid per distinct t, the state after every event there:
    :func:`slipstep.output.history.distinct_time_snapshots`) of the fields of :func:`xdmf_step` on
    2D points, with the case's units in an ``Information`` element ``units`` of the Domain
    (``length: mm, force: N, stress: MPa``; absent when ``[case] units`` does not give them).
    Beside the fields results.h5 keeps each step's :func:`snapshot_record` (group
    :data:`RECORD_GROUP`), which the XDMF does not name: with them :func:`slipstep.output.saved.load`
    reads the run back exactly."""
    import h5py
    import meshio

    idealisation = scene.idealisation
    cells = [(idealisation.cell_type, scene.elements)]
    step = idealisation.xdmf_step
    kept = distinct_time_snapshots(result)
    with _working_directory(folder):
        with meshio.xdmf.TimeSeriesWriter(f"{name}.xdmf") as writer:
            writer.write_points_cells(scene.nodes, cells)
            for k in kept:
                snap = result["snapshots"][k]
                point_data, cell_data = step(scene, snap)
                writer.write_data(snapshot_time(snap), point_data=point_data, cell_data=cell_data)
    records = [snapshot_record(result["snapshots"][k]) for k in kept]
    with h5py.File(Path(folder) / f"{name}.h5", "a") as h5:
        group = h5.create_group(RECORD_GROUP)
        for key in records[0]:
            group.create_dataset(key, data=np.stack([r[key] for r in records]))
    if scene.case.units:
        _record_units(Path(folder) / f"{name}.xdmf", scene.case.units)


#: The group of results.h5 that holds the steps' :func:`snapshot_record`.
RECORD_GROUP = "slipstep_snapshots"


def snapshot_record(snap: dict) -> dict:
    """What results.h5 keeps of a snapshot beside its fields: its place on the path (t, stage
    0-based, load_fraction) and the engine's per-pair arrays (lambda_n, lambda_t, status, gap,
    rtd), as the engine gave them."""
    out = {
        "t": np.float64(snapshot_time(snap)),
        "stage": np.int64(snap.get("stage", 0)),
        "load_fraction": np.float64(snap["load_fraction"]),
    }
    for key in ("lambda_n", "lambda_t", "status", "gap", "rtd"):
        out[key] = np.asarray(snap[key])
    return out


def _record_units(path: Path, units: dict) -> None:
    """Add ``<Information Name="units" Value="length: mm, ...">`` to the file's Domain."""
    import xml.etree.ElementTree as ET

    tree = ET.parse(path)
    info = ET.Element(
        "Information",
        Name="units",
        Value=", ".join(f"{kind}: {unit}" for kind, unit in units.items()),
    )
    tree.getroot().find("Domain").insert(0, info)
    tree.write(path)


def xdmf_step(scene, snap: dict) -> tuple[dict, dict]:
    """(point_data, cell_data) of one snapshot as results.xdmf holds it (meshio's layout: cell
    data as one-block lists).  Point data: ``u`` and, when the result has it, ``reaction``
    (padded to 3 components, z = 0), ``nodal_stress`` (the recovered nodal stresses,
    :func:`slipstep.output.fields.nodal_stress`, as a 9-component tensor) and ``nodal_von_mises``,
    and the contact fields of :func:`contact_point_data`.  Cell data: sigma_x, sigma_y,
    sigma_z, tau_xy (axisymmetric: sigma_r, sigma_z, sigma_theta, tau_rz), ``stress`` (the
    same as a 9-component tensor, :func:`slipstep.output.fields.stress_tensor`), von_mises (plus
    plastic_strain, the equivalent plastic strain, and plastic, the 0/1 flag, in elastoplastic
    cases, with yield_drift = |sigma_e - sigma_y(eps_p)|/sigma_y per plastic element; and body,
    the body index, when there are several)."""
    n = len(scene.nodes)
    s = np.asarray(snap["stress"], dtype=float).reshape(-1, 4)
    nodal = nodal_stress(scene, s)
    point_data = {key: _padded(snap[key], n) for key in ("u", "reaction") if key in snap}
    point_data.update(nodal_stress=stress_tensor(nodal), nodal_von_mises=von_mises(nodal))
    point_data.update(contact_point_data(scene, snap))
    cell_data = {name: [s[:, k]] for k, name in enumerate(stress_names(scene))}
    cell_data["stress"] = [stress_tensor(s)]
    cell_data["von_mises"] = [von_mises(s)]
    cell_data.update(state_cell_data(scene, snap))
    return point_data, cell_data


def xdmf_step_3d(scene, snap: dict) -> tuple[dict, dict]:
    """(point_data, cell_data) of one snapshot of a 3D scene as results.xdmf holds it.  Point
    data: ``u``, ``reaction`` (when the result has it), ``nodal_stress`` (the volume-weighted
    nodal average, a 9-component tensor) and ``nodal_von_mises``, and the contact fields on
    node a of each candidate pair (0 elsewhere): contact_pressure, contact_status (0 open, 1
    stick, 2 slip), contact_gap, and the vectors contact_tangential_stress, contact_slip and
    contact_slip_direction in x, y, z.  Cell data: the six stress columns (sigma_xx, sigma_yy,
    sigma_zz, tau_yz, tau_xz, tau_xy), ``stress`` as a symmetric 9-component tensor, von_mises,
    and in elastoplastic cases plastic_strain, plastic and yield_drift; body with several."""
    s = np.asarray(snap["stress"], dtype=float).reshape(-1, 6)
    nodal = nodal_stress_3d(scene.nodes, scene.tetrahedra, s)
    point_data = {
        key: np.asarray(snap[key], dtype=float).reshape(-1, 3)
        for key in ("u", "reaction")
        if key in snap
    }
    point_data.update(nodal_stress=stress_tensor_3d(nodal), nodal_von_mises=von_mises_3d(nodal))
    if len(scene.pair_xy):
        prof = contact_profile_3d(scene, snap)
        order = np.lexsort((prof["pressure"], prof["node_a"]))  # the largest pressure last
        for name, key in (
            ("contact_pressure", "pressure"),
            ("contact_status", "status"),
            ("contact_gap", "gap"),
            ("contact_tangential_stress", "tangential_stress"),
            ("contact_slip", "slip_xyz"),
            ("contact_slip_direction", "slip_direction"),
        ):
            values = np.asarray(prof[key], dtype=float)
            field = np.zeros((len(scene.nodes), *values.shape[1:]))
            field[prof["node_a"][order]] = values[order]
            point_data[name] = field
    cell_data = {name: [s[:, k]] for k, name in enumerate(STRESS_NAMES_3D)}
    cell_data.update(stress=[stress_tensor_3d(s)], von_mises=[von_mises_3d(s)])
    cell_data.update(state_cell_data(scene, snap))
    return point_data, cell_data


def state_cell_data(scene, snap: dict) -> dict:
    """The cell data beside the stresses: in elastoplastic cases plastic_strain, plastic and
    yield_drift; body (the body index) when there are several."""
    out = {}
    if is_elastoplastic(scene):
        for key in ("plastic_strain", "plastic"):
            if key in snap:
                out[key] = [np.asarray(snap[key], dtype=np.float64)]
        if "plastic" in snap:
            out["yield_drift"] = [yield_drift(scene, snap)]
    if len(scene.bodies) > 1:
        out["body"] = [scene.element_body.astype(np.float64)]
    return out


#: Point data of the contact (name in results.xdmf -> column of contact_profile.csv).
CONTACT_POINT_DATA = {
    "contact_pressure": "pressure",
    "contact_tangential_stress": "tangential_stress",
    "contact_gap": "gap",
    "contact_status": "status",
    "contact_slip": "rtd",
}


def contact_point_data(scene, snap: dict) -> dict:
    """The contact fields as point data (N,), each on node a of its candidate pair (the
    contactor node) as contact_profile.csv has them: pressure, tangential stress, gap, status
    (0 open, 1 stick, 2 slip) and slip (the RTD, relative tangential displacement); 0 at every
    other node (no NaN: status 0 there reads as open).  A node that is node a of several pairs
    shows the one with the largest pressure.  Empty without candidate pairs."""
    if not len(scene.pair_xy):
        return {}
    prof = contact_profile(scene, snap)
    node = np.asarray(prof["node_a"], dtype=np.int64)
    order = np.lexsort((prof["pressure"], node))  # by node, the largest pressure last
    shown = order[np.append(node[order][1:] != node[order][:-1], True)]
    out = {}
    for name, column in CONTACT_POINT_DATA.items():
        values = np.zeros(len(scene.nodes))
        values[node[shown]] = np.asarray(prof[column], dtype=float)[shown]
        out[name] = values
    return out


def _padded(values, n: int) -> np.ndarray:
    """(n, 3) float64: (n, 2) nodal vectors with z = 0, for ParaView."""
    out = np.zeros((n, 3))
    out[:, :2] = np.asarray(values, dtype=float).reshape(n, 2)
    return out


def write_summary_json(path: Path, summary: dict) -> None:
    """summary.json: the summary (NaN and inf as null)."""
    with open(path, "w") as fh:
        json.dump(json_safe(summary), fh, indent=2)
        fh.write("\n")


def json_safe(value):
    """A value JSON can hold: numpy scalars as Python numbers, NaN/inf as None."""
    if isinstance(value, dict):
        return {k: json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_safe(v) for v in value]
    if isinstance(value, (np.floating, np.integer, np.bool_)):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value
