"""Case + meshes -> the engine's ``model`` dict (docs/engine_api.md).

Everything here is set up once, vectorised where it matters; the event loop itself is the
engine's.  Besides the model, :class:`Scene` keeps what the output needs and the engine does
not: which body each node belongs to, each candidate pair's node position, tributary length
and contact area (contact pressure = lambda_n / area), the Hertz reference when it applies, and
the load path (named loads, stages, factors, supports and prescribed displacements).

Plane strain, plane stress and axisymmetry (``[analysis] plane``) differ here only in how a
boundary integral is weighted (:func:`boundary_shares`: t ds, or 2 pi r ds over the full ring),
which edge loads, point loads, contact areas and the supports on the axis x = 0 follow.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from . import mesh as meshing
from . import mortar
from .case import Case
from .errors import CaseError, InputError
from .loadpath import Load, LoadPath, case_loads
from .overrides import element_key
from .schema import RIGID_KINDS, block_divisions
from .references import effective_modulus, hertz_line, hertz_sphere


@dataclass
class Scene:
    """The assembled problem: global mesh, the engine model, and per-pair bookkeeping."""

    case: Case
    bodies: list[str]
    meshes: dict[str, meshing.Mesh]
    offsets: dict[str, int]           # first global node id of each body
    nodes: np.ndarray                 # (N, 2)
    triangles: np.ndarray             # (M, 3)
    element_body: np.ndarray          # (M,) index into bodies
    model: dict                       # the engine model
    pair_xy: np.ndarray               # (P, 2) position of node_a
    pair_length: np.ndarray           # (P,) tributary length of node_a on its candidate edge
    pair_contact: np.ndarray          # (P,) index of the [[contact]] entry it came from
    # (P,) the area its contact force acts on: L t, or its ring 2 pi int N_a r ds (contact_areas)
    pair_area: np.ndarray = field(default_factory=lambda: np.zeros(0))
    # node-to-segment rows: node a's closest target point (end nodes l1, l2 and parameter eta)
    # and its own initial gap, where the outputs measure gap and RTD; (-1, -1, 0) and nan else
    pair_foot: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    pair_point_gap: np.ndarray = field(default_factory=lambda: np.zeros(0))
    # per [[contact]]: True when some nodes of its candidate edge are not candidates (window,
    # no partner), so contact reaching the outermost candidate may be cut short
    contact_truncated: list = field(default_factory=list)
    reference: dict = field(default_factory=dict)  # Hertz a, p0 when the case is Hertz-like
    # the load path (docs: cases/README.md, [[stage]]); see build_scene
    load_names: list = field(default_factory=lambda: ["load"])  # factor order, "load" first
    stage_names: list = field(default_factory=lambda: ["stage 1"])
    n_stages: int = 1
    support_dofs: dict = field(default_factory=dict)  # bc name -> (k,) DOFs it holds
    prescribed: dict = field(default_factory=dict)    # load name -> {"dofs", "values"}
    motions: dict = field(default_factory=dict)       # load name -> {"contact", "motion"}
    factors: np.ndarray = field(default_factory=lambda: np.array([[0.0], [1.0]]))

    @property
    def n_dofs(self) -> int:
        return 2 * len(self.nodes)

    def global_edge(self, body: str, tag: str) -> np.ndarray:
        """Segments of a body's edge tag in global node numbers (body on the left)."""
        return self.meshes[body].edges[tag] + self.offsets[body]


def mesh_body(case: Case, index: int) -> meshing.Mesh:
    """Mesh one body from its [body.mesh] table."""
    body = case.data["body"][index]
    spec = body["mesh"]
    where = f"body {body['name']!r}"
    if spec.get("generator") == "given":
        raise CaseError(f'{case.source}: body.{body["name"]}.mesh.generator = "given": pass '
                        f'its mesh from Python, slipstep.run(case, meshes={{"{body["name"]}": '
                        f'mesh}}) (slipstep.mesh.from_arrays or from_meshio)')
    try:
        if spec.get("file"):
            path = (case.base_dir / spec["file"])
            edge_file = case.base_dir / spec["edge_file"] if spec["edge_file"] else None
            return meshing.read_mesh(path, edge_file, spec["scale"])
        if spec["generator"] in ("quarter_cylinder", "half_cylinder", "disc"):
            make = getattr(meshing, spec["generator"])
            return make(spec["R"], spec["h_contact"], spec["contact_zone"], spec["h_max"],
                        spec["growth"])
        if spec["generator"] == "quarter_annulus":
            return meshing.quarter_annulus(spec["a"], spec["b"], spec["h"], spec["h_outer"])
        if spec["h_contact"] > 0:  # the graded block (gmsh); else the structured one
            return meshing.graded_block(spec["width"], spec["height"], spec["h_contact"],
                                        spec["contact_zone"], spec["h_max"], spec["growth"],
                                        spec["focus"], spec["x0"], spec["y0"],
                                        spec["uniform_edges"])
        nx, ny = block_divisions(spec)
        if spec["refine_box"] is not None:  # the structured grid inside it, coarse outside
            return meshing.refined_block(spec["width"], spec["height"], nx, ny,
                                         spec["refine_box"], spec["h_max"], spec["growth"],
                                         spec["x0"], spec["y0"])
        return meshing.block(spec["width"], spec["height"], nx, ny, spec["x0"], spec["y0"])
    except meshing.MeshError as exc:
        raise CaseError(f"{case.source}: {where}: {exc}") from None


def build_scene(case: Case, meshes: dict[str, meshing.Mesh] | None = None) -> Scene:
    """Mesh every body (except those whose mesh ``meshes`` gives, by body name), merge them,
    and build the engine model."""
    data = case.data
    bodies = [b["name"] for b in data["body"]]
    given = dict(meshes or {})
    unknown = sorted(set(given) - set(bodies))
    if unknown:
        raise InputError(f"build_scene: meshes given for {', '.join(map(repr, unknown))}, "
                         f"which the case has no body of (its bodies: {', '.join(bodies)})")
    body_meshes = {name: given[name] if name in given else mesh_body(case, i)
                   for i, name in enumerate(bodies)}
    _check_file_mesh_tags(case, body_meshes)

    offsets, start = {}, 0
    for name in bodies:
        offsets[name] = start
        start += body_meshes[name].n_nodes
    nodes = np.concatenate([body_meshes[b].nodes for b in bodies])
    triangles = np.concatenate([body_meshes[b].triangles + offsets[b] for b in bodies])
    element_body = np.concatenate([np.full(body_meshes[b].n_elements, i, dtype=np.int64)
                                   for i, b in enumerate(bodies)])

    scene = Scene(case=case, bodies=bodies, meshes=body_meshes, offsets=offsets, nodes=nodes,
                  triangles=triangles, element_body=element_body, model={},
                  pair_xy=np.zeros((0, 2)), pair_length=np.zeros(0),
                  pair_contact=np.zeros(0, dtype=np.int64))
    _check_radii(scene)
    pairs = contact_pairs(scene)
    _check_duplicate_nodes(scene, pairs)
    path = case.path
    fixed = supports(scene)
    scene.model = {
        "nodes": nodes,
        "triangles": triangles,
        "element_material": element_body.copy(),
        "materials": materials(case),
        "plane": data["analysis"]["plane"],
        "thickness": float(data["analysis"]["thickness"]),  # the engine ignores it for rings
        "fixed_dofs": fixed,
        "load": load_vector(scene) if not path.staged else load_force(scene, path.head),
        "pairs": pairs,
        "options": solver_options(case),
        # names for the engine's messages (docs/engine_api.md)
        "body_names": list(bodies),
        "element_body": element_body,
        "contact_names": contact_names(case),
    }
    scene.pair_area = contact_areas(scene)
    set_load_path(scene, path)
    _check_pairs_not_held(scene)
    _check_stick_on_half_held(scene)
    scene.reference = hertz_reference(scene)
    return scene


