"""Hybrid mode: slipstep's event-driven contact on a user's dolfinx model.

The user keeps their dolfinx workflow (mesh, P1 vector space, UFL forms, Dirichlet
conditions, facet tags) and asks slipstep to solve frictional contact of the tagged boundary
against a rigid straight line::

    from slipstep.fenicsx.hybrid import solve_contact
    out = solve_contact(V, a, L, facet_tags, contact_tag, E=70e3, nu=0.3, bcs=[bc],
                        flat_point=(0, 0), flat_normal=(0, 1), mu=0.2)
    out.u          # dolfinx Function on V: the displacement at load fraction 1
    out.pressure   # dolfinx Function (P1 scalar): contact pressure at the contact nodes
    out.traction   # dolfinx Function (P1 scalar): tangential contact stress
    out.result     # the engine's result dict (events, steps, snapshots)

What is taken from where (the restriction): slipstep's engine is not a linear solver fed
with a matrix; it takes a mesh and its materials (docs/engine_api.md).  So

- the mesh comes from ``V`` (affine P1 triangles, 2D, serial), node i = dolfinx geometry
  node i, triangles made counter-clockwise;
- the material is isotropic linear elastic with the given ``E``, ``nu`` (scalars or per-cell
  arrays in dolfinx cell order), ``plane`` and ``thickness``;
- the bilinear form ``a`` is assembled with petsc4py and its CSR arrays
  (``Mat.getValuesCSR``) are checked against the CST stiffness of that mesh and material
  (``K x`` for random ``x``, relative 1e-10): a form that is not that operator is refused
  rather than silently replaced;
- the load is the assembled linear form ``L`` (the total load at load fraction 1);
- ``bcs`` must be homogeneous (u = 0 on their dofs; any dolfinx DirichletBC on V or V.sub(i));
- contact candidates: the vertices of the facets tagged ``contact_tag``; the pressure is
  lambda_n / (L_trib t), so that ``t * assemble(pressure * ds(contact_tag))`` is the total
  normal force exactly.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from . import dolfinx_api as api


@dataclass
class HybridResult:
    u: object  # dolfinx Function on V
    pressure: object  # dolfinx Function, P1 scalar
    traction: object  # dolfinx Function, P1 scalar (tangential, direction t = (-n_y, n_x))
    result: dict  # engine result
    model: dict  # engine model built from the dolfinx objects
    contact_nodes: np.ndarray  # geometry nodes of the candidate pairs
    tributary_length: np.ndarray
    operator_difference: float = float("nan")
    info: dict = field(default_factory=dict)

    def functions_at(self, k: int):
        """(u, pressure, traction) Functions of snapshot k of ``result``."""
        return _functions(self, self.result["snapshots"][k])


def cst_matvec(nodes, triangles, E, nu, plane: str, thickness: float, x: np.ndarray):
    """K x for the CST stiffness (dof = 2 node + component), vectorised."""
    from .plasticity import in_plane_d

    p = nodes[triangles]
    b = np.stack([p[:, 1, 1] - p[:, 2, 1], p[:, 2, 1] - p[:, 0, 1], p[:, 0, 1] - p[:, 1, 1]], 1)
    c = np.stack([p[:, 2, 0] - p[:, 1, 0], p[:, 0, 0] - p[:, 2, 0], p[:, 1, 0] - p[:, 0, 0]], 1)
    area2 = (
        p[:, 1, 0] * p[:, 2, 1]
        - p[:, 2, 0] * p[:, 1, 1]
        - p[:, 0, 0] * p[:, 2, 1]
        + p[:, 2, 0] * p[:, 0, 1]
        + p[:, 0, 0] * p[:, 1, 1]
        - p[:, 1, 0] * p[:, 0, 1]
    )
    M = len(triangles)
    B = np.zeros((M, 3, 6))
    B[:, 0, 0::2] = b
    B[:, 1, 1::2] = c
    B[:, 2, 0::2] = c
    B[:, 2, 1::2] = b
    B /= area2[:, None, None]
    D = in_plane_d(np.broadcast_to(E, (M,)), np.broadcast_to(nu, (M,)), plane)
    dofs = (2 * triangles[:, :, None] + np.arange(2)).reshape(M, 6)
    ue = x[dofs]
    fe = np.einsum("mji,mjk,mkl,ml->mi", B, D, B, ue) * (0.5 * np.abs(area2) * thickness)[:, None]
    out = np.zeros_like(x)
    np.add.at(out, dofs, fe)
    return out


def _csr_matvec(indptr, indices, values, x):
    y = np.zeros(len(indptr) - 1)
    rows = np.repeat(np.arange(len(indptr) - 1), np.diff(indptr))
    np.add.at(y, rows, values * x[indices])
    return y


def _mesh_arrays(V):
    """(nodes, counter-clockwise triangles, dof block of each geometry node) of V's mesh."""
    mesh = api.mesh_of(V)
    cell, degree, gdim = api.mesh_kind(mesh)
    if cell != "triangle" or degree != 1:
        raise ValueError("hybrid mode: the mesh must be affine (P1) triangles")
    if gdim != 2:
        raise ValueError("hybrid mode: the mesh must be 2D (gdim 2)")
    if api.block_size(V) != 2 or api.dofs_per_cell(V) != 3:
        raise ValueError("hybrid mode: V must be a P1 vector space with 2 components")
    nodes = np.ascontiguousarray(api.node_coordinates(mesh), dtype=np.float64)
    tris = api.cell_nodes(mesh).astype(np.int64)
    block_of_geom = np.empty(len(nodes), dtype=np.int64)
    block_of_geom[tris.ravel()] = api.cell_dofs(V).ravel()
    p = nodes[tris]
    area = 0.5 * (
        (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
        - (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0])
    )
    tris = np.where((area < 0)[:, None], tris[:, [0, 2, 1]], tris)
    return nodes, tris, block_of_geom


