"""The engine's model as typed records (docs/engine_api.md, "model"): every key
:func:`slipstep._engine.solve` reads is a field here, under the key's own name, with the type
the binding reads it as (bindings/src/lib.rs; tests/scene/test_engine_model.py holds the two to
the same set of keys).  The builders (:mod:`slipstep.builders`) make one :class:`EngineModel`
per scene (``scene.engine_model``); its :meth:`~EngineModel.to_engine` is the dict the engine
reads (``scene.model``).

A field that is None is absent from the dict (the engine's default); ``dimension`` is written
only in 3D (absent = 2).
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np


class _Record:
    """A record of the engine's model: its dict is its fields by name."""

    def to_engine(self) -> dict:
        """The fields by name, None ones left out, tuples as lists and records as dicts."""
        out = {}
        for f in fields(self):
            value = getattr(self, f.name)
            if value is None:
                continue
            if isinstance(value, tuple):
                value = [v.to_engine() if isinstance(v, _Record) else v for v in value]
            elif isinstance(value, _Record):
                value = value.to_engine()
            out[f.name] = value
        return out


@dataclass(frozen=True, kw_only=True)
class EngineMaterial(_Record):
    """One body's material (rust/src/material.rs ``Material``): Young's modulus ``E`` and
    Poisson's ratio ``nu``; when plastic the yield stress ``Sy`` and plastic modulus ``H``."""

    E: float
    nu: float
    Sy: float | None = None
    H: float | None = None


@dataclass(frozen=True, kw_only=True)
class ContactPairs(_Record):
    """The candidate contact pairs, arrays of length P (the engine's ``PairInput`` rows), in
    the order of :func:`slipstep.contact.pairs.contact_pairs`."""

    node_a: np.ndarray  # (P,) int64 contactor node
    node_b: np.ndarray  # (P,) int64 target node, -1 for a rigid obstacle
    normal: np.ndarray  # (P, dim) float64 unit normal, from the target towards node a
    tangent: np.ndarray | None = None  # 3D: (P, 2, 3) the basis (t1, t2), t1 x t2 = n
    gap: np.ndarray  # (P,) float64 initial gap >= 0
    mu: np.ndarray  # (P,) float64 Coulomb friction coefficient
    contact: np.ndarray  # (P,) int64 index into contact_names
    # node-to-segment / node-to-surface rows, compressed: (P+1,) int64, (W,) int64, (W,) float64
    weight_ptr: np.ndarray | None = None
    weight_node: np.ndarray | None = None
    weight_value: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.node_a)


@dataclass(frozen=True, kw_only=True)
class LoadPattern(_Record):
    """One further load pattern at factor 1 (rust/src/model.rs ``LoadPattern``): a force, the
    prescribed displacements of some DOFs, the motion of some rigid contacts' obstacles."""

    name: str
    force: np.ndarray | None = None  # (dim N,) float64
    displacement_dofs: np.ndarray | None = None  # (k,) int64
    displacement_values: np.ndarray | None = None  # (k,) float64
    motion_contacts: np.ndarray | None = None  # (m,) int64 index into contact_names
    motion: np.ndarray | None = None  # (m, dim) float64


@dataclass(frozen=True, kw_only=True)
class Stage(_Record):
    """One stage of the load path: the factors of ``load`` and of each pattern at its end."""

    name: str | None
    factors: np.ndarray  # (1 + len(patterns),) float64

    def to_engine(self) -> dict:
        return {"name": self.name, "factors": self.factors}  # a None name too, as given


@dataclass(frozen=True, kw_only=True)
class EngineModel(_Record):
    """The model :func:`slipstep._engine.solve` runs (rust/src/model.rs ``Model``): the mesh
    of its dimension, materials, supports, loads, candidate pairs, options and the names its
    messages use."""

    dimension: int = 2  # 2: a plane or axisymmetric section of triangles; 3: tetrahedra
    nodes: np.ndarray  # (N, dim) float64
    triangles: np.ndarray | None = None  # 2D: (M, 3) int64, counter-clockwise
    tetrahedra: np.ndarray | None = None  # 3D: (M, 4) int64, positively oriented
    element_material: np.ndarray  # (M,) int64 index into materials
    materials: tuple[EngineMaterial, ...]
    plane: str | None = None  # 2D: "strain", "stress" or "axisymmetric"
    thickness: float | None = None  # 2D: out of plane (ignored for rings)
    fixed_dofs: np.ndarray  # (K,) int64, dof = dim node + component
    load: np.ndarray  # (dim N,) float64 at factor 1
    pairs: ContactPairs
    options: dict  # the [solver] table's keys and the snapshot request (slipstep.options)
    body_names: tuple[str, ...]
    element_body: np.ndarray  # (M,) int64 index into body_names
    contact_names: tuple[str, ...]
    support_names: tuple[str, ...]  # the supports whose reactions the engine records
    support_dofs: tuple[np.ndarray, ...]  # the DOFs of each, (k,) int64
    patterns: tuple[LoadPattern, ...] | None = None  # absent: no pattern besides load
    stages: tuple[Stage, ...] | None = None  # absent: one stage, every factor 1

    def __post_init__(self):
        if self.dimension not in (2, 3) or self.elements is None:
            elements = {2: "triangles", 3: "tetrahedra"}.get(self.dimension, "dimension 2 or 3")
            raise ValueError(f"an engine model of dimension {self.dimension} needs {elements}")

    @property
    def elements(self) -> np.ndarray:
        """The element connectivity of the model's dimension."""
        return self.triangles if self.dimension == 2 else self.tetrahedra

    def to_engine(self) -> dict:
        """The dict :func:`slipstep._engine.solve` reads (its arrays are this record's)."""
        out = super().to_engine()
        if self.dimension == 2:
            del out["dimension"]
        return out
