//! The dimension of a model as a type, chosen once (at the front end) and carried by the mesh,
//! the model and the engine: `Planar` (triangles, two DOFs per node, a stress state and a
//! thickness) or `Spatial` (tetrahedra, three DOFs per node). What differs between the two is
//! a method or an associated type of the dimension, in the spirit of nalgebra's dimension types
//! and the fenris crate's; the code that is the same in both is written once, generic over
//! `Dim`. (What a dimension's elements are is `element::Discretization`, a step up.)

use crate::bail;
use crate::contact::Frame;
use crate::error::Result;
use crate::material::Plane;
use crate::section::{Solid, StressState};
use std::fmt::Debug;

/// A space the engine runs in: its points, its cells and what its model adds to them.
pub trait Dim: Copy + Clone + Debug + Default + Send + Sync + 'static {
    /// DOFs per node: the number of coordinates.
    const N: usize;
    /// Elementary rigid motions of a body: translations, then rotations (3 in the plane, 6 in
    /// space).
    const RIGID_MODES: usize;
    /// A slip's direction turns in the contact's tangent plane (space), rather than being one
    /// of ±t along its one tangent (the plane, eq. 41).
    const SLIP_TURNS: bool;
    /// A body can turn about a contact's normal, a motion only friction resists (space; the
    /// plane's one rotation is about its own normal, resisted by the normal forces).
    const TURNS_ABOUT_A_NORMAL: bool;
    /// An obstacle's motion counts in the force scale once per contact surface, as one punch
    /// (space: E |Δc| ℓ), rather than per pair (the plane: E t |Δc|, as its histories have it;
    /// `driver::problem`'s `motion_forces`).
    const OBSTACLE_FORCE_PER_SURFACE: bool;
    /// The nodes with a trailing (contact) DOF are joined into a clique and end the factor with
    /// all their DOFs (the plane), rather than their trailing DOFs alone (space, where their
    /// other DOFs would triple the dense last block; `linalg::DofMap::ordered`).
    const TRAILING_CLIQUE: bool;
    /// A fill-reducing order's separators are surfaces (space), not lines (the plane): its
    /// dense supernodes are large, and a large factorization runs on every thread
    /// (`factor::faer_llt`).
    const WIDE_SEPARATORS: bool;
    /// A node's coordinates.
    type Point: Copy + Debug + Send + Sync + AsRef<[f64]>;
    /// An element's nodes: a triangle, counter-clockwise, or a tetrahedron, positively oriented.
    type Cell: Copy + Debug + Send + Sync + AsRef<[usize]>;
    /// What only the model in this space has: in the plane its stress state and thickness
    /// (`PlaneSection`), in space nothing.
    type Section: Copy + Debug + Send + Sync;

    /// A node's coordinates with three components (z = 0 in the plane).
    fn coordinates(p: &Self::Point) -> [f64; 3];

    /// The nodes as points in space, for the orders that cut space (`linalg::NodeOrder`); None
    /// in the plane.
    fn in_space(nodes: &[Self::Point]) -> Option<&[[f64; 3]]>;

    /// Reject cells the element routines cannot integrate (`mesh::Mesh::validate`): no cells,
    /// non-finite coordinates, node ids out of range, repeated nodes, inverted or degenerate
    /// cells.
    fn validate_cells(nodes: &[Self::Point], cells: &[Self::Cell]) -> Result<()>;

    /// The stress state the materials are bound to (`section`).
    fn stress_state(section: &Self::Section) -> &'static dyn StressState;

    /// Whether the model is of rings about the axis x = 0.
    fn is_axisymmetric(section: &Self::Section) -> bool;

    /// The out-of-plane thickness, in plane strain and plane stress; None in axisymmetry (forces
    /// are ring totals) and in space.
    fn thickness(section: &Self::Section) -> Option<f64>;

    /// The frame of a contact pair of unit `normal` (`contact::Frame`): in the plane
    /// t = (−n_y, n_x); in space the `tangents` given or the engine's own.
    fn pair_frame(normal: [f64; 3], tangents: Option<[[f64; 3]; 2]>) -> Frame<3, 2>;

    /// Storage for what exists only in space (a pair's second tangent, its facets): the value
    /// itself in space, nothing in the plane.
    type OnlyInSpace<T: Clone + Debug + Send + Sync>: InSpace<T>;
}

/// A value that exists in space only (`Dim::OnlyInSpace`): `Present` there, `Absent` (zero-sized,
/// no value) in the plane.
pub trait InSpace<T>: Clone + Debug + Send + Sync {
    fn new(value: impl FnOnce() -> T) -> Self;
    fn get(&self) -> Option<&T>;
    fn get_mut(&mut self) -> Option<&mut T>;
}