def materials(case: Case) -> list[dict]:
    """The engine's material of each body, in body order (``Sy``, ``H`` only when plastic)."""
    out = []
    for b in case.data["body"]:
        m = {"E": b["material"]["E"], "nu": b["material"]["nu"]}
        if b["material"]["Sy"] is not None:
            m["Sy"] = b["material"]["Sy"]
            m["H"] = b["material"]["H"] if b["material"]["H"] is not None else 0.0
        out.append(m)
    return out


def contact_names(case: Case) -> list[str]:
    """The name of each [[contact]]: its ``name``, else ``contact <i>`` (0-based)."""
    return [c["name"] or f"contact {i}" for i, c in enumerate(case.data["contact"])]


def contactor_edge(contact: dict) -> tuple[str, str]:
    """(body, edge tag) of a [[contact]]'s contactor side: the deformable body of a
    rigid obstacle (``rigid_line``, ``rigid_circle``, ``rigid_polyline``), body_a/edge_a of a
    deformable pair."""
    if contact["kind"] in RIGID_KINDS:
        return contact["body"], contact["edge"]
    return contact["body_a"], contact["edge_a"]


def contact_bodies(contact: dict) -> list[str]:
    """The deformable bodies a [[contact]] touches, contactor first."""
    if contact["kind"] in RIGID_KINDS:
        return [contact["body"]]
    return [contact["body_a"], contact["body_b"]]


def _check_duplicate_nodes(scene: Scene, pairs: dict) -> None:
    """Two nodes of one body at the same point cut the mesh there (a crack, or parts that are
    not connected): allowed only when a node_to_node contact pairs them."""
    joined = {(min(a, b), max(a, b)) for a, b in zip(pairs["node_a"].tolist(),
                                                      pairs["node_b"].tolist()) if b >= 0}
    for name in scene.bodies:
        xy = scene.meshes[name].nodes
        if len(xy) < 2:
            continue
        size = float(np.ptp(xy, axis=0).max()) or 1.0
        key = np.round(xy / (1e-9 * size)).astype(np.int64)
        _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
        inverse = inverse.reshape(-1)
        for group in np.flatnonzero(counts > 1):
            ids = np.flatnonzero(inverse == group) + scene.offsets[name]
            for i, j in zip(ids[:-1], ids[1:]):
                if (int(i), int(j)) not in joined:
                    x, y = scene.nodes[i]
                    raise CaseError(
                        f"{scene.case.source}: body '{name}': nodes {int(i) - scene.offsets[name]}"
                        f" and {int(j) - scene.offsets[name]} are both at ({x:.6g}, {y:.6g}) but "
                        f"are not joined: duplicate nodes cut the mesh there (a crack or "
                        f"unconnected parts); merge them (gmsh: Coherence), or pair the two "
                        f"sides with a node_to_node [[contact]]")


def _check_pairs_not_held(scene: Scene) -> None:
    """A pair whose normal direction is entirely held by supports or prescribed displacements
    can carry no contact force (the engine refuses it too; here the message can name the case
    key)."""
    pairs, fixed = scene.model["pairs"], np.zeros(2 * len(scene.nodes), dtype=bool)
    fixed[scene.model["fixed_dofs"]] = True
    for p in scene.prescribed.values():
        fixed[p["dofs"]] = True
    n = pairs["normal"]
    free = np.zeros(len(n), dtype=bool)
    for node in (pairs["node_a"], pairs["node_b"]):
        ok = node >= 0
        for c in (0, 1):
            free[ok] |= (n[ok, c] != 0.0) & ~fixed[2 * node[ok] + c]
    if not free.all():
        k = int(np.argmin(free))
        i = int(pairs["node_a"][k])
        c = int(scene.pair_contact[k])
        key = "contact" if len(scene.case.data["contact"]) == 1 else f"contact.{c}"
        x, y = scene.nodes[i]
        raise scene.case.error(key, f"node {i} ({x:.6g}, {y:.6g}) is held by supports in the "
                               f"contact normal direction, so its pair can carry no contact "
                               f"force: remove the support ([[bc]] fix/symmetry/displacement) "
                               f"there or the node from the candidates (x_min/x_max/y_min/"
                               f"y_max)")


def _check_stick_on_half_held(scene: Scene) -> None:
    """A frictional pair of a rigid circle or polyline on a node with one component held (a
    symmetry line) would close in stick with its normal and tangential conditions both acting
    on the one free component (a singular system), unless its normal or tangent lies along the
    held component (the engine's tolerance 1e-12; the normal entirely held is refused above).
    Refused with the fix (the rigid line's fixed normal is the user's, and is left to the
    engine)."""
    pairs, contacts = scene.model["pairs"], scene.case.data["contact"]
    fixed = np.zeros(2 * len(scene.nodes), dtype=bool)
    fixed[scene.model["fixed_dofs"]] = True
    for p in scene.prescribed.values():
        fixed[p["dofs"]] = True
    a, n = np.asarray(pairs["node_a"]), np.asarray(pairs["normal"])
    curved = np.isin(np.array([c["kind"] for c in contacts] or [""])[scene.pair_contact],
                     ("rigid_circle", "rigid_polyline"))
    held_x, held_y = fixed[2 * a], fixed[2 * a + 1]
    free = np.where(held_x, 1, 0)  # the one free component when exactly one is held
    n_free = np.abs(n[np.arange(len(a)), free])
    t_free = np.abs(n[np.arange(len(a)), 1 - free])  # t = (-n_y, n_x): t_x = -n_y, t_y = n_x
    bad = (curved & (held_x != held_y) & (np.asarray(pairs["mu"]) > 0.0)
           & (n_free >= 1e-12) & (t_free >= 1e-12))
    if bad.any():
        k = int(np.argmax(bad))
        i, c = int(a[k]), int(scene.pair_contact[k])
        key = "contact" if len(contacts) == 1 else f"contact.{c}"
        x, y = scene.nodes[i]
        held, other = ("x", "y") if held_x[k] else ("y", "x")
        raise scene.case.error(key, f"node {i} ({x:.6g}, {y:.6g}) is held in {held} by "
                               f"supports and its contact normal ({n[k, 0]:.6g}, {n[k, 1]:.6g}) "
                               f"is oblique to {other}, its free component: with mu > 0 it would "
                               f"stick with both contact conditions on that one component (a "
                               f"singular system); make the obstacle's normal there along "
                               f"{other} (on a symmetry line: the circle's centre, or a polyline "
                               f"vertex between mirrored segments or a segment across it at a "
                               f"right angle), or leave the node out of the candidates "
                               f"(x_min/x_max/y_min/y_max)")


