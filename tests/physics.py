"""Independent physics checks on result arrays (not the engine's own residuals).  Nothing here
calls the engine or slipstep.

Equilibrium
    ``equilibrium_residual(model, snapshot)`` recomputes equilibrium of a snapshot from its
    arrays alone: the internal force Σ_e t A_e B_eᵀ σ_e of the constant-strain triangles (B from
    the nodes), minus the applied load at the snapshot's load fraction, minus the contact forces
    λ_n n + λ_t t on node a (and the opposite on node b; t = (−n_y, n_x), docs/engine_api.md and
    the module doc of rust/src/contact.rs: gap = gap0 + w_nᵀu, force on the bodies
    w_n λ_n + w_t λ_t), over the DOFs that are not supported.  In plane strain and in plane
    stress alike σz does no work on in-plane virtual strains, so the internal force is built
    from (σx, σy, τxy) = stress columns 0, 1, 3 and the thickness.  In axisymmetry (x = r,
    y = z; ``model["plane"] == "axisymmetric"``) it is the ring's virtual work
    2π ∫ (σr δεr + σz δεz + σθ δεθ + τrz δγrz) r dA with the hoop strain δεθ = δu_r/r taken at
    the centroid (the documented element, rust/src/element.rs), and the supports include u_r = 0
    at every node on the axis r = 0 (the engine's contract).

In space (``model["dimension"] == 3``) the internal force is that of linear tetrahedra,
    Σ_e V_e B_eᵀ σ_e with the six Voigt stress columns (xx, yy, zz, yz, xz, xy) and the shape
    functions' gradients from the nodes (``tet_internal_force``), and the contact force
    λ_n n + λ_t1 t1 + λ_t2 t2 with each pair's tangent basis (``pairs["tangent"]``, or the
    contract's default basis: t1 = e × n / |e × n|, e the axis least aligned with n, t2 = n × t1).

Balance
    ``balance_terms(model, snapshot)``: each body's resultant contact force, applied load and
    support reaction (the snapshot's ``reaction``), which must sum to zero;
    ``obstacle_force`` a contact's total force on the bodies; ``recomputed_reaction`` the
    supports' forces from the stresses (internal − load − contact at the held DOFs).

Friction in space
    ``friction_in_space(model, snapshots, slip_turn, floors, events)``: what the 3D friction
    design implies (rust/src/coulomb.rs: a pair stuck on the round cone until it first slips,
    then on the polygon laid at that onset, slipping on a side e of it with no slip across e, or
    at a vertex), pair by pair over consecutive snapshots taken at every event: the cone (round,
    or the polygon, for stuck pairs, the facet for slipping ones), the work slipping pairs do,
    and the angle by which a slipping pair's force lags its slip.

Refinement
    ``observed_order`` of an error between two meshes, ``richardson`` extrapolation to h -> 0.

Energy
    ``strain_energy`` of constant-stress triangles.

The closed-form references the checks compare with (Hertz, Johnson, Huber, Lamé, Hill,
Cattaneo–Mindlin, Mindlin–Deresiewicz, Spence, Kogut–Etsion, Jackson–Green) are the package's
own, in one module with their sources: :mod:`slipstep.measures.references`.
"""

from __future__ import annotations

import math

import numpy as np

# Relative equilibrium residual accepted on every snapshot: the engine's documented
# equilibrium_tol default (docs/engine_api.md), i.e. its contract.  What the recomputation
# itself adds is round-off of summing element forces of size |σ| h t into nodal sums, ~1e-16 of
# them relative to the load (far below); a state off equilibrium by an unbalanced force of
# relative size 1e-9 or more is not a round-off effect.
EQUILIBRIUM_TOL = 1e-9


