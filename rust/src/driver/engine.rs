//! The assembled problem the procedure works on: elements and their tangents, contact pairs
//! (eqs. 45–46), free rigid-body modes, the SPD factor of K with the contact DOFs last, and the
//! contact flexibility read from it.

use super::path::{LoadPath, StageLoad};
use super::plasticity::IncrementStart;
use super::trial::TrialBase;
use super::space::{Full, Reduced, Space};
use crate::bail;
use crate::contact::{Pair, HELD_BY_SUPPORTS};
use crate::element::{Cst, Element};
use crate::error::Result;
use crate::events::Noise;
use crate::linalg::{DofMap, SpdSolver, StiffnessPattern};
use crate::low_rank::{Cost, LowRank};
use crate::material::Tangent;
use crate::section::Section;
use crate::model::{Model, Timings};
use crate::rigid_modes::{free_modes, RigidMode};
use nalgebra::Vector4;
use std::time::Instant;

/// Round-off scale of forces: noise floor of a force rate, × Σ|load|.
const FORCE_NOISE: f64 = 1e-12;

/// The scales tolerances are relative to.
pub(super) struct Scales {
    /// |P| over the free DOFs (1 for a tractionless scene: residuals are then absolute).
    pub load_norm: f64,
    /// Σ|P|: the scale of forces.
    pub force: f64,
    /// The mesh's bounding-box diagonal.
    pub length: f64,
}

pub(super) struct Engine<'m> {
    pub model: &'m Model,
    pub elements: Vec<Cst>,
    /// Material of every element under the model's stress state.
    pub sections: Vec<Section>,
    /// D or D_ep of every element (eq. 11) as K holds it (`tangents`), and whether K must be
    /// refactorized for them.
    pub tangents: Vec<Tangent>,
    pub tangents_changed: bool,
    /// The tangents in the last factor K_f; K = K_f + the low-rank terms of the elements whose
    /// tangent changed since (`low_rank`), and what those terms have cost so far (flops).
    pub factored: Vec<Tangent>,
    pub low_rank: LowRank,
    pub low_rank_spent: f64,
    pub n_low_rank_updates: usize,
    /// Renew every plastic tangent at the next update (a stage's final correction).
    pub renew_all_tangents: bool,
    /// A grouped increment's start, for its re-integration (`plasticity`).
    pub increment_start: Option<IncrementStart>,
    /// While a window is retaken (`retake`): the path time where it ended; until then the
    /// increments are not grouped.
    pub retake_until: Option<f64>,
    /// The last full-space trial for the remaining load, and, during an increment's contact
    /// sub-steps, the one they scale (`substeps`).
    pub trial_base: Option<TrialBase>,
    pub substep: Option<TrialBase>,
    /// The elements around each node (whether a closure's neighbourhood is elastic, `substeps`).
    pub node_elements: Vec<Vec<usize>>,
    /// The work of a factorization and of a solve pair (from the factor's structure).
    pub cost: Cost,
    /// The pairs over the DOFs the loop carries (`space`).
    pub pairs: Vec<Pair>,
    pub modes: Vec<RigidMode>,
    /// Body (connected component) of every node, and the first element of every body (its
    /// name in messages, `Model::body_name`).
    pub body_of_node: Vec<usize>,
    pub body_first_element: Vec<usize>,
    /// The rigid modes over the DOFs the loop carries.
    pub mode_vectors: Vec<Vec<f64>>,
    /// Nᵀ P_start and Nᵀ ΔP of the current stage per mode (the rigid-body rows without a full
    /// vector per event).
    pub mode_force: Vec<[f64; 2]>,
    /// The load path and the current stage's loads.
    pub path: LoadPath,
    pub stage: StageLoad,
    /// Elements with a prescribed DOF (their K_fp Δū loads the free DOFs).
    pub prescribed_elements: Vec<usize>,
    pub map: DofMap,
    pub pattern: StiffnessPattern,
    pub fixed: Vec<bool>,
    pub solver: SpdSolver,
    /// K# restricted to the contact DOFs that are equations (t × t, by slot), read from the
    /// trailing block of the factor after every factorization (`flexibility_factored`) and
    /// corrected for the low-rank terms: every Cᵀ K# E entry of the small system is a lookup
    /// here, no triangular solve per contact pair.
    pub flexibility: faer::Mat<f64>,
    pub flexibility_factored: faer::Mat<f64>,
    /// Slot in `flexibility` of each DOF of the loop's DOF space (usize::MAX: not a contact
    /// DOF, or fixed/pinned, where K# is zero).
    pub contact_slot: Vec<usize>,
    pub space: Space,
    pub max_snapshot_residual: f64,
    pub scales: Scales,
    pub noise: Noise,
    pub timings: Timings,
}

