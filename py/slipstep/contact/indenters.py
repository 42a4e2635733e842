"""Pyramidal indenters as closed triangulated surfaces (``[[contact]]`` ``kind =
"rigid_surface"``, ``indenter = ...``), tip down at a point, axis z, and an STL writer for any
surface (to give another code the same indenter).

Vickers: a square pyramid, 136 degrees between opposite faces, so each face makes 68 degrees
with the axis; Berkovich: a three-sided pyramid whose faces make 65.27 degrees with the axis
(the angle that gives it the Vickers' area-to-depth ratio, A = 24.5 h^2).  Each face is a
triangle from the tip to an edge of the base, closed by the base at the height ``size``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

#: The angle between the axis and a face, degrees.
FACE_ANGLE = {"vickers": 68.0, "berkovich": 65.27}
SIDES = {"vickers": 4, "berkovich": 3}


def pyramid(kind: str, tip, size: float) -> tuple[np.ndarray, np.ndarray]:
    """(points, triangles) of the closed pyramid ``kind`` with its tip at ``tip`` and its base
    ``size`` above it, triangles oriented outwards.  The base polygon's inradius is
    size tan(face angle); a Vickers' base edges run along x and y, a Berkovich has a vertex on
    the +y axis."""
    sides = SIDES[kind]
    inradius = size * math.tan(math.radians(FACE_ANGLE[kind]))
    circumradius = inradius / math.cos(math.pi / sides)
    first = math.pi / 4 if sides == 4 else math.pi / 2
    angles = first + 2 * math.pi * np.arange(sides) / sides
    base = np.column_stack(
        [circumradius * np.cos(angles), circumradius * np.sin(angles), np.full(sides, size)]
    )
    points = np.vstack([[0.0, 0.0, 0.0], base]) + np.asarray(tip, dtype=float)
    ring = np.arange(1, sides + 1)
    # sides: tip, next, this (outward: the base runs counter-clockwise seen from above)
    faces = np.column_stack([np.zeros(sides, int), np.roll(ring, -1), ring])
    # the base seen from above (outside): counter-clockwise, a fan from its first vertex
    lid = np.column_stack([np.ones(sides - 2, int), ring[1:-1], ring[2:]])
    return points, np.vstack([faces, lid]).astype(np.int64)


def write_stl(
    path: str | Path, points: np.ndarray, triangles: np.ndarray, name: str = "surface"
) -> Path:
    """Write a triangulated surface as an ASCII STL (facet normals by the right-hand rule)."""
    path = Path(path)
    lines = [f"solid {name}"]
    for tri in np.asarray(triangles):
        a, b, c = points[tri]
        n = np.cross(b - a, c - a)
        n = n / (np.linalg.norm(n) or 1.0)
        lines += [
            f"  facet normal {n[0]!r} {n[1]!r} {n[2]!r}",
            "    outer loop",
            *(f"      vertex {p[0]!r} {p[1]!r} {p[2]!r}" for p in (a, b, c)),
            "    endloop",
            "  endfacet",
        ]
    lines.append(f"endsolid {name}")
    path.write_text("\n".join(lines) + "\n")
    return path
