"""A validated case as typed records (:class:`CaseRecord`, ``Case.record``): one frozen
dataclass per table of the schema (:mod:`slipstep.schema`), its fields the table's keys under
their own names, so that a value's path reads like its ``--set`` key: ``record.analysis.plane``,
``record.body[0].material.E``, ``record.contact[i].mu``.  A contact is the record of its kind
(:data:`CONTACT_KINDS`); a body's mesh stays its validated table, read-only (its keys depend on
the generator).  tests/case/test_case_record.py holds every record to its schema table, key by
key and type by type.

Vectors are tuples, inline tables (a displacement, a stage's factors) read-only mappings; the
values are those of the validated document (``Case.data``), defaults filled in.
"""

from __future__ import annotations

import copy
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, fields
from typing import Any

__all__ = [
    "CONTACT_KINDS",
    "ReadOnlyTable",
    "contact_record",
    "CaseInfo",
    "Analysis",
    "HertzLoad",
    "Output",
    "Solver",
    "Material",
    "Body",
    "Bc",
    "PointLoad",
    "LoadStage",
    "Contact",
    "Window2D",
    "Window3D",
    "RigidObstacle",
    "RigidObstacle2D",
    "RigidObstacle3D",
    "RigidLine",
    "RigidCircle",
    "RigidPolyline",
    "RigidPlane",
    "RigidSphere",
    "RigidCylinder",
    "RigidSurface",
    "Pair",
    "NodeToNode",
    "NodeToSegment",
    "NodeToSurface",
    "CaseRecord",
]


class ReadOnlyTable(Mapping):
    """A table of a record (an inline table, a mesh table), read-only; unlike a
    ``MappingProxyType`` it copies and pickles, so a case does."""

    __slots__ = ("_items",)

    def __init__(self, items: dict):
        self._items = dict(items)

    def __getitem__(self, key: str):
        return self._items[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._items)

    def __len__(self) -> int:
        return len(self._items)

    def __repr__(self) -> str:
        return f"ReadOnlyTable({self._items!r})"


def _frozen(value):
    """``value`` with lists as tuples and dicts as read-only tables, recursively."""
    if isinstance(value, list):
        return tuple(_frozen(v) for v in value)
    if isinstance(value, dict):
        return ReadOnlyTable({k: _frozen(v) for k, v in value.items()})
    return value


class _Table:
    """A record of one table: built from the validated table, key by key."""

    @classmethod
    def of(cls, table: dict, **records):
        """The record of ``table`` (``records``: its sub-tables, already records)."""
        values = {f.name: _frozen(table[f.name]) for f in fields(cls) if f.name not in records}
        return cls(**values, **records)


# --------------------------------------------------------------------------- single tables
@dataclass(frozen=True, kw_only=True)
class CaseInfo(_Table):
    """[case]: its name, description and the units note."""

    name: str
    description: str
    units: str


@dataclass(frozen=True, kw_only=True)
class Analysis(_Table):
    """[analysis]: the dimension and, in 2D, the plane idealisation and thickness."""

    dimension: int
    plane: str
    thickness: float


@dataclass(frozen=True, kw_only=True)
class HertzLoad(_Table):
    """[load]: the Hertz load P on a quarter_cylinder (3D: sphere) ``body``."""

    P: float
    body: str


@dataclass(frozen=True, kw_only=True)
class Output(_Table):
    """[output]: which snapshots are kept, and whether figures and XDMF are written."""

    snapshots: str | tuple[float, ...]
    figures: bool
    xdmf: bool


@dataclass(frozen=True, kw_only=True)
class Solver(_Table):
    """[solver]: the engine's options (rust/src/options.rs), key for key."""

    tie_tol: float
    group_tol: float
    max_events: int
    equilibrium_tol: float
    drift_control: bool
    max_stress_step: float
    tangent_turn: float
    slip_turn: float
    stop_at_first_yield: bool
    limit_stiffness: float
    max_zero_length_switches: int
    reduced_elastic: bool
    factorization: str
    near_hops: int


# --------------------------------------------------------------------------- arrays of tables
@dataclass(frozen=True, kw_only=True)
class Material(_Table):
    """[body.material]: E and nu; Sy and H when plastic (None otherwise)."""

    E: float
    nu: float
    Sy: float | None
    H: float | None


@dataclass(frozen=True, kw_only=True)
class Body(_Table):
    """[[body]]: its name, its mesh table (validated, read-only: its keys are its generator's
    or a file's, and ``edges``, the tags a generator creates) and its material."""

    name: str
    mesh: Mapping[str, Any]
    material: Material

    @classmethod
    def of(cls, table: dict, **records):
        mesh = ReadOnlyTable(copy.deepcopy(table["mesh"]))
        return super().of(table, mesh=mesh, material=Material.of(table["material"]))

    @property
    def generator(self) -> str | None:
        """Its mesh generator (None for a file mesh)."""
        return self.mesh.get("generator")


