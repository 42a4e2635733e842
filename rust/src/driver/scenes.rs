//! Tiny models for the phases' unit tests, each with its answer in closed form (test code).

use super::clock::Clock;
use super::engine::Engine;
use super::state::State;
use crate::dim::{Dim, Planar, PlaneSection, Spatial};
use crate::element::Discretization;
use crate::material::{Material, Plane};
use crate::mesh::Mesh;
use crate::model::{LoadPattern, Model, Names, Options, PairInput, Stage};

/// Young's modulus and Poisson's ratio of the scenes.
pub const E: f64 = 1000.0;
pub const NU: f64 = 0.25;

/// The box [0, nx h] × [0, ny h] × [0, nz h] of cubes of side h, each split into Kuhn's six
/// tetrahedra along its diagonal (positively oriented); node (i, j, k) is i + (nx + 1)(j +
/// (ny + 1) k).
pub fn cube_block(n: [usize; 3], h: f64) -> Mesh<Spatial> {
    let id = |i: usize, j: usize, k: usize| i + (n[0] + 1) * (j + (n[1] + 1) * k);
    let mut points = vec![[0.0; 3]; (n[0] + 1) * (n[1] + 1) * (n[2] + 1)];
    for k in 0..=n[2] {
        for j in 0..=n[1] {
            for i in 0..=n[0] {
                points[id(i, j, k)] = [i as f64 * h, j as f64 * h, k as f64 * h];
            }
        }
    }
    let mut tets = vec![];
    for (i, j, k) in
        (0..n[2]).flat_map(|k| (0..n[1]).flat_map(move |j| (0..n[0]).map(move |i| (i, j, k))))
    {
        for perm in [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]] {
            let mut at = [0usize; 3];
            let mut t = vec![id(i, j, k)];
            for &axis in &perm {
                at[axis] = 1;
                t.push(id(i + at[0], j + at[1], k + at[2]));
            }
            let d = |a: usize| [0, 1, 2].map(|c| points[t[a]][c] - points[t[0]][c]);
            let (a, b, c) = (d(1), d(2), d(3));
            let det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]);
            if det < 0.0 {
                t.swap(2, 3);
            }
            tets.push([t[0], t[1], t[2], t[3]]);
        }
    }
    Mesh::<Spatial>::new(points, tets)
}

/// The unit square [0, 1]² of two CSTs: nodes 0 (0, 0), 1 (1, 0), 2 (1, 1), 3 (0, 1).
pub fn unit_square() -> Mesh<Planar> {
    Mesh::<Planar>::new(
        vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        vec![[0, 1, 2], [0, 2, 3]],
    )
}

/// The section of the scenes: plane stress of thickness 1 in the plane.
pub trait SceneDim: Dim {
    fn section() -> Self::Section;
}

impl SceneDim for Planar {
    fn section() -> PlaneSection {
        PlaneSection { plane: Plane::Stress, thickness: 1.0 }
    }
}

impl SceneDim for Spatial {
    fn section() {}
}

/// A one-material model (in plane stress of thickness 1 in the plane).
pub fn model<D: SceneDim>(
    mesh: Mesh<D>,
    fixed_dofs: Vec<usize>,
    load: Vec<f64>,
    pairs: Vec<PairInput>,
    material: Material,
) -> Model<D> {
    let n_el = mesh.elements.len();
    Model {
        mesh,
        element_material: vec![0; n_el],
        materials: vec![material],
        section: D::section(),
        fixed_dofs,
        load,
        patterns: vec![],
        stages: vec![],
        pairs,
        names: Names::default(),
        options: Options::default(),
    }
}

/// A pair of node `a` with a rigid obstacle of normal `normal` (towards the node) at `gap`.
pub fn against_obstacle(a: usize, normal: [f64; 2], gap: f64, mu: f64) -> PairInput {
    PairInput {
        node_a: a,
        node_b: None,
        normal: [normal[0], normal[1], 0.0],
        tangents: None,
        gap,
        mu,
        contact: 0,
        weights: vec![],
    }
}

/// The unit square on rollers (u_x = 0 on x = 0, u_y = 0 on y = 0): a traction `right` on its
/// right edge and `top` on its top edge (consistent nodal forces) give the uniform stress
/// σx = right, σy = top, τ = 0 in every element (the CST's patch test).
pub fn square_on_rollers(right: f64, top: f64, material: Material) -> Model<Planar> {
    let fixed = vec![0, 1, 3, 6]; // u_x, u_y of node 0; u_y of node 1; u_x of node 3
    model(unit_square(), fixed, edge_loads(right, top), vec![], material)
}

