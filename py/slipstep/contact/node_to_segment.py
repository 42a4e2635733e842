"""Node-to-segment contact between independently meshed bodies, mortar-style.

One constraint row per contactor node j: its gap is the mean of the normal gap over the
interface weighted by its shape function N_j (integrals over the contactor surface, the
target's points at the closest-point projection, small sliding: all fixed at the start):

    S_j   = ∫ N_j ds                                  (tributary length)
    D_jk  = ∫ N_j N_k ds      (contactor nodes k)     M_jl = ∫ N_j N̂_l ds  (target nodes l)
    g_j   = ∫ N_j (x − y(x))·n ds / S_j               (initial gap)
    w_n^j = n_j (Σ_k D_jk e_k − Σ_l M_jl e_l) / S_j   (the engine's pair weights; w_t with t_j)

with n the target's outward normal at the projection (n_j: its N_j-weighted mean). Since
Σ_k D_jk = Σ_l M_jl = S_j the weights cancel (a rigid translation keeps the gap). A uniform
pressure p, λ_j = p t S_j, loads both surfaces with their consistent nodal forces p t ∫N, and a
linear displacement field (u = ε x, the Poisson expansion of the patch) gives zero relative
slip Σ_k D_jk u_k − Σ_l M_jl u_l = ∫N_j (u − u) = 0 in every row, so the contact patch test
passes to round-off for any ratio of the two meshes, with friction too. Plain node-to-segment
(the target weights of the single point closest to node j) does not; nor does lumping the
contactor side (e_j alone: its mean slip is then off by the N_j-centroid's offset, measured
1-4 % stress error with μ = 0.2). The contact force of row j is λ_j, its pressure λ_j/(S_j t).
The row of a contactor node that itself touches the target starts closed with gap 0: on a
curved contactor (a cylinder on a block) the weighted mean gap at the first point of contact is
second order in the element size, h²/(12R), and a contact that starts at one point must start
closed there (else nothing holds the body). `point_gap` is that node's own distance, `foot` its
closest target point (segment end nodes and parameter): the outputs report a row's gap and RTD
there, node by node as for the other kinds, not the row's weighted means.
A row whose contactor node is held tangentially by supports (a symmetry line) carries no stick
constraint, as a node-to-node pair there (the engine's `tangent_held`): with matching meshes
its slip row would repeat its neighbour's.

Axisymmetry (``radial=True``, x = r): every integral carries the ring's weight r, ds -> r ds
(the 2 pi cancels in the normalised weights): S_j = ∫ N_j r ds, D_jk = ∫ N_j N_k r ds, and so
on. A uniform pressure p then gives λ_j = 2π p S_j, the pressure of its ring area 2π ∫ N_j r ds,
at every row, the one at the axis included (planar weights would put there λ = 0: the mortar
multiplier of a linear force density 2π p r vanishes at r = 0), and the Coulomb limit μ λ_n of
each row is its ring's. ``length`` stays the plain tributary length ∫ N_j ds (the outputs'
areas are the ring areas of :func:`slipstep.contact.edges.contact_areas`).

Coverage: only the parts of the contactor surface whose closest target point is inside the
target polyline count. A contactor point whose projection falls beyond either end of the target
edge projects nowhere and adds nothing; a contactor node none of whose surface projects gets
no row. At a target vertex the closest point is the vertex and the normal the adjacent
segment's that is nearer (ties: the first): for small sliding on a smooth or flat target this
is the same surface.
"""

from __future__ import annotations

import numpy as np

from ..mesh import triangles as meshing

#: Gauss–Legendre points and weights on [0, 1]: three points integrate the products of two
#: linear shape functions (and a linear gap) exactly on every piece between breakpoints.
GAUSS_X = 0.5 + 0.5 * np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)])
GAUSS_W = np.array([5.0, 8.0, 5.0]) / 18.0


def _closest_on_target(x, nodes, target):
    """For points x (G, 2): target segment index, its parameter η in [0, 1], the closest point
    y, and whether the projection lies on the target (not beyond one of its free ends)."""
    a, b = nodes[target[:, 0]], nodes[target[:, 1]]
    d = b - a
    eta = np.einsum("gsk,sk->gs", x[:, None, :] - a[None], d) / np.einsum("sk,sk->s", d, d)
    clamped = np.clip(eta, 0.0, 1.0)
    y = a[None] + clamped[..., None] * d[None]
    seg = np.argmin(np.linalg.norm(x[:, None, :] - y, axis=2), axis=1)
    g = np.arange(len(x))
    ends = _free_ends(target)
    beyond = ((eta[g, seg] < 0.0) & np.isin(target[seg, 0], ends)) | (
        (eta[g, seg] > 1.0) & np.isin(target[seg, 1], ends)
    )
    return seg, clamped[g, seg], y[g, seg], ~beyond


