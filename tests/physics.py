"""Independent physics checks on result arrays (not the engine's own residuals), and closed-form
or independently computed references.  Nothing here calls the engine or slipstep.

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

Balance
    ``balance_terms(model, snapshot)``: each body's resultant contact force, applied load and
    support reaction (the snapshot's ``reaction``), which must sum to zero;
    ``obstacle_force`` a contact's total force on the bodies; ``recomputed_reaction`` the
    supports' forces from the stresses (internal − load − contact at the held DOFs).

Refinement
    ``observed_order`` of an error between two meshes, ``richardson`` extrapolation to h -> 0.

Hertz line contact (Johnson, Contact Mechanics, §4.3): a = √(4PR/(πE*)), p0 = 2P/(πa); for an
    elastic body on a rigid flat E* = E/(1−ν²) in plane strain and E* = E in plane stress.

Hertz sphere on a rigid flat (Johnson §4.2, §3.4): a = (3PR/(4E*))^(1/3), p0 = 3P/(2πa²),
    δ = a²/R; Huber's stresses along the axis (eq. 3.45) and the compression of the axis below a
    depth, which says where the approach of "distant points" is measured (``sphere_axis_*``).

Thick-walled sphere under internal pressure (Hill, The Mathematical Theory of Plasticity,
    ch. V; von Mises = Tresca under the spherical symmetry σθ = σφ): ``thick_sphere_*``.

Cattaneo–Mindlin (Johnson §7.1–7.3): ``cattaneo_traction`` the shear of a line contact under
    Q < μP, ``line_contact_dissipation`` the energy dissipated per cycle ±Q* (the planar analogue
    of Mindlin–Deresiewicz, derived in the comment above it), ``strain_energy`` of CST elements.

Spence's stick zone (frictional Hertz line contact, monotonic normal loading): see
    ``goodman_stick_ratio`` (closed form, Goodman's approximation) and ``spence_stick_ratio``
    (the exact coupled problem, solved numerically).
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
def internal_force(nodes: np.ndarray, triangles: np.ndarray, stress: np.ndarray,
                   thickness: float, plane: str = "strain") -> np.ndarray:
    """Σ_e t A_e B_eᵀ (σx, σy, τxy)_e over all DOFs (2 per node), for triangles of either
    orientation; the ring's forces for ``plane == "axisymmetric"`` (``ring_internal_force``)."""
    if plane == "axisymmetric":
        return ring_internal_force(nodes, triangles, stress)
    nodes, triangles = np.asarray(nodes, dtype=float), np.asarray(triangles)
    stress = np.asarray(stress, dtype=float).reshape(-1, 4)
    x, y = nodes[triangles, 0], nodes[triangles, 1]            # (M, 3)
    area2 = (x[:, 1] - x[:, 0]) * (y[:, 2] - y[:, 0]) - (x[:, 2] - x[:, 0]) * (y[:, 1] - y[:, 0])
    b = np.stack([y[:, 1] - y[:, 2], y[:, 2] - y[:, 0], y[:, 0] - y[:, 1]], axis=1)  # area2 ∂N/∂x
    c = np.stack([x[:, 2] - x[:, 1], x[:, 0] - x[:, 2], x[:, 1] - x[:, 0]], axis=1)  # area2 ∂N/∂y
    sx, sy, txy = stress[:, 0:1], stress[:, 1:2], stress[:, 3:4]
    # t A Bᵀσ with A = |area2|/2 and ∂N/∂x = b/area2: sign(area2) t/2 (b σx + c τxy, c σy + b τxy)
    half_t = 0.5 * thickness * np.sign(area2)[:, None]
    fx = half_t * (b * sx + c * txy)
    fy = half_t * (c * sy + b * txy)
    n = 2 * len(nodes)
    return (np.bincount((2 * triangles).ravel(), weights=fx.ravel(), minlength=n)
            + np.bincount((2 * triangles + 1).ravel(), weights=fy.ravel(), minlength=n))