# --------------------------------------------------------------------------- equilibrium
def internal_force(
    nodes: np.ndarray,
    triangles: np.ndarray,
    stress: np.ndarray,
    thickness: float,
    plane: str = "strain",
) -> np.ndarray:
    """Σ_e t A_e B_eᵀ (σx, σy, τxy)_e over all DOFs (2 per node), for triangles of either
    orientation; the ring's forces for ``plane == "axisymmetric"`` (``ring_internal_force``)."""
    if plane == "axisymmetric":
        return ring_internal_force(nodes, triangles, stress)
    nodes, triangles = np.asarray(nodes, dtype=float), np.asarray(triangles)
    stress = np.asarray(stress, dtype=float).reshape(-1, 4)
    x, y = nodes[triangles, 0], nodes[triangles, 1]  # (M, 3)
    area2 = (x[:, 1] - x[:, 0]) * (y[:, 2] - y[:, 0]) - (x[:, 2] - x[:, 0]) * (y[:, 1] - y[:, 0])
    b = np.stack([y[:, 1] - y[:, 2], y[:, 2] - y[:, 0], y[:, 0] - y[:, 1]], axis=1)  # area2 ∂N/∂x
    c = np.stack([x[:, 2] - x[:, 1], x[:, 0] - x[:, 2], x[:, 1] - x[:, 0]], axis=1)  # area2 ∂N/∂y
    sx, sy, txy = stress[:, 0:1], stress[:, 1:2], stress[:, 3:4]
    # t A Bᵀσ with A = |area2|/2 and ∂N/∂x = b/area2: sign(area2) t/2 (b σx + c τxy, c σy + b τxy)
    half_t = 0.5 * thickness * np.sign(area2)[:, None]
    fx = half_t * (b * sx + c * txy)
    fy = half_t * (c * sy + b * txy)
    n = 2 * len(nodes)
    return np.bincount((2 * triangles).ravel(), weights=fx.ravel(), minlength=n) + np.bincount(
        (2 * triangles + 1).ravel(), weights=fy.ravel(), minlength=n
    )


def tet_internal_force(nodes: np.ndarray, tets: np.ndarray, stress: np.ndarray) -> np.ndarray:
    """Σ_e V_e B_eᵀ σ_e over all DOFs (3 per node) of linear tetrahedra: node k of element e
    gets V_e σ_e ∇N_k (σ the symmetric tensor of the six Voigt columns xx, yy, zz, yz, xz, xy),
    ∇N_k from the inverse of J = [x1 − x0, x2 − x0, x3 − x0] (rows k = 1..3 of J⁻¹, ∇N_0 minus
    their sum), V_e = |det J|/6."""
    nodes, tets = np.asarray(nodes, dtype=float), np.asarray(tets)
    s = np.asarray(stress, dtype=float).reshape(-1, 6)
    x = nodes[tets]  # (M, 4, 3)
    jac = np.transpose(x[:, 1:, :] - x[:, :1, :], (0, 2, 1))  # columns x_k − x_0
    inv = np.linalg.inv(jac)  # rows: ∇N_1..3
    grad = np.concatenate([-inv.sum(axis=1, keepdims=True), inv], axis=1)  # (M, 4, 3)
    volume = np.abs(np.linalg.det(jac)) / 6.0
    tensor = s[:, [[0, 5, 4], [5, 1, 3], [4, 3, 2]]]  # (M, 3, 3)
    f_nodes = volume[:, None, None] * np.einsum("mij,mkj->mki", tensor, grad)  # (M, 4, 3)
    f = np.zeros(3 * len(nodes))
    for c in range(3):
        np.add.at(f, 3 * tets + c, f_nodes[:, :, c])
    return f


def tangent_basis(normal: np.ndarray, tangent=None) -> tuple[np.ndarray, np.ndarray]:
    """(t1, t2) of every pair in space: the given ``tangent`` (P, 2, 3), or the contract's
    default: t1 = e × n / |e × n| with e the coordinate axis least aligned with n, t2 = n × t1."""
    if tangent is not None:
        tangent = np.asarray(tangent, dtype=float)
        return tangent[:, 0, :], tangent[:, 1, :]
    e = np.eye(3)[np.argmin(np.abs(normal), axis=1)]
    t1 = np.cross(e, normal)
    t1 /= np.linalg.norm(t1, axis=1)[:, None]
    return t1, np.cross(normal, t1)


def model_internal_force(model: dict, stress: np.ndarray) -> np.ndarray:
    """The internal force of a snapshot's stresses for a model of either dimension."""
    if model.get("dimension", 2) == 3:
        return tet_internal_force(model["nodes"], model["tetrahedra"], stress)
    return internal_force(
        np.asarray(model["nodes"], dtype=float),
        np.asarray(model["triangles"]),
        np.asarray(stress),
        model["thickness"],
        model.get("plane", "strain"),
    )


