//! The problem the procedure works on, fixed for the whole run: the elements with their
//! kinematics and sections, the contact pairs (eqs. 45–46), the bodies and their free
//! rigid-body modes, the load path, the DOF maps (supports, pinned DOFs, the contact DOFs last
//! in the factor) and the DOF space the loop carries (`space`); and the scales its tolerances
//! are relative to.

use super::path::{LoadPath, StageLoad};
use super::space::{Reduced, Space};
use super::state::State;
use crate::bail;
use crate::contact::{Pair, PairGeometry, SparseVec, Status, HELD_BY_SUPPORTS};
use crate::coulomb::Coulomb;
use crate::dim::Dim;
use crate::element::{Discretization, Elements};
use crate::error::Result;
use crate::linalg::{DofMap, NodeOrder};
use crate::material::{Tangent, Voigt};
use crate::model::Model;
use crate::on_elements;
use crate::rigid_modes::{free_modes, RigidMode};
use crate::section::Section;

/// Zero-gap pairs start closed: a gap within this × the length scale counts as zero.
const INITIAL_CONTACT: f64 = 1e-12;
/// Round-off scale of forces: noise floor of a force rate, × Σ|load|.
const FORCE_NOISE: f64 = 1e-12;
/// Element loops run on the cores in chunks of at least this many elements (below it the
/// threads' start costs more than the loop).
pub(super) const PARALLEL_CHUNK: usize = 1024;

/// The scales tolerances are relative to.
pub(super) struct Scales {
    /// |P| over the free DOFs (1 for a tractionless scene: residuals are then absolute).
    pub load_norm: f64,
    /// Σ|P|: the scale of forces.
    pub force: f64,
    /// The mesh's bounding-box diagonal.
    pub length: f64,
    /// A force rate below this is round-off (`FORCE_NOISE` × `force`).
    pub force_noise: f64,
}

impl Scales {
    /// A gap within this is zero: the pair starts closed, or touches (`INITIAL_CONTACT`).
    pub fn touching(&self) -> f64 {
        INITIAL_CONTACT * self.length
    }
}

/// Where every DOF goes: supports and prescribed DOFs (fixed), the equations of the factor,
/// and the slot of each contact DOF in the flexibility.
pub(super) struct Dofs {
    pub map: DofMap,
    pub fixed: Vec<bool>,
    /// Slot in the flexibility of each DOF of the loop's DOF space (usize::MAX: not a contact
    /// DOF, or fixed/pinned, where K# is zero).
    pub contact_slot: Vec<usize>,
    /// The global DOF of each slot: the trailing equations of the factor.
    pub slot_dofs: Vec<usize>,
}

/// The connected components of the mesh and their free rigid-body modes.
pub(super) struct Bodies {
    /// Body of every node, and the first element of every body (its name in messages,
    /// `Model::body_name`).
    pub of_node: Vec<usize>,
    pub first_element: Vec<usize>,
    pub modes: Vec<RigidMode>,
    /// The rigid modes over the DOFs the loop carries.
    pub mode_vectors: Vec<Vec<f64>>,
}

pub(super) struct Problem<'m, D: Dim> {
    pub model: &'m Model<D>,
    pub elements: Elements,
    /// The material of every element under the model's stress state.
    pub sections: Vec<Section>,
    /// The elements around each node (whether a closure's neighbourhood is elastic).
    pub node_elements: Vec<Vec<usize>>,
    /// Elements with a prescribed DOF (their K_fp Δū loads the free DOFs).
    pub prescribed_elements: Vec<usize>,
    /// The pairs over the DOFs the loop carries (`space`).
    pub pairs: Vec<Pair>,
    pub space: Space,
    pub bodies: Bodies,
    pub dofs: Dofs,
    pub path: LoadPath,
    pub scales: Scales,
}

