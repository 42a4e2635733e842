"""The contact of a result: per-pair pressure and tangential stress, positions along each
contact, the extents of contact and stick and how they grow along the path, and the
force-displacement curves of moving obstacles (numpy only, nothing is written here).

Contact quantities per candidate pair follow the engine's conventions (docs/engine_api.md):
pressure = lambda_n / area, tangential stress = lambda_t / area, with area = L t (L the
tributary length of node a on its edge, t the thickness), or in axisymmetry node a's ring
2 pi int N_a r ds (``scene.pair_area``, :func:`slipstep.contact.edges.contact_areas`).

Position along a contact: ``s``, the coordinate of node a along the unit vector
tau = (n_y, -n_x) of the contact's target surface (n = the normal pointing from the target
into the contactor), measured from the line's ``point`` for a ``rigid_line`` and from the
coordinate origin for a ``node_to_node`` (n = its fixed normal, else the mean of its pair
normals).  For a flat below the body (n = (0, 1)) tau = +x, so s = x - point_x.  Along a
curved or broken obstacle s is the arc length of the point's closest point on it, increasing
along tau = (n_y, -n_x) likewise (walking towards +s the body is on the left): for a
``rigid_circle`` s = R theta, theta in (-pi, pi] the angle about the centre from the circle's
point nearest the body (the closest point of the candidate with the smallest initial gap, the
first of a tie), clockwise for a body outside the circle and counter-clockwise inside it; for
a ``rigid_polyline`` the arc length from its first point, for side "left" (for "right" its
negative; beyond an end of an open polyline, the projection on the extended end segment).
:func:`contact_axis` gives the point where s = 0 and the unit tangent there.
"""

from __future__ import annotations

import numpy as np

from ..case_record import NodeToNode
from ..contact.edges import polyline_closest
from ..output.history import event_times, final_time, load_factor, snapshot_time


def weighted_rows(pairs: dict) -> np.ndarray:
    """(P,) True for the node-to-segment rows (pairs with their own node weights)."""
    if "weight_ptr" not in pairs:
        return np.zeros(len(pairs["node_a"]), dtype=bool)
    return np.diff(pairs["weight_ptr"]) > 0


def target_points(scene) -> np.ndarray:
    """(P, 2) the target point of each pair: node b, or for a rigid obstacle and a
    node-to-segment row (whose node b only names it) the foot of node a, x_a - gap n."""
    pairs = scene.model["pairs"]
    node_b = np.where(weighted_rows(pairs), -1, np.asarray(pairs["node_b"]))
    foot = scene.pair_xy - np.asarray(pairs["gap"])[:, None] * np.asarray(pairs["normal"])
    return np.where((node_b >= 0)[:, None], scene.nodes[np.maximum(node_b, 0)], foot)


def contact_axis(scene, index: int) -> tuple[np.ndarray, np.ndarray]:
    """(origin, tau) of [[contact]] ``index``: the point where s = 0 and the unit tangent there
    in the direction of increasing s (module docstring); s = (x - origin) . tau for a
    ``rigid_line`` and a ``node_to_node``."""
    c = scene.case.record.contact[index]
    if c.kind == "rigid_circle":
        centre, u = _circle_reference(scene, index)
        n = u if c.side == "outside" else -u  # the normal there, into the body
        return centre + c.radius * u, np.array([n[1], -n[0]]) + 0.0
    if c.kind == "rigid_polyline":
        p = np.asarray(c.points, dtype=float)
        sign = 1.0 if c.side == "left" else -1.0
        return p[0].copy(), sign * (p[1] - p[0]) / np.linalg.norm(p[1] - p[0]) + 0.0
    if c.kind == "rigid_line":
        n, origin = np.asarray(c.normal, dtype=float), np.asarray(c.point, dtype=float)
    else:
        mine = scene.pair_contact == index
        n = (
            np.asarray(c.normal, dtype=float)
            if isinstance(c, NodeToNode) and c.normal is not None
            else np.asarray(scene.model["pairs"]["normal"])[mine].sum(axis=0)
        )
        origin = np.zeros(2)
    length = np.linalg.norm(n)
    n = n / length if length > 0 else np.array([0.0, 1.0])  # normals that cancel (a ring): s = x
    return origin, np.array([n[1], -n[0]]) + 0.0  # + 0.0: no -0.0 in the summary