def ring_internal_force(nodes: np.ndarray, triangles: np.ndarray, stress: np.ndarray) -> np.ndarray:
    """Axisymmetric internal forces, totals over the ring: per element 2π r̄ A (∂N_k/∂r σr +
    ∂N_k/∂z τrz + σθ/(3 r̄)) on u_r of node k and 2π r̄ A (∂N_k/∂z σz + ∂N_k/∂r τrz) on u_z
    (r̄ the centroid radius, N_k = 1/3 there; stress columns σr, σz, σθ, τrz)."""
    nodes, triangles = np.asarray(nodes, dtype=float), np.asarray(triangles)
    s = np.asarray(stress, dtype=float).reshape(-1, 4)
    r, z = nodes[triangles, 0], nodes[triangles, 1]  # (M, 3)
    area2 = (r[:, 1] - r[:, 0]) * (z[:, 2] - z[:, 0]) - (r[:, 2] - r[:, 0]) * (z[:, 1] - z[:, 0])
    dn_dr = np.stack([z[:, 1] - z[:, 2], z[:, 2] - z[:, 0], z[:, 0] - z[:, 1]], 1) / area2[:, None]
    dn_dz = np.stack([r[:, 2] - r[:, 1], r[:, 0] - r[:, 2], r[:, 1] - r[:, 0]], 1) / area2[:, None]
    r_bar = r.mean(axis=1)
    volume = (2.0 * math.pi * r_bar * 0.5 * np.abs(area2))[:, None]
    sr, sz, st, trz = (s[:, k : k + 1] for k in range(4))
    fr = volume * (dn_dr * sr + dn_dz * trz + st / (3.0 * r_bar[:, None]))
    fz = volume * (dn_dz * sz + dn_dr * trz)
    n = 2 * len(nodes)
    return np.bincount((2 * triangles).ravel(), weights=fr.ravel(), minlength=n) + np.bincount(
        (2 * triangles + 1).ravel(), weights=fz.ravel(), minlength=n
    )


def contact_force(
    n_nodes: int, pairs: dict, lambda_n: np.ndarray, lambda_t: np.ndarray
) -> np.ndarray:
    """The contact forces on the bodies over all DOFs: λ_n n + λ_t t on node a, the opposite on
    node b (none for node_b = −1, a rigid target); t = (−n_y, n_x). A node-to-segment row
    (``weight_ptr`` etc.) puts c_i (λ_n n + λ_t t) on each of its nodes i instead."""
    lambda_n, lambda_t = np.asarray(lambda_n, dtype=float), np.asarray(lambda_t, dtype=float)
    a, b = np.asarray(pairs["node_a"]), np.asarray(pairs["node_b"])
    normal = np.asarray(pairs["normal"], dtype=float)
    dim = normal.shape[1] if normal.ndim == 2 else 2  # (P, 2) or (P, 3), also with P = 0
    normal = normal.reshape(-1, dim)
    if dim == 3:  # λ_t (P, 2) in each pair's (t1, t2)
        t1, t2 = tangent_basis(normal, pairs.get("tangent"))
        lt = lambda_t.reshape(-1, 2)
        force = lambda_n[:, None] * normal + lt[:, :1] * t1 + lt[:, 1:] * t2
    else:
        tangent = np.stack([-normal[:, 1], normal[:, 0]], axis=1)
        force = lambda_n[:, None] * normal + lambda_t[:, None] * tangent
    f = np.zeros(dim * n_nodes)
    ptr = np.asarray(pairs.get("weight_ptr", np.zeros(len(a) + 1, dtype=np.int64)))
    weighted = np.diff(ptr) > 0  # node-to-segment rows: Σ_i c_i force at node i
    for comp in range(dim):
        plain = ~weighted
        np.add.at(f, dim * a[plain] + comp, force[plain, comp])
        np.add.at(f, dim * b[plain & (b >= 0)] + comp, -force[plain & (b >= 0), comp])
        if weighted.any():
            rows = np.repeat(np.arange(len(a)), np.diff(ptr))
            np.add.at(
                f,
                dim * np.asarray(pairs["weight_node"]) + comp,
                np.asarray(pairs["weight_value"]) * force[rows, comp],
            )
    return f


def path_factors(model: dict, t: float) -> np.ndarray:
    """The factor of every load pattern (``load`` first, then ``model["patterns"]``) at path
    time t: linear from 0 at t = 0 through each stage's factors at t = 1, 2, … (one stage
    with every factor 1 when the model has no ``stages``; docs/engine_api.md)."""
    n = 1 + len(model.get("patterns", []))
    ends = [np.asarray(s["factors"], dtype=float) for s in model.get("stages", [])] or [np.ones(n)]
    table = np.vstack([np.zeros(n), *ends])
    k = min(int(math.floor(t)), len(ends) - 1)
    return table[k] + (t - k) * (table[k + 1] - table[k])