def _check_radii(scene: Scene) -> None:
    """Axisymmetry: x is the radius r >= 0; an element with a node at x < 0 (beyond round-off,
    AXIS_TOLERANCE of the scene's size) is an error naming the body, element and node."""
    if not is_axisymmetric(scene.case):
        return
    size = float(np.linalg.norm(np.ptp(scene.nodes, axis=0))) or 1.0
    for name in scene.bodies:
        mesh = scene.meshes[name]
        left = (mesh.nodes[mesh.triangles, 0] < -AXIS_TOLERANCE * size).any(axis=1)
        if left.any():
            e = int(np.argmax(left))
            node = int(mesh.triangles[e][np.argmin(mesh.nodes[mesh.triangles[e], 0])])
            x, y = mesh.nodes[node]
            raise CaseError(f"{scene.case.source}: body '{name}': element {e} has node {node} at "
                            f'({x:.6g}, {y:.6g}), x < 0: with analysis.plane = "axisymmetric" '
                            f"x is the radius r >= 0 (the axis is x = 0); move the body to "
                            f'x >= 0, or use plane = "strain"')


def _check_file_mesh_tags(case: Case, body_meshes: dict) -> None:
    """Edge tags of file meshes are only known now: check the BCs and contacts that use them."""
    data = case.data
    uses = []  # (key, body, tag)
    for i, bc in enumerate(data["bc"]):
        k = "bc." if len(data["bc"]) == 1 else f"bc.{i}."
        if bc["edge"]:
            uses.append((k + "edge", bc["body"], bc["edge"], "edges"))
        if bc["nodes"]:
            uses.append((k + "nodes", bc["body"], bc["nodes"], "node_sets"))
    for i, c in enumerate(data["contact"]):
        k = "contact." if len(data["contact"]) == 1 else f"contact.{i}."
        if c["kind"] in RIGID_KINDS:
            uses.append((k + "edge", c["body"], c["edge"], "edges"))
        else:
            for s in "ab":
                uses.append((f"{k}edge_{s}", c[f"body_{s}"], c[f"edge_{s}"], "edges"))
    for key, body, tag, kind in uses:
        known = getattr(body_meshes[body], kind)
        if tag not in known:
            what = "edge" if kind == "edges" else "node set"
            raise CaseError(f'{case.source}: {key} = "{tag}" is not allowed: body "{body}" has '
                            f"no {what} with that tag (its {what}s: {', '.join(known) or 'none'})")


# --------------------------------------------------------------------------- supports
def supports(scene: Scene) -> np.ndarray:
    """The engine's ``fixed_dofs``: ``fix`` components, and ``symmetry`` = the normal component
    of an edge parallel to an axis (dof = 2*node + component).  Fills ``scene.support_dofs``
    (per bc name: its fix, symmetry and displacement DOFs) and ``scene.prescribed`` (per load
    name: the displacement DOFs and their values at factor 1, never among the fixed ones)."""
    bcs = scene.case.data["bc"]
    holder = np.full(2 * len(scene.nodes), -1, dtype=np.int64)  # the bc fixing each DOF
    fixed, scene.support_dofs, scene.prescribed = [], {}, {}
    for i, bc in enumerate(bcs):
        nodes = _bc_nodes(scene, bc)
        components = {"xy".index(c) for c in bc["fix"]}
        if bc["symmetry"]:
            components.add(_symmetry_component(scene, bc, element_key("bc", bcs, i)))
        dofs = [2 * nodes + c for c in sorted(components)]
        fixed.extend(dofs)
        for d in dofs:
            holder[d[holder[d] < 0]] = i
        _add_support(scene, bc["name"] or f"bc {i}", dofs)
    owner = holder.copy()  # the bc fixing or prescribing each DOF
    for load in case_loads(scene.case.data):
        if load.array == "bc" and load.kinematic:
            dofs, values = _prescribed(scene, load, owner, holder)
            scene.prescribed[load.label] = {"dofs": dofs, "values": values}
            _add_support(scene, bcs[load.index]["name"] or f"bc {load.index}", [dofs])
    if is_axisymmetric(scene.case):
        fixed.append(_axis_supports(scene))
    if not fixed:
        return np.zeros(0, dtype=np.int64)
    return np.unique(np.concatenate(fixed)).astype(np.int64)


def _axis_supports(scene: Scene) -> np.ndarray:
    """Axisymmetry: u_r = 0 at every node on the axis x = 0 (within 1e-9 of the scene's size,
    the engine's AXIS_TOLERANCE; the engine adds them too); a prescribed radial displacement
    there is an error naming the [[bc]]."""
    size = float(np.linalg.norm(np.ptp(scene.nodes, axis=0))) or 1.0
    dofs = 2 * np.flatnonzero(np.abs(scene.nodes[:, 0]) <= AXIS_TOLERANCE * size)
    for name, p in scene.prescribed.items():
        clash = np.isin(p["dofs"], dofs)
        if clash.any():
            node = int(p["dofs"][np.argmax(clash)]) // 2
            load = next(x for x in case_loads(scene.case.data) if x.label == name)
            raise scene.case.error(f"{load.key}.displacement.x", f"node {node} (0, "
                                   f"{scene.nodes[node, 1]:.6g}) lies on the axis x = 0, where "
                                   f'plane = "axisymmetric" holds u_r = 0 already: drop x '
                                   f"from displacement, or use a node set off the axis")
    return dofs.astype(np.int64)


def _add_support(scene: Scene, name: str, dofs: list) -> None:
    """Add DOFs to a bc's entry of ``scene.support_dofs`` (bcs sharing a name share it; a bc
    that holds nothing, a pure force load, has none)."""
    if name not in scene.support_dofs and not any(len(d) for d in dofs):
        return
    old = scene.support_dofs.get(name, np.zeros(0, dtype=np.int64))
    scene.support_dofs[name] = np.unique(np.concatenate([old, *dofs])).astype(np.int64)


def _bc_nodes(scene: Scene, bc: dict) -> np.ndarray:
    """Global ids (sorted, unique) of the nodes of a [[bc]]'s edge or node set."""
    mesh = scene.meshes[bc["body"]]
    nodes = mesh.edge_nodes(bc["edge"]) if bc["edge"] else mesh.node_sets[bc["nodes"]]
    return np.unique(np.asarray(nodes, dtype=np.int64)) + scene.offsets[bc["body"]]


def _symmetry_component(scene: Scene, bc: dict, key: str) -> int:
    """The component a ``symmetry`` edge holds: x for a vertical edge, y for a horizontal one
    (each segment normal within 1e-9 of the axis: straight up to round-off)."""
    n = meshing.outward_normals(scene.nodes, scene.global_edge(bc["body"], bc["edge"]))
    for c in (0, 1):
        if np.all(np.abs(n[:, c]) > 1 - 1e-9):
            if "xy"[c] in bc["displacement"]:
                raise scene.case.error(f"{key}.displacement.{'xy'[c]}", f"symmetry = true "
                                       f"holds {'xy'[c]} on edge '{bc['edge']}' (its normal "
                                       f"component): a component is held or prescribed, not "
                                       f"both; remove symmetry or {'xy'[c]} from displacement")
            return c
    raise scene.case.error(f"{key}.symmetry", f"edge '{bc['edge']}' is not a straight line "
                           f"parallel to the x or y axis: use fix = [...] instead")