def ring_internal_force(nodes: np.ndarray, triangles: np.ndarray, stress: np.ndarray) -> np.ndarray:
    """Axisymmetric internal forces, totals over the ring: per element 2π r̄ A (∂N_k/∂r σr +
    ∂N_k/∂z τrz + σθ/(3 r̄)) on u_r of node k and 2π r̄ A (∂N_k/∂z σz + ∂N_k/∂r τrz) on u_z
    (r̄ the centroid radius, N_k = 1/3 there; stress columns σr, σz, σθ, τrz)."""
    nodes, triangles = np.asarray(nodes, dtype=float), np.asarray(triangles)
    s = np.asarray(stress, dtype=float).reshape(-1, 4)
    r, z = nodes[triangles, 0], nodes[triangles, 1]                                  # (M, 3)
    area2 = (r[:, 1] - r[:, 0]) * (z[:, 2] - z[:, 0]) - (r[:, 2] - r[:, 0]) * (z[:, 1] - z[:, 0])
    dn_dr = np.stack([z[:, 1] - z[:, 2], z[:, 2] - z[:, 0], z[:, 0] - z[:, 1]], 1) / area2[:, None]
    dn_dz = np.stack([r[:, 2] - r[:, 1], r[:, 0] - r[:, 2], r[:, 1] - r[:, 0]], 1) / area2[:, None]
    r_bar = r.mean(axis=1)
    volume = (2.0 * math.pi * r_bar * 0.5 * np.abs(area2))[:, None]
    sr, sz, st, trz = (s[:, k:k + 1] for k in range(4))
    fr = volume * (dn_dr * sr + dn_dz * trz + st / (3.0 * r_bar[:, None]))
    fz = volume * (dn_dz * sz + dn_dr * trz)
    n = 2 * len(nodes)
    return (np.bincount((2 * triangles).ravel(), weights=fr.ravel(), minlength=n)
            + np.bincount((2 * triangles + 1).ravel(), weights=fz.ravel(), minlength=n))


def contact_force(n_nodes: int, pairs: dict, lambda_n: np.ndarray,
                  lambda_t: np.ndarray) -> np.ndarray:
    """The contact forces on the bodies over all DOFs: λ_n n + λ_t t on node a, the opposite on
    node b (none for node_b = −1, a rigid target); t = (−n_y, n_x). A node-to-segment row
    (``weight_ptr`` etc.) puts c_i (λ_n n + λ_t t) on each of its nodes i instead."""
    normal = np.asarray(pairs["normal"], dtype=float).reshape(-1, 2)
    tangent = np.stack([-normal[:, 1], normal[:, 0]], axis=1)
    lambda_n, lambda_t = np.asarray(lambda_n, dtype=float), np.asarray(lambda_t, dtype=float)
    force = lambda_n[:, None] * normal + lambda_t[:, None] * tangent
    f = np.zeros(2 * n_nodes)
    a, b = np.asarray(pairs["node_a"]), np.asarray(pairs["node_b"])
    ptr = np.asarray(pairs.get("weight_ptr", np.zeros(len(a) + 1, dtype=np.int64)))
    weighted = np.diff(ptr) > 0  # node-to-segment rows: Σ_i c_i force at node i
    for comp in (0, 1):
        plain = ~weighted
        np.add.at(f, 2 * a[plain] + comp, force[plain, comp])
        np.add.at(f, 2 * b[plain & (b >= 0)] + comp, -force[plain & (b >= 0), comp])
        if weighted.any():
            rows = np.repeat(np.arange(len(a)), np.diff(ptr))
            np.add.at(f, 2 * np.asarray(pairs["weight_node"]) + comp,
                      np.asarray(pairs["weight_value"]) * force[rows, comp])
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
    held += [np.asarray(p["displacement_dofs"], dtype=np.int64)
             for p in model.get("patterns", []) if "displacement_dofs" in p]
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
    internal = internal_force(nodes, np.asarray(model["triangles"]),
                              np.asarray(snapshot["stress"]), model["thickness"],
                              model.get("plane", "strain"))
    r = (internal - applied_load(model, t)
         - contact_force(len(nodes), model["pairs"], np.asarray(snapshot["lambda_n"]),
                         np.asarray(snapshot["lambda_t"])))
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
def node_body(model: dict) -> np.ndarray:
    """The body index (``element_body``) of every node, from the elements it belongs to."""
    body = np.full(len(model["nodes"]), -1, dtype=np.int64)
    body[np.asarray(model["triangles"]).ravel()] = np.repeat(np.asarray(model["element_body"]), 3)
    return body


