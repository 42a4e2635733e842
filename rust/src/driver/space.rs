//! Which DOFs the event loop carries between events: all of them (the general path), or, in an
//! elastic run, only the contact DOFs (the reduced elastic space).
//!
//! Reduced space: with no plastic material the state is fully described by the load fraction φ,
//! the multipliers λ and the rigid amplitudes α, u = φ K#P + K#(W λ) + N α, and an event needs
//! only contact-DOF values: no triangular solve per event, one per requested snapshot. The loop
//! then carries u only at the *reduced DOFs*: the contact DOFs that are equations (index =
//! flexibility slot), then the pinned ones (K# = 0 there, u = N α); no element arrays. An event
//! costs O(contact DOFs²), independent of the mesh size. (K# of each stage's load over these
//! DOFs: `loads::ReducedLoad`.)

use crate::contact::{Pair, SparseVec, Tangent};

pub(super) enum Space {
    Full,
    Reduced(Reduced),
}

pub(super) struct Reduced {
    /// The pairs over the global DOFs (full fields, snapshots); the loop's pairs are over the
    /// reduced DOFs.
    pub global_pairs: Vec<Pair>,
    /// Global DOF of each reduced DOF.
    pub dofs: Vec<usize>,
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
    pub fn new(
        pairs: Vec<Pair>,
        slot_dofs: &[usize],
        contact_slot: &[usize],
        modes: &[Vec<f64>],
    ) -> (Self, ReducedView) {
        let mut index = contact_slot.to_vec();
        let mut dofs = slot_dofs.to_vec();
        for pair in &pairs {
            for &(d, _) in pair.slot_vectors().into_iter().flat_map(|w| &w.entries) {
                if index[d] == usize::MAX {
                    index[d] = dofs.len();
                    dofs.push(d);
                }
            }
        }
        // (a frictionless 3D pair's tangential DOFs are not among them: its λ_t is 0)
        let remap = |w: &SparseVec| SparseVec {
            entries: w
                .entries
                .iter()
                .filter(|&&(d, _)| index[d] != usize::MAX)
                .map(|&(d, v)| (index[d], v))
                .collect(),
        };
        let view = ReducedView {
            pairs: pairs
                .iter()
                .map(|p| Pair {
                    w_n: remap(&p.w_n),
                    tangents: p
                        .tangents
                        .iter()
                        .map(|t| Tangent { w: remap(&t.w), ..t.clone() })
                        .collect(),
                    ..p.clone()
                })
                .collect(),
            contact_slot: (0..dofs.len())
                .map(|r| if r < slot_dofs.len() { r } else { usize::MAX })
                .collect(),
            mode_vectors: modes.iter().map(|m| dofs.iter().map(|&d| m[d]).collect()).collect(),
        };
        (Reduced { global_pairs: pairs, dofs }, view)
    }
}
