//! Which DOFs the event loop carries between events: all of them (the general path), or, in an
//! elastic run, only the contact DOFs (the reduced elastic space).
//!
//! Reduced space: with no plastic material the state is fully described by the load fraction φ,
//! the multipliers λ and the rigid amplitudes α, u = φ K#P + K#(W λ) + N α, and an event needs
//! only contact-DOF values: no triangular solve per event, one per requested snapshot. The loop
//! then carries u only at the *reduced DOFs*: the contact DOFs that are equations (index =
//! flexibility slot), then the pinned ones (K# = 0 there, u = N α); no element arrays. An event
//! costs O(contact DOFs²), independent of the mesh size.

use crate::contact::{Pair, SparseVec};
use crate::linalg::ElementScatter;

pub(super) enum Space {
    Full(Full),
    Reduced(Reduced),
}

/// The general path. Plastic runs keep K with every element elastic (the first assembly) and
/// where each element's entries sit in it: a refactorization re-adds t A Bᵀ (D_ep − D) B of the
/// plastic elements only.
#[derive(Default)]
pub(super) struct Full {
    pub elastic_values: Vec<f64>,
    pub scatter: Option<ElementScatter>,
    /// The forward sweep of the current stage's load change, for the factor it was swept with
    /// (`trial`: a balanced state's trial is that sweep scaled).
    pub load_sweep: Option<LoadSweep>,
}

/// L⁻¹ ΔP_eq of stage `stage` with the factor of factorization number `factorization`.
pub(super) struct LoadSweep {
    pub stage: usize,
    pub factorization: usize,
    pub load: Vec<f64>,
    pub sweep: Vec<f64>,
}

pub(super) struct Reduced {
    /// The pairs over the global DOFs (full fields, snapshots); the engine's loop pairs are
    /// over the reduced DOFs.
    pub global_pairs: Vec<Pair>,
    /// Global DOF of each reduced DOF.
    pub dofs: Vec<usize>,
    /// u_stage = K#(ΔP − K_fp Δū) of the current stage (`path`) over all DOFs and over the
    /// reduced DOFs; max |u_stage| for tolerances.
    pub u_load: Vec<f64>,
    pub u_load_reduced: Vec<f64>,
    pub u_load_max: f64,
    /// Σ u_stage of the completed stages (empty in the first) and its max |·|.
    pub u_done: Vec<f64>,
    pub u_done_max: f64,
}

/// The loop's view of the problem in the reduced space: pairs, flexibility slots and rigid
/// modes over the reduced DOFs.
pub(super) struct ReducedView {
    pub pairs: Vec<Pair>,
    pub contact_slot: Vec<usize>,
    pub mode_vectors: Vec<Vec<f64>>,
}

impl Reduced {
    /// The reduced DOFs: the `slot_dofs` (contact DOFs that are equations), then the pinned
    /// contact DOFs; the pairs and rigid modes re-indexed over them.
    pub fn new(pairs: Vec<Pair>, slot_dofs: &[usize], contact_slot: &[usize], modes: &[Vec<f64>]) -> (Self, ReducedView) {
        let mut index = contact_slot.to_vec();
        let mut dofs = slot_dofs.to_vec();
        for pair in &pairs {
            for &(d, _) in pair.w_n.entries.iter().chain(&pair.w_t.entries) {
                if index[d] == usize::MAX {
                    index[d] = dofs.len();
                    dofs.push(d);
                }
            }
        }
        let remap = |w: &SparseVec| SparseVec { entries: w.entries.iter().map(|&(d, v)| (index[d], v)).collect() };
        let view = ReducedView {
            pairs: pairs.iter().map(|p| Pair { w_n: remap(&p.w_n), w_t: remap(&p.w_t), ..p.clone() }).collect(),
            contact_slot: (0..dofs.len()).map(|r| if r < slot_dofs.len() { r } else { usize::MAX }).collect(),
            mode_vectors: modes.iter().map(|m| dofs.iter().map(|&d| m[d]).collect()).collect(),
        };
        (Reduced { global_pairs: pairs, dofs, u_load: vec![], u_load_reduced: vec![], u_load_max: 0.0, u_done: vec![], u_done_max: 0.0 }, view)
    }
}