def body_sums(model: dict, force: np.ndarray) -> np.ndarray:
    """(B, 2): a nodal force vector (2N,) summed over each body's nodes, per component."""
    body, f = node_body(model), np.asarray(force, dtype=float).reshape(-1, 2)
    n_bodies = int(np.max(model["element_body"])) + 1
    return np.stack([np.bincount(body, f[:, c], n_bodies) for c in (0, 1)], axis=1)


def recomputed_reaction(model: dict, snapshot: dict) -> np.ndarray:
    """(2N,) the force the supports exert on the body, from the stresses: internal force −
    applied load − contact forces at the held DOFs (``held_dofs``), 0 elsewhere."""
    nodes = np.asarray(model["nodes"], dtype=float)
    t = float(snapshot.get("t", snapshot["load_fraction"]))
    r = (internal_force(nodes, np.asarray(model["triangles"]), np.asarray(snapshot["stress"]),
                        model["thickness"], model.get("plane", "strain"))
         - applied_load(model, t)
         - contact_force(len(nodes), model["pairs"], np.asarray(snapshot["lambda_n"]),
                         np.asarray(snapshot["lambda_t"])))
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
    forces = {"contact": contact_force(n, model["pairs"], np.asarray(snapshot["lambda_n"]),
                                       np.asarray(snapshot["lambda_t"])),
              "load": applied_load(model, t),
              "reaction": np.asarray(snapshot["reaction"], dtype=float).reshape(-1)}
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
    return (np.asarray(snapshot["lambda_n"])[mine] @ n
            + np.asarray(snapshot["lambda_t"])[mine] @ t)


# --------------------------------------------------------------------------- refinement
def observed_order(error_coarse: float, error_fine: float, ratio: float = 2.0) -> float:
    """The convergence order of an error that falls from ``error_coarse`` to ``error_fine``
    when the element size is divided by ``ratio``: log(e_coarse/e_fine)/log(ratio)."""
    return math.log(abs(error_coarse) / abs(error_fine)) / math.log(ratio)


def richardson(coarse: float, fine: float, order: float, ratio: float = 2.0) -> float:
    """Richardson's extrapolation to h -> 0 of a value converging at ``order`` from the meshes
    h (``coarse``) and h/ratio (``fine``): fine + (fine - coarse)/(ratio^order - 1)."""
    return fine + (fine - coarse) / (ratio ** order - 1.0)


# --------------------------------------------------------------------------- stresses
def von_mises(stress: np.ndarray) -> np.ndarray:
    """Von Mises stress of (M, 4) rows σx, σy, σz, τxy, from the deviator: √(3/2 s:s)."""
    s = np.asarray(stress, dtype=float).reshape(-1, 4)
    mean = s[:, :3].mean(axis=1, keepdims=True)
    dev = s[:, :3] - mean
    return np.sqrt(1.5 * (np.sum(dev ** 2, axis=1) + 2.0 * s[:, 3] ** 2))


# --------------------------------------------------------------------------- thick cylinder
def hill_pressure(c: float, a: float, b: float, k: float) -> float:
    """Hill (ch. V): internal pressure at which the plastic zone of a thick cylinder (bore a,
    outer radius b, shear yield stress k) reaches radius c: k [2 ln(c/a) + 1 − c²/b²]."""
    return k * (2.0 * math.log(c / a) + 1.0 - c ** 2 / b ** 2)


def hill_radius(p: float, a: float, b: float, k: float) -> float:
    """Inverse of hill_pressure on [a, b] (increasing there: dp/dc = 2k (1/c − c/b²) > 0)."""
    return _inverse(lambda c: hill_pressure(c, a, b, k), p, a, b)


def _inverse(increasing, value: float, lo: float, hi: float) -> float:
    """x in [lo, hi] with increasing(x) = value, by bisection (100 halvings: to round-off)."""
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if increasing(mid) < value else (lo, mid)
    return 0.5 * (lo + hi)


# --------------------------------------------------------------------------- thick sphere
def thick_sphere_lame(rho, p: float, a: float, b: float) -> tuple[np.ndarray, np.ndarray]:
    """Lamé's elastic sphere a <= ρ <= b under internal pressure p: (σ_R, σ_t) at the spherical
    radius ρ, σ_R = −p (b³/ρ³ − 1)/(b³/a³ − 1), σ_t = σθ = σφ = p (b³/(2ρ³) + 1)/(b³/a³ − 1)."""
    rho = np.asarray(rho, dtype=float)
    k = b ** 3 / a ** 3 - 1.0
    return -p * (b ** 3 / rho ** 3 - 1.0) / k, p * (0.5 * b ** 3 / rho ** 3 + 1.0) / k