@dataclass(frozen=True, kw_only=True)
class Bc(_Table):
    """[[bc]]: supports (fix, symmetry), loads (pressure, traction) and a prescribed
    displacement on an ``edge`` (3D: ``face``) or a node set of ``body``."""

    name: str
    body: str
    edge: str
    face: str
    nodes: str
    fix: tuple[str, ...]
    symmetry: bool
    pressure: float
    traction: tuple[float, ...]
    displacement: Mapping[str, float]

    @property
    def boundary_tag(self) -> str:
        """The boundary tag it names: its edge, or in 3D its face ("" for a node set)."""
        return self.face or self.edge

    @property
    def force(self) -> bool:
        """Whether it applies forces (a pressure or traction)."""
        return self.pressure != 0.0 or any(c != 0.0 for c in self.traction)


@dataclass(frozen=True, kw_only=True)
class PointLoad(_Table):
    """[[point_load]]: a force on the node nearest ``at`` (of ``body``, or of any)."""

    name: str
    body: str
    at: tuple[float, ...]
    force: tuple[float, ...]


@dataclass(frozen=True, kw_only=True)
class LoadStage(_Table):
    """[[stage]]: the factor each named load reaches at its end."""

    name: str
    factors: Mapping[str, float]


# --------------------------------------------------------------------------- contacts
@dataclass(frozen=True, kw_only=True)
class Contact(_Table):
    """[[contact]]: the keys every kind has."""

    kind: str
    name: str
    mu: float

    @property
    def bodies(self) -> tuple[str, ...]:
        """The deformable bodies it touches, contactor first."""
        raise NotImplementedError

    @property
    def surfaces(self) -> tuple[tuple[str, str, str], ...]:
        """(key, body, tag) of each surface it names, contactor first: ``edge``/``face`` of a
        rigid obstacle, ``edge_a``/``face_a`` and ``edge_b``/``face_b`` of a pair."""
        raise NotImplementedError

    @property
    def contactor(self) -> tuple[str, str]:
        """(body, tag) of its contactor side."""
        return self.surfaces[0][1:]

    @property
    def motion_load(self) -> tuple[float, ...] | None:
        """The obstacle's motion at factor 1 (None: it does not move, or a pair)."""
        return None


@dataclass(frozen=True, kw_only=True)
class Window2D:
    """The candidate window of a contact in the plane."""

    x_min: float
    x_max: float
    y_min: float
    y_max: float

    def window(self, axis: str) -> tuple[float, float]:
        """(min, max) of the candidates' coordinate ``axis`` ("x", "y", in 3D "z")."""
        return getattr(self, f"{axis}_min"), getattr(self, f"{axis}_max")


@dataclass(frozen=True, kw_only=True)
class Window3D(Window2D):
    """The candidate window of a contact in space."""

    z_min: float
    z_max: float


@dataclass(frozen=True, kw_only=True)
class RigidObstacle(Contact):
    """A deformable ``body`` against a rigid obstacle."""

    body: str
    tolerance: float

    @property
    def bodies(self) -> tuple[str, ...]:
        return (self.body,)

    @property
    def surface_key(self) -> str:
        """The key of the body's candidate tag: "edge" (3D: "face")."""
        raise NotImplementedError

    @property
    def surfaces(self) -> tuple[tuple[str, str, str], ...]:
        return ((self.surface_key, self.body, getattr(self, self.surface_key)),)


@dataclass(frozen=True, kw_only=True)
class RigidObstacle2D(RigidObstacle, Window2D):
    """A rigid obstacle in the plane: the body's ``edge``, the obstacle's ``motion`` [dx, dy]."""

    edge: str
    motion: tuple[float, float] | None

    @property
    def surface_key(self) -> str:
        return "edge"

    @property
    def motion_load(self) -> tuple[float, ...] | None:
        return self.motion


@dataclass(frozen=True, kw_only=True)
class RigidObstacle3D(RigidObstacle, Window3D):
    """A rigid obstacle in space: the body's ``face``, the obstacle's ``motion`` [dx, dy, dz]."""

    face: str
    motion: tuple[float, float, float] | None

    @property
    def surface_key(self) -> str:
        return "face"

    @property
    def motion_load(self) -> tuple[float, ...] | None:
        return self.motion


@dataclass(frozen=True, kw_only=True)
class RigidLine(RigidObstacle2D):
    """kind = "rigid_line": the line through ``point`` with ``normal`` towards the body."""

    point: tuple[float, float]
    normal: tuple[float, float]


@dataclass(frozen=True, kw_only=True)
class RigidCircle(RigidObstacle2D):
    """kind = "rigid_circle": the body outside or inside (``side``) a circle."""

    centre: tuple[float, float]
    radius: float
    side: str


@dataclass(frozen=True, kw_only=True)
class RigidPolyline(RigidObstacle2D):
    """kind = "rigid_polyline": the body on one ``side`` of a polyline."""

    points: tuple[tuple[float, float], ...]
    side: str


@dataclass(frozen=True, kw_only=True)
class RigidPlane(RigidObstacle3D):
    """kind = "rigid_plane": the plane through ``point`` with ``normal`` towards the body."""

    point: tuple[float, float, float]
    normal: tuple[float, float, float]