impl<'m, D: Dim> Problem<'m, D> {
    /// Everything the loop needs from `model`, which must have passed `Model::validate`.
    pub fn new(model: &'m Model<D>) -> Result<Self>
    where
        D: Discretization,
    {
        let mesh = &model.mesh;
        let dim = D::N;
        let n_dofs = dim * mesh.n_nodes();
        let path = LoadPath::new(model);
        let mut fixed = vec![false; n_dofs];
        model.supported_dofs().iter().chain(&path.prescribed_dofs()).for_each(|&d| fixed[d] = true);
        let pairs = contact_pairs(model, &fixed)?;
        let (body_of_node, n_bodies) = mesh.bodies();
        let (modes, pinned) =
            free_modes(mesh, &body_of_node, n_bodies, &fixed, model.is_axisymmetric());
        let (contact_slot, slot_dofs) = contact_slots(&pairs, &fixed, &pinned);
        let stress_state = D::stress_state(&model.section);
        let elements = D::elements(mesh, &model.section);
        let map = on_elements!(&elements, els => DofMap::ordered_by(els, n_dofs, &fixed, &pinned, &slot_dofs, NodeOrder::of_mesh(mesh)))?;
        let sections: Vec<Section> = model
            .element_material
            .iter()
            .map(|&m| Section::new(model.materials[m], stress_state))
            .collect();
        let prescribed_elements = elements_touching(&elements, &path.prescribed_dofs());
        let full_modes: Vec<Vec<f64>> = modes.iter().map(|m| m.vector.clone()).collect();
        let reducible = !model.has_plastic_material();
        let (space, pairs, contact_slot, mode_vectors) =
            if model.options.reduced_elastic && reducible {
                let (reduced, view) = Reduced::new(pairs, &slot_dofs, &contact_slot, &full_modes);
                (Space::Reduced(reduced), view.pairs, view.contact_slot, view.mode_vectors)
            } else {
                (Space::Full, pairs, contact_slot, full_modes)
            };
        let mut problem = Problem {
            model,
            node_elements: node_elements(&elements, mesh.n_nodes()),
            elements,
            sections,
            prescribed_elements,
            pairs,
            space,
            bodies: Bodies {
                first_element: first_elements(model, &body_of_node, n_bodies),
                of_node: body_of_node,
                modes,
                mode_vectors,
            },
            dofs: Dofs { map, fixed, contact_slot, slot_dofs },
            path,
            scales: Scales {
                load_norm: 1.0,
                force: 1.0,
                length: mesh.diameter(),
                force_noise: 0.0,
            },
        };
        let (load_norm, force) = problem.path_force_scales();
        let force = force.max(f64::MIN_POSITIVE);
        problem.scales.load_norm = if load_norm > 0.0 { load_norm } else { 1.0 };
        problem.scales.force = force;
        problem.scales.force_noise = FORCE_NOISE * force;
        Ok(problem)
    }

    pub fn is_reduced(&self) -> bool {
        matches!(self.space, Space::Reduced(_))
    }

    /// The pairs over the global DOFs (full fields, snapshots).
    pub fn global_pairs(&self) -> &[Pair] {
        match &self.space {
            Space::Reduced(r) => &r.global_pairs,
            Space::Full => &self.pairs,
        }
    }

    /// Length of the displacement vectors the loop carries.
    pub fn loop_dofs(&self) -> usize {
        match &self.space {
            Space::Reduced(r) => r.dofs.len(),
            Space::Full => self.dofs.map.role.len(),
        }
    }

    /// Number of element arrays the loop carries (none in the reduced space).
    pub fn loop_elements(&self) -> usize {
        if self.is_reduced() {
            0
        } else {
            self.elements.len()
        }
    }

    /// The gap of pair p with its obstacle's motion: gap₀ + w_nᵀu + c_n.
    pub fn gap(&self, state: &State<D>, p: usize) -> f64 {
        self.pairs[p].gap(&state.u) + state.shift[p][0]
    }

    /// The RTD of pair p with its obstacle's motion: w_tᵀu + c_t.
    pub fn rtd(&self, state: &State<D>, p: usize) -> f64 {
        self.pairs[p].rtd(&state.u) + state.shift[p][1]
    }

    /// 3D: the RTD along t2 with its obstacle's motion: w_t2ᵀu + c_t2.
    pub fn rtd2(&self, state: &State<D>, p: usize) -> f64 {
        self.pairs[p].w_t2().map_or(0.0, |w| w.dot(&state.u)) + state.shift[p][2]
    }

    /// λ_t = τ λ_n of a slipping pair (eq. 41), τ = (τ1, τ2) along (t1, t2): in 2D (−dμ, 0),
    /// in 3D μ e with e its held direction (`State::slip_dir`), μ / cos(slip_turn) m at a
    /// vertex m (`State::vertex`); 0 unless it slips with friction.
    pub fn slip_ratios(&self, state: &State<D>, p: usize) -> [f64; 2] {
        let pair = &self.pairs[p];
        match state.status[p] {
            _ if pair.slips_along_a_line() => [pair.slip_ratio(state.status[p]), 0.0],
            Status::Slip { direction } if direction != 0 => {
                pair.friction.slip_ratio(state.slip_dir(p), state.at_vertex(p))
            }
            _ => [0.0; 2],
        }
    }

    /// 3D: the cross direction e⊥ = (−e2, e1) (along t1, t2) of a slipping pair that holds its
    /// facet's cross row (`contact`'s module text): both tangents free, a held direction e, and
    /// a normal force to bound its cross force by (a pair slipping at zero force has none yet:
    /// `slip_turn`). None for every other pair.
    pub fn cross_direction(&self, state: &State<D>, p: usize) -> Option<[f64; 2]> {
        self.facet_cross(state, p)
            .filter(|_| state.lambda_n[p] > self.scales.force_noise || state.facet_laid(p))
    }

    /// 3D: e⊥ of a slipping pair that could slip on a facet, whatever its normal force: both
    /// tangents free, with friction and a held direction e.
    pub fn facet_cross(&self, state: &State<D>, p: usize) -> Option<[f64; 2]> {
        let (pair, e) = (&self.pairs[p], state.slip_dir(p));
        let slipping = matches!(state.status[p], Status::Slip { direction } if direction != 0);
        let directed = slipping
            && !state.at_vertex(p)
            && pair.friction.acts()
            && pair.has_tangent_plane()
            && e != [0.0; 2];
        directed.then_some([-e[1], e[0]])
    }

    /// 3D: the polygon pair p's friction has been on since it last began to slip (its sides
    /// about `State::slip_dir`, a vertex there or a side: `coulomb`); None for a pair that has
    /// not slipped since it closed (the round cone), one at zero normal force (where every
    /// side holds at once), in the plane, or along one free tangent.
    pub fn polygon_of(&self, state: &State<D>, p: usize) -> Option<([f64; 2], bool)> {
        let pair = &self.pairs[p];
        let pressed = state.lambda_n[p] > self.scales.force_noise;
        let laid = pair.friction.acts()
            && pair.has_tangent_plane()
            && state.slip_dir(p) != [0.0; 2]
            && pressed;
        laid.then_some((state.slip_dir(p), state.at_vertex(p)))
    }

    /// How far pair p's friction force is beyond its cone (round, or its polygon): > 0 violates
    /// Coulomb's law.
    pub fn friction_excess(&self, state: &State<D>, p: usize) -> f64 {
        self.pairs[p].friction.excess(
            self.polygon_of(state, p),
            state.lambda_n[p],
            state.lambda_t_of(p),
        )
    }

    /// The friction force (along t1, t2) of a slipping pair: −d μ λ_n in the plane (eq. 41), on
    /// its facet in space (eq. 62: μ λ_n along e, the cross force of `lambda_t` kept within the
    /// band where the pair has a cross row), or at its vertex; zero without compression.
    pub fn slip_force(&self, state: &State<D>, p: usize, lambda_t: [f64; 2]) -> [f64; 2] {
        let law = self.pairs[p].friction;
        match state.status[p] {
            Status::Slip { direction } if self.pairs[p].slips_along_a_line() => {
                [-(direction as f64) * law.capacity(state.lambda_n[p]), 0.0]
            }
            Status::Slip { direction } if direction != 0 && state.at_vertex(p) => {
                law.vertex_force(state.lambda_n[p], state.slip_dir(p))
            }
            Status::Slip { direction } if direction != 0 => law.on_facet(
                state.lambda_n[p],
                state.slip_dir(p),
                lambda_t,
                self.cross_direction(state, p).is_some(),
            ),
            _ => [0.0; 2],
        }
    }

    /// Nᵀ W λ: the contact forces' share of free rigid mode k (over the loop's DOFs).
    pub fn mode_contact_force(&self, state: &State<D>, k: usize) -> f64 {
        let mode = &self.bodies.mode_vectors[k];
        self.pairs
            .iter()
            .enumerate()
            .map(|(p, pair)| {
                let [n, t1, t2] = pair.dots(mode);
                state.lambda_n[p] * n + state.lambda_t[p] * t1 + state.lambda_t_of(p)[1] * t2
            })
            .sum()
    }

    pub fn body_of_pair(&self, p: usize) -> usize {
        self.bodies.of_node[self.global_pairs()[p].node_a]
    }

    /// Internal nodal forces P_σ = Σ w Bᵀ σ (eq. 42; w = t A, or 2π r̄ A in axisymmetry).
    pub fn internal_force(&self, stress: &[Voigt]) -> Vec<f64> {
        let mut f = vec![0.0; self.dofs.map.role.len()];
        for (e, s) in stress.iter().enumerate() {
            self.elements.add_internal_force(e, s, 1.0, |_| true, &mut f);
        }
        f
    }

    /// cᵀ x for a constraint vector c and x given at the contact slots.
    pub fn dot_slots(&self, c: &SparseVec, x: &[f64]) -> f64 {
        c.entries
            .iter()
            .map(|&(d, v)| match self.dofs.contact_slot[d] {
                usize::MAX => 0.0,
                slot => v * x[slot],
            })
            .sum()
    }

    /// A vector over all DOFs from its values at the contact slots (0 elsewhere).
    pub fn slots_to_dofs(&self, at_slots: &[f64]) -> Vec<f64> {
        let mut v = vec![0.0; self.dofs.map.role.len()];
        for (d, &slot) in self.dofs.contact_slot.iter().enumerate() {
            if slot != usize::MAX {
                v[d] = at_slots[slot];
            }
        }
        v
    }

    /// −K_fp Δū over all DOFs (zero at held ones): the force on the free DOFs of the elements
    /// that touch prescribed increments Δū, with the `tangents` K holds. None when Δū = 0.
    pub fn prescribed_force(
        &self,
        tangents: &[Tangent],
        increments: &[(usize, f64)],
    ) -> Option<Vec<f64>> {
        if increments.iter().all(|&(_, v)| v == 0.0) {
            return None;
        }
        let mut du = vec![0.0; self.dofs.map.role.len()];
        increments.iter().for_each(|&(d, v)| du[d] = v);
        let mut f = vec![0.0; du.len()];
        for &e in &self.prescribed_elements {
            let s = self.sections[e].stress_increment(&tangents[e], &self.elements.strain(e, &du));
            self.elements.add_internal_force(e, &s, -1.0, |d| !self.dofs.fixed[d], &mut f);
        }
        Some(f)
    }

    /// A stage's effective load over the free DOFs, ΔP − K_fp Δū, and its part −K_fp Δū.
    pub fn effective_load(
        &self,
        stage: &StageLoad,
        tangents: &[Tangent],
    ) -> (Vec<f64>, Option<Vec<f64>>) {
        let mut load: Vec<f64> = stage
            .force_change()
            .iter()
            .enumerate()
            .map(|(d, v)| if self.dofs.fixed[d] { 0.0 } else { *v })
            .collect();
        let held = self.prescribed_force(tangents, &stage.prescribed_changes());
        if let Some(f) = &held {
            load.iter_mut().zip(f).for_each(|(l, x)| *l += x);
        }
        (load, held)
    }

    /// The loads of stage k over the global DOFs and pairs.
    pub fn stage_load(&self, k: usize) -> StageLoad {
        self.path.stage(k, self.dofs.map.role.len(), self.global_pairs().len())
    }

    /// Scales of the whole path: max over stages of |ΔP − K_fp Δū| over the free DOFs, and
    /// of Σ|ΔP| (+ Σ|K_fp Δū|), with every element elastic; an obstacle's motion counts as the
    /// force it takes to press its contact surface by its largest |Δc| (`motion_forces`).
    /// (norm, sum)
    fn path_force_scales(&self) -> (f64, f64) {
        let elastic: Vec<Tangent> =
            self.sections.iter().map(|s| s.tangent(&Voigt::zeros(), false)).collect();
        let young = self.sections.iter().map(|s| s.material.young).fold(0.0f64, f64::max);
        let surfaces =
            if D::OBSTACLE_FORCE_PER_SURFACE { self.contact_surface_lengths() } else { vec![] };
        let (mut norm, mut sum) = (0.0f64, 0.0f64);
        for k in 0..self.path.n_stages() {
            let stage = self.stage_load(k);
            let mut total: f64 = stage.force_change().iter().map(|v| v.abs()).sum();
            let (mut effective, held) = self.effective_load(&stage, &elastic);
            if let Some(f) = held {
                total += f.iter().map(|v| v.abs()).sum::<f64>();
            }
            for moved in self.motion_forces(&stage, young, &surfaces) {
                total += moved;
                effective.push(moved);
            }
            norm = norm.max(effective.iter().map(|v| v * v).sum::<f64>().sqrt());
            sum = sum.max(total);
        }
        (norm, sum)
    }

    /// The forces obstacle motions over `stage` produce. In space, per contact of the case:
    /// E |Δc| ℓ with |Δc| its pairs' largest shift (normal and tangential) and ℓ the length
    /// its surface can press over (`contact_surface_lengths`). Not summed over the pairs: a
    /// rigid surface moved by Δc presses the body as one punch, whose force is the body's
    /// stiffness at that surface's size times Δc (Boussinesq's flat punch: P = 2aE*δ), not
    /// the stiffness of every node it could touch at once (E h |Δc| per node, (ℓ/h)² nodes:
    /// a Vickers pyramid on a 0.1-mesh counted 4.2e6 for reactions of ~40, so the force noise
    /// floor, 1e-12 of it, was a freshly closed pair's force). In the plane, per pair E t |Δc|
    /// (t = `Model::depth`) as the 2D histories have always had it: the count there is ℓ/h,
    /// not its square.
    fn motion_forces(&self, stage: &StageLoad, young: f64, surfaces: &[f64]) -> Vec<f64> {
        if !D::OBSTACLE_FORCE_PER_SURFACE {
            let pairs = 0..self.global_pairs().len();
            return pairs
                .map(|p| (stage.shift(p, 1.0), stage.shift(p, 0.0)))
                .map(|(c, c0)| young * self.model.depth() * (c[0] - c0[0]).hypot(c[1] - c0[1]))
                .collect();
        }
        let mut largest = vec![0.0f64; surfaces.len()];
        for (p, input) in self.model.pairs.iter().enumerate() {
            let (c, c0) = (stage.shift(p, 1.0), stage.shift(p, 0.0));
            let moved = (c[0] - c0[0]).hypot(c[1] - c0[1]).hypot(c[2] - c0[2]);
            largest[input.contact] = largest[input.contact].max(moved);
        }
        largest.iter().zip(surfaces).map(|(d, l)| young * d * l).collect()
    }

    /// 3D: per contact of the case, the length its motion can press over: the diagonal of the
    /// bounding box of its contactor nodes (the largest punch it can be), at least the longest
    /// element edge at them (a contact of one node).
    fn contact_surface_lengths(&self) -> Vec<f64> {
        let n_contacts = self.model.pairs.iter().map(|p| p.contact + 1).max().unwrap_or(0);
        let mesh = &self.model.mesh;
        let (mut low, mut high, mut edge) = (
            vec![[f64::MAX; 3]; n_contacts],
            vec![[f64::MIN; 3]; n_contacts],
            vec![0.0f64; n_contacts],
        );
        for p in &self.model.pairs {
            let (a, c) = (mesh.point(p.node_a), p.contact);
            (0..3).for_each(|k| {
                (low[c][k], high[c][k]) = (low[c][k].min(a[k]), high[c][k].max(a[k]))
            });
            for &e in &self.node_elements[p.node_a] {
                edge[c] = mesh
                    .element_nodes(e)
                    .iter()
                    .map(|&b| distance(a, mesh.point(b)))
                    .fold(edge[c], f64::max);
            }
        }
        (0..n_contacts)
            .map(|c| if edge[c] > 0.0 { distance(low[c], high[c]).max(edge[c]) } else { 0.0 })
            .collect()
    }
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1]).hypot(a[2] - b[2])
}