def _circle_reference(scene, index: int) -> tuple[np.ndarray, np.ndarray]:
    """(centre, u) of a ``rigid_circle`` contact: u the unit direction from the centre to the
    node of its candidate pair with the smallest initial gap (the first of a tie), where s = 0."""
    c = scene.case.record.contact[index]
    centre = np.asarray(c.centre, dtype=float)
    mine = np.flatnonzero(scene.pair_contact == index)
    k = mine[np.argmin(np.asarray(scene.model["pairs"]["gap"])[mine])]
    v = scene.pair_xy[k] - centre
    return centre, v / np.linalg.norm(v)  # never 0: a candidate at the centre is refused


def contact_coordinate(scene, index: int, xy) -> np.ndarray:
    """s of the points ``xy`` (K, 2) along [[contact]] ``index`` (module docstring)."""
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    c = scene.case.record.contact[index]
    if c.kind == "rigid_circle":
        centre, u = _circle_reference(scene, index)
        v = xy - centre
        theta = np.arctan2(u[0] * v[:, 1] - u[1] * v[:, 0], v @ u)  # counter-clockwise
        return (-1.0 if c.side == "outside" else 1.0) * c.radius * theta + 0.0
    if c.kind == "rigid_polyline":
        sign = 1.0 if c.side == "left" else -1.0
        return sign * polyline_closest(np.asarray(c.points, dtype=float), c.side, xy)["s"] + 0.0
    origin, tau = contact_axis(scene, index)
    return (xy - origin) @ tau


def pair_coordinate(scene) -> np.ndarray:
    """(P,) s of every candidate pair along its own contact (module docstring)."""
    s = np.zeros(len(scene.pair_xy))
    for i in range(len(scene.case.record.contact)):
        mine = scene.pair_contact == i
        s[mine] = contact_coordinate(scene, i, scene.pair_xy[mine])
    return s


def pair_forces(scene, snap: dict) -> np.ndarray:
    """(P, 3) each pair's force on its contactor side in global axes, λ_n n + λ_t t (t: n
    turned a quarter counter-clockwise; z = 0), from a snapshot's arrays."""
    n = np.asarray(scene.model["pairs"]["normal"], dtype=float).reshape(-1, 2)
    lam_n = np.asarray(snap["lambda_n"], dtype=float)
    tangent = np.stack([-n[:, 1], n[:, 0]], axis=1)
    f = lam_n[:, None] * n + np.asarray(snap["lambda_t"], dtype=float)[:, None] * tangent
    return np.column_stack([f, np.zeros(len(f))])


def contactor_forces(scene, lam) -> np.ndarray:
    """The contact force each pair's node a receives: its own multiplier, except for
    node-to-segment rows, whose multipliers spread over the contactor nodes by their positive
    weights (slipstep.contact.node_to_segment): node a then gets Σ_i c_ia λ_i. Over its tributary length this is
    the pressure (a node-to-node pair's definition); the rows' own λ_i/S_i, the mortar
    multiplier field, oscillates where the pressure is steep on non-matching meshes (measured
    ±10 % at a punch edge, against ±5 % for the forces)."""
    lam = np.asarray(lam, dtype=float)
    pairs = scene.model["pairs"]
    weighted = weighted_rows(pairs)
    if not weighted.any():
        return lam
    ptr, node, value = pairs["weight_ptr"], pairs["weight_node"], pairs["weight_value"]
    rows = np.repeat(np.arange(len(lam)), np.diff(ptr))
    at_node = np.zeros(len(scene.nodes))
    np.add.at(at_node, node[value > 0], value[value > 0] * lam[rows[value > 0]])
    return np.where(weighted, at_node[pairs["node_a"]], lam)