@dataclass(frozen=True, kw_only=True)
class RigidSphere(RigidObstacle3D):
    """kind = "rigid_sphere": the body outside or inside (``side``) a sphere."""

    centre: tuple[float, float, float]
    radius: float
    side: str


@dataclass(frozen=True, kw_only=True)
class RigidCylinder(RigidObstacle3D):
    """kind = "rigid_cylinder": the body outside or inside an infinite cylinder."""

    point: tuple[float, float, float]
    axis: tuple[float, float, float]
    radius: float
    side: str


@dataclass(frozen=True, kw_only=True)
class RigidSurface(RigidObstacle3D):
    """kind = "rigid_surface": a triangulated surface (a ``file``) or an ``indenter``
    pyramid."""

    file: str
    scale: float
    indenter: str
    tip: tuple[float, float, float]
    size: float
    side: str


@dataclass(frozen=True, kw_only=True)
class Pair(Contact):
    """A deformable pair: contactor ``body_a`` against target ``body_b``."""

    body_a: str
    body_b: str
    tolerance: float

    @property
    def bodies(self) -> tuple[str, ...]:
        return (self.body_a, self.body_b)

    def side_key(self, side: str) -> str:
        """The key of side ``side``'s ("a" or "b") tag: "edge" or "face"."""
        raise NotImplementedError

    @property
    def surfaces(self) -> tuple[tuple[str, str, str], ...]:
        keys = ((f"{self.side_key(s)}_{s}", s) for s in "ab")
        return tuple((key, getattr(self, f"body_{s}"), getattr(self, key)) for key, s in keys)


@dataclass(frozen=True, kw_only=True)
class NodeToNode(Pair):
    """kind = "node_to_node": nodes of edge_a (3D: face_a) paired with the nearest of edge_b
    (face_b), under a fixed ``normal`` or edge_b's own."""

    edge_a: str
    face_a: str
    edge_b: str
    face_b: str
    normal: tuple[float, ...] | None

    def side_key(self, side: str) -> str:
        return "face" if getattr(self, f"face_{side}") else "edge"


@dataclass(frozen=True, kw_only=True)
class NodeToSegment(Pair, Window2D):
    """kind = "node_to_segment": nodes of edge_a against the segments of edge_b."""

    edge_a: str
    edge_b: str

    def side_key(self, side: str) -> str:
        return "edge"


@dataclass(frozen=True, kw_only=True)
class NodeToSurface(Pair, Window3D):
    """kind = "node_to_surface": nodes of face_a against the triangles of face_b."""

    face_a: str
    face_b: str

    def side_key(self, side: str) -> str:
        return "face"


#: The record of each contact kind.
CONTACT_KINDS: dict[str, type[Contact]] = {
    "rigid_line": RigidLine,
    "rigid_circle": RigidCircle,
    "rigid_polyline": RigidPolyline,
    "node_to_node": NodeToNode,
    "node_to_segment": NodeToSegment,
    "rigid_plane": RigidPlane,
    "rigid_sphere": RigidSphere,
    "rigid_cylinder": RigidCylinder,
    "rigid_surface": RigidSurface,
    "node_to_surface": NodeToSurface,
}


def contact_record(table: dict) -> Contact:
    """The record of a validated [[contact]] table, by its kind."""
    return CONTACT_KINDS[table["kind"]].of(table)


# --------------------------------------------------------------------------- the case
@dataclass(frozen=True, kw_only=True)
class CaseRecord:
    """A validated case, table by table: [case], [analysis], [load] (None without it),
    [output], [solver], and the arrays body, bc, point_load, contact and stage."""

    case: CaseInfo
    analysis: Analysis
    load: HertzLoad | None
    output: Output
    solver: Solver
    body: tuple[Body, ...]
    bc: tuple[Bc, ...]
    point_load: tuple[PointLoad, ...]
    contact: tuple[Contact, ...]
    stage: tuple[LoadStage, ...]

    @classmethod
    def of(cls, data: dict) -> CaseRecord:
        """The records of a validated document (:class:`slipstep.case.Case` ``data``)."""
        return cls(
            case=CaseInfo.of(data["case"]),
            analysis=Analysis.of(data["analysis"]),
            load=None if data["load"] is None else HertzLoad.of(data["load"]),
            output=Output.of(data["output"]),
            solver=Solver.of(data["solver"]),
            body=tuple(Body.of(b) for b in data["body"]),
            bc=tuple(Bc.of(b) for b in data["bc"]),
            point_load=tuple(PointLoad.of(p) for p in data["point_load"]),
            contact=tuple(contact_record(c) for c in data["contact"]),
            stage=tuple(LoadStage.of(s) for s in data["stage"]),
        )

    def body_named(self, name: str) -> Body:
        """The [[body]] called ``name`` (KeyError if none)."""
        for b in self.body:
            if b.name == name:
                return b
        raise KeyError(name)

    @property
    def hertz_body(self) -> Body | None:
        """The body [load] P acts on (None without [load])."""
        return None if self.load is None else self.body_named(self.load.body)

    @property
    def frictionless(self) -> bool:
        """Whether every contact has mu = 0."""
        return all(c.mu == 0.0 for c in self.contact)