def thick_sphere_displacement(rho, p: float, a: float, b: float, E: float, nu: float) -> np.ndarray:
    """Lamé's radial displacement: p a³/(E (b³ − a³)) [(1 − 2ν) ρ + (1 + ν) b³/(2ρ²)]."""
    rho = np.asarray(rho, dtype=float)
    return p * a ** 3 / (E * (b ** 3 - a ** 3)) * ((1 - 2 * nu) * rho + (1 + nu) * b ** 3 / (2 * rho ** 2))


def thick_sphere_pressure(c: float, a: float, b: float, Y: float) -> float:
    """Hill (ch. V): internal pressure at which the plastic zone of a thick sphere (von Mises =
    Tresca here: σθ = σφ) reaches radius c: 2Y ln(c/a) + (2Y/3)(1 − c³/b³).  At c = a it is the
    elastic limit p_e = (2Y/3)(1 − a³/b³), at c = b the limit 2Y ln(b/a)."""
    return 2.0 * Y * math.log(c / a) + 2.0 * Y / 3.0 * (1.0 - c ** 3 / b ** 3)


def thick_sphere_radius(p: float, a: float, b: float, Y: float) -> float:
    """Inverse of thick_sphere_pressure on [a, b] (increasing: dp/dc = 2Y (1/c − c²/b³) > 0)."""
    return _inverse(lambda c: thick_sphere_pressure(c, a, b, Y), p, a, b)


# --------------------------------------------------------------------------- Hertz
def hertz_line(P: float, R: float, E: float, nu: float, plane: str = "strain") -> tuple[float, float]:
    """Contact half-width a and peak pressure p0 of an elastic cylinder (radius R, line load P
    per unit thickness on the full cylinder) on a rigid flat."""
    e_star = E / (1.0 - nu ** 2) if plane == "strain" else E
    a = math.sqrt(4.0 * P * R / (math.pi * e_star))
    return a, 2.0 * P / (math.pi * a)


def hertz_sphere(P: float, R: float, E: float, nu: float) -> tuple[float, float, float]:
    """Contact radius a, peak pressure p0 and approach δ of an elastic sphere (radius R, total
    force P) on a rigid flat: a³ = 3PR/(4E*), p0 = 3P/(2πa²), δ = a²/R, E* = E/(1 − ν²)."""
    e_star = E / (1.0 - nu ** 2)
    a = (3.0 * P * R / (4.0 * e_star)) ** (1.0 / 3.0)
    return a, 3.0 * P / (2.0 * math.pi * a ** 2), a ** 2 / R


def sphere_axis_stresses(zeta, nu: float) -> tuple[np.ndarray, np.ndarray]:
    """Huber's stresses on the axis below a Hertz sphere contact (Johnson eq. 3.45), over p0,
    at depths ζ = z/a > 0: σr = σθ = −(1 + ν)(1 − ζ arctan(1/ζ)) + 1/(2(1 + ζ²)),
    σz = −1/(1 + ζ²) (τrz = 0 on the axis)."""
    zeta = np.asarray(zeta, dtype=float)
    sigma_z = -1.0 / (1.0 + zeta ** 2)
    return -(1.0 + nu) * (1.0 - zeta * np.arctan(1.0 / zeta)) - 0.5 * sigma_z, sigma_z


def sphere_axis_compression(zeta, nu: float) -> np.ndarray:
    """The shortening, over p0 a/E, of the axis of the half-space from depth ζ = z/a down to
    infinity under the Hertz pressure: −∫_ζ^∞ (σz − 2ν σr) dζ'/p0 from
    ``sphere_axis_stresses``, integrated in closed form,
    (1 + ν) [arccot ζ − 2ν (π/4 − G(ζ))], G(ζ) = ζ/2 − (ζ²/2) arccot ζ + (1/2) arctan ζ.
    At ζ = 0 it is the approach of distant points, (1 − ν²) π/2 = δ E/(p0 a)."""
    zeta = np.asarray(zeta, dtype=float)
    arccot = np.arctan2(1.0, zeta)
    g = 0.5 * zeta - 0.5 * zeta ** 2 * arccot + 0.5 * np.arctan(zeta)
    return (1.0 + nu) * (arccot - 2.0 * nu * (0.25 * math.pi - g))