impl<'m> Engine<'m> {
    /// Assemble everything up to (not including) the first factorization. `model` must have
    /// passed `Model::validate`.
    pub fn new(model: &'m Model) -> Result<Self> {
        let mesh = &model.mesh;
        let n_dofs = 2 * mesh.n_nodes();
        let path = LoadPath::new(model);
        let mut fixed = vec![false; n_dofs];
        model.supported_dofs().iter().chain(&path.prescribed_dofs()).for_each(|&d| fixed[d] = true);
        let pairs = contact_pairs(model, &fixed)?;
        let (body_of_node, n_bodies) = mesh.bodies();
        let (modes, pinned) = free_modes(&mesh.nodes, &body_of_node, n_bodies, &fixed, model.plane);
        let (contact_slot, slot_dofs) = contact_slots(&pairs, &fixed, &pinned);
        let stress_state = model.plane.stress_state();
        let elements: Vec<Cst> = (0..mesh.triangles.len()).map(|e| stress_state.element(mesh, e, model.thickness)).collect();
        let map = DofMap::ordered(&elements, n_dofs, &fixed, &pinned, &slot_dofs)?;
        let pattern = StiffnessPattern::new(&elements, &map)?;
        let sections: Vec<Section> = model.element_material.iter().map(|&m| Section::new(model.materials[m], stress_state)).collect();
        let tangents: Vec<Tangent> = sections.iter().map(|s| s.tangent(&Vector4::zeros(), false)).collect();
        let prescribed_elements = elements_touching(&elements, &path.prescribed_dofs());
        let n_pairs = pairs.len();
        let full_modes: Vec<Vec<f64>> = modes.iter().map(|m| m.vector.clone()).collect();
        let elastic = !model.materials.iter().any(|m| m.is_plastic());
        let (space, pairs, contact_slot, mode_vectors) = if model.options.reduced_elastic && elastic {
            let (reduced, view) = Reduced::new(pairs, &slot_dofs, &contact_slot, &full_modes);
            (Space::Reduced(reduced), view.pairs, view.contact_slot, view.mode_vectors)
        } else {
            (Space::Full(Full::default()), pairs, contact_slot, full_modes)
        };
        let elements_of_mesh: Vec<Vec<usize>> = elements.iter().map(|el| el.nodes().to_vec()).collect();
        // The first K: every element elastic; a plastic run keeps its values and where each
        // element's entries sit (`stiffness`).
        let d: Vec<_> = tangents.iter().zip(&sections).map(|(t, s)| s.element_matrix(t)).collect();
        let k = pattern.assemble(&elements, &d, &map)?;
        let mut space = space;
        if let Space::Full(full) = &mut space {
            if sections.iter().any(|s| s.material.is_plastic()) {
                full.elastic_values = k.val().to_vec();
                full.scatter = Some(pattern.element_scatter(&elements, &map));
            }
        }
        let solver = SpdSolver::new(&k, &map.dof_of_equation, slot_dofs.len())?;
        let mut eng = Engine {
            model,
            elements,
            sections,
            factored: tangents.clone(),
            tangents,
            tangents_changed: false,
            low_rank: LowRank::default(),
            low_rank_spent: 0.0,
            n_low_rank_updates: 0,
            renew_all_tangents: false,
            increment_start: None,
            retake_until: None,
            trial_base: None,
            substep: None,
            node_elements: node_elements(&elements_of_mesh, mesh.n_nodes()),
            cost: Cost::default(),
            pairs,
            modes,
            body_first_element: first_elements(model, &body_of_node, n_bodies),
            body_of_node,
            mode_vectors,
            mode_force: vec![],
            stage: path.stage(0, n_dofs, n_pairs),
            path,
            prescribed_elements,
            map,
            pattern,
            fixed,
            solver,
            flexibility: faer::Mat::zeros(0, 0),
            flexibility_factored: faer::Mat::zeros(0, 0),
            contact_slot,
            space,
            max_snapshot_residual: 0.0,
            scales: Scales { load_norm: 1.0, force: 1.0, length: mesh.diameter() },
            noise: Noise { displacement: 0.0, force: 0.0 },
            timings: Timings::default(),
        };
        let (load_norm, force) = eng.path_force_scales();
        let force = force.max(f64::MIN_POSITIVE);
        eng.scales.load_norm = if load_norm > 0.0 { load_norm } else { 1.0 };
        eng.scales.force = force;
        eng.noise.force = FORCE_NOISE * force;
        Ok(eng)
    }