def _functions(out: HybridResult, snap: dict):
    """(u, pressure, traction) Functions of an engine snapshot."""
    V, Q = api.space_of(out.u), api.space_of(out.pressure)
    u = api.function(V, "u")
    api.dof_values(u).reshape(-1, 2)[out.info["block_of_geom"]] = np.asarray(snap["u"])
    p = api.function(Q, "contact_pressure")
    tr = api.function(Q, "contact_traction")
    q = out.info["q_of_geom"][out.contact_nodes]
    area = out.tributary_length * out.model["thickness"]
    api.dof_values(p)[q] = np.asarray(snap["lambda_n"]) / area
    api.dof_values(tr)[q] = np.asarray(snap["lambda_t"]) / area
    for f in (u, p, tr):
        api.scatter(f)
    return u, p, tr


def _fixed_dofs(V, bcs, perm: np.ndarray) -> np.ndarray:
    """slipstep dofs held by homogeneous Dirichlet conditions ``bcs`` (refuses others)."""
    if not bcs:
        return np.zeros(0, dtype=np.int64)
    dofs, values = api.dirichlet_values(V, bcs)
    if np.abs(values).max(initial=0.0) != 0.0:
        raise ValueError(
            "hybrid mode: the Dirichlet conditions must be homogeneous (u = 0):"
            " slipstep's engine holds fixed dofs at zero"
        )
    inv = np.empty(len(perm), dtype=np.int64)
    inv[perm] = np.arange(len(perm))
    return np.unique(inv[dofs])


def _operator_difference(a_form, perm, nodes, tris, E, nu, plane: str, thickness: float):
    """max |A x - K x| / max |K x| over three random x: A the assembled form (CSR from
    petsc4py), K the CST stiffness of the mesh and material."""
    A = api.assemble_matrix(a_form)
    indptr, indices, values = api.csr(A)
    api.destroy(A)
    rng = np.random.default_rng(0)
    worst = 0.0
    for _ in range(3):
        xs = rng.normal(size=len(perm))
        xd = np.zeros(len(perm))
        xd[perm] = xs
        ya = _csr_matvec(indptr, indices, values, xd)[perm]
        yk = cst_matvec(nodes, tris, E, nu, plane, thickness, xs)
        worst = max(worst, np.abs(ya - yk).max() / np.abs(yk).max())
    return float(worst)


def _candidates(mesh, facet_tags, contact_tag: int, nodes: np.ndarray):
    """(candidate geometry nodes, their tributary lengths): the vertices of the tagged facets."""
    facets = api.tagged(facet_tags, contact_tag)
    if len(facets) == 0:
        raise ValueError(f"hybrid mode: no facet carries the contact tag {contact_tag}")
    segs = api.facet_nodes(mesh, facets)
    seg_len = np.linalg.norm(nodes[segs[:, 1]] - nodes[segs[:, 0]], axis=1)
    trib = np.zeros(len(nodes))
    np.add.at(trib, segs[:, 0], 0.5 * seg_len)
    np.add.at(trib, segs[:, 1], 0.5 * seg_len)
    cand = np.unique(segs)
    return cand, trib[cand]