/// Nothing: the plane's `OnlyInSpace`.
#[derive(Debug, Clone, Copy, Default)]
pub struct Absent;

/// The value: space's `OnlyInSpace`.
#[derive(Debug, Clone)]
pub struct Present<T>(pub T);

impl<T> InSpace<T> for Absent {
    fn new(_: impl FnOnce() -> T) -> Self {
        Absent
    }
    fn get(&self) -> Option<&T> {
        None
    }
    fn get_mut(&mut self) -> Option<&mut T> {
        None
    }
}

impl<T: Clone + Debug + Send + Sync> InSpace<T> for Present<T> {
    fn new(value: impl FnOnce() -> T) -> Self {
        Present(value())
    }
    fn get(&self) -> Option<&T> {
        Some(&self.0)
    }
    fn get_mut(&mut self) -> Option<&mut T> {
        Some(&mut self.0)
    }
}

/// The plane: triangles (CST), two DOFs per node, in plane strain, plane stress or axisymmetry.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Planar;

/// Space: linear tetrahedra, three DOFs per node.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Spatial;

/// What a model in the plane adds to its mesh: the stress state and the out-of-plane thickness
/// t (plane strain and plane stress; ignored in axisymmetry, where every force is a total over
/// the full ring).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneSection {
    pub plane: Plane,
    pub thickness: f64,
}

impl Dim for Planar {
    const N: usize = 2;
    const RIGID_MODES: usize = 3;
    const SLIP_TURNS: bool = false;
    const TURNS_ABOUT_A_NORMAL: bool = false;
    const OBSTACLE_FORCE_PER_SURFACE: bool = false;
    const TRAILING_CLIQUE: bool = true;
    const WIDE_SEPARATORS: bool = false;
    type Point = [f64; 2];
    type Cell = [usize; 3];
    type Section = PlaneSection;
    type OnlyInSpace<T: Clone + Debug + Send + Sync> = Absent;

    fn coordinates(p: &[f64; 2]) -> [f64; 3] {
        [p[0], p[1], 0.0]
    }

    fn in_space(_: &[[f64; 2]]) -> Option<&[[f64; 3]]> {
        None
    }

    fn validate_cells(nodes: &[[f64; 2]], cells: &[[usize; 3]]) -> Result<()> {
        validate_triangles(nodes, cells)
    }

    fn stress_state(section: &PlaneSection) -> &'static dyn StressState {
        section.plane.stress_state()
    }

    fn pair_frame(normal: [f64; 3], _: Option<[[f64; 3]; 2]>) -> Frame<3, 2> {
        Frame::in_plane(normal)
    }

    fn is_axisymmetric(section: &PlaneSection) -> bool {
        section.plane == Plane::Axisymmetric
    }

    fn thickness(section: &PlaneSection) -> Option<f64> {
        (section.plane != Plane::Axisymmetric).then_some(section.thickness)
    }
}

impl Dim for Spatial {
    const N: usize = 3;
    const RIGID_MODES: usize = 6;
    const SLIP_TURNS: bool = true;
    const TURNS_ABOUT_A_NORMAL: bool = true;
    const OBSTACLE_FORCE_PER_SURFACE: bool = true;
    const TRAILING_CLIQUE: bool = false;
    const WIDE_SEPARATORS: bool = true;
    type Point = [f64; 3];
    type Cell = [usize; 4];
    type Section = ();
    type OnlyInSpace<T: Clone + Debug + Send + Sync> = Present<T>;

    fn coordinates(p: &[f64; 3]) -> [f64; 3] {
        *p
    }

    fn in_space(nodes: &[[f64; 3]]) -> Option<&[[f64; 3]]> {
        Some(nodes)
    }

    fn validate_cells(nodes: &[[f64; 3]], cells: &[[usize; 4]]) -> Result<()> {
        validate_tetrahedra(nodes, cells)
    }

    fn stress_state(_: &()) -> &'static dyn StressState {
        &Solid
    }

    fn pair_frame(normal: [f64; 3], tangents: Option<[[f64; 3]; 2]>) -> Frame<3, 2> {
        Frame::in_space(normal, tangents)
    }

    fn is_axisymmetric(_: &()) -> bool {
        false
    }

    fn thickness(_: &()) -> Option<f64> {
        None
    }
}

/// A flat or inverted tetrahedron: |det[x1 − x0, x2 − x0, x3 − x0]| at most this × the cube of
/// its longest edge (the triangles' 1e-10 of the squared longest side, one dimension up).
const FLAT_TETRAHEDRON: f64 = 1e-10;