/// The contact pairs over the global DOFs (eqs. 45–46), supports removed from their vectors.
fn contact_pairs<D: Dim>(model: &Model<D>, fixed: &[bool]) -> Result<Vec<Pair>> {
    let mut pairs = Vec::with_capacity(model.pairs.len());
    let dim = model.dim();
    for (k, p) in model.pairs.iter().enumerate() {
        let nn = (p.normal[0].powi(2) + p.normal[1].powi(2) + p.normal[2].powi(2)).sqrt();
        let normal = p.normal.map(|v| v / nn);
        let frame = D::pair_frame(normal, p.tangents);
        let pair = Pair::build(
            PairGeometry { node_a: p.node_a, node_b: p.node_b, weights: &p.weights, dim, frame },
            p.gap.max(0.0),
            Coulomb::new(p.mu, model.options.slip_turn),
            fixed,
        );
        if pair.w_n.norm() < HELD_BY_SUPPORTS {
            bail!(Input, "{}: its normal direction is held by supports, so it can carry no contact force; remove the pair or the support", model.pair_name(k));
        }
        pairs.push(pair);
    }
    Ok(pairs)
}

/// The contact DOFs that are equations (neither fixed nor pinned) go last in the factor, in
/// slot order: their flexibility block (`factor::Backend::trailing_inverse`). Returns the slot of every DOF and the
/// DOF of every slot.
fn contact_slots(pairs: &[Pair], fixed: &[bool], pinned: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let mut is_pinned = vec![false; fixed.len()];
    pinned.iter().for_each(|&d| is_pinned[d] = true);
    let mut slot = vec![usize::MAX; fixed.len()];
    let mut slot_dofs = Vec::new();
    for pair in pairs {
        for &(d, _) in pair.slot_vectors().into_iter().flat_map(|w| &w.entries) {
            if slot[d] == usize::MAX && !fixed[d] && !is_pinned[d] {
                slot[d] = slot_dofs.len();
                slot_dofs.push(d);
            }
        }
    }
    (slot, slot_dofs)
}