def applied_load(model: dict, t: float) -> np.ndarray:
    """Σ factor_j(t) P_j over the patterns' forces (the applied load at path time t)."""
    f = path_factors(model, t)
    load = f[0] * np.asarray(model["load"], dtype=float)
    for fj, pat in zip(f[1:], model.get("patterns", [])):
        if "force" in pat:
            load = load + fj * np.asarray(pat["force"], dtype=float)
    return load


def held_dofs(model: dict) -> np.ndarray:
    """Supported DOFs: fixed ones, those with a prescribed displacement, and in axisymmetry u_r
    of the nodes on the axis r = 0 (within 1e-9 of the mesh's bounding-box diagonal)."""
    held = [np.asarray(model["fixed_dofs"], dtype=np.int64)]
    held += [
        np.asarray(p["displacement_dofs"], dtype=np.int64)
        for p in model.get("patterns", [])
        if "displacement_dofs" in p
    ]
    if model.get("plane") == "axisymmetric":
        nodes = np.asarray(model["nodes"], dtype=float)
        size = float(np.linalg.norm(np.ptp(nodes, axis=0)))
        held.append(2 * np.flatnonzero(np.abs(nodes[:, 0]) <= 1e-9 * size))
    return np.concatenate(held)


def equilibrium_residual(model: dict, snapshot: dict) -> float:
    """|internal − load − contact| over the unsupported DOFs, relative to the largest |load|
    there along the path (absolute for a scene without load); the load is the path's at the
    snapshot's time t (its load fraction for a run without stages).  With prescribed
    displacements or obstacle motions (``patterns``) the scale is at least |internal force| at
    the supported DOFs (the reactions, recomputed), so a displacement-driven run is measured
    relative to the forces it carries."""
    nodes = np.asarray(model["nodes"], dtype=float)
    t = float(snapshot.get("t", snapshot["load_fraction"]))
    internal = model_internal_force(model, snapshot["stress"])
    r = (
        internal
        - applied_load(model, t)
        - contact_force(
            len(nodes),
            model["pairs"],
            np.asarray(snapshot["lambda_n"]),
            np.asarray(snapshot["lambda_t"]),
        )
    )
    free = np.ones(len(r), bool)
    free[held_dofs(model)] = False
    n_stages = max(1, len(model.get("stages", [])))
    scale = max(np.linalg.norm(applied_load(model, k)[free]) for k in range(1, n_stages + 1))
    if "patterns" in model:  # displacement control: the supports' forces set the scale too
        scale = max(scale, float(np.linalg.norm(internal[~free])))
    return float(np.linalg.norm(r[free]) / (scale if scale > 0 else 1.0))


def worst_equilibrium(model: dict, snapshots) -> tuple[float, int, float]:
    """(largest recomputed residual, index of its snapshot, that snapshot's load fraction) over
    a sequence of snapshots, for assertion messages."""
    residuals = [equilibrium_residual(model, s) for s in snapshots]
    k = int(np.argmax(residuals))
    return residuals[k], k, float(snapshots[k]["load_fraction"])


# --------------------------------------------------------------------------- balance
def slipped_since_closing(events: dict, n_pairs: int, t: float) -> np.ndarray:
    """(P,) bool: the pairs that began to slip since they last closed, by path time t (its
    events included), from a run's event history: in space their friction is on the polygon
    laid at that slip's onset (rust/src/coulomb.rs), the round cone before."""
    on_polygon = np.zeros(n_pairs, dtype=bool)
    for kind, p, when in zip(events["kind"], events["entity"], events["t"]):
        if when > t:
            break
        if kind == "stick_to_slip":
            on_polygon[p] = True
        elif kind in ("close", "separate"):
            on_polygon[p] = False
    return on_polygon