def _prescribed(scene: Scene, load: Load, owner: np.ndarray, holder: np.ndarray):
    """(dofs, values) of a displacement [[bc]], sorted by DOF; a DOF already fixed or
    prescribed by another [[bc]] is an error (the engine eliminates each DOF once)."""
    bcs = scene.case.data["bc"]
    bc = bcs[load.index]
    nodes = _bc_nodes(scene, bc)
    comps = sorted("xy".index(c) for c in bc["displacement"])
    dofs = np.concatenate([2 * nodes + c for c in comps])
    values = np.concatenate([np.full(len(nodes), bc["displacement"]["xy"[c]]) for c in comps])
    order = np.argsort(dofs, kind="stable")
    dofs, values = dofs[order], values[order]
    clash = owner[dofs] >= 0
    if clash.any():
        d = int(dofs[np.argmax(clash)])
        c, (x, y) = "xy"[d % 2], scene.nodes[d // 2]
        how = "fix/symmetry" if holder[d] >= 0 else "displacement"
        raise scene.case.error(f"{load.key}.displacement.{c}", f"node {d // 2} ({x:.6g}, "
                               f"{y:.6g}) is also held in {c} by "
                               f"{element_key('bc', bcs, int(owner[d]))} ({how}): each "
                               f"component is fixed or prescribed once; drop {c} from one of "
                               f'them (a zero component is a support: fix = ["{c}"] may '
                               f"overlap others), or use a node set without that node")
    owner[dofs] = load.index
    return dofs.astype(np.int64), values.astype(np.float64)


# --------------------------------------------------------------------------- the section
#: A node within this x the scene's size of x = 0 lies on the axis (the engine's AXIS_TOLERANCE).
AXIS_TOLERANCE = 1e-9


def is_axisymmetric(case: Case) -> bool:
    """True for ``[analysis] plane = "axisymmetric"`` (x = r, y = z, rings about x = 0)."""
    return case.data["analysis"]["plane"] == "axisymmetric"


def boundary_shares(nodes: np.ndarray, segments: np.ndarray, plane: str,
                    thickness: float) -> np.ndarray:
    """(S, 2): int N_k w ds over each linear segment for its end nodes k = 0, 1, the weight of a
    uniform traction at each end (its consistent nodal force = traction x share, exact for
    linear N).  Plane strain and plane stress: w = t, so t L/2 each; axisymmetric: w = 2 pi r,
    the full ring, so 2 pi L (2 r_k + r_other)/6 (r linear along the segment)."""
    length = np.linalg.norm(nodes[segments[:, 1]] - nodes[segments[:, 0]], axis=1)
    if plane == "axisymmetric":
        r0, r1 = nodes[segments[:, 0], 0], nodes[segments[:, 1], 0]
        return (2.0 * math.pi / 6.0) * length[:, None] * np.stack([2 * r0 + r1, r0 + 2 * r1], 1)
    half = 0.5 * (length * thickness)
    return np.stack([half, half], axis=1)


def node_shares(nodes: np.ndarray, segments: np.ndarray, plane: str, thickness: float,
                ids: np.ndarray) -> np.ndarray:
    """Sum of :func:`boundary_shares` at each node of ``ids`` over the segments touching it:
    t L (L the tributary length) in the plane, int N_i 2 pi r ds (its ring) in axisymmetry."""
    per_node = np.zeros(len(nodes))
    if len(segments):
        share = boundary_shares(nodes, segments, plane, thickness)
        np.add.at(per_node, segments[:, 0], share[:, 0])
        np.add.at(per_node, segments[:, 1], share[:, 1])
    return per_node[ids]


def contact_areas(scene: Scene) -> np.ndarray:
    """(P,) the area each candidate pair's contact force acts on (pressure = lambda_n / area):
    node a's tributary length L x the thickness in plane strain and plane stress; in
    axisymmetry its ring over the contactor edge, 2 pi int N_a r ds (:func:`node_shares`;
    2 pi r L inside a uniformly divided edge, pi L^2/3 at the axis with L its segment), times
    L / L_edge for a node-to-segment row (the part of its surface that projects).  This is the
    consistent area: a uniform pressure p puts lambda = p x area on every node, so a smooth
    pressure is read node by node to O(h^2), also at the axis (the lumped disc pi (L/2)^2 there
    would read it 4/3 too high)."""
    data = scene.case.data
    plane, t = data["analysis"]["plane"], data["analysis"]["thickness"]
    if plane != "axisymmetric":
        return scene.pair_length * t
    pairs = scene.model["pairs"]
    area = np.zeros(len(scene.pair_length))
    for i, c in enumerate(data["contact"]):
        mine = np.flatnonzero(scene.pair_contact == i)
        seg = scene.global_edge(*contactor_edge(c))
        a = pairs["node_a"][mine]
        area[mine] = node_shares(scene.nodes, seg, plane, t, a)
        if c["kind"] == "node_to_segment":
            area[mine] *= scene.pair_length[mine] / tributary_lengths(scene.nodes, seg, a)
    return area


# --------------------------------------------------------------------------- loads
def edge_load(nodes: np.ndarray, segments: np.ndarray, n_nodes: int, thickness: float,
              pressure: float = 0.0, traction=(0.0, 0.0), plane: str = "strain") -> np.ndarray:
    """Consistent nodal loads of a uniform pressure and/or traction on linear edge segments.

    Traction on a segment: t = traction - pressure * n (n outward); each end node gets t times
    its :func:`boundary_shares` (half of t L thickness in the plane; in axisymmetry the ring
    load 2 pi int N_i r t ds).  Returns a (2 n_nodes,) vector.
    """
    f = np.zeros(2 * n_nodes)
    if len(segments) == 0:
        return f
    t = np.asarray(traction, dtype=np.float64)[None, :] - pressure * meshing.outward_normals(nodes, segments)
    share = boundary_shares(nodes, segments, plane, thickness)
    for end in (0, 1):
        force = t * share[:, end, None]
        for c in (0, 1):
            np.add.at(f, 2 * segments[:, end] + c, force[:, c])
    return f


def load_vector(scene: Scene) -> np.ndarray:
    """The summed nodal force at load fraction 1 of a case without [[stage]] (``[[bc]]``
    pressure/traction, ``[load] P``, ``[[point_load]]``, in this order), thickness included."""
    rank = {"bc": 0, "load": 1, "point_load": 2}
    f = np.zeros(2 * len(scene.nodes))
    for load in sorted((x for x in case_loads(scene.case.data) if x.force),
                       key=lambda x: rank[x.array]):
        f += load_force(scene, load)
    return f


def load_force(scene: Scene, load: Load | None) -> np.ndarray:
    """The nodal force of one load at factor 1, thickness included (ring totals in
    axisymmetry; zeros for None or a load without force)."""
    data, n = scene.case.data, len(scene.nodes)
    t, plane = data["analysis"]["thickness"], data["analysis"]["plane"]
    f = np.zeros(2 * n)
    if load is None or not load.force:
        return f
    if load.array == "load":
        return edge_load(scene.nodes, scene.global_edge(data["load"]["body"], "top"), n, t,
                         pressure=hertz_cut_pressure(scene.case), plane=plane)
    if load.array == "bc":
        bc = data["bc"][load.index]
        return edge_load(scene.nodes, scene.global_edge(bc["body"], bc["edge"]), n, t,
                         bc["pressure"], bc["traction"], plane=plane)
    pl = data["point_load"][load.index]
    candidates = ([pl["body"]] if pl["body"] else scene.bodies)
    ids = np.concatenate([np.arange(scene.meshes[b].n_nodes) + scene.offsets[b]
                          for b in candidates])
    node = ids[np.argmin(np.linalg.norm(scene.nodes[ids] - np.asarray(pl["at"]), axis=1))]
    f[2 * node:2 * node + 2] += np.asarray(pl["force"]) * (1.0 if plane == "axisymmetric" else t)
    return f


def set_load_path(scene: Scene, path: LoadPath) -> None:
    """The engine's ``patterns`` and ``stages`` (only when the case needs them: a case without
    [[stage]], displacement and motion keeps the model it always had) and the scene's load-path
    attributes."""
    scene.load_names = list(path.names)
    scene.stage_names = list(path.stage_names)
    scene.n_stages = path.n_stages
    scene.factors = np.array(path.factors, dtype=np.float64)
    contacts = scene.case.data["contact"]
    scene.motions = {x.label: {"contact": x.index, "motion": list(contacts[x.index]["motion"])}
                     for x in path.loads if x.array == "contact"}
    if path.patterns:
        scene.model["patterns"] = [load_pattern(scene, x, path.staged) for x in path.patterns]
    if path.staged:
        scene.model["stages"] = [{"name": s["name"], "factors": np.array(row, dtype=np.float64)}
                                 for s, row in zip(scene.case.data["stage"], path.factors[1:])]


def load_pattern(scene: Scene, load: Load, with_force: bool) -> dict:
    """One entry of the engine's ``patterns`` (its force only ``with_force``: without
    [[stage]] forces are summed into ``load``)."""
    out = {"name": load.label}
    if with_force and load.force:
        out["force"] = load_force(scene, load)
    if load.label in scene.prescribed:
        out["displacement_dofs"] = scene.prescribed[load.label]["dofs"]
        out["displacement_values"] = scene.prescribed[load.label]["values"]
    if load.label in scene.motions:
        out["motion_contacts"] = np.array([load.index], dtype=np.int64)
        out["motion"] = np.array([scene.motions[load.label]["motion"]], dtype=np.float64)
    return out


def hertz_cut_pressure(case: Case) -> float:
    """q = P / (2R): the quarter model carries half the total load P across its cut of
    length R (the other half is carried by the mirrored quarter).  In axisymmetry the quarter
    section is a hemisphere whose cut is the disc of radius R: q = P / (pi R^2)."""
    load = case.data["load"]
    R = case.body(load["body"])["mesh"]["R"]
    if is_axisymmetric(case):
        return load["P"] / (math.pi * R ** 2)
    return load["P"] / (2.0 * R)


# --------------------------------------------------------------------------- contact
def contact_pairs(scene: Scene) -> dict:
    """Candidate pairs of every ``[[contact]]``: node_a, node_b (-1 rigid), normal (from the
    target towards node_a), initial gap, mu (the C_n, C_t columns of Eqs. 45-46 per pair).
    Also fills the scene's pair positions and tributary lengths."""
    case = scene.case
    cols = {k: [] for k in ("node_a", "node_b", "normal", "gap", "mu", "length", "contact",
                            "weights", "foot", "point_gap")}
    for i, c in enumerate(case.data["contact"]):
        key = "contact" if len(case.data["contact"]) == 1 else f"contact.{i}"
        body_a, edge_a = contactor_edge(c)
        if c["kind"] == "node_to_segment":
            a, b, normal, gap, length, weights, foot, point = _node_to_segment_pairs(scene, c, key)
        elif c["kind"] in RIGID_KINDS:
            a, b, normal, gap = RIGID_PAIRS[c["kind"]](scene, c, key)
        else:
            a, b, normal, gap = _node_to_node_pairs(scene, c, key)
        if c["kind"] != "node_to_segment":
            length = tributary_lengths(scene.nodes, scene.global_edge(body_a, edge_a), a)
            weights = [[]] * len(a)
            foot, point = np.tile([-1.0, -1.0, 0.0], (len(a), 1)), np.full(len(a), np.nan)
        edge_nodes = np.unique(scene.global_edge(body_a, edge_a))
        scene.contact_truncated.append(bool(len(np.unique(a)) < len(edge_nodes)))
        cols["node_a"].append(a)
        cols["node_b"].append(b)
        cols["normal"].append(normal)
        cols["gap"].append(gap)
        cols["mu"].append(np.full(len(a), c["mu"]))
        cols["length"].append(length)
        cols["contact"].append(np.full(len(a), i, dtype=np.int64))
        cols["weights"].extend(weights)
        cols["foot"].append(foot)
        cols["point_gap"].append(point)
    if not cols["node_a"]:
        scene.pair_xy = np.zeros((0, 2))
        return {"node_a": np.zeros(0, np.int64), "node_b": np.zeros(0, np.int64),
                "normal": np.zeros((0, 2)), "gap": np.zeros(0), "mu": np.zeros(0),
                "contact": np.zeros(0, np.int64)}
    pairs = {"node_a": np.concatenate(cols["node_a"]).astype(np.int64),
             "node_b": np.concatenate(cols["node_b"]).astype(np.int64),
             "normal": np.concatenate(cols["normal"]).reshape(-1, 2),
             "gap": np.concatenate(cols["gap"]),
             "mu": np.concatenate(cols["mu"]).astype(np.float64),
             "contact": np.concatenate(cols["contact"]).astype(np.int64)}
    if any(cols["weights"]):  # node-to-segment rows (docs/engine_api.md)
        pairs["weight_ptr"], pairs["weight_node"], pairs["weight_value"] = \
            mortar.compressed_weights(cols["weights"])
    scene.pair_xy = scene.nodes[pairs["node_a"]]
    scene.pair_foot = np.concatenate(cols["foot"]).reshape(-1, 3)
    scene.pair_point_gap = np.concatenate(cols["point_gap"])
    scene.pair_length = np.concatenate(cols["length"])
    scene.pair_contact = pairs["contact"]
    return pairs


def _node_to_segment_pairs(scene: Scene, c: dict, key: str):
    """Mortar-style rows of the contactor nodes of edge_a in the window against the polyline
    edge_b (slipstep.mortar): node_a, node_b, normal, gap, tributary length, weights."""
    seg_a = scene.global_edge(c["body_a"], c["edge_a"])
    seg_b = scene.global_edge(c["body_b"], c["edge_b"])
    candidates = np.unique(seg_a)
    xy = scene.nodes[candidates]
    inside = ((xy[:, 0] >= c["x_min"]) & (xy[:, 0] <= c["x_max"]) &
              (xy[:, 1] >= c["y_min"]) & (xy[:, 1] <= c["y_max"]))
    length_scale = float(np.linalg.norm(scene.nodes[seg_a[:, 1]] - scene.nodes[seg_a[:, 0]], axis=1).min())
    rows = mortar.node_to_segment_pairs(scene.nodes, seg_a, seg_b, candidates[inside],
                                        1e-9 * length_scale, radial=is_axisymmetric(scene.case))
    if not rows["node_a"]:
        raise scene.case.error(f"{key}.edge_b", f"no node of {c['body_a']}:{c['edge_a']} in the "
                               f"candidate window projects onto {c['body_b']}:{c['edge_b']}: "
                               f"check the edges, or widen x_min/x_max/y_min/y_max")
    a = np.asarray(rows["node_a"], dtype=np.int64)
    normal, gap, point = (np.asarray(rows[k]) for k in ("normal", "gap", "point_gap"))
    _check_gaps(scene, a, np.minimum(gap, point), c["tolerance"], key,
                f"move body '{c['body_a']}' away from body '{c['body_b']}'")
    # a node that touches starts its row closed (slipstep.mortar: first point of contact)
    gap = np.where((np.abs(gap) <= c["tolerance"]) | (np.abs(point) <= c["tolerance"]), 0.0, gap)
    return (a, np.asarray(rows["node_b"], dtype=np.int64), normal, gap,
            np.asarray(rows["length"]), rows["weights"], np.asarray(rows["foot"], dtype=float),
            point)


def tributary_lengths(nodes: np.ndarray, segments: np.ndarray, ids: np.ndarray) -> np.ndarray:
    """Half the summed length of the edge segments touching each node (lumped length L)."""
    length = np.linalg.norm(nodes[segments[:, 1]] - nodes[segments[:, 0]], axis=1)
    per_node = np.zeros(len(nodes))
    np.add.at(per_node, segments[:, 0], 0.5 * length)
    np.add.at(per_node, segments[:, 1], 0.5 * length)
    return per_node[ids]


def _window_candidates(scene: Scene, c: dict, key: str) -> np.ndarray:
    """Global ids (sorted) of the nodes of a rigid contact's ``edge`` inside its x/y window."""
    candidates = np.unique(scene.global_edge(c["body"], c["edge"]))
    xy = scene.nodes[candidates]
    inside = ((xy[:, 0] >= c["x_min"]) & (xy[:, 0] <= c["x_max"]) &
              (xy[:, 1] >= c["y_min"]) & (xy[:, 1] <= c["y_max"]))
    a = candidates[inside]
    if len(a) == 0:
        raise scene.case.error(f"{key}.x_max", f"no node of edge '{c['edge']}' of body "
                               f"'{c['body']}' lies in the candidate window: widen x_min/x_max/"
                               f"y_min/y_max")
    return a


def _rigid_pairs(scene: Scene, c: dict, key: str, a, n, gap, fix: str, flip: str):
    """The pairs of a rigid obstacle from its candidates ``a``, their normals ``n`` (from the
    obstacle into the body, fixed: small sliding) and initial gaps: the facing and penetration
    checks, gaps within tolerance snapped to 0, node_b = -1."""
    _check_facing(scene, a, n, gap, c["tolerance"], scene.global_edge(c["body"], c["edge"]),
                  None, None, key, flip)
    _check_gaps(scene, a, gap, c["tolerance"], key, fix)
    gap = np.where(np.abs(gap) <= c["tolerance"], 0.0, gap)
    return a, np.full(len(a), -1, dtype=np.int64), n, gap


def _rigid_line_pairs(scene: Scene, c: dict, key: str):
    """Body nodes on ``edge`` within the x/y window, against the line through ``point``."""
    a = _window_candidates(scene, c, key)
    n = np.asarray(c["normal"]) / np.linalg.norm(c["normal"])
    gap = (scene.nodes[a] - np.asarray(c["point"])) @ n
    return _rigid_pairs(scene, c, key, a, np.tile(n, (len(a), 1)), gap,
                        "move the body away from the line or the line (contact.point) away "
                        "from the body", FLIP)


def _rigid_circle_pairs(scene: Scene, c: dict, key: str):
    """Body nodes on ``edge`` within the x/y window, against the circle (``centre``,
    ``radius``): per node the closest point of the circle, the normal from the circle into the
    body, (x - c)/|x - c| for a body ``outside`` it and (c - x)/|x - c| ``inside``, and the gap
    |x - c| - R (outside) or R - |x - c| (inside).  A candidate at the centre (within 1e-9 R:
    round-off) has no closest point, hence no normal: an error naming it."""
    a = _window_candidates(scene, c, key)
    centre, radius = np.asarray(c["centre"], dtype=float), float(c["radius"])
    d = scene.nodes[a] - centre
    r = np.linalg.norm(d, axis=1)
    at_centre = r <= 1e-9 * radius
    if at_centre.any():
        k = int(np.argmax(at_centre))
        x, y = scene.nodes[a[k]]
        raise scene.case.error(f"{key}.centre", f"node {int(a[k])} ({x:.6g}, {y:.6g}) lies at "
                               f"the centre of the rigid circle, where the normal (the direction "
                               f"to the nearest point of the circle) is undefined: move the "
                               f"centre, or leave the node out of the candidates (x_min/x_max/"
                               f"y_min/y_max)")
    sign = 1.0 if c["side"] == "outside" else -1.0
    n = sign * d / r[:, None]
    gap = sign * (r - radius)
    return _rigid_pairs(scene, c, key, a, n, gap,
                        "move the body or the circle (contact.centre, contact.radius) so that "
                        "they do not overlap",
                        'check contact.side ("outside": the body is outside the circle; '
                        '"inside": in a hole or cup) and contact.centre')


def _rigid_polyline_pairs(scene: Scene, c: dict, key: str):
    """Body nodes on ``edge`` within the x/y window, against the polyline ``points``
    (:func:`polyline_closest`, told the body's outward normal at each node and the contact's
    tolerance, which set the contact direction of a node sitting on a convex corner).  A node
    that projects nowhere (its closest point is an end point of an open polyline and it lies
    beyond it) is not a candidate."""
    a = _window_candidates(scene, c, key)
    outward = _node_normals(scene.nodes, scene.global_edge(c["body"], c["edge"]), a)
    near = polyline_closest(np.asarray(c["points"], dtype=float), c["side"], scene.nodes[a],
                            outward, c["tolerance"])
    if not near["onto"].any():
        raise scene.case.error(f"{key}.points", f"no candidate node of edge '{c['edge']}' of "
                               f"body '{c['body']}' projects onto the rigid polyline (a "
                               f"contactor node that projects nowhere is not a candidate): "
                               f"extend the polyline (points) or widen the window (x_min/x_max/"
                               f"y_min/y_max)")
    keep = near["onto"]
    return _rigid_pairs(scene, c, key, a[keep], near["normal"][keep], near["gap"][keep],
                        "move the body or the polyline (contact.points) so that they do not "
                        "overlap",
                        'check contact.side (the side the body lies on, walking the polyline '
                        'from its first point to its last)')


def polyline_closest(points: np.ndarray, side: str, xy: np.ndarray,
                     outward: np.ndarray | None = None, touch: float = 0.0) -> dict:
    """The closest points of the polyline ``points`` (M, 2) to the points ``xy`` (N, 2).

    Per point: ``segment`` (the closest segment, the first one of a tie), ``vertex`` (the index
    of the vertex that is the closest point, else -1), ``foot`` (the closest point), ``normal``
    (the direction in which the obstacle resists the point: the unit normal of its segment
    towards ``side``, "left" or "right" walking from the first point to the last; at a vertex
    :func:`_vertex_normals`), ``gap`` = (x - foot).normal, ``onto`` (False for a point that
    projects nowhere: its closest point is an end point of an open polyline and its
    projection on that end segment lies beyond it, by more than 1e-9 of the segment's length)
    and ``s`` (the arc length of the foot from the first point; beyond an end, the projection
    on the extended end segment, so s < 0 before the first point and s > the length after the
    last).  ``outward`` (N, 2), the body's outward surface normals at the points, and
    ``touch``, the distance within which a point sits on a vertex, serve convex corners."""
    points, xy = np.asarray(points, dtype=float), np.asarray(xy, dtype=float).reshape(-1, 2)
    start, d = points[:-1], np.diff(points, axis=0)
    length = np.linalg.norm(d, axis=1)
    cum = np.concatenate([[0.0], np.cumsum(length)])
    seg_n = np.stack([-d[:, 1], d[:, 0]], axis=1) / length[:, None]  # left normals
    if side == "right":
        seg_n = -seg_n
    raw = np.einsum("psk,sk->ps", xy[:, None, :] - start[None], d) / length ** 2
    t = np.clip(raw, 0.0, 1.0)
    dist = np.linalg.norm(xy[:, None, :] - (start[None] + t[..., None] * d[None]), axis=2)
    seg = np.argmin(dist, axis=1)
    rows = np.arange(len(xy))
    t_seg, raw_seg = t[rows, seg], raw[rows, seg]
    vertex = np.where(t_seg == 0.0, seg, np.where(t_seg == 1.0, seg + 1, -1))
    foot = start[seg] + t_seg[:, None] * d[seg]
    at = vertex >= 0
    foot[at] = points[vertex[at]]
    closed = bool(np.array_equal(points[0], points[-1]))
    m = np.zeros_like(xy) if outward is None else np.asarray(outward, dtype=float).reshape(-1, 2)
    normal = _vertex_normals(points, seg_n, closed, xy, vertex, seg_n[seg], m, touch)
    gap = np.einsum("pk,pk->p", xy - foot, normal)
    last = len(d) - 1
    beyond = np.zeros(len(xy), dtype=bool)
    if not closed:
        beyond = (((seg == 0) & (raw_seg < -1e-9)) | ((seg == last) & (raw_seg > 1.0 + 1e-9)))
    s = cum[seg] + t_seg * length[seg]
    s = np.where(beyond & (seg == 0) & (raw_seg < 0.0), raw_seg * length[0], s)
    s = np.where(beyond & (seg == last) & (raw_seg > 1.0), cum[last] + raw_seg * length[last], s)
    return {"segment": seg, "vertex": vertex, "foot": foot, "normal": normal, "gap": gap,
            "onto": ~beyond, "s": s}


def _vertex_normals(points, seg_n, closed: bool, xy, vertex, normal, outward, touch: float):
    """``normal`` with the rule for the points whose closest point is an interior vertex (or
    the joint of a closed polyline, between its last and first segments; an end point of an
    open polyline keeps its one segment's normal).

    * A concave vertex (the segment after it turns towards the body side of the one before,
      n_before . d_after >= 0; or goes straight on): the normalised average of the two
      segments' normals.  Only a point on the vertex itself has it as closest point there (a
      body in a corner of a die), pressed by both faces.
    * A convex vertex (the obstacle's corner points into the body): for a point off it, the
      direction from the vertex to the point, the true closest-point normal (gap = the
      distance).  A point that sits on it (within ``touch``, or 1e-9 of the shorter segment:
      round-off) has no such direction: :func:`_corner_contact_normal`."""
    normal = normal.copy()
    length = np.linalg.norm(np.diff(points, axis=0), axis=1)
    last = len(length) - 1
    for k in np.unique(vertex[vertex >= 0]):
        if 0 < k < len(points) - 1:
            before, after = k - 1, k
        elif closed:
            before, after = last, 0
        else:
            continue  # an end point: its one segment's normal
        here = vertex == k
        mean = seg_n[before] + seg_n[after]  # never 0: the schema refuses folding segments
        mean /= np.linalg.norm(mean)
        if seg_n[before] @ (points[after + 1] - points[after]) >= 0.0:  # concave or straight
            normal[here] = mean
            continue
        r = xy[here] - points[k]
        dist = np.linalg.norm(r, axis=1)
        sits = dist <= max(touch, 1e-9 * min(length[before], length[after]))
        on = _corner_contact_normal(seg_n[before], seg_n[after], mean, outward[here])
        normal[here] = np.where(sits[:, None], on, r / np.where(sits, 1.0, dist)[:, None])
    return normal


def _corner_contact_normal(n0, n1, mean, outward):
    """The contact normal of body points sitting on a convex corner whose faces have the
    normals n0, n1 (towards the body; ``mean`` their normalised average), given the body's
    outward surface normals there (K, 2).

    At the corner a frictionless obstacle can push along any direction of its cone of normals
    (between n0 and n1); which one acts is set by the body's own surface, whose normal m
    points at the obstacle: the contact normal is the direction of the cone nearest to -m.
    Inside the cone it is -m itself (a wedge's tip on a flat: the flat's normal); outside, the
    nearer face's normal, the face the body's surface lies along (a punch's edge node is
    pressed by the punch face, not pushed sideways by its side: the average of the faces would
    push it outwards at 45 degrees with a force no face in contact exerts).  Without a body
    normal (zero) the cone's middle, ``mean``."""
    size = np.linalg.norm(outward, axis=1)
    v = -outward / np.where(size > 0.0, size, 1.0)[:, None]
    turn = _cross(n0, n1)
    inside = (_cross(n0, v) * turn >= 0.0) & (_cross(v, n1) * turn >= 0.0) & (v @ mean > 0.0)
    nearer = np.where((v @ n0 >= v @ n1)[:, None], n0, n1)
    return np.where((size == 0.0)[:, None], mean, np.where(inside[:, None], v, nearer))


def _cross(a, b):
    """The z component of a x b for 2D vectors (any leading shape)."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


#: The pair builder of each rigid obstacle kind.
RIGID_PAIRS = {"rigid_line": _rigid_line_pairs, "rigid_circle": _rigid_circle_pairs,
               "rigid_polyline": _rigid_polyline_pairs}


def _node_to_node_pairs(scene: Scene, c: dict, key: str):
    """Each node of edge_a with the nearest node of edge_b within ``tolerance``; the normal is
    body b's outward normal averaged over the edge_b segments at node b (or the given one)."""
    seg_a = scene.global_edge(c["body_a"], c["edge_a"])
    seg_b = scene.global_edge(c["body_b"], c["edge_b"])
    nodes_a, nodes_b = np.unique(seg_a), np.unique(seg_b)
    xa, xb = scene.nodes[nodes_a], scene.nodes[nodes_b]
    d = np.linalg.norm(xa[:, None, :] - xb[None, :, :], axis=2)  # small: edge nodes only
    nearest = np.argmin(d, axis=1)
    ok = d[np.arange(len(nodes_a)), nearest] <= c["tolerance"]
    if not ok.any():
        raise scene.case.error(f"{key}.tolerance", f"no node of {c['body_a']}:{c['edge_a']} is "
                               f"within {c['tolerance']:g} of a node of {c['body_b']}:"
                               f"{c['edge_b']}: the meshes must match on the interface, or "
                               f"increase tolerance")
    a, b = nodes_a[ok], nodes_b[nearest[ok]]
    label_a, label_b = f"{c['body_a']}:{c['edge_a']}", f"{c['body_b']}:{c['edge_b']}"
    _check_matching(scene, nodes_a[~ok], seg_b, c["tolerance"], label_a, label_b, key)
    _check_matching(scene, np.setdiff1d(nodes_b, b), seg_a, c["tolerance"], label_b, label_a,
                    key)
    if len(np.unique(b)) != len(b):
        raise scene.case.error(f"{key}.tolerance", f"= {c['tolerance']:g} pairs one target node "
                               f"with several contactor nodes: decrease it")
    if c["normal"] is not None:
        n = np.tile(np.asarray(c["normal"]) / np.linalg.norm(c["normal"]), (len(a), 1))
    else:
        seg_n = meshing.outward_normals(scene.nodes, seg_b)
        acc = np.zeros((len(scene.nodes), 2))
        np.add.at(acc, seg_b[:, 0], seg_n)
        np.add.at(acc, seg_b[:, 1], seg_n)
        n = acc[b] / np.linalg.norm(acc[b], axis=1, keepdims=True)
    gap = np.einsum("ij,ij->i", scene.nodes[a] - scene.nodes[b], n)
    _check_facing(scene, a, n, gap, c["tolerance"], seg_a, b, seg_b, key)
    _check_gaps(scene, a, gap, c["tolerance"], key,
                f"move body '{c['body_a']}' away from body '{c['body_b']}'")
    gap = np.where(np.abs(gap) <= c["tolerance"], 0.0, gap)
    return a, b, n, gap


def _node_normals(nodes: np.ndarray, segments: np.ndarray, ids: np.ndarray) -> np.ndarray:
    """Outward normal of an edge at each node of ``ids``: the segment normals meeting there,
    summed (not normalised; zero where they cancel)."""
    acc = np.zeros((len(nodes), 2))
    seg_n = meshing.outward_normals(nodes, segments)
    np.add.at(acc, segments[:, 0], seg_n)
    np.add.at(acc, segments[:, 1], seg_n)
    return acc[ids]


FLIP = "flip contact.normal (or swap the contactor and target edges)"


def _check_facing(scene: Scene, a, n, gap, tol, seg_a, b, seg_b, key: str,
                  fix: str = FLIP) -> None:
    """Pairs that start closed (or penetrating) must face each other: body a's surface faces
    the target (its outward normal against n) and, node to node, body b's surface faces body a
    (its outward normal along n).  Otherwise the normal points the wrong way and the pairing
    is geometrically impossible (it would hold the bodies together, or report a penetration
    that is not there)."""
    touching = gap <= tol
    away_a = touching & (np.einsum("ij,ij->i", _node_normals(scene.nodes, seg_a, a), n) > 1e-6)
    away_b = np.zeros_like(away_a)
    if b is not None:
        away_b = touching & (np.einsum("ij,ij->i", _node_normals(scene.nodes, seg_b, b), n)
                             < -1e-6)
    if (away_a | away_b).any():
        k = int(np.argmax(away_a | away_b))
        x, y = scene.nodes[a[k]]
        side = "the contactor surface faces away from the target" if away_a[k] else \
            "the target surface faces away from the contactor"
        raise scene.case.error(key, f"the contact normal ({n[k, 0]:.6g}, {n[k, 1]:.6g}) at node "
                               f"{int(a[k])} ({x:.6g}, {y:.6g}) points the wrong way ({side}): "
                               f"the normal must point from the target into the contactor body; "
                               f"{fix}")


def _check_matching(scene: Scene, unpaired, seg_other, tol: float, label: str, other: str,
                    key: str) -> None:
    """Node to node needs matching meshes: an unpaired node of one side that lies on the other
    side's edge (within tolerance of one of its segments) would be free to pass through it."""
    if len(unpaired) == 0 or len(seg_other) == 0:
        return
    x = scene.nodes[unpaired][:, None, :]
    p, q = scene.nodes[seg_other[:, 0]][None], scene.nodes[seg_other[:, 1]][None]
    d = q - p
    t = np.einsum("ijk,ijk->ij", x - p, d) / np.einsum("ijk,ijk->ij", d, d)
    dist = np.linalg.norm(x - (p + t[..., None] * d), axis=2)
    # on a segment: within tolerance of it and strictly between its end nodes
    on = ((dist <= tol) & (t > 1e-9) & (t < 1.0 - 1e-9)).any(axis=1)
    if on.any():
        k = int(unpaired[np.argmax(on)])
        x0, y0 = scene.nodes[k]
        raise scene.case.error(f"{key}.tolerance", f"non-matching interface: node {k} "
                               f"({x0:.6g}, {y0:.6g}) of {label} lies on {other} but is paired "
                               f"with no node of it within {tol:g}: node_to_node contact needs "
                               f"matching interface nodes (same spacing and aligned origins "
                               f"on both sides)")


def _check_gaps(scene: Scene, a: np.ndarray, gap: np.ndarray, tol: float, key: str,
                fix: str) -> None:
    if (gap < -tol).any():
        k = int(np.argmin(gap))
        x, y = scene.nodes[a[k]]
        raise scene.case.error(key, f"initial penetration at node {int(a[k])} ({x:.6g}, {y:.6g}) "
                               f"by {-gap[k]:.3g}: {fix}")


# --------------------------------------------------------------------------- options
def solver_options(case: Case) -> dict:
    """The engine's ``options``: snapshots at every event or at given path times, every stage
    end added (``"fractions"`` as always for a case without [[stage]], displacement and
    motion, ``"times"`` otherwise)."""
    snaps = case.data["output"]["snapshots"]
    solver = case.data["solver"]
    options = {"tie_tol": float(solver["tie_tol"]), "group_tol": float(solver["group_tol"]),
               "max_events": int(solver["max_events"]),
               "equilibrium_tol": float(solver["equilibrium_tol"]),
               "drift_control": bool(solver["drift_control"]),
               "max_stress_step": float(solver["max_stress_step"]),
               "tangent_turn": float(solver["tangent_turn"]),
               "stop_at_first_yield": bool(solver["stop_at_first_yield"])}
    if snaps == "events":
        options["output"] = "events"
    else:
        path = case.path
        times = sorted(set(snaps) | {float(k) for k in range(1, path.n_stages + 1)})
        options["output"] = "times" if path.new else "fractions"
        options[options["output"]] = np.asarray(times, dtype=np.float64)
    return options


# --------------------------------------------------------------------------- reference
def hertz_reference(scene: Scene) -> dict:
    """Hertz contact on a rigid flat (§5.1 of the paper) for a case with ``[load] P`` and a
    rigid_line contact on that body: a cylinder in plane strain or stress
    (:func:`slipstep.references.hertz_line`; a and p0 grow as P^(1/2), ``load_exponent``), a
    sphere in axisymmetry (:func:`slipstep.references.hertz_sphere`; a and p0 as P^(1/3), the
    approach delta as P^(2/3)).  ``contact`` says which ("line" or "sphere")."""
    data = scene.case.data
    load = data["load"]
    if load is None:
        return {}
    if not any(c["kind"] == "rigid_line" and c["body"] == load["body"] for c in data["contact"]):
        return {}
    body = scene.case.body(load["body"])
    E, nu = body["material"]["E"], body["material"]["nu"]
    P, R = load["P"], body["mesh"]["R"]
    plane = data["analysis"]["plane"]
    E_star = effective_modulus(E, nu, plane)
    if plane == "axisymmetric":
        a, p0, delta = hertz_sphere(P, R, E, nu)
        return {"contact": "sphere", "a_hertz": a, "p0_hertz": p0, "delta_hertz": delta, "P": P,
                "R": R, "E_star": E_star, "load_exponent": 1.0 / 3.0}
    a, p0 = hertz_line(P, R, E, nu, plane)
    return {"contact": "line", "a_hertz": a, "p0_hertz": p0, "P": P, "R": R, "E_star": E_star,
            "load_exponent": 0.5}
