"""The contact of a 3D result (docs/engine_api.md, "3D models"): per pair the force on node a
in x, y, z, its pressure, tangential stress (in the pair's (t1, t2) and in x, y, z), slip and
slip direction; per contact its area, equivalent radii and resultants, for the FULL contact when
the model is a symmetric part of it; the pressure along a line through the contact (numpy only,
nothing written here).  The 3D counterpart of :mod:`slipstep.measures.contact_edges`.

A contact's area is where its contact forces act, by the kind of its rows (:func:`zone_area`):
- rows at nodes (``rigid_plane``, ``rigid_surface``, ``node_to_node``: each pair's gap and slip
  are node a's own, its force acts at node a): the consistent tributary areas of its closed
  pairs' contactor nodes (``scene.pair_area``: int N_a dA), whose sum puts the zone's edge
  midway between the last closed node and the first open one;
- mortar rows (``node_to_surface``: row j's gap and slip are means over its node's support,
  weighted by N_j; its force spreads over the contactor as the traction (lambda_j / S_j) N_j):
  the contactor triangles with a closed row at a corner, the support of that traction field.
  A closed row holds its weighted gap at zero over its whole support, so the contact covers
  the supports of the closed rows: the last closed row lies about half a spacing inside the
  edge, and a tributary sum would put the edge there (the sphere of mindlin_sphere_3d.toml
  pressed onto its block without friction: -0.42 to -0.52 spacings off Hertz's a from a/h = 5
  to 10, this measure -0.06 to +0.05; bench/mindlin_convergence_3d.md);
its stick area likewise with the sticking pairs, and ``contact_radius`` = sqrt(area / pi),
``stick_radius`` likewise.
A symmetric part: every body a contact touches is cut by the same symmetry planes ([[bc]]
``symmetry`` faces) through its candidates, all on one side of each (:func:`mirror_planes`);
its full contact is 2^k times the part's, resultants mirrored (the components along the k plane
normals cancel, the others add).
"""

from __future__ import annotations

import math

import numpy as np

from .contact_edges import contactor_forces
from ..mesh.tetrahedra import triangle_normals


def row_forces(scene, snapshot: dict) -> tuple[np.ndarray, np.ndarray]:
    """(normal (P, 3), tangential (P, 3)): each pair's contact force on node a in x, y, z,
    lambda_n n and lambda_t1 t1 + lambda_t2 t2."""
    pairs = scene.model["pairs"]
    n, t = np.asarray(pairs["normal"], dtype=float), scene.pair_tangent
    lam_n = np.asarray(snapshot["lambda_n"], dtype=float)
    lam_t = np.asarray(snapshot["lambda_t"], dtype=float).reshape(-1, 2)
    return lam_n[:, None] * n, lam_t[:, :1] * t[:, 0] + lam_t[:, 1:] * t[:, 1]


def pair_forces(scene, snap: dict) -> np.ndarray:
    """(P, 3) each pair's force on its contactor side in global axes, λ_n n + λ_t1 t1 + λ_t2 t2,
    from a snapshot's arrays."""
    n = np.asarray(scene.model["pairs"]["normal"], dtype=float)
    lam_n = np.asarray(snap["lambda_n"], dtype=float)
    lam_t = np.asarray(snap["lambda_t"], dtype=float).reshape(-1, 2)
    t = scene.pair_tangent
    return lam_n[:, None] * n + lam_t[:, :1] * t[:, 0] + lam_t[:, 1:] * t[:, 1]


def node_forces(scene, snapshot: dict) -> np.ndarray:
    """(P, 3) the contact force node a receives: its pair's own, except for node-to-surface rows
    whose forces spread over the contactor nodes by their positive weights
    (:func:`slipstep.measures.contact_edges.contactor_forces`, component by component)."""
    normal, tangential = row_forces(scene, snapshot)
    total = normal + tangential
    return np.stack([contactor_forces(scene, total[:, c]) for c in range(3)], axis=1)