def friction_in_space(
    model: dict, snapshots, slip_turn: float, floors: tuple[float, float], events: dict
) -> dict:
    """Worst values over a 3D run's snapshots (every event) of what Coulomb's cone and the
    friction design imply (module text; ``events``: the run's event history, which tells the
    stuck pairs on the round cone from those on their polygon), each to be compared with
    round-off:

    - ``outside_round``: max |λ_t| − μλ_n of stuck pairs that have not slipped since they
      closed (≤ 0), and ``outside_polygon``: max |λ_t| − μλ_n/cos(slip_turn) of those that have
      (≤ 0: the polygon circumscribed about the round cone, sides 2θ ≤ 2 slip_turn apart);
    - ``inside_facet``, ``beyond_facet``: max μλ_n − |λ_t| and |λ_t| − μλ_n/cos(slip_turn) of
      slipping pairs (≤ 0: on its facet the force is up to 1/cos(slip_turn) of μλ_n);
    - ``work``: max λ_t·ΔRTD of a pair slipping at both ends of a step, with either end's force
      (≤ 0: over a step its slip lies between two consecutive facet directions −e, −e', at most
      slip_turn apart, and its force within slip_turn of e', so the force has a component
      against the slip for slip_turn < π/4);
    - ``lag``: max angle (rad) between such a pair's force at the step's end and its slip over
      the step (≤ 2 slip_turn, by the same argument), over the pairs whose slip and force exceed
      ``floors`` = (length, force), below which a direction is round-off;
    - ``slipping_steps``: how many (pair, step) the lag was measured on."""
    mu = np.asarray(model["pairs"]["mu"], dtype=float)
    out = {
        "outside_round": -np.inf,
        "outside_polygon": -np.inf,
        "inside_facet": -np.inf,
        "beyond_facet": -np.inf,
        "work": -np.inf,
        "lag": 0.0,
        "slipping_steps": 0,
    }
    worst = lambda key, values: out.__setitem__(key, max(out[key], values.max(initial=-np.inf)))  # noqa: E731
    for k, s in enumerate(snapshots):
        stick, slip = s["status"] == 1, s["status"] == 2
        ln, lt = np.asarray(s["lambda_n"]), np.asarray(s["lambda_t"])
        size = np.linalg.norm(lt, axis=1)
        polygon = slipped_since_closing(events, len(mu), float(s.get("t", s["load_fraction"])))
        worst("outside_round", (size - mu * ln)[stick & ~polygon])
        worst("outside_polygon", (size - mu * ln / math.cos(slip_turn))[stick & polygon])
        worst("inside_facet", (mu * ln - size)[slip])
        worst("beyond_facet", (size - mu * ln / math.cos(slip_turn))[slip])
        if k == 0:
            continue
        prev = snapshots[k - 1]
        both = slip & (prev["status"] == 2)
        d = np.asarray(s["rtd"]) - prev["rtd"]
        for ends in (np.asarray(prev["lambda_t"]), lt):
            worst("work", np.einsum("ij,ij->i", ends[both], d[both]))
        moved = both & (np.linalg.norm(d, axis=1) > floors[0]) & (size > floors[1])
        cos = -np.einsum("ij,ij->i", lt[moved], d[moved]) / (
            size[moved] * np.linalg.norm(d[moved], axis=1)
        )
        out["lag"] = max(out["lag"], float(np.arccos(np.clip(cos, -1.0, 1.0)).max(initial=0.0)))
        out["slipping_steps"] += int(moved.sum())
    return out


def node_body(model: dict) -> np.ndarray:
    """The body index (``element_body``) of every node, from the elements it belongs to."""
    body = np.full(len(model["nodes"]), -1, dtype=np.int64)
    cells = np.asarray(
        model["tetrahedra"] if model.get("dimension", 2) == 3 else model["triangles"]
    )
    body[cells.ravel()] = np.repeat(np.asarray(model["element_body"]), cells.shape[1])
    return body


def body_sums(model: dict, force: np.ndarray) -> np.ndarray:
    """(B, dim): a nodal force vector (dim N,) summed over each body's nodes, per component."""
    dim = model.get("dimension", 2)
    body, f = node_body(model), np.asarray(force, dtype=float).reshape(-1, dim)
    n_bodies = int(np.max(model["element_body"])) + 1
    return np.stack([np.bincount(body, f[:, c], n_bodies) for c in range(dim)], axis=1)


def recomputed_reaction(model: dict, snapshot: dict) -> np.ndarray:
    """(2N,) the force the supports exert on the body, from the stresses: internal force −
    applied load − contact forces at the held DOFs (``held_dofs``), 0 elsewhere."""
    nodes = np.asarray(model["nodes"], dtype=float)
    t = float(snapshot.get("t", snapshot["load_fraction"]))
    r = (
        model_internal_force(model, snapshot["stress"])
        - applied_load(model, t)
        - contact_force(
            len(nodes),
            model["pairs"],
            np.asarray(snapshot["lambda_n"]),
            np.asarray(snapshot["lambda_t"]),
        )
    )
    out = np.zeros_like(r)
    held = held_dofs(model)
    out[held] = r[held]
    return out