    pub fn is_reduced(&self) -> bool {
        matches!(self.space, Space::Reduced(_))
    }

    /// The pairs over the global DOFs (full fields, snapshots).
    pub fn global_pairs(&self) -> &[Pair] {
        match &self.space {
            Space::Reduced(r) => &r.global_pairs,
            Space::Full(_) => &self.pairs,
        }
    }

    /// Length of the displacement vectors the loop carries.
    pub fn loop_dofs(&self) -> usize {
        match &self.space {
            Space::Reduced(r) => r.dofs.len(),
            Space::Full(_) => self.map.role.len(),
        }
    }

    /// Number of element arrays the loop carries (none in the reduced space).
    pub fn loop_elements(&self) -> usize {
        if self.is_reduced() { 0 } else { self.elements.len() }
    }
}

/// The contact pairs over the global DOFs (eqs. 45–46), supports removed from their vectors.
fn contact_pairs(model: &Model, fixed: &[bool]) -> Result<Vec<Pair>> {
    let mut pairs = Vec::with_capacity(model.pairs.len());
    for (k, p) in model.pairs.iter().enumerate() {
        let nn = (p.normal[0].powi(2) + p.normal[1].powi(2)).sqrt();
        let normal = [p.normal[0] / nn, p.normal[1] / nn];
        let pair = match p.weights.is_empty() {
            true => Pair::new(p.node_a, p.node_b, normal, p.gap.max(0.0), p.mu, fixed),
            false => Pair::weighted(p.node_a, p.node_b, &p.weights, normal, p.gap.max(0.0), p.mu, fixed),
        };
        if pair.w_n.norm() < HELD_BY_SUPPORTS {
            bail!(Input, "{}: its normal direction is held by supports, so it can carry no contact force; remove the pair or the support", model.pair_name(k));
        }
        pairs.push(pair);
    }
    Ok(pairs)
}

/// The contact DOFs that are equations (neither fixed nor pinned) go last in the factor, in
/// slot order: their flexibility block (`SpdSolver`). Returns the slot of every DOF and the
/// DOF of every slot.
fn contact_slots(pairs: &[Pair], fixed: &[bool], pinned: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let mut is_pinned = vec![false; fixed.len()];
    pinned.iter().for_each(|&d| is_pinned[d] = true);
    let mut slot = vec![usize::MAX; fixed.len()];
    let mut slot_dofs = Vec::new();
    for pair in pairs {
        for &(d, _) in pair.w_n.entries.iter().chain(&pair.w_t.entries) {
            if slot[d] == usize::MAX && !fixed[d] && !is_pinned[d] {
                slot[d] = slot_dofs.len();
                slot_dofs.push(d);
            }
        }
    }
    (slot, slot_dofs)
}

/// The elements with a DOF in `dofs`.
fn elements_touching(elements: &[Cst], dofs: &[usize]) -> Vec<usize> {
    if dofs.is_empty() {
        return vec![];
    }
    let set: std::collections::HashSet<usize> = dofs.iter().copied().collect();
    (0..elements.len()).filter(|&e| elements[e].dofs().iter().any(|d| set.contains(d))).collect()
}

/// The first element of every body (connected component).
fn first_elements(model: &Model, body_of_node: &[usize], n_bodies: usize) -> Vec<usize> {
    let mut first = vec![usize::MAX; n_bodies];
    for (e, t) in model.mesh.triangles.iter().enumerate() {
        let b = body_of_node[t[0]];
        if first[b] == usize::MAX {
            first[b] = e;
        }
    }
    first
}

/// Seconds since `t`.
pub(super) fn since(t: Instant) -> f64 {
    t.elapsed().as_secs_f64()
}

/// The elements around each node.
fn node_elements(triangles: &[Vec<usize>], n_nodes: usize) -> Vec<Vec<usize>> {
    let mut around = vec![vec![]; n_nodes];
    for (e, tri) in triangles.iter().enumerate() {
        tri.iter().for_each(|&n| around[n].push(e));
    }
    around
}