/// Nodal forces of the tractions `right` (σx) and `top` (σy) on the unit square's edges.
pub fn edge_loads(right: f64, top: f64) -> Vec<f64> {
    let mut load = vec![0.0; 8];
    for n in [1, 2] {
        load[2 * n] += right / 2.0;
    }
    for n in [2, 3] {
        load[2 * n + 1] += top / 2.0;
    }
    load
}

/// The square on rollers pressed by q on its top (σy = −q): in plane stress its right edge
/// moves out by ν q / E (Poisson), towards a rigid wall at `gap` to the right of node 2 (the
/// wall's normal (−1, 0) points back at the node).
pub fn poisson_wall(q: f64, gap: f64) -> Model<Planar> {
    let mut m = square_on_rollers(0.0, -q, Material::elastic(E, NU));
    m.pairs = vec![against_obstacle(2, [-1.0, 0.0], gap, 0.0)];
    m
}

/// One triangle whose nodes 1 and 2 are held; node 0 rests on a rigid flat (normal (0, 1), gap
/// 0, friction μ). Stage 1 presses node 0 into the flat by N, stage 2 adds a tangential force T
/// (+x). The stuck pair holds node 0 in place, so the element carries nothing and the pair
/// carries the load: λ_n = N, λ_t = T (t = (−1, 0), the force on the node w_t λ_t = −T e_x).
pub fn pressed_then_sheared(n: f64, t: f64, mu: f64) -> Model<Planar> {
    let mesh = Mesh::<Planar>::new(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], vec![[0, 1, 2]]);
    let mut m = model(
        mesh,
        vec![2, 3, 4, 5],
        vec![0.0, -n, 0.0, 0.0, 0.0, 0.0],
        vec![against_obstacle(0, [0.0, 1.0], 0.0, mu)],
        Material::elastic(E, NU),
    );
    m.patterns = vec![LoadPattern {
        name: "shear".into(),
        force: vec![t, 0.0, 0.0, 0.0, 0.0, 0.0],
        ..Default::default()
    }];
    m.stages = vec![
        Stage { name: "press".into(), factors: vec![1.0, 0.0] },
        Stage { name: "shear".into(), factors: vec![1.0, 1.0] },
    ];
    m
}

/// A strip [0, 2] × [0, 1] of two squares (nodes 0, 1, 2 along the bottom, 3, 4, 5 along the
/// top), held in x on its left edge (symmetry) and resting on a rigid flat with its bottom
/// nodes 0 and 1 (gap 0, friction μ), pushed towards the symmetry edge at node 2 by 0.5
/// (ν = 0). Every pair starts at zero force, and nothing but contact holds the strip
/// vertically: switched one at a time, pair 1 separates and closes again and again at zero
/// load (found by a search over small strips; the rate problem settles it).
pub fn pushed_strip(mu: f64) -> Model<Planar> {
    let nodes = vec![[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [0.0, 1.0], [1.0, 1.0], [2.0, 1.0]];
    let triangles = vec![[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]];
    let mut load = vec![0.0; 12];
    load[4] = -0.5;
    let pairs =
        vec![against_obstacle(0, [0.0, 1.0], 0.0, mu), against_obstacle(1, [0.0, 1.0], 0.0, mu)];
    model(Mesh::<Planar>::new(nodes, triangles), vec![0, 6], load, pairs, Material::elastic(E, 0.0))
}

/// The square on rollers in two stages: stage 1 pulls its right edge to σx = `a`, stage 2
/// presses its top to σy = −`b` (σx held).
pub fn pulled_then_pressed(a: f64, b: f64, material: Material) -> Model<Planar> {
    let mut m = square_on_rollers(a, 0.0, material);
    m.patterns = vec![LoadPattern {
        name: "press".into(),
        force: edge_loads(0.0, -b),
        ..Default::default()
    }];
    m.stages = vec![
        Stage { name: "pull".into(), factors: vec![1.0, 0.0] },
        Stage { name: "press".into(), factors: vec![1.0, 1.0] },
    ];
    m
}

/// A hardening material of yield stress `sy` and plastic modulus `h`.
pub fn plastic(sy: f64, h: f64) -> Material {
    Material { yield_stress: sy, hardening: h, ..Material::elastic(E, NU) }
}

/// The engine of a model (which must be valid) and its initial state.
pub fn start<'m, 'c, D: Discretization>(
    model: &'m Model<D>,
    clock: &'c Clock,
) -> (Engine<'m, 'c, D>, State<D>) {
    model.validate().expect("a valid scene");
    let eng = Engine::new(model, clock).expect("the scene assembles");
    let state = eng.initial_state();
    (eng, state)
}