def balance_terms(model: dict, snapshot: dict) -> dict:
    """Each body's external forces at a snapshot, (B, 2) each: ``contact`` (λ_n n + λ_t t of
    every pair, node-to-segment rows spread by their weights: ``contact_force``), ``load`` (the
    applied load at the snapshot's path time), ``reaction`` (the snapshot's ``reaction``), and
    ``scale``, the sum of the absolute nodal terms (the size of the numbers summed)."""
    n = len(model["nodes"])
    t = float(snapshot.get("t", snapshot["load_fraction"]))
    forces = {
        "contact": contact_force(
            n, model["pairs"], np.asarray(snapshot["lambda_n"]), np.asarray(snapshot["lambda_t"])
        ),
        "load": applied_load(model, t),
        "reaction": np.asarray(snapshot["reaction"], dtype=float).reshape(-1),
    }
    out = {k: body_sums(model, f) for k, f in forces.items()}
    out["scale"] = sum(body_sums(model, np.abs(f)) for f in forces.values())
    return out


def obstacle_force(model: dict, snapshot: dict, contact: int) -> np.ndarray:
    """(2,) the total force of [[contact]] ``contact`` on the bodies: Σ (λ_n n + λ_t t) over its
    pairs (t = (−n_y, n_x)); for a rigid obstacle, minus the force the bodies exert on it."""
    pairs = model["pairs"]
    mine = np.asarray(pairs.get("contact", np.zeros(len(pairs["node_a"]), np.int64))) == contact
    n = np.asarray(pairs["normal"], dtype=float).reshape(-1, 2)[mine]
    t = np.stack([-n[:, 1], n[:, 0]], axis=1)
    return np.asarray(snapshot["lambda_n"])[mine] @ n + np.asarray(snapshot["lambda_t"])[mine] @ t


# --------------------------------------------------------------------------- refinement
def observed_order(error_coarse: float, error_fine: float, ratio: float = 2.0) -> float:
    """The convergence order of an error that falls from ``error_coarse`` to ``error_fine``
    when the element size is divided by ``ratio``: log(e_coarse/e_fine)/log(ratio)."""
    return math.log(abs(error_coarse) / abs(error_fine)) / math.log(ratio)


def richardson(coarse: float, fine: float, order: float, ratio: float = 2.0) -> float:
    """Richardson's extrapolation to h -> 0 of a value converging at ``order`` from the meshes
    h (``coarse``) and h/ratio (``fine``): fine + (fine - coarse)/(ratio^order - 1)."""
    return fine + (fine - coarse) / (ratio**order - 1.0)


# --------------------------------------------------------------------------- stresses
def von_mises(stress: np.ndarray) -> np.ndarray:
    """Von Mises stress of (M, 4) rows σx, σy, σz, τxy, from the deviator: √(3/2 s:s)."""
    s = np.asarray(stress, dtype=float).reshape(-1, 4)
    mean = s[:, :3].mean(axis=1, keepdims=True)
    dev = s[:, :3] - mean
    return np.sqrt(1.5 * (np.sum(dev**2, axis=1) + 2.0 * s[:, 3] ** 2))


# --------------------------------------------------------------------------- energy
def strain_energy(
    nodes: np.ndarray,
    triangles: np.ndarray,
    stress: np.ndarray,
    E: float,
    nu: float,
    thickness: float,
) -> float:
    """Elastic energy of constant-stress triangles of one isotropic material (plane strain or
    stress): Σ_e t A_e w_e, w = (σx² + σy² + σz² − 2ν(σxσy + σyσz + σzσx))/(2E) + τ²(1+ν)/E
    (σz = 0 in plane stress; in plane strain εz = 0, so σz does no work and w = σ:ε/2 still)."""
    nodes, triangles = np.asarray(nodes, dtype=float), np.asarray(triangles)
    sx, sy, sz, txy = np.asarray(stress, dtype=float).reshape(-1, 4).T
    x, y = nodes[triangles, 0], nodes[triangles, 1]
    area = 0.5 * np.abs(
        (x[:, 1] - x[:, 0]) * (y[:, 2] - y[:, 0]) - (x[:, 2] - x[:, 0]) * (y[:, 1] - y[:, 0])
    )
    w = (sx**2 + sy**2 + sz**2 - 2.0 * nu * (sx * sy + sy * sz + sz * sx)) / (2.0 * E) + txy**2 * (
        1.0 + nu
    ) / E
    return float(thickness * np.sum(area * w))