def _free_ends(segments):
    """Nodes of a polyline used by one segment only."""
    ids, counts = np.unique(segments, return_counts=True)
    return ids[counts == 1]


def _breakpoints(p, q, nodes, target):
    """Parameters in (0, 1) along the contactor segment p→q where target vertices project."""
    d = q - p
    v = nodes[np.unique(target)]
    xi = (v - p) @ d / (d @ d)
    return np.unique(np.concatenate([[0.0, 1.0], xi[(xi > 0.0) & (xi < 1.0)]]))


def mortar_integrals(nodes, contactor, target, rows, radial: bool = False):
    """D, M (dicts row -> {node: integral}), G (row -> ∫N_j g), NS (row -> ∫N_j n) over the
    contactor segments touching a row node, with the weight r in axisymmetry (``radial``);
    L (row -> ∫N_j ds, unweighted, over the part that projects)."""
    normals = meshing.outward_normals(nodes, target)
    D, M = {j: {} for j in rows}, {j: {} for j in rows}
    G, NS, L = dict.fromkeys(rows, 0.0), {j: np.zeros(2) for j in rows}, dict.fromkeys(rows, 0.0)
    rowset = set(rows)
    for s0, s1 in contactor:
        if s0 not in rowset and s1 not in rowset:
            continue
        p, q = nodes[s0], nodes[s1]
        cuts = _breakpoints(p, q, nodes, target)
        xi = (cuts[:-1, None] + np.diff(cuts)[:, None] * GAUSS_X[None]).ravel()
        w = (np.diff(cuts)[:, None] * GAUSS_W[None]).ravel() * np.linalg.norm(q - p)
        x = p + xi[:, None] * (q - p)
        plain = w
        if radial:
            w = w * x[:, 0]
        seg, eta, y, on = _closest_on_target(x, nodes, target)
        n = normals[seg]
        gap = np.einsum("gk,gk->g", x - y, n)
        shape = {s0: 1.0 - xi, s1: xi}
        for j in (s0, s1):
            if j not in rowset:
                continue
            wj = np.where(on, w * shape[j], 0.0)
            L[j] += float(np.where(on, plain * shape[j], 0.0).sum())
            for k in (s0, s1):
                D[j][k] = D[j].get(k, 0.0) + float(wj @ shape[k])
            for end, hat in ((0, 1.0 - eta), (1, eta)):
                for l, v in zip(target[seg, end], wj * hat):
                    M[j][int(l)] = M[j].get(int(l), 0.0) + float(v)
            G[j] += float(wj @ gap)
            NS[j] += wj @ n
    return D, M, G, NS, L


def node_to_segment_pairs(nodes, contactor, target, candidates, min_length, radial: bool = False):
    """The rows of the contactor nodes `candidates` (see the module doc): arrays node_a,
    node_b (the target node of largest weight, for names), normal, gap, length (∫ N_j ds),
    and the weights as a list of [(node, c)] per row; ring-weighted in axisymmetry
    (``radial``). Rows with a length <= min_length are dropped (they project nowhere)."""
    D, M, G, NS, L = mortar_integrals(
        nodes, contactor, target, [int(j) for j in candidates], radial
    )
    out = {
        "node_a": [],
        "node_b": [],
        "normal": [],
        "gap": [],
        "point_gap": [],
        "foot": [],
        "length": [],
        "weights": [],
    }
    for j in candidates:
        j = int(j)
        S = sum(D[j].values())
        if L[j] <= min_length:
            continue
        n = NS[j] / np.linalg.norm(NS[j])
        out["node_a"].append(j)
        out["node_b"].append(max(M[j], key=lambda l: M[j][l]))
        out["normal"].append(n)
        out["gap"].append(G[j] / S)
        seg, eta, y, _ = _closest_on_target(nodes[j][None], nodes, target)
        out["point_gap"].append(
            float((nodes[j] - y[0]) @ meshing.outward_normals(nodes, target[seg])[0])
        )
        out["foot"].append((int(target[seg[0], 0]), int(target[seg[0], 1]), float(eta[0])))
        out["length"].append(L[j])
        out["weights"].append(
            [(k, v / S) for k, v in D[j].items() if v != 0.0]
            + [(l, -v / S) for l, v in M[j].items() if v != 0.0]
        )
    return out