def dundurs_beta(nu: float, plane: str = "strain") -> float:
    """Dundurs' β of an elastic body (ν) against a rigid one: (1 − 2ν)/(2(1 − ν)) in plane
    strain; plane stress is plane strain with ν/(1 + ν), giving (1 − ν)/2."""
    if plane == "stress":
        nu = nu / (1.0 + nu)
    return (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu))


# --------------------------------------------------------------------------- Cattaneo-Mindlin
def strain_energy(nodes: np.ndarray, triangles: np.ndarray, stress: np.ndarray, E: float,
                  nu: float, thickness: float) -> float:
    """Elastic energy of constant-stress triangles of one isotropic material (plane strain or
    stress): Σ_e t A_e w_e, w = (σx² + σy² + σz² − 2ν(σxσy + σyσz + σzσx))/(2E) + τ²(1+ν)/E
    (σz = 0 in plane stress; in plane strain εz = 0, so σz does no work and w = σ:ε/2 still)."""
    nodes, triangles = np.asarray(nodes, dtype=float), np.asarray(triangles)
    sx, sy, sz, txy = np.asarray(stress, dtype=float).reshape(-1, 4).T
    x, y = nodes[triangles, 0], nodes[triangles, 1]
    area = 0.5 * np.abs((x[:, 1] - x[:, 0]) * (y[:, 2] - y[:, 0])
                        - (x[:, 2] - x[:, 0]) * (y[:, 1] - y[:, 0]))
    w = ((sx ** 2 + sy ** 2 + sz ** 2 - 2.0 * nu * (sx * sy + sy * sz + sz * sx)) / (2.0 * E)
         + txy ** 2 * (1.0 + nu) / E)
    return float(thickness * np.sum(area * w))


def cattaneo_traction(x, a: float, c: float, p0: float, mu: float) -> np.ndarray:
    """Cattaneo–Mindlin shear of a Hertz line contact (Johnson §7.1, the cylinder; half-width
    a, peak pressure p0, stick zone |x| < c, c/a = √(1 − Q/(μP))):
    q = μ p0 [√(1 − x²/a²) − (c/a) √(1 − x²/c²)] in the stick zone, μ p(x) in the slip zones,
    0 outside the contact."""
    x = np.asarray(x, dtype=float)
    full = mu * p0 * np.sqrt(np.clip(1.0 - (x / a) ** 2, 0.0, None))
    stick = mu * p0 * (c / a) * np.sqrt(np.clip(1.0 - (x / c) ** 2, 0.0, None))
    return full - np.where(np.abs(x) < c, stick, 0.0)


# The energy a Hertz line contact of two equal bodies (β = 0: shear and pressure uncoupled)
# dissipates per cycle of tangential load ±Q*, the planar analogue of Mindlin–Deresiewicz
# (Johnson §7.3 for the sphere), derived here.  One half-plane under a surface shear q has
# ∂u_x/∂x = −(K/π) PV∫ q(s)/(x − s) ds, K = 2(1 − ν²)/E (Johnson eq. 2.25; plane strain); an
# elliptical shear of total F over half-width b moves its centre by (K F/π)(ln(d/b) + C)
# against a point at distance d ≫ b.  Cattaneo's q is such a shear μP over a minus one of
# μP (c/a)² over c, and the stick zone moves rigidly, so the relative displacement of the two
# bodies there (2K, two equal bodies) is linear in Q (the d and C terms: elastic) plus
#     δ(Q) = (2K μP/(2π)) (1 − r) ln(1 − r),   r = Q/(μP),   ((c/a)² = 1 − r),
# convex in Q.  Unloading follows Masing (Mindlin & Deresiewicz's superposition:
# δ_unload(Q) = δ(Q*) − 2 δ((Q* − Q)/2)), so the loop's area is
#     W = 4 ∫_0^{Q*} [δ(Q*) − δ(u) − δ(Q* − u)] du
#       = (4 K (μP)²/π) [(1 − r*) ln(1 − r*) + r* − r*²/2],   r* = Q*/(μP),
# linear terms cancelling; for small r* W ≈ 2 K Q*³/(3π μP), cubic as for the sphere.
def line_contact_dissipation(P: float, Q_star: float, mu: float, E: float, nu: float) -> float:
    """W per cycle ±Q* (per unit thickness) of a line contact of two equal elastic bodies
    pressed by P (plane strain), from the derivation above."""
    K, F = 2.0 * (1.0 - nu ** 2) / E, mu * P
    r = Q_star / F
    return 4.0 * K * F ** 2 / math.pi * ((1.0 - r) * math.log1p(-r) + r - 0.5 * r * r)