/// The elements with a DOF in `dofs`.
fn elements_touching(elements: &Elements, dofs: &[usize]) -> Vec<usize> {
    if dofs.is_empty() {
        return vec![];
    }
    let set: std::collections::HashSet<usize> = dofs.iter().copied().collect();
    (0..elements.len()).filter(|&e| elements.dofs(e).iter().any(|d| set.contains(d))).collect()
}

/// The first element of every body (connected component).
fn first_elements<D: Dim>(model: &Model<D>, body_of_node: &[usize], n_bodies: usize) -> Vec<usize> {
    let mut first = vec![usize::MAX; n_bodies];
    for e in 0..model.mesh.n_elements() {
        let b = body_of_node[model.mesh.element_nodes(e)[0]];
        if first[b] == usize::MAX {
            first[b] = e;
        }
    }
    first
}

/// The elements around each node.
fn node_elements(elements: &Elements, n_nodes: usize) -> Vec<Vec<usize>> {
    let mut around = vec![vec![]; n_nodes];
    for e in 0..elements.len() {
        elements.nodes(e).iter().for_each(|&n| around[n].push(e));
    }
    around
}

#[cfg(test)]
mod tests {
    use super::super::scenes::{cube_block, model, E};
    use super::*;
    use crate::dim::Spatial;
    use crate::material::Material;
    use crate::model::{LoadPattern, PairInput};