def pointwise(scene, snapshot: dict, key: str) -> np.ndarray:
    """A pair's gap (P,) or slip, the RTD (P, 2) in (t1, t2), at node a: the engine's value,
    except for node-to-surface rows (weighted means there), measured from node a's own closest
    target point (``scene.pair_foot``: triangle nodes, barycentric coordinates)."""
    width = 1 if key == "gap" else 2  # (a scene without candidate pairs has none to reshape)
    value = np.array(snapshot[key], dtype=float).reshape(len(scene.pair_xy), width)
    foot = scene.pair_foot
    rows = np.flatnonzero(foot[:, 0] >= 0) if len(foot) == len(value) else []
    if len(rows):
        u = np.asarray(snapshot["u"], dtype=float).reshape(-1, 3)
        corners, bary = foot[rows, :3].astype(np.int64), foot[rows, 3:]
        rel = u[scene.model["pairs"]["node_a"][rows]] - np.einsum("pk,pkd->pd", bary, u[corners])
        if key == "gap":
            n = np.asarray(scene.model["pairs"]["normal"], dtype=float)[rows]
            value[rows, 0] = scene.pair_point_gap[rows] + np.einsum("pd,pd->p", rel, n)
        else:
            value[rows] = np.einsum("pd,ptd->pt", rel, scene.pair_tangent[rows])
    return value[:, 0] if key == "gap" else value


def contact_profile_3d(scene, snapshot: dict) -> dict:
    """Per candidate pair at one snapshot, sorted by x, then y, then z of node a: position,
    contact (index), pressure and the tangential stress (its (t1, t2) components ``tau`` and
    the vector ``tangential_stress`` in x, y, z), the slip (RTD in (t1, t2), and in x, y, z),
    ``slip_direction`` (a slipping pair's: opposite to its friction force, the direction of its
    slip rate; 0 for open and sticking pairs), status (0 open, 1 stick, 2 slip) and gap."""
    x = scene.pair_xy
    order = np.lexsort((x[:, 2], x[:, 1], x[:, 0]))
    n, t, area = np.asarray(scene.model["pairs"]["normal"]), scene.pair_tangent, scene.pair_area
    force = node_forces(scene, snapshot)
    normal = np.einsum("pd,pd->p", force, n)
    tangential = (force - normal[:, None] * n) / area[:, None]
    status = np.asarray(snapshot["status"]).astype(int)
    size = np.linalg.norm(tangential, axis=1)
    slipping = (status == 2) & (size > 0)
    direction = np.zeros_like(tangential)
    direction[slipping] = -tangential[slipping] / size[slipping, None]
    rtd = pointwise(scene, snapshot, "rtd")
    out = {
        "pair": order,
        "node_a": scene.model["pairs"]["node_a"],
        "x": x,
        "contact": scene.pair_contact,
        "pressure": normal / area,
        "tau": np.einsum("pd,ptd->pt", tangential, t),
        "tangential_stress": tangential,
        "slip": rtd,
        "slip_xyz": np.einsum("pt,ptd->pd", rtd, t),
        "slip_direction": direction,
        "status": status,
        "gap": pointwise(scene, snapshot, "gap"),
    }
    return {k: (v if k == "pair" else np.asarray(v)[order]) for k, v in out.items()}


def mirror_planes(scene, index: int) -> list[tuple[int, float]]:
    """The symmetry planes (axis, value) the model of [[contact]] ``index`` is cut by: a plane
    x_axis = value that is a ``symmetry`` face of every body the contact touches, with the
    contact's candidates all on one side of it and some on it."""
    mine = scene.pair_xy[scene.pair_contact == index]
    return mirror_planes_of(scene, scene.case.record.contact[index].bodies, mine)