/// Twice the signed area of a triangle (> 0 when counter-clockwise).
pub fn signed_area2(p: [[f64; 2]; 3]) -> f64 {
    let (pa, pb, pc) = (p[0], p[1], p[2]);
    (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pc[0] - pa[0]) * (pb[1] - pa[1])
}

/// det[x1 − x0, x2 − x0, x3 − x0] of a tetrahedron (6 × its signed volume).
pub fn signed_volume6(p: [[f64; 3]; 4]) -> f64 {
    let d = |k: usize| [p[k][0] - p[0][0], p[k][1] - p[0][1], p[k][2] - p[0][2]];
    let (a, b, c) = (d(1), d(2), d(3));
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}

/// Triangles: some, finite coordinates, node ids in range, three distinct nodes, neither
/// inverted nor degenerate.
fn validate_triangles(nodes: &[[f64; 2]], elements: &[[usize; 3]]) -> Result<()> {
    if elements.is_empty() {
        bail!(Input, "the mesh has no triangles: give each body a mesh with at least one element");
    }
    for (i, p) in nodes.iter().enumerate() {
        if !p[0].is_finite() || !p[1].is_finite() {
            bail!(
                Input,
                "node {i} has a non-finite coordinate ({}, {}): fix the mesh file",
                p[0],
                p[1]
            );
        }
    }
    let n = nodes.len();
    for (e, t) in elements.iter().enumerate() {
        if let Some(&bad) = t.iter().find(|&&v| v >= n) {
            bail!(Input, "element {e} refers to node {bad}, but the mesh has only {n} nodes: fix the connectivity");
        }
        if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
            bail!(Input, "element {e} repeats a node ({:?}): remove the degenerate triangle", t);
        }
    }
    for e in 0..elements.len() {
        let a2 = signed_area2(elements[e].map(|i| nodes[i]));
        let [a, b, c] = elements[e];
        let longest2 = [(a, b), (b, c), (c, a)]
            .iter()
            .map(|&(i, j)| {
                let (p, q) = (nodes[i], nodes[j]);
                (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)
            })
            .fold(0.0, f64::max);
        // Degenerate: height below 1e-10 of the longest side (zero area or collinear nodes).
        if a2.abs() <= 1e-10 * longest2 {
            bail!(Input, "element {e} is degenerate (area {:.3e} for a longest side of {:.3e}): remove it or move its nodes apart", a2 / 2.0, longest2.sqrt());
        }
        if a2 < 0.0 {
            bail!(
                Input,
                "element {e} is inverted (signed area {:.3e}): list its nodes counter-clockwise",
                a2 / 2.0
            );
        }
    }
    Ok(())
}

/// Tetrahedra: some, finite coordinates, node ids in range, four distinct nodes, positive
/// volume (an inverted or flat tetrahedron is named by its index).
fn validate_tetrahedra(nodes: &[[f64; 3]], elements: &[[usize; 4]]) -> Result<()> {
    if elements.is_empty() {
        bail!(
            Input,
            "the mesh has no tetrahedra: give each body a volume mesh with at least one element"
        );
    }
    if let Some((i, p)) = nodes.iter().enumerate().find(|(_, p)| p.iter().any(|v| !v.is_finite())) {
        bail!(
            Input,
            "node {i} has a non-finite coordinate ({}, {}, {}): fix the mesh file",
            p[0],
            p[1],
            p[2]
        );
    }
    let n = nodes.len();
    for (e, t) in elements.iter().enumerate() {
        if let Some(&bad) = t.iter().find(|&&v| v >= n) {
            bail!(Input, "element {e} refers to node {bad}, but the mesh has only {n} nodes: fix the connectivity");
        }
        if (0..4).any(|k| t[k + 1..].contains(&t[k])) {
            bail!(Input, "element {e} repeats a node ({t:?}): remove the degenerate tetrahedron");
        }
        let det = signed_volume6(t.map(|i| nodes[i]));
        let longest = (0..4)
            .flat_map(|a| (a + 1..4).map(move |b| (a, b)))
            .map(|(a, b)| {
                let (p, q) = (nodes[t[a]], nodes[t[b]]);
                ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
            })
            .fold(0.0, f64::max);
        if det.abs() <= FLAT_TETRAHEDRON * longest.powi(3) {
            bail!(Input, "element {e} is a flat tetrahedron (volume {:.3e} for a longest edge of {longest:.3e}): remove it or move its nodes apart", det / 6.0);
        }
        if det < 0.0 {
            bail!(Input, "element {e} is an inverted tetrahedron (signed volume {:.3e}): list its nodes so that det[x1 - x0, x2 - x0, x3 - x0] > 0", det / 6.0);
        }
    }
    Ok(())
}