def contact_profile(scene, snapshot: dict) -> dict:
    """Per candidate pair at one snapshot, sorted by x (then y) of node a: x, y, s (position
    along its contact), contact (index), pressure, tangential stress (node a's contact force
    over its area ``scene.pair_area``, `contactor_forces`), RTD, status (0 open, 1 stick,
    2 slip), gap."""
    order = np.lexsort((scene.pair_xy[:, 1], scene.pair_xy[:, 0]))
    area = scene.pair_area
    return {
        "pair": order,
        "node_a": scene.model["pairs"]["node_a"][order],
        "x": scene.pair_xy[order, 0],
        "y": scene.pair_xy[order, 1],
        "s": pair_coordinate(scene)[order],
        "contact": scene.pair_contact[order],
        "pressure": (contactor_forces(scene, snapshot["lambda_n"]) / area)[order],
        "tangential_stress": (contactor_forces(scene, snapshot["lambda_t"]) / area)[order],
        "rtd": pointwise(scene, snapshot, "rtd")[order],
        "status": np.asarray(snapshot["status"]).astype(int)[order],
        "gap": pointwise(scene, snapshot, "gap")[order],
    }


def pointwise(scene, snapshot: dict, key: str) -> np.ndarray:
    """A pair's gap or RTD at node a: the engine's value, except for node-to-segment rows,
    whose engine values are the rows' weighted means; for them node a against its own closest
    target point (scene.pair_foot), n·(u_a − u_foot) + its initial gap, or t·(u_a − u_foot), as
    for a node-to-node pair (on the same structured mesh the weighted RTD differs from the
    node-to-node one by 4.6 % rms, the pointwise one by 0.3 %: paper_block_plastic, μ = 0.2)."""
    value = np.asarray(snapshot[key], dtype=float).copy()
    foot = getattr(scene, "pair_foot", np.zeros((0, 3)))
    rows = np.flatnonzero(foot[:, 0] >= 0) if len(foot) == len(value) else []
    if len(rows) == 0:
        return value
    u = np.asarray(snapshot["u"], dtype=float).reshape(-1, 2)
    l1, l2, eta = foot[rows, 0].astype(int), foot[rows, 1].astype(int), foot[rows, 2]
    rel = u[scene.model["pairs"]["node_a"][rows]] - (
        (1 - eta)[:, None] * u[l1] + eta[:, None] * u[l2]
    )
    n = np.asarray(scene.model["pairs"]["normal"], dtype=float)[rows]
    if key == "gap":
        value[rows] = scene.pair_point_gap[rows] + np.einsum("ij,ij->i", rel, n)
    else:
        value[rows] = rel[:, 1] * n[:, 0] - rel[:, 0] * n[:, 1]  # t = (−n_y, n_x)
    return value


def edge_crossings(scene, result) -> dict:
    """Where the edges of the closed zones moved, for :func:`crossing_times`: every ``close``
    and ``separate`` event as arrays ``pair``, ``t``, ``stage`` (0-based) and ``closes``, the
    pairs closed from the start (initial gap 0) counted as closing at t = 0 in stage 0."""
    ev = result["events"]
    kinds = np.asarray(ev["kind"], dtype=str)
    t, stage = event_times(result)
    mine = np.isin(kinds, ("close", "separate"))
    start = np.flatnonzero(np.asarray(scene.model["pairs"]["gap"]) == 0.0)
    return {
        "pair": np.concatenate([start, np.asarray(ev["entity"], dtype=np.int64)[mine]]),
        "t": np.concatenate([np.zeros(len(start)), t[mine]]),
        "stage": np.concatenate([np.zeros(len(start), dtype=np.int64), stage[mine]]),
        "closes": np.concatenate([np.ones(len(start), dtype=bool), kinds[mine] == "close"]),
    }


