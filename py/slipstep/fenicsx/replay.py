"""Contact replay: a slipstep contact state imposed on the dolfinx bulk model as boundary
conditions, and the bulk fields compared.

At a snapshot, per candidate pair (docs/engine_api.md: n the normal, t = (-n_y, n_x)):

- closed (stick or slip): the normal displacement of node a is prescribed,
  n . u_a = -gap0 (the contact constraint gap = 0 itself, not slipstep's displacement);
- stick: the tangential displacement is held at its value, t . u_a = RTD (snapshot);
- slip: the node is loaded by the friction force lambda_t t with lambda_t = sign(lambda_t) mu
  lambda_n (slipstep's lambda_n; the normal force itself is the dolfinx reaction);
- open: nothing.

The dolfinx reactions then give lambda_n on every closed pair and lambda_t on stick pairs,
which are compared with slipstep's.  Restrictions (raise ``NotImplementedError``): rigid
targets only (node_b = -1; a node-to-node pair is a multi-point constraint) with a normal
along x or y (the constraint is then one Cartesian dof).

Elastic: every snapshot is solved on its own (linear problem, path independent).
Elastoplastic: the snapshots are replayed in order, each reached by ``substeps`` dolfinx
load steps (constraints and loads ramped linearly, which is exact between two events for
the contact variables: the engine's path is piecewise linear in them).
"""

from __future__ import annotations

import numpy as np

from .bulk import BulkProblem, relative_difference


def _axis(n: np.ndarray, where: str) -> int:
    for c in (0, 1):
        if abs(abs(n[c]) - 1.0) <= 1e-12 and abs(n[1 - c]) <= 1e-12:
            return c
    raise NotImplementedError(
        f"{where}: the contact normal ({n[0]:.6g}, {n[1]:.6g}) is not along "
        f"x or y: the replay prescribes one Cartesian dof per constraint"
    )


def replay_conditions(scene, snapshot: dict):
    """(prescribed {slipstep dof: value}, extra_load (2N,), info) for one snapshot."""
    pairs = scene.model["pairs"]
    status = np.asarray(snapshot["status"])
    prescribed: dict[int, float] = {}
    extra = np.zeros(2 * len(scene.nodes))
    info = {
        "closed": [],
        "stick": [],
        "slip": [],
        "normal_dof": [],
        "tangent_dof": [],
        "tangent_sign": [],
    }
    for p in np.flatnonzero(status > 0):
        if pairs["node_b"][p] != -1:
            raise NotImplementedError(
                f"pair {p}: node-to-node pairs are multi-point constraints;"
                f" the replay handles rigid targets only"
            )
        n = np.asarray(pairs["normal"][p], dtype=float)
        cn = _axis(n, f"pair {p}")
        ct = 1 - cn
        tvec = np.array([-n[1], n[0]])
        a = int(pairs["node_a"][p])
        dn, dt = 2 * a + cn, 2 * a + ct
        prescribed[dn] = -float(pairs["gap"][p]) / n[cn]
        info["closed"].append(p)
        info["normal_dof"].append(dn)
        info["tangent_dof"].append(dt)
        info["tangent_sign"].append(tvec[ct])
        if status[p] == 1:
            prescribed[dt] = float(snapshot["rtd"][p]) / tvec[ct]
            info["stick"].append(p)
        else:
            lam_t = np.sign(snapshot["lambda_t"][p]) * pairs["mu"][p] * snapshot["lambda_n"][p]
            extra[dt] += lam_t * tvec[ct]
            info["slip"].append(p)
    info = {k: np.asarray(v) for k, v in info.items()}
    info["normal_sign"] = np.array(
        [pairs["normal"][p][_axis(pairs["normal"][p], "")] for p in info["closed"]]
    )
    return prescribed, extra, info


def compare(scene, snapshot: dict, res, info: dict, fixed_dofs: np.ndarray) -> dict:
    """Differences between a dolfinx replay result and the slipstep snapshot."""
    out = {
        "load_fraction": float(snapshot["load_fraction"]),
        "n_closed": int(len(info["closed"])),
        "n_stick": int(len(info["stick"])),
        "n_slip": int(len(info["slip"])),
        "u": relative_difference(res.u, snapshot["u"]),
        "stress": relative_difference(res.stress, snapshot["stress"]),
    }
    if "plastic_strain" in snapshot and np.abs(snapshot["plastic_strain"]).max(initial=0) > 0:
        out["plastic_strain"] = relative_difference(res.plastic_strain, snapshot["plastic_strain"])
    lam_n = np.asarray(snapshot["lambda_n"])
    if len(info["closed"]):
        got = res.reaction[info["normal_dof"]] * info["normal_sign"]
        out["lambda_n"] = relative_difference(got, lam_n[info["closed"]])
    fixed = set(int(d) for d in fixed_dofs)
    stick_rows = [
        i
        for i, p in enumerate(info["closed"])
        if p in set(info["stick"].tolist()) and int(info["tangent_dof"][i]) not in fixed
    ]
    if stick_rows:
        got = res.reaction[info["tangent_dof"][stick_rows]] * info["tangent_sign"][stick_rows]
        want = np.asarray(snapshot["lambda_t"])[info["closed"][stick_rows]]
        out["lambda_t_stick"] = float(np.abs(got - want).max() / max(lam_n.max(), 1e-300))
    if len(info["slip"]):
        mu = scene.model["pairs"]["mu"][info["slip"]]
        lt = np.abs(np.asarray(snapshot["lambda_t"])[info["slip"]])
        out["coulomb_slip"] = float(
            np.abs(lt - mu * lam_n[info["slip"]]).max() / max(lam_n.max(), 1e-300)
        )
    return out


def replay_elastic(scene, result: dict, bulk: BulkProblem | None = None, snapshots=None):
    """Replay every snapshot (or the given indices) of an elastic slipstep run.
    Returns (rows of differences, the dolfinx result of the last one)."""
    bulk = bulk or BulkProblem(scene)
    snaps = result["snapshots"]
    rows, res = [], None
    for i in range(len(snaps)) if snapshots is None else snapshots:
        s = snaps[i]
        presc, extra, info = replay_conditions(scene, s)
        res = bulk.solve_elastic(float(s["load_fraction"]), presc, extra)
        rows.append(compare(scene, s, res, info, bulk.fixed_dofs))
    return rows, res


def replay_plastic(scene, result: dict, bulk: BulkProblem | None = None, substeps: int = 1):
    """Replay the snapshots of an elastoplastic slipstep run in order (see the module doc).
    Returns (rows of differences, the dolfinx result at the last snapshot)."""
    bulk = bulk or BulkProblem(scene)
    snaps = result["snapshots"]
    schedule, infos = [], []
    for s in snaps:
        presc, extra, info = replay_conditions(scene, s)
        schedule.append((float(s["load_fraction"]), presc, extra))
        infos.append(info)
    rows = []

    def record(res):
        k = len(rows)
        rows.append(compare(scene, snaps[k], res, infos[k], bulk.fixed_dofs))

    last = bulk.solve_plastic(schedule=schedule, substeps=substeps, callback=record)
    return rows, last