# --------------------------------------------------------------------------- Spence
#
# The problem (2D, half-plane theory, Johnson's Contact Mechanics ch. 2 and 5): an elastic
# half-plane (compliance A = 2(1−ν²)/E per unit load, Dundurs' β) indented by a rigid profile,
# contact |x| < a, pressure p, shear q.  Surface displacements (z into the body):
#     u_z(x) = −(A/π) ∫ p(s) ln|x − s| ds + (βA/2) ∫ q(s) sgn(x − s) ds
#     u_x(x) = −(A/π) ∫ q(s) ln|x − s| ds − (βA/2) ∫ p(s) sgn(x − s) ds
# (the sgn terms: a normal line load pulls surface points towards it, Johnson ch. 2, line
# loading of a half-space; the sign of the other is fixed by reciprocity).  Under monotonic loading of a Hertz
# profile the solution is self-similar (Spence 1968, Proc. R. Soc. A 305, 55-80; 1975,
# J. Elasticity 5, 297-319): the stick zone |x| < c grows with a at a fixed ratio c/a, and the
# rates ṗ = ∂p/∂a, q̇ = ∂q/∂a at fixed x solve a flat-punch problem (∂/∂a of the profile term
# x/R vanishes): u̇_z = const on |x| < a, u̇_x = 0 in the stick zone, q̇ = μ ṗ sgn(x) in the slip
# zones c < |x| < a (friction on the body points outwards: the body's surface moves inwards).
# c/a is the one for which q̇ stays bounded at ±c; it depends on μ and β only.
#
# Goodman's approximation drops β q from u_z (ṗ is then the flat-punch 1/√(a²−x²)); with
# q̇ = μ sgn(x) ṗ + q*, q* supported on the stick zone, the stick condition is a finite Hilbert
# transform equation for q* on (−c, c) whose solution is bounded at both ends only if its
# right-hand side g has ∫ g/√(c²−x²) dx = 0 (a = 1, k = √(1−x²)):
#     g = −β/k + (μ/(πk)) ln((1−k)/(1+k)),   ∫_0^c dx/(k√(c²−x²)) = K(c),
#     ∫_0^c ln((1+k)/(1−k)) dx/(k√(c²−x²)) = π K'(c)   (checked numerically to 1e-10),
# so that
#     β/μ = K'(c/a) / K(c/a)          (K complete elliptic integral of the 1st kind, modulus c/a).
# Its limits: c/a → 0 as μ/β → 0, c/a ≈ 4 exp(−πβ/(2μ)); c/a → 1 only as μ/β → ∞,
# √(1 − (c/a)²) ≈ 4 exp(−πμ/(2β)); self-dual: c(β/μ)² + c(μ/β)² = 1, c = 1/√2 at μ = β.
# The exact (coupled) problem is a vector Riemann-Hilbert problem without an elementary closed
# form; ``spence_stick_ratio`` solves it by collocation (piecewise-constant tractions, the
# kernels above integrated exactly over each panel, the stick zone found by bisection on its
# number of panels), and with ``coupled=False`` reproduces the closed form (a check of the
# solver, tests/physics/test_spence.py).


def _elliptic_ratio(k: float) -> float:
    """K'(k)/K(k) for the modulus k in (0, 1), accurate near both ends."""
    from scipy.special import ellipkm1

    kp2 = (1.0 - k) * (1.0 + k)                  # k'² without cancellation
    return float(ellipkm1(k * k) / ellipkm1(kp2))  # K(m = 1 − k²) / K(m = k²)