def crossing_times(scene, result, snapshot: dict, crossings: dict | None = None):
    """(last, upcoming) per candidate pair at ``snapshot``, within the snapshot's stage (one
    linear change of the loads; -inf / inf where the stage has no such time): ``last`` the path
    time at which the pair took its present state (a closed pair its closure, an open one its
    separation), ``upcoming`` the time at which it next leaves it (from the run's later events;
    for a pair open at the run's last snapshot also the engine's ``predicted_closure``).
    ``crossings``: :func:`edge_crossings`, computed once for many snapshots."""
    c = edge_crossings(scene, result) if crossings is None else crossings
    n = len(scene.pair_xy)
    t, stage = snapshot_time(snapshot), int(snapshot.get("stage", 0))
    closed = np.asarray(snapshot["status"]) > 0
    here = c["stage"] == stage
    keeps = c["closes"] == closed[c["pair"]]  # the event put the pair in its present state
    took, leaves = here & keeps & (c["t"] <= t), here & ~keeps & (c["t"] >= t)
    last, upcoming = np.full(n, -np.inf), np.full(n, np.inf)
    np.maximum.at(last, c["pair"][took], c["t"][took])
    np.minimum.at(upcoming, c["pair"][leaves], c["t"][leaves])
    snaps = result.get("snapshots", [])
    if snaps and snapshot is snaps[-1] and "predicted_closure" in result:
        predicted = np.asarray(result["predicted_closure"], dtype=float)
        upcoming = np.where(closed, upcoming, np.fmin(upcoming, predicted))
    return last, upcoming


def contact_half_width(s, status, last, upcoming, t) -> float:
    """The far end (largest s) of the closed zone at path time t: it lies between the outermost
    closed pair c and the next open pair o beyond it, and moves linearly in t from where it
    crossed last (c closing or o separating, whichever is later in ``last``) to where it
    crosses next (c separating or o closing, whichever is sooner in ``upcoming``; NaN, inf, a
    ``last`` after t or an ``upcoming`` before it: none), clipped there; at s_c without both
    crossings; 0 if nothing is closed.  Growing:
    s_c + (s_o - s_c)(t - t_c)/(t_o - t_c).  With s measured from the symmetry line of a half
    model this is the contact half-width a."""
    closed = status > 0
    if not closed.any():
        return 0.0
    ic = np.flatnonzero(closed)[np.argmax(s[closed])]
    beyond = np.flatnonzero(~closed & (s > s[ic]))
    if len(beyond) == 0:
        return float(s[ic])
    io = beyond[np.argmin(s[beyond])]
    last = np.where(np.asarray(last, dtype=float) <= t, last, -np.inf)  # NaN too
    upcoming = np.where(np.asarray(upcoming, dtype=float) >= t, upcoming, np.inf)
    i0 = ic if last[ic] >= last[io] else io
    i1 = ic if upcoming[ic] <= upcoming[io] else io
    t0, t1 = last[i0], upcoming[i1]
    if not (np.isfinite(t0) and np.isfinite(t1)) or t1 <= t0:
        return float(s[ic])
    w = min(max((t - t0) / (t1 - t0), 0.0), 1.0)
    return float(s[i0] + (s[i1] - s[i0]) * w)


def stick_half_width(s, status, edge) -> float:
    """The far end (largest s) of the stick zone: the midpoint between the outermost stick pair
    and the first closed (slipping) pair beyond it; ``edge`` (the closed zone's end) if every
    closed pair out there sticks; 0 if nothing sticks.  The stick half-width c of a half
    model."""
    stick = status == 1
    if not stick.any():
        return 0.0
    ss = s[stick].max()
    beyond = np.flatnonzero((status > 0) & (s > ss))
    if len(beyond) == 0:
        return float(edge)
    return float(0.5 * (ss + s[beyond].min()))


def closed_extent(s, status, last, upcoming, t) -> list[float] | None:
    """[s_min, s_max] of the closed zone at path time t, each end placed as
    :func:`contact_half_width` places the far one; None if nothing is closed."""
    if not (status > 0).any():
        return None
    return [
        -contact_half_width(-s, status, last, upcoming, t),
        contact_half_width(s, status, last, upcoming, t),
    ]


def stick_extent(s, status, closed: list[float]) -> list[float] | None:
    """[s_min, s_max] spanned by the stick pairs, each end placed as :func:`stick_half_width`
    places the far one (``closed`` = the closed extent); None if nothing sticks."""
    if not (status == 1).any():
        return None
    return [-stick_half_width(-s, status, -closed[0]), stick_half_width(s, status, closed[1])]


