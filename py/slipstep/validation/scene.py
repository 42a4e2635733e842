"""The built scene, where the case alone cannot tell: edge tags of file meshes, nodes left of
the axis, duplicate nodes, contact pairs held by supports, a frictional pair on a
half-held node."""

from __future__ import annotations

import numpy as np

from ..case import Case
from ..errors import CaseError
from ..scene import Scene
from ..section import AXIS_TOLERANCE, is_axisymmetric
from ..toml_writing import point_text


def check_file_mesh_tags(case: Case, body_meshes: dict, surface: str) -> None:
    """Edge tags (3D: face tags; ``surface``: "edge" or "face") of file meshes are only known
    now: check the BCs and contacts that use them."""
    bcs, contacts = case.record.bc, case.record.contact
    uses = []  # (key, body, tag)
    for i, bc in enumerate(bcs):
        k = "bc." if len(bcs) == 1 else f"bc.{i}."
        if getattr(bc, surface):
            uses.append((k + surface, bc.body, getattr(bc, surface), "tags"))
        if bc.nodes:
            uses.append((k + "nodes", bc.body, bc.nodes, "node_sets"))
    for i, c in enumerate(contacts):
        k = "contact." if len(contacts) == 1 else f"contact.{i}."
        uses += [(k + key, body, tag, "tags") for key, body, tag in c.surfaces]
    for key, body, tag, kind in uses:
        known = getattr(body_meshes[body], kind)
        if tag not in known:
            what = surface if kind == "tags" else "node set"
            raise CaseError(
                f'{case.source}: {key} = "{tag}" is not allowed: body "{body}" has '
                f"no {what} with that tag (its {what}s: {', '.join(known) or 'none'})"
            )


def check_radii(scene: Scene) -> None:
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
            raise CaseError(
                f"{scene.case.source}: body '{name}': element {e} has node {node} at "
                f'({x:.6g}, {y:.6g}), x < 0: with analysis.plane = "axisymmetric" '
                f"x is the radius r >= 0 (the axis is x = 0); move the body to "
                f'x >= 0, or use plane = "strain"'
            )


def check_duplicate_nodes(scene: Scene, pairs: dict) -> None:
    """Two nodes of one body at the same point cut the mesh there (a crack, or parts that are
    not connected): allowed only when a node_to_node contact pairs them."""
    joined = {
        (min(a, b), max(a, b))
        for a, b in zip(pairs["node_a"].tolist(), pairs["node_b"].tolist())
        if b >= 0
    }
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
                    raise CaseError(
                        f"{scene.case.source}: body '{name}': nodes {int(i) - scene.offsets[name]}"
                        f" and {int(j) - scene.offsets[name]} are both at "
                        f"{point_text(scene.nodes[i])} but "
                        f"are not joined: duplicate nodes cut the mesh there (a crack or "
                        f"unconnected parts); merge them (gmsh: Coherence), or pair the two "
                        f"sides with a node_to_node [[contact]]"
                    )


def check_pairs_not_held(scene: Scene) -> None:
    """A pair whose normal direction is entirely held by supports or prescribed displacements
    can carry no contact force (the engine refuses it too; here the message can name the case
    key)."""
    d = scene.dimension
    pairs, fixed = scene.model["pairs"], np.zeros(d * len(scene.nodes), dtype=bool)
    fixed[scene.model["fixed_dofs"]] = True
    for p in scene.prescribed.values():
        fixed[p["dofs"]] = True
    n = pairs["normal"]
    free = np.zeros(len(n), dtype=bool)
    for node in (pairs["node_a"], pairs["node_b"]):
        ok = node >= 0
        for c in range(d):
            free[ok] |= (n[ok, c] != 0.0) & ~fixed[d * node[ok] + c]
    if not free.all():
        k = int(np.argmin(free))
        i = int(pairs["node_a"][k])
        c = int(scene.pair_contact[k])
        key = "contact" if len(scene.case.record.contact) == 1 else f"contact.{c}"
        raise scene.case.error(
            key,
            f"node {i} {point_text(scene.nodes[i])} is held by supports "
            f"in the contact normal direction, so its pair can carry no "
            f"contact force: remove the support ([[bc]] fix/symmetry/"
            f"displacement) there or the node from the candidates (x_min/"
            f"x_max/y_min/y_max)",
        )


def check_stick_on_half_held(scene: Scene) -> None:
    """A frictional pair of a rigid circle or polyline on a node with one component held (a
    symmetry line) would close in stick with its normal and tangential conditions both acting
    on the one free component (a singular system), unless its normal or tangent lies along the
    held component (the engine's tolerance 1e-12; the normal entirely held is refused above).
    Refused with the fix (the rigid line's fixed normal is the user's, and is left to the
    engine)."""
    pairs, contacts = scene.model["pairs"], scene.case.record.contact
    fixed = np.zeros(2 * len(scene.nodes), dtype=bool)
    fixed[scene.model["fixed_dofs"]] = True
    for p in scene.prescribed.values():
        fixed[p["dofs"]] = True
    a, n = np.asarray(pairs["node_a"]), np.asarray(pairs["normal"])
    curved = np.isin(
        np.array([c.kind for c in contacts] or [""])[scene.pair_contact],
        ("rigid_circle", "rigid_polyline"),
    )
    held_x, held_y = fixed[2 * a], fixed[2 * a + 1]
    free = np.where(held_x, 1, 0)  # the one free component when exactly one is held
    n_free = np.abs(n[np.arange(len(a)), free])
    t_free = np.abs(n[np.arange(len(a)), 1 - free])  # t = (-n_y, n_x): t_x = -n_y, t_y = n_x
    bad = (
        curved
        & (held_x != held_y)
        & (np.asarray(pairs["mu"]) > 0.0)
        & (n_free >= 1e-12)
        & (t_free >= 1e-12)
    )
    if bad.any():
        k = int(np.argmax(bad))
        i, c = int(a[k]), int(scene.pair_contact[k])
        key = "contact" if len(contacts) == 1 else f"contact.{c}"
        x, y = scene.nodes[i]
        held, other = ("x", "y") if held_x[k] else ("y", "x")
        raise scene.case.error(
            key,
            f"node {i} ({x:.6g}, {y:.6g}) is held in {held} by "
            f"supports and its contact normal ({n[k, 0]:.6g}, {n[k, 1]:.6g}) "
            f"is oblique to {other}, its free component: with mu > 0 it would "
            f"stick with both contact conditions on that one component (a "
            f"singular system); make the obstacle's normal there along "
            f"{other} (on a symmetry line: the circle's centre, or a polyline "
            f"vertex between mirrored segments or a segment across it at a "
            f"right angle), or leave the node out of the candidates "
            f"(x_min/x_max/y_min/y_max)",
        )