    /// The block [0, 2]² × [0, 1] of cubes of side 1/`cells` (ν = 0), its top face held, on a
    /// rigid flat z = 0 (a frictionless pair at every bottom node, gap 0) that is moved up by δ.
    fn pressed_by_its_flat(cells: usize, delta: f64) -> Model<Spatial> {
        let n = [2 * cells, 2 * cells, cells];
        let mesh = cube_block(n, 1.0 / cells as f64);
        let node = |i: usize, j: usize, k: usize| i + (n[0] + 1) * (j + (n[1] + 1) * k);
        let grid = |k: usize| (0..=n[1]).flat_map(move |j| (0..=n[0]).map(move |i| node(i, j, k)));
        let fixed = grid(n[2]).flat_map(|v| (0..3).map(move |c| 3 * v + c)).collect();
        let pairs = grid(0)
            .map(|a| PairInput {
                node_a: a,
                node_b: None,
                normal: [0.0, 0.0, 1.0],
                tangents: None,
                gap: 0.0,
                mu: 0.0,
                contact: 0,
                weights: vec![],
            })
            .collect();
        let (n_dofs, n_tets) = (3 * mesh.nodes.len(), mesh.elements.len());
        let mut m = model(mesh, fixed, vec![0.0; n_dofs], pairs, Material::elastic(E, 0.0));
        m.element_material = vec![0; n_tets];
        m.patterns = vec![LoadPattern {
            name: "press".into(),
            motion: vec![(0, [0.0, 0.0, delta])],
            ..Default::default()
        }];
        m
    }

    /// A rigid flat moved by δ presses the block as one punch: it carries E δ A / H = 4 E δ
    /// (ν = 0: uniform strain δ/H, exact on any mesh of the block), whatever the mesh. The force
    /// scale of the motion is E δ ℓ with ℓ the pressed face's diagonal (2√2), the same on a
    /// mesh twice as fine; counted per candidate pair (E D δ each, D the mesh's diameter), it
    /// grew with the pairs, 9 to 25, for the same force.
    #[test]
    fn a_motions_force_scale_is_its_punchs_not_its_pairs() {
        let delta = 0.01;
        for cells in [1, 2] {
            let m = pressed_by_its_flat(cells, delta);
            m.validate().expect("a valid scene");
            let problem = Problem::new(&m).expect("a problem");
            let expected = E * delta * 8f64.sqrt();
            // a few operations on O(1) numbers: round-off of 1e-15 each
            assert!(
                (problem.scales.force - expected).abs() <= 1e-12 * expected,
                "{cells} cells: {} vs {expected}",
                problem.scales.force
            );
            assert!((problem.scales.load_norm - expected).abs() <= 1e-12 * expected);
        }
    }
}