def mirror_planes_of(scene, bodies, points: np.ndarray) -> list[tuple[int, float]]:
    """The symmetry planes (axis, value) that cut every one of ``bodies`` (a [[bc]]
    ``symmetry`` face of each) with ``points`` all on one side of the plane and some on it: the
    planes across which the model's part of a contact, a load or a support is mirrored into the
    whole."""
    mine = np.asarray(points, dtype=float).reshape(-1, 3)
    tol = 1e-9 * float(np.ptp(scene.nodes, axis=0).max())
    per_body = []
    for body in bodies:
        planes = set()
        for bc in scene.case.record.bc:
            if not (bc.symmetry and bc.body == body):
                continue
            face = scene.nodes[np.unique(scene.global_boundary(body, bc.face))]
            axis = int(np.argmin(np.ptp(face, axis=0)))
            side = mine[:, axis] - face[0, axis]
            if ((side >= -tol).all() or (side <= tol).all()) and (np.abs(side) <= tol).any():
                # on the tolerance's grid: a plane of two bodies is one plane though a mesh
                # file puts its nodes at 1e-16 and the other's at 0
                planes.add((axis, float(np.round(face[0, axis] / tol) * tol)))
        per_body.append(planes)
    return sorted(set.intersection(*per_body)) if per_body and len(mine) else []