def reached_last_candidate(scene, snapshot) -> bool:
    """True if a contact whose candidates stop short of the end of its edge (x/y window,
    unpaired nodes) has its last candidate on that side closed: the contact may be cut short."""
    status = np.asarray(snapshot["status"])
    s_pair = pair_coordinate(scene)
    for i, c in enumerate(scene.case.record.contact):
        mine = np.flatnonzero(scene.pair_contact == i)
        edge = np.unique(scene.global_edge(*c.contactor))
        s_edge = contact_coordinate(scene, i, scene.nodes[edge])
        tol = 1e-9 * max(float(np.ptp(s_edge)), 1.0)  # round-off of the node coordinates
        for sign in (1.0, -1.0):
            last = mine[np.argmax(sign * s_pair[mine])]
            cut = (sign * s_edge > sign * s_pair[last] + tol).any()
            if cut and status[last] > 0:
                return True
    return False


def contact_growth(scene, result) -> tuple[np.ndarray, np.ndarray]:
    """Outermost closed node x after each step, replaying the close/separate events
    (initially closed pairs, gap = 0, start closed).  Returns (t, x) from t = 0 (t = the path
    time, the load fraction of a run without stages)."""
    x = scene.pair_xy[:, 0]
    closed = set(np.flatnonzero(np.asarray(scene.model["pairs"]["gap"]) == 0.0).tolist())

    def outer():
        return max((x[i] for i in closed), default=0.0)

    fs, xs = [0.0], [outer()]
    ev = result["events"]
    times, _ = event_times(result)
    steps = np.asarray(ev["step"])
    for k in range(len(steps)):
        kind, entity = ev["kind"][k], int(ev["entity"][k])
        if kind == "close":
            closed.add(entity)
        elif kind == "separate":
            closed.discard(entity)
        if k + 1 == len(steps) or steps[k + 1] != steps[k]:
            fs.append(float(times[k]))
            xs.append(outer())
    final = final_time(result)
    if final > fs[-1]:
        fs.append(final)
        xs.append(xs[-1])
    return np.asarray(fs), np.asarray(xs)


def path_history(scene, result) -> dict:
    """Per snapshot along the load path: ``t``, ``stage``, and per contact (columns in
    ``contact_names`` order) ``normal_force`` = sum lambda_n, ``tangential_force`` =
    sum lambda_t, ``n_closed`` and ``extent`` = its :func:`closed_extent` (NaN when open), as
    the summary's; ``total_normal_force`` and ``total_tangential_force`` over every contact."""
    snaps = result.get("snapshots", [])
    n_c = len(scene.model["contact_names"])
    which = np.asarray(scene.pair_contact, dtype=np.int64)
    s = pair_coordinate(scene)
    crossings = edge_crossings(scene, result)
    out = {
        "t": np.array([snapshot_time(x) for x in snaps]),
        "stage": np.array([int(x.get("stage", 0)) for x in snaps], dtype=np.int64),
        "normal_force": np.zeros((len(snaps), n_c)),
        "tangential_force": np.zeros((len(snaps), n_c)),
        "n_closed": np.zeros((len(snaps), n_c), dtype=np.int64),
        "extent": np.full((len(snaps), n_c, 2), np.nan),
    }
    for k, snap in enumerate(snaps):
        closed = np.asarray(snap["status"]) > 0
        out["normal_force"][k] = np.bincount(which, np.asarray(snap["lambda_n"]), n_c)
        out["tangential_force"][k] = np.bincount(which, np.asarray(snap["lambda_t"]), n_c)
        out["n_closed"][k] = np.bincount(which[closed], minlength=n_c)
        last, upcoming = crossing_times(scene, result, snap, crossings)
        status = np.asarray(snap["status"])
        for c in np.unique(which[closed]):
            mine = which == c
            out["extent"][k, c] = closed_extent(
                s[mine], status[mine], last[mine], upcoming[mine], out["t"][k]
            )
    out["total_normal_force"] = out["normal_force"].sum(axis=1)
    out["total_tangential_force"] = out["tangential_force"].sum(axis=1)
    return out


