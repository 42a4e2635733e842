"""The run's resultants along its path, one row per increment: each contact's force
and moment, each support's reaction, the applied loads, the obstacles' motions and prescribed
displacements, and the load-displacement curves of the loads that drive the run
(``history.csv``, the summary's driving force, the load-depth and Q-delta figures).

The engine records at every increment (docs/engine_api.md, ``steps``): per contact the
resultant of its pairs' forces on the contactor body, Σ (n λ_n + t1 λ_t1 + t2 λ_t2), in global
axes, and its moment about the origin (undeformed coordinates); per support group (a [[bc]]
that holds or prescribes DOFs, :func:`slipstep.loads.supports.support_groups`) its reaction on the
body; per force pattern its work P_j·u at factor 1.  The rest is the load path itself (factors
linear in t within a stage): applied resultants, obstacle motions, prescribed displacements.
A result without these arrays (an older engine) gets the same rows at its snapshots only,
recomputed from their arrays.

Model and whole: the rows are what the model carries (the part a symmetric model meshes).
:func:`drivers` mirrors a 3D part across its symmetry planes into the whole (like the 3D
summary's contact numbers: the components along the planes' normals cancel, the others add);
2D values stay the model's (per thickness, or ring totals in axisymmetry), as in the 2D summary.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from ..case_record import RigidCircle, RigidSphere, RigidSurface
from ..output.history import load_factor, snapshot_time
from ..loads.supports import support_groups

#: Component names of the force columns.
AXES = "xyz"


def force_components(scene) -> list[int]:
    """The components a force of the scene has: x, y (2D), z of (r, z) in axisymmetry (a ring
    force has no radial resultant), x, y, z (3D)."""
    return list(scene.idealisation.force_components)


def moment_components(scene) -> list[int]:
    """The moment components: x, y, z in 3D, z in 2D (none in axisymmetry)."""
    return list(scene.idealisation.moment_components)


def component_name(scene, c: int) -> str:
    """x, y, z; r, z in axisymmetry."""
    return scene.idealisation.component_names[c]


def _padded(a, dim: int) -> np.ndarray:
    """(..., dim) -> (..., 3), zeros after."""
    a = np.asarray(a, dtype=float)
    out = np.zeros((*a.shape[:-1], 3))
    out[..., :dim] = a
    return out


def pattern_forces(scene) -> list[np.ndarray | None]:
    """Per load name (``scene.load_names``: "load", then the engine's patterns) its nodal force
    at factor 1 (None for a pattern without forces)."""
    model = scene.model
    out = [np.asarray(model["load"], dtype=float)]
    for p in model.get("patterns", []):
        out.append(np.asarray(p["force"], dtype=float) if "force" in p else None)
    names = list(getattr(scene, "load_names", ["load"]))
    out += [None] * (len(names) - len(out))
    return [None if f is None or not np.any(f) else f for f in out[: len(names)]]


def _factors(scene, t: np.ndarray) -> np.ndarray:
    """(R, L) the factor of every load at the path times t."""
    return (
        np.stack([load_factor(scene, name, t) for name in scene.load_names], axis=1)
        if len(t)
        else np.zeros((0, len(scene.load_names)))
    )


def prescribed_vector(scene, name: str) -> np.ndarray:
    """(3,) the displacement a prescribed-displacement load gives its nodes at factor 1 (its
    [[bc]]'s uniform ``displacement``, read back from the engine's DOF values)."""
    p, d = scene.prescribed[name], scene.dimension
    dofs, values = np.asarray(p["dofs"], dtype=np.int64), np.asarray(p["values"], dtype=float)
    out = np.zeros(3)
    for c in range(d):
        mine = values[dofs % d == c]
        out[c] = float(mine.mean()) if len(mine) else 0.0
    return out


def step_history(scene, result) -> dict:
    """The resultants at t = 0 and after every increment (``steps``; at every snapshot for a
    result without the engine's resultants).  Arrays with one row per entry of ``t``:

    - ``step`` (0 = the start, k = increment k), ``t``, ``stage`` (0-based), ``load_fraction``;
    - ``contact_force`` (R, C, 3), ``contact_moment`` (R, C, 3) per contact (``contact_names``);
    - ``reaction`` (R, G, 3) per support group (``support_names``; NaN where the engine did not
      know it: contact sub-steps of grouped plastic increments);
    - ``factor`` (R, L), ``applied`` (R, L, 3) (each load's applied resultant), ``load_work``
      (R, L) (P_j·u at factor 1; NaN where unknown) per load (``load_names``);
    - ``motion`` (R, C, 3) each contact's obstacle translation; ``prescribed`` (R, L, 3) each
      displacement load's prescribed displacement.

    Vectors have three components (z = 0 in 2D)."""
    dim = scene.dimension
    steps = result.get("steps", {})
    groups = support_groups(scene)
    forces = pattern_forces(scene)
    n_c = (
        len(scene.model.get("contact_names", [])) or int(np.max(scene.pair_contact, initial=-1)) + 1
    )
    if "contact_force" in steps:
        t = np.concatenate([[0.0], np.asarray(steps["t"], dtype=float)])
        n = len(t) - 1
        stage = np.concatenate([[0], np.asarray(steps["stage"], dtype=np.int64)])
        phi = np.concatenate([[0.0], np.asarray(steps["load_fraction"], dtype=float)])
        force = np.zeros((n + 1, n_c, 3))
        force[1:, : steps["contact_force"].shape[1]] = _padded(steps["contact_force"], dim)
        moment = np.zeros((n + 1, n_c, 3))
        m = np.asarray(steps["contact_moment"], dtype=float)
        axes = list(scene.idealisation.engine_moment_axes)
        moment[1:, : m.shape[1], axes] = m.reshape(n, m.shape[1], len(axes))
        reaction = np.zeros((n + 1, len(groups), 3))
        r = np.asarray(steps["reaction"], dtype=float)
        if r.shape[1] == len(groups):
            reaction[1:] = _padded(r, dim)
        else:  # a model built without the support groups: none recorded
            reaction[1:] = np.nan
        work = np.zeros((n + 1, len(forces)))
        w = np.asarray(steps["load_work"], dtype=float)
        work[1:, : w.shape[1]] = w[:, : len(forces)]
        step = np.arange(n + 1)
    else:
        t, stage, phi, force, moment, reaction, work, step = _from_snapshots(
            scene, result, groups, forces, n_c
        )
    factor = _factors(scene, t)
    applied = np.zeros((len(t), len(forces), 3))
    for j, f in enumerate(forces):
        if f is not None:
            applied[:, j] = factor[:, j : j + 1] * _padded(f.reshape(-1, dim).sum(axis=0), dim)
    motion = np.zeros((len(t), n_c, 3))
    for name, mo in getattr(scene, "motions", {}).items():
        motion[:, int(mo["contact"])] += np.outer(
            load_factor(scene, name, t), _padded(mo["motion"], dim)
        )
    prescribed = np.zeros((len(t), len(forces), 3))
    for name in getattr(scene, "prescribed", {}):
        j = list(scene.load_names).index(name)
        prescribed[:, j] = np.outer(factor[:, j], prescribed_vector(scene, name))
    return {
        "step": step,
        "t": t,
        "stage": stage,
        "load_fraction": phi,
        "contact_force": force,
        "contact_moment": moment,
        "reaction": reaction,
        "factor": factor,
        "applied": applied,
        "load_work": work,
        "motion": motion,
        "prescribed": prescribed,
        "contact_names": list(scene.model.get("contact_names", [])),
        "support_names": list(groups),
        "load_names": list(scene.load_names),
    }


def contactor_points(scene) -> np.ndarray:
    """(P, 3) where each pair's force acts on its contactor side: node a, or Σ c_i x_i over the
    contactor nodes (weights c_i > 0) of a weighted row (the engine's moment arm)."""
    pairs = scene.model["pairs"]
    x = _padded(scene.nodes, scene.dimension)
    out = x[np.asarray(pairs["node_a"], dtype=np.int64)].copy()
    ptr = np.asarray(pairs.get("weight_ptr", np.zeros(len(out) + 1, dtype=np.int64)))
    for k in np.flatnonzero(np.diff(ptr) > 0):
        nodes = np.asarray(pairs["weight_node"])[ptr[k] : ptr[k + 1]]
        c = np.asarray(pairs["weight_value"], dtype=float)[ptr[k] : ptr[k + 1]]
        mine = c > 0
        out[k] = (c[mine, None] * x[nodes[mine]]).sum(axis=0) / c[mine].sum()
    return out


def snapshot_resultants(scene, snap: dict, n_contacts: int) -> tuple[np.ndarray, np.ndarray]:
    """(C, 3) force and (C, 3) moment about the origin of every contact at a snapshot, from its
    arrays (the engine's per-increment ``contact_force`` / ``contact_moment``)."""
    f = scene.idealisation.pair_forces(scene, snap)
    m = np.cross(contactor_points(scene), f)
    which = np.asarray(scene.pair_contact, dtype=np.int64)
    force = np.stack([np.bincount(which, f[:, c], n_contacts) for c in range(3)], axis=1)
    moment = np.stack([np.bincount(which, m[:, c], n_contacts) for c in range(3)], axis=1)
    return force, moment


def _from_snapshots(scene, result, groups: dict, forces: list, n_c: int):
    """The rows of :func:`step_history` at t = 0 and every snapshot, from their arrays."""
    dim = scene.dimension
    snaps = list(result.get("snapshots", []))
    t = np.array([snapshot_time(s) for s in snaps])
    first = [] if len(t) and t[0] == 0.0 else [None]
    rows = first + snaps
    n = len(rows)
    out_t = np.array([0.0 if s is None else snapshot_time(s) for s in rows])
    stage = np.array([0 if s is None else int(s.get("stage", 0)) for s in rows], dtype=np.int64)
    phi = np.array([0.0 if s is None else float(s["load_fraction"]) for s in rows])
    force, moment = np.zeros((n, n_c, 3)), np.zeros((n, n_c, 3))
    reaction = np.zeros((n, len(groups), 3))
    work = np.zeros((n, len(forces)))
    for k, s in enumerate(rows):
        if s is None:
            continue
        if len(scene.pair_xy):
            force[k], moment[k] = snapshot_resultants(scene, s, n_c)
        if "reaction" in s:
            r = np.asarray(s["reaction"], dtype=float).reshape(-1, dim)
            for g, dofs in enumerate(groups.values()):
                for c in range(dim):
                    mine = dofs[dofs % dim == c] // dim
                    reaction[k, g, c] = r[mine, c].sum()
        else:
            reaction[k] = np.nan
        u = np.asarray(s["u"], dtype=float).reshape(-1)
        work[k] = [0.0 if f is None else float(f @ u) for f in forces]
    # the components the engine records: about z in 2D (x and y of a cross of planar vectors
    # are zeros, or -0.0)
    kept = np.zeros(3, dtype=bool)
    kept[list(scene.idealisation.engine_moment_axes)] = True
    moment[..., ~kept] = 0.0
    return out_t, stage, phi, force, moment, reaction, work, np.arange(n)


# --------------------------------------------------------------------------- whole model
def whole(vectors: np.ndarray, planes) -> np.ndarray:
    """(..., 3) vectors of a part mirrored into the whole: × 2 per plane, the component along
    each plane's normal 0."""
    out = np.array(vectors, dtype=float) * 2.0 ** len(planes)
    for axis, _ in planes:
        out[..., axis] = 0.0
    return out


def body_of_nodes(scene, nodes) -> list[str]:
    """The bodies the given nodes belong to, in body order."""
    nodes = np.asarray(nodes, dtype=np.int64)
    first = {b: scene.offsets[b] for b in scene.bodies}
    return [
        b
        for b in scene.bodies
        if ((nodes >= first[b]) & (nodes < first[b] + scene.meshes[b].n_nodes)).any()
    ]


def contact_planes(scene, index: int) -> list[tuple[int, float]]:
    """The planes [[contact]] ``index``'s part is mirrored across (3D; the summary's)."""
    return scene.idealisation.mirror_planes(scene, index)


def drivers(scene, hist: dict) -> dict[str, dict]:
    """The loads that drive the run, by load name, each with its curve from t = 0 along the
    history: an obstacle's motion (``kind`` "motion": ``displacement`` = its translation along
    the motion's direction, ``force`` = its contact's force on the body along it, the force that
    pushes the obstacle), a prescribed displacement ("displacement": the displacement along
    its direction, and its [[bc]]'s reaction along it), a force ("load": the work-conjugate
    displacement P·u / |P| along its resultant, and its resultant's size).  ``force`` is the
    whole's (3D: mirrored across the part's symmetry planes), ``force_model`` the part's;
    ``direction`` the unit vector (3,), ``contact`` / ``support`` the index it is read from."""
    out = {}
    dim = scene.dimension
    for name, mo in getattr(scene, "motions", {}).items():
        c = int(mo["contact"])
        m = _padded(mo["motion"], dim)
        if not np.any(m):
            continue
        e = m / np.linalg.norm(m)
        planes = contact_planes(scene, c)
        out[name] = {
            "kind": "motion",
            "contact": c,
            "direction": e,
            "planes": planes,
            "displacement": hist["motion"][:, c] @ e,
            "force_model": hist["contact_force"][:, c] @ e,
            "force": whole(hist["contact_force"][:, c], planes) @ e,
        }
    groups = support_groups(scene)
    for name in getattr(scene, "prescribed", {}):
        d = prescribed_vector(scene, name)
        dofs = np.asarray(scene.prescribed[name]["dofs"], dtype=np.int64)
        # its [[bc]]'s group: the one that holds its DOFs
        g = next((g for g, held in enumerate(groups.values()) if np.isin(dofs, held).all()), None)
        if not np.any(d) or g is None or name not in hist["load_names"]:
            continue
        e = d / np.linalg.norm(d)
        j = list(hist["load_names"]).index(name)
        nodes = np.unique(dofs // dim)
        planes = scene.idealisation.mirror_planes_of(
            scene, body_of_nodes(scene, nodes), scene.nodes[nodes]
        )
        out[name] = {
            "kind": "displacement",
            "support": g,
            "direction": e,
            "planes": planes,
            "displacement": hist["prescribed"][:, j] @ e,
            "force_model": hist["reaction"][:, g] @ e,
            "force": whole(hist["reaction"][:, g], planes) @ e,
        }
    for j, (name, f) in enumerate(zip(hist["load_names"], pattern_forces(scene))):
        if f is None:
            continue
        part = _padded(f.reshape(-1, dim).sum(axis=0), dim)
        loaded = np.flatnonzero(np.abs(f.reshape(-1, dim)).sum(axis=1) > 0)
        planes = scene.idealisation.mirror_planes_of(
            scene, body_of_nodes(scene, loaded), scene.nodes[loaded]
        )
        full = whole(part, planes)
        if np.linalg.norm(full) <= 1e-12 * np.abs(f).sum():
            continue  # self-balanced (a pressure inside a ring): no resultant to follow
        e = full / np.linalg.norm(full)
        along = float(part @ e)
        out[name] = {
            "kind": "load",
            "direction": e,
            "planes": planes,
            "displacement": hist["load_work"][:, j] / along,
            "force_model": hist["factor"][:, j] * along,
            "force": hist["factor"][:, j] * float(full @ e),
        }
    for name, d in out.items():
        d["t"], d["stage"] = hist["t"], hist["stage"]
        d["bodies"] = _driver_bodies(scene, name, d)
        d["tangential"] = is_tangential(scene, d)
    return out


def _driver_bodies(scene, name: str, d: dict) -> list[str]:
    """The bodies a driving load acts on: its contact's (a motion), its [[bc]]'s, or those of
    its loaded nodes."""
    if d["kind"] == "motion":
        pairs = np.asarray(scene.model["pairs"]["node_a"])[scene.pair_contact == d["contact"]]
        return body_of_nodes(scene, pairs)
    if d["kind"] == "displacement":
        return body_of_nodes(scene, np.asarray(scene.prescribed[name]["dofs"]) // scene.dimension)
    f = pattern_forces(scene)[list(scene.load_names).index(name)].reshape(-1, scene.dimension)
    return body_of_nodes(scene, np.flatnonzero(np.abs(f).sum(axis=1) > 0))


def contact_normal(scene, index: int) -> np.ndarray:
    """(3,) the mean unit normal of [[contact]] ``index``'s pairs, of the whole contact (3D: the
    components across its mirror planes cancel)."""
    normals = np.asarray(scene.model["pairs"]["normal"], dtype=float)
    n = _padded(normals[scene.pair_contact == index], scene.dimension).sum(axis=0)
    n = whole(n, contact_planes(scene, index))
    size = np.linalg.norm(n)
    return n / size if size > 0 else n


def is_tangential(scene, d: dict) -> bool:
    """A driving load along the contact rather than into it: every contact that touches its
    bodies has its mean normal more than 60 degrees off the load's direction (a shear after a
    press: the Q-delta curve, not a load-depth curve)."""
    if d["kind"] == "motion":
        touching = [d["contact"]]
    else:
        a = np.asarray(scene.model["pairs"]["node_a"], dtype=np.int64)
        b = np.asarray(scene.model["pairs"]["node_b"], dtype=np.int64)
        ids = (
            np.concatenate(
                [np.arange(scene.meshes[x].n_nodes) + scene.offsets[x] for x in d["bodies"]]
            )
            if d["bodies"]
            else np.zeros(0, np.int64)
        )
        mine = np.isin(a, ids) | np.isin(b, ids)
        touching = np.unique(np.asarray(scene.pair_contact)[mine]).tolist()
    normals = [contact_normal(scene, c) for c in touching]
    return bool(normals) and all(abs(float(n @ d["direction"])) < 0.5 for n in normals)


def driving_forces(scene, hist: dict) -> dict[str, dict]:
    """The summary's driving forces (:func:`drivers`) at the end of the history, with the
    largest reached: ``kind``, ``force`` (the whole's, along ``direction``), ``force_model``,
    ``displacement``, ``max_force`` and ``displacement_at_max``, ``direction``."""
    out = {}
    for name, d in drivers(scene, hist).items():
        force, disp = np.nan_to_num(d["force"]), np.nan_to_num(d["displacement"])
        model = np.nan_to_num(d["force_model"])
        k = int(np.argmax(force))  # (a history has its row at t = 0 at least)
        out[name] = {
            "kind": d["kind"],
            "force": float(force[-1]),
            "force_model": float(model[-1]),
            "displacement": float(disp[-1]),
            "max_force": float(force[k]),
            "displacement_at_max": float(disp[k]),
            "direction": d["direction"].tolist(),
            "symmetry_planes": [f"{'xyz'[a]} = {v:g}" for a, v in d["planes"]],
        }
    return out


# --------------------------------------------------------------------------- history.csv
def _unit(scene, kind: str) -> str:
    units = scene.case.units
    if kind == "moment":
        return f"{units['force']} {units['length']}" if units else "force*length"
    return units.get(kind, kind)


def history_columns(scene, hist: dict) -> list[tuple[str, np.ndarray]]:
    """(header, column) of history.csv, in order (cases/README.md, Outputs)."""
    f_unit, l_unit, m_unit = (_unit(scene, k) for k in ("force", "length", "moment"))
    comps, mcomps = force_components(scene), moment_components(scene)
    cols = [
        ("step", hist["step"]),
        ("t", hist["t"]),
        ("stage", hist["stage"] + 1),
        ("load_fraction", hist["load_fraction"]),
    ]
    for name, d in drivers(scene, hist).items():
        cols.append((f"driver.{name}.displacement [{l_unit}]", d["displacement"]))
        cols.append((f"driver.{name}.force [{f_unit}]", d["force"]))
    for c, name in enumerate(hist["contact_names"]):
        cols += [
            (
                f"contact.{name}.F_{component_name(scene, k)} [{f_unit}]",
                hist["contact_force"][:, c, k],
            )
            for k in comps
        ]
        cols += [
            (f"contact.{name}.M_{AXES[k]} [{m_unit}]", hist["contact_moment"][:, c, k])
            for k in mcomps
        ]
        if np.any(hist["motion"][:, c]):
            cols += [
                (f"contact.{name}.u_{component_name(scene, k)} [{l_unit}]", hist["motion"][:, c, k])
                for k in range(scene.dimension)
            ]
    groups = support_groups(scene)
    for g, name in enumerate(hist["support_names"]):
        held = set((np.asarray(groups.get(name, []), dtype=np.int64) % scene.dimension).tolist())
        cols += [
            (f"bc.{name}.R_{component_name(scene, k)} [{f_unit}]", hist["reaction"][:, g, k])
            for k in comps
            if k in held
        ]
    forces = pattern_forces(scene)
    for j, name in enumerate(hist["load_names"]):
        kinematic = np.any(hist["prescribed"][:, j]) or name in getattr(scene, "motions", {})
        if forces[j] is None and not kinematic:
            continue
        cols.append((f"load.{name}.factor", hist["factor"][:, j]))
        if forces[j] is not None:
            cols += [
                (f"load.{name}.F_{component_name(scene, k)} [{f_unit}]", hist["applied"][:, j, k])
                for k in comps
            ]
            cols.append(
                (f"load.{name}.work_per_factor [{f_unit} {l_unit}]", hist["load_work"][:, j])
            )
        if np.any(hist["prescribed"][:, j]):
            cols += [
                (
                    f"load.{name}.u_{component_name(scene, k)} [{l_unit}]",
                    hist["prescribed"][:, j, k],
                )
                for k in range(scene.dimension)
            ]
    return cols


def write_history_csv(path: Path, scene, result, hist: dict | None = None) -> None:
    """history.csv: one row per increment from t = 0 (:func:`step_history`), the columns of
    :func:`history_columns` (cases/README.md, Outputs)."""
    hist = step_history(scene, result) if hist is None else hist
    cols = history_columns(scene, hist)
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow([h for h, _ in cols])
        for k in range(len(hist["t"])):
            w.writerow([_cell(v[k]) for _, v in cols])


def _cell(v) -> str:
    if isinstance(v, (np.integer, int)):
        return str(int(v))
    return repr(float(v))


# --------------------------------------------------------------------------- indentation
def indenter_shape(scene, index: int) -> tuple[str, float | None] | None:
    """(indenter, radius) of [[contact]] ``index`` for the Oliver–Pharr analysis
    (:mod:`slipstep.measures.indentation`): a ``rigid_surface`` Vickers or Berkovich pyramid, a
    ``rigid_sphere`` (3D) or, in axisymmetry, a ``rigid_circle`` centred on the axis, with the
    body outside; None for any other obstacle."""
    c = scene.case.record.contact[index]
    if isinstance(c, RigidSurface) and c.indenter in ("vickers", "berkovich"):
        return c.indenter, None
    if getattr(c, "side", "outside") != "outside":  # (a kind without a side: outside)
        return None
    if isinstance(c, RigidSphere):
        return "sphere", float(c.radius)
    if (
        isinstance(c, RigidCircle)
        and scene.model.get("plane") == "axisymmetric"
        and abs(c.centre[0]) <= 1e-12 * max(1.0, abs(c.radius))
    ):
        return "sphere", float(c.radius)
    return None


def indentation(scene, hist: dict) -> dict:
    """Per moving obstacle that is an indenter (:func:`indenter_shape`) and unloads: the
    Oliver–Pharr numbers of its load-depth curve (:func:`slipstep.measures.indentation.oliver_pharr`,
    the whole indenter's force against its depth), by load name; {} when none unloads."""
    from .indentation import oliver_pharr

    out = {}
    for name, d in drivers(scene, hist).items():
        shape = indenter_shape(scene, d["contact"]) if d["kind"] == "motion" else None
        if shape is None:
            continue
        try:
            out[name] = oliver_pharr(d["displacement"], d["force"], shape[0], radius=shape[1])
        except ValueError:
            continue  # no unloading branch (or too few points on it)
    return out