def contact_frame(scene, index: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(n, e1, e2) of [[contact]] ``index``: the mean pair normal of its FULL contact (the
    components across its mirror planes cancel, as the resultants' do), and in-plane axes e1
    (x projected onto the contact plane; y when the normal is near x) and e2 = n x e1, the view
    along the normal."""
    n = np.asarray(scene.model["pairs"]["normal"])[scene.pair_contact == index].sum(axis=0)
    for axis, _ in mirror_planes(scene, index):
        n[axis] = 0.0
    n = n / (np.linalg.norm(n) or 1.0)
    axis = np.eye(3)[1 if abs(n[0]) > 0.9 else 0]
    e1 = axis - (axis @ n) * n
    e1 /= np.linalg.norm(e1)
    return n, e1, np.cross(n, e1)


def contact_numbers_3d(scene, snapshot: dict, index: int) -> dict:
    """The numbers of [[contact]] ``index`` at a snapshot, for its full contact (module doc):
    pair counts, contact and stick areas and equivalent radii, the total normal force (sum
    lambda_n: the pairs' normal forces each along its own normal, not a resultant), the
    resultant ``force`` on the contactor body in x, y, z (sum lambda_n n + lambda_t t; the
    model's part of it ``force_model``), the tangential resultant (vector and size), the peak
    pressure."""
    mine = scene.pair_contact == index
    planes = mirror_planes(scene, index)
    factor = 2.0 ** len(planes)
    status = np.asarray(snapshot["status"])[mine]
    closed = factor * zone_area(scene, index, status > 0)
    stick = factor * zone_area(scene, index, status == 1)
    normal, tangential = row_forces(scene, snapshot)
    resultant = factor * tangential[mine].sum(axis=0)
    part = (normal + tangential)[mine].sum(axis=0)
    force = factor * part
    for axis, _ in planes:
        resultant[axis] = 0.0  # mirrored: along the plane's normal the halves cancel
        force[axis] = 0.0
    profile = contact_profile_3d(scene, snapshot)
    peak = profile["pressure"][profile["contact"] == index]
    return {
        "n_pairs": int(mine.sum()),
        "n_closed": int((status > 0).sum()),
        "n_stick": int((status == 1).sum()),
        "n_slip": int((status == 2).sum()),
        "symmetry_planes": [f"{'xyz'[a]} = {v:g}" for a, v in planes],
        "contact_area": closed,
        "contact_radius": math.sqrt(closed / math.pi),
        "stick_area": stick,
        "stick_radius": math.sqrt(stick / math.pi),
        "total_normal_force": factor * float(np.asarray(snapshot["lambda_n"])[mine].sum()),
        "force": force.tolist(),
        "force_model": part.tolist(),
        "tangential_force": resultant.tolist(),
        "total_tangential_force": float(np.linalg.norm(resultant)),
        "peak_pressure": recovered_peak(scene, profile, index, math.sqrt(closed / math.pi)),
        "max_nodal_pressure": float(peak.max()) if len(peak) else 0.0,
    }


def zone_area(scene, index: int, chosen: np.ndarray) -> float:
    """The area of the modelled part of [[contact]] ``index`` on which its ``chosen`` pairs
    (a mask over its pairs: the closed, the sticking ones) act (module doc): for mortar rows
    (``node_to_surface``) the area of the contactor face's triangles with a chosen row's node
    at a corner, else the sum of the chosen pairs' tributary areas ``scene.pair_area``."""
    mine = np.flatnonzero(scene.pair_contact == index)
    contact = scene.case.record.contact[index]
    if contact.kind != "node_to_surface":
        return float(scene.pair_area[mine][chosen].sum())
    face = scene.global_boundary(*contact.contactor)
    on = np.zeros(len(scene.nodes), dtype=bool)
    on[scene.model["pairs"]["node_a"][mine][chosen]] = True
    _, area = triangle_normals(scene.nodes, face)
    return float(area[on[face].any(axis=1)].sum())


#: The fit window of :func:`recovered_peak`: PEAK_SPACINGS node spacings around the largest
#: nodal pressure (a spacing: the median distance from that node to its six nearest), at most
#: PEAK_RADIUS_FRACTION of the contact's equivalent radius.  4 spacings hold some 50 nodes of
#: the full contact, so one node's error counts ~1/7 as much as in the raw maximum; within half
#: the radius a smooth peak p0 sqrt(1 - r^2/a^2) is quadratic to 1 % (its r^4 term).
PEAK_SPACINGS, PEAK_RADIUS_FRACTION = 4.0, 0.5


def recovered_peak(scene, profile: dict, index: int, radius: float) -> float:
    """The peak pressure of [[contact]] ``index`` recovered from its nodal pressures: the maximum
    of the quadratic least-squares fit p0 + g.x + x.Hx/2 (in the contact plane) to the closed
    nodes of the FULL contact (mirrored across its mirror planes) in the window above around
    the largest nodal pressure (``radius``: the contact's equivalent radius).  On unstructured
    tetrahedra the nodal pressures scatter by a few per cent from node to node, and their
    maximum is one node's; the fit averages that scatter out.  The largest nodal pressure when
    the fit does not describe a peak: fewer than 12 nodes in the window (a contact a few
    elements wide), a Hessian not negative definite, or a vertex outside the window (an edge,
    a singular rim)."""
    mine = (profile["contact"] == index) & (profile["status"] > 0)
    if mine.sum() == 0:
        return 0.0
    _, e1, e2 = contact_frame(scene, index)
    x, p = mirrored_points(scene, index, profile["x"][mine], profile["pressure"][mine])
    top = int(np.argmax(p))
    if len(p) < 12:  # no window of 12 nodes (one closed node has no spacing either)
        return float(p[top])
    plane = (x - x[top]) @ np.stack([e1, e2]).T
    distance = np.linalg.norm(plane, axis=1)
    spacing = float(np.median(np.sort(distance)[1:7]))
    window = min(PEAK_SPACINGS * spacing, PEAK_RADIUS_FRACTION * radius)
    near = distance <= window
    if near.sum() < 12:
        return float(p[top])
    u, v = plane[near].T
    basis = np.column_stack([np.ones_like(u), u, v, u * u, u * v, v * v])
    c = np.linalg.lstsq(basis, p[near], rcond=None)[0]
    hessian = np.array([[2 * c[3], c[4]], [c[4], 2 * c[5]]])
    if np.linalg.eigvalsh(hessian).max() >= 0:
        return float(p[top])
    vertex = -np.linalg.solve(hessian, c[1:3])
    if np.linalg.norm(vertex) > window:
        return float(p[top])
    return float(c[0] + 0.5 * c[1:3] @ vertex)


def mirrored_points(scene, index: int, x: np.ndarray, values: np.ndarray):
    """Points of [[contact]] ``index`` and their values with their images across each of its
    mirror planes (a point on a plane once)."""
    for axis, plane in mirror_planes(scene, index):
        off = np.abs(x[:, axis] - plane) > 1e-12 * (1.0 + abs(plane))
        image = x[off].copy()
        image[:, axis] = 2 * plane - image[:, axis]
        x, values = np.vstack([x, image]), np.concatenate([values, values[off]])
    return x, values


def pressure_centre(scene, prof: dict, index: int) -> np.ndarray:
    """The centre of pressure of [[contact]] ``index``'s FULL contact: the pressure-weighted
    mean of its nodes, on every mirror plane of the model (the mirrored halves balance there);
    the peak-pressure node when nothing is closed."""
    mine = prof["contact"] == index
    x, p = prof["x"][mine], prof["pressure"][mine]
    centre = (p @ x) / p.sum() if p.sum() > 0 else x[np.argmax(p)].astype(float)
    for axis, value in mirror_planes(scene, index):
        centre[axis] = value
    return centre


def pressure_line(scene, snapshot: dict, index: int, samples: int = 201) -> dict:
    """The pressure of [[contact]] ``index`` along the line through its centre of pressure
    (:func:`pressure_centre`) in the direction e1 of :func:`contact_frame`: the nodal pressures
    interpolated linearly on the contactor face's triangles seen along the normal.  ``s``
    (distance along the line from that centre, so Hertz's p0 sqrt(1 - s^2/a^2) compares
    directly), ``pressure`` (NaN off the face), ``origin``, ``direction``."""
    prof = contact_profile_3d(scene, snapshot)
    mine = prof["contact"] == index
    nodal = np.zeros(len(scene.nodes))
    nodal[prof["node_a"][mine]] = prof["pressure"][mine]
    origin = pressure_centre(scene, prof, index)
    n, e1, e2 = contact_frame(scene, index)
    face = scene.global_boundary(*scene.case.record.contact[index].contactor)
    face = face[np.isin(face, prof["node_a"][mine]).any(axis=1)]
    plane = (scene.nodes - origin) @ np.stack([e1, e2]).T
    along = plane[np.unique(face), 0]
    s = np.linspace(along.min(), along.max(), samples)
    value = np.full(samples, np.nan)
    corners = plane[face]
    for k, point in enumerate(np.column_stack([s, np.zeros(samples)])):
        a, b, c = corners[:, 0], corners[:, 1], corners[:, 2]
        det = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1])
        with np.errstate(divide="ignore", invalid="ignore"):
            v = (
                (point[0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                - (c[:, 0] - a[:, 0]) * (point[1] - a[:, 1])
            ) / det
            w = (
                (b[:, 0] - a[:, 0]) * (point[1] - a[:, 1])
                - (point[0] - a[:, 0]) * (b[:, 1] - a[:, 1])
            ) / det
        inside = np.flatnonzero((v >= -1e-12) & (w >= -1e-12) & (v + w <= 1 + 1e-12))
        if len(inside):
            t = inside[0]
            value[k] = nodal[face[t]] @ [1 - v[t] - w[t], v[t], w[t]]
    return {"s": s, "pressure": value, "origin": origin, "direction": e1}


def reached_window_edge(scene, snapshot: dict) -> bool:
    """True when a contact whose candidates stop short of its face (a window) has a closed pair
    on their border, a candidate sharing a face triangle with a node that is none: the contact
    may extend beyond the candidates."""
    status, node_a = np.asarray(snapshot["status"]), scene.model["pairs"]["node_a"]
    for i, c in enumerate(scene.case.record.contact):
        mine = np.flatnonzero(scene.pair_contact == i)
        face = scene.global_boundary(*c.contactor)
        inside = np.isin(face, node_a[mine])
        border = face[inside.any(axis=1) & ~inside.all(axis=1)][
            inside[inside.any(axis=1) & ~inside.all(axis=1)]
        ]
        if (status[mine[np.isin(node_a[mine], border)]] > 0).any():
            return True
    return False