def force_displacement(scene, result) -> dict[str, dict]:
    """The load-path curves, from t = 0 (all zero) through every snapshot, by load name:
    for a prescribed displacement (``scene.prescribed``) the displacement d = factor(t) A
    (A = its largest nodal displacement at factor 1) against the work-conjugate support force
    sum_dofs R u1 / A (the reaction along the prescribed direction for a uniform one); for a
    motion of a rigid contact (``scene.motions``) the motion along the contact normal
    against its total normal force (along its tangent t = (-n_y, n_x) and sum lambda_t for a
    mainly tangential motion); for a ``rigid_circle`` or ``rigid_polyline`` (no single
    normal) the motion's length against the resultant contact force along it
    (:func:`_motion_curve`).  Each: ``t``, ``displacement``, ``force``, ``what``."""
    snaps = result.get("snapshots", [])
    t = np.array([0.0] + [snapshot_time(x) for x in snaps])
    out = {}
    for name, p in getattr(scene, "prescribed", {}).items():
        dofs, u1 = np.asarray(p["dofs"], dtype=np.int64), np.asarray(p["values"], dtype=float)
        per_node = np.zeros((len(scene.nodes), 2))
        per_node[dofs // 2, dofs % 2] = u1
        amp = float(np.linalg.norm(per_node, axis=1).max()) if len(dofs) else 0.0
        if amp == 0.0 or not snaps or "reaction" not in snaps[0]:
            continue
        force = [np.asarray(x["reaction"], dtype=float).reshape(-1)[dofs] @ u1 / amp for x in snaps]
        out[name] = {
            "t": t,
            "displacement": load_factor(scene, name, t) * amp,
            "force": np.array([0.0] + force),
            "what": "support reaction",
        }
    which = np.asarray(scene.pair_contact, dtype=np.int64)
    for name, m in getattr(scene, "motions", {}).items():
        c, motion = int(m["contact"]), np.asarray(m["motion"], dtype=float)
        if scene.case.record.contact[c].kind in ("rigid_circle", "rigid_polyline"):
            curve = _motion_curve(scene, result, c, motion, load_factor(scene, name, t))
            if curve is not None:
                out[name] = {"t": t, **curve}
            continue
        _, tau = contact_axis(scene, c)
        n, tangent = np.array([-tau[1], tau[0]]), -tau
        key, axis = (
            ("lambda_n", n) if abs(motion @ n) >= abs(motion @ tangent) else ("lambda_t", tangent)
        )
        force = [float(np.asarray(x[key])[which == c].sum()) for x in snaps]
        out[name] = {
            "t": t,
            "displacement": load_factor(scene, name, t) * float(motion @ axis),
            "force": np.array([0.0] + force),
            "what": "normal force" if key == "lambda_n" else "tangential force",
        }
    return out


def _motion_curve(scene, result, index: int, motion: np.ndarray, factor) -> dict | None:
    """A curved or broken obstacle's motion (no single normal): the motion's length
    factor(t) |m| against the resultant of its contact forces on the body along the motion,
    sum (lambda_n n + lambda_t t) . m/|m| (t = (-n_y, n_x)), the force that pushes the obstacle
    along its path; None for a zero motion."""
    amp = float(np.linalg.norm(motion))
    if amp == 0.0:
        return None
    mine = np.asarray(scene.pair_contact, dtype=np.int64) == index
    n = np.asarray(scene.model["pairs"]["normal"], dtype=float)[mine]
    along_n, along_t = n @ motion / amp, np.stack([-n[:, 1], n[:, 0]], axis=1) @ motion / amp
    force = [
        float(np.asarray(x["lambda_n"])[mine] @ along_n + np.asarray(x["lambda_t"])[mine] @ along_t)
        for x in result.get("snapshots", [])
    ]
    return {
        "displacement": np.asarray(factor) * amp,
        "force": np.array([0.0] + force),
        "what": "contact force along the motion",
    }