def _initial_gap(nodes, cand, flat_point, n, tolerance: float) -> np.ndarray:
    """Gap of each candidate to the flat (refuses penetration; |gap| <= tolerance -> 0)."""
    gap = (nodes[cand] - np.asarray(flat_point, dtype=float)) @ n
    if (gap < -tolerance).any():
        k = int(np.argmin(gap))
        raise ValueError(
            f"hybrid mode: initial penetration at node {int(cand[k])} "
            f"({nodes[cand[k], 0]:.6g}, {nodes[cand[k], 1]:.6g}) by {-gap[k]:.3g}"
        )
    return np.where(np.abs(gap) <= tolerance, 0.0, gap)


def solve_contact(
    V,
    a,
    L,
    facet_tags,
    contact_tag: int,
    *,
    E,
    nu,
    plane: str = "strain",
    thickness: float = 1.0,
    bcs=(),
    flat_point=(0.0, 0.0),
    flat_normal=(0.0, 1.0),
    mu: float = 0.0,
    tolerance: float = 1e-9,
    fractions=None,
    options: dict | None = None,
    check_operator: bool = True,
    progress: bool = False,
) -> HybridResult:
    """Run slipstep's event loop on a dolfinx elastic model in contact with a rigid line.

    ``a``, ``L``: UFL forms (or compiled dolfinx forms) on V; ``facet_tags``: dolfinx MeshTags
    of dimension 1; ``contact_tag``: the candidate surface's value; ``fractions``: extra load
    fractions to keep snapshots at (1.0 is always kept).  See the module doc.
    """
    from ..runner import engine

    if plane not in ("strain", "stress"):
        raise ValueError(
            f"hybrid mode: plane = {plane!r} is not supported; the hybrid mode checks "
            f"and solves plane CST models only ('strain' or 'stress'); for an "
            f"axisymmetric scene run slipstep itself and cross-check with "
            f"slipstep.fenicsx.bulk"
        )
    api.require_dolfinx()
    nodes, tris, block_of_geom = _mesh_arrays(V)
    M = len(tris)
    perm = (2 * block_of_geom[:, None] + np.arange(2)).ravel()  # slipstep dof -> V dof
    E_c = np.broadcast_to(np.asarray(E, dtype=float), (M,))
    nu_c = np.broadcast_to(np.asarray(nu, dtype=float), (M,))
    mats, element_material = np.unique(np.stack([E_c, nu_c], 1), axis=0, return_inverse=True)
    load = api.assemble_vector(L)[perm]  # fraction 1, slipstep numbering
    fixed = _fixed_dofs(V, bcs, perm)
    op_diff = float("nan")
    if check_operator:
        op_diff = _operator_difference(a, perm, nodes, tris, E_c, nu_c, plane, thickness)
        if op_diff > 1e-10:
            raise ValueError(
                f"hybrid mode: the bilinear form is not the plane-{plane} CST "
                f"elasticity operator of the E, nu and thickness given "
                f"(relative difference {op_diff:.3g}): slipstep's engine takes the "
                f"mesh and an isotropic elastic material, not a matrix; pass the "
                f"E, nu, plane, thickness your form uses"
            )
    mesh = api.mesh_of(V)
    cand, trib = _candidates(mesh, facet_tags, contact_tag, nodes)
    n = np.asarray(flat_normal, dtype=float)
    n = n / np.linalg.norm(n)
    opts = {
        "output": "fractions",
        "fractions": np.asarray(sorted(set(fractions or ()) | {1.0}), dtype=float),
    }
    opts.update(options or {})
    model = {
        "nodes": nodes,
        "triangles": tris,
        "element_material": element_material.astype(np.int64),
        "materials": [{"E": float(e), "nu": float(v)} for e, v in mats],
        "plane": plane,
        "thickness": float(thickness),
        "fixed_dofs": fixed,
        "load": load,
        "pairs": {
            "node_a": cand.astype(np.int64),
            "node_b": np.full(len(cand), -1, np.int64),
            "normal": np.tile(n, (len(cand), 1)),
            "gap": _initial_gap(nodes, cand, flat_point, n, tolerance),
            "mu": np.full(len(cand), float(mu)),
        },
        "options": opts,
    }
    result = engine().solve(model, progress)

    Q = api.function_space(mesh, "Lagrange", 1)
    q_of_geom = np.empty(len(nodes), dtype=np.int64)
    q_of_geom[api.cell_nodes(mesh)] = api.cell_dofs(Q)
    out = HybridResult(
        u=api.function(V),
        pressure=api.function(Q),
        traction=api.function(Q),
        result=result,
        model=model,
        contact_nodes=cand,
        tributary_length=trib,
        operator_difference=op_diff,
        info={"block_of_geom": block_of_geom, "q_of_geom": q_of_geom},
    )
    out.u, out.pressure, out.traction = _functions(out, result["snapshots"][-1])
    return out