def goodman_stick_ratio(beta_over_mu: float) -> float:
    """c/a from β/μ = K'(c/a)/K(c/a) (Goodman's approximation), by bisection (brentq)."""
    from scipy.optimize import brentq

    if beta_over_mu <= 0:
        return 1.0
    return float(brentq(lambda k: _elliptic_ratio(k) - beta_over_mu, 1e-300, 1.0 - 1e-16,
                        xtol=1e-15, rtol=1e-14))


def _panel_log(x, s1, s2):
    """−(1/π) ∫_{s1}^{s2} ln|x − s| ds."""
    def F(t):
        at = np.abs(t)
        return np.where(at > 0, t * np.log(np.where(at > 0, at, 1.0)) - t, 0.0)
    return -(F(x - s1) - F(x - s2)) / math.pi


def _panel_sign(x, s1, s2):
    """(1/2) ∫_{s1}^{s2} sgn(x − s) ds."""
    return 0.5 * (np.abs(x - s1) - np.abs(x - s2))


def spence_stick_ratio(mu: float, beta: float, panels: int = 1000, coupled: bool = True) -> float:
    """c/a of the self-similar frictional Hertz line contact (the flat-punch rate problem
    above), by collocation with ``panels`` equal panels on 0 < x < a = 1 (p even, q odd).
    The stick zone is located to one panel: the result is the panel edge between the last stick
    and the first slip panel (resolution 1/panels of a)."""
    e = np.linspace(0.0, 1.0, panels + 1)
    x = 0.5 * (e[1:] + e[:-1])[:, None]
    s1, s2 = e[None, :-1], e[None, 1:]
    length = np.diff(e)
    log_p = _panel_log(x, s1, s2) + _panel_log(x, -s2, -s1)   # even density on both halves
    log_q = _panel_log(x, s1, s2) - _panel_log(x, -s2, -s1)   # odd density
    sgn_p = _panel_sign(x, s1, s2) + _panel_sign(x, -s2, -s1)
    sgn_q = _panel_sign(x, s1, s2) - _panel_sign(x, -s2, -s1)
    uz_p, uz_q = log_p, (beta * sgn_q if coupled else 0.0 * sgn_q)
    ux_p, ux_q = -beta * sgn_p, log_q
    n = panels

    def solve(k):
        """Tractions with the first k panels sticking, the others slipping (q = μ p: friction
        on the body outwards); returns (a stick panel beyond the cone outwards, a slip panel
        slipping against its friction, every stick panel inside the cone)."""
        stick = np.arange(n) < k
        M = np.zeros((2 * n + 1, 2 * n + 1))
        rhs = np.zeros(2 * n + 1)
        M[:n, :n], M[:n, n:2 * n], M[:n, 2 * n] = uz_p, uz_q, -1.0   # u_z = rigid approach
        M[n:2 * n, :n] = np.where(stick[:, None], ux_p, 0.0)         # stick: u_x = 0
        M[n:2 * n, n:2 * n] = np.where(stick[:, None], ux_q, 0.0)
        slip = np.flatnonzero(~stick)                                # slip: q = μ p
        M[n + slip, n + slip] = 1.0
        M[n + slip, slip] = -mu
        M[2 * n, :n] = 2.0 * length                                  # total load 1
        rhs[2 * n] = 1.0
        sol = np.linalg.solve(M, rhs)
        p, q = sol[:n], sol[n:2 * n]
        ux = ux_p @ p + ux_q @ q
        over = bool(np.any(q[stick] > mu * p[stick]))
        inside = bool(np.all(np.abs(q[stick]) <= mu * p[stick]))
        return over, bool(np.any(ux[~stick] > 0)), inside

    # Bisection on the number k of stick panels: too many and q̇ exceeds the cone outwards at
    # the stick edge (the square-root singularity of an oversized stick zone), too few and q̇
    # turns inwards there while the slip next to it runs against its friction.
    lo, hi = 0, n          # invariant: k <= lo is too small (or 0), k >= hi too large (or n)
    while hi - lo > 1:
        mid = (lo + hi) // 2
        over, against, _ = solve(mid)
        if over and against:
            raise RuntimeError(f"spence_stick_ratio: no consistent stick zone near {mid}/{n}")
        if over:
            hi = mid
        elif against:
            lo = mid
        else:
            lo = hi = mid
    k = lo
    over, against, inside = solve(k)
    if over or against:
        raise RuntimeError("spence_stick_ratio: the stick/slip set is not consistent")
    return float(e[k])
