//! The load path (issue 13): named load patterns scaled by stages.
//!
//! A pattern holds forces P_j, prescribed displacements ū_j and rigid-obstacle motions m_j at
//! factor 1. Stage k runs over path time t ∈ [k−1, k]; inside it every factor is linear in the
//! stage fraction s = t − (k−1), so
//!   P(s) = P_start + s ΔP,   ū(s) = ū_start + s Δū,   c(s) = c_start + s Δc,
//! where c = (c_n, c_t) shifts a pair's gap and RTD by the motion of its obstacle:
//!   gap = gap₀ + w_nᵀu + c_n,  RTD = w_tᵀu + c_t,  c_n = −n·m,  c_t = −t·m.
//! The procedure of §4 runs unchanged inside a stage with s in place of the load fraction: each
//! trial solves for the stage's remaining load from the current state in residual form, so
//! unloading, reloading and displacement control are the same loop. With no stages the path is
//! one stage with every factor 1: P(s) = 0 + s·P, today's proportional load, to the bit.

use crate::contact::Shift;
use crate::dim::Dim;
use crate::model::{Model, PairInput};

/// The loads of one stage, linear in its fraction s ∈ [0, 1].
pub(super) struct StageLoad {
    /// P_start and ΔP over all DOFs.
    force_start: Vec<f64>,
    force_change: Vec<f64>,
    /// Prescribed DOFs: (DOF, ū_start, Δū).
    pub prescribed: Vec<(usize, f64, f64)>,
    /// Per pair: (c_n, c_t) at the stage's start and their change over it.
    shift_start: Vec<Shift>,
    shift_change: Vec<Shift>,
}

impl StageLoad {
    /// P(s) at DOF d.
    pub fn force(&self, d: usize, s: f64) -> f64 {
        self.force_start[d] + s * self.force_change[d]
    }

    /// P_start and ΔP over the whole stage.
    pub fn force_start(&self) -> &[f64] {
        &self.force_start
    }

    pub fn force_change(&self) -> &[f64] {
        &self.force_change
    }

    /// Δū over the whole stage at every prescribed DOF.
    pub fn prescribed_changes(&self) -> Vec<(usize, f64)> {
        self.prescribed.iter().map(|&(d, _, change)| (d, change)).collect()
    }

    /// ū(s) at every prescribed DOF.
    pub fn prescribed_at(&self, s: f64) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.prescribed.iter().map(move |&(d, start, change)| (d, start + s * change))
    }

    /// (c_n, c_t)(s) of pair p.
    pub fn shift(&self, p: usize, s: f64) -> Shift {
        let (a, b) = (self.shift_start[p], self.shift_change[p]);
        [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]
    }
}

/// Every pattern and the factors of every stage.
pub(super) struct LoadPath {
    /// Factors at t = 0, 1, …, n_stages (`load` first, then `Model::patterns`).
    factors: Vec<Vec<f64>>,
    forces: Vec<Vec<f64>>,
    displacements: Vec<Vec<(usize, f64)>>,
    /// Per pattern: the (c_n, c_t) of every pair at factor 1.
    shifts: Vec<Vec<Shift>>,
    pub stage_names: Vec<String>,
}

impl LoadPath {
    pub fn new<D: Dim>(model: &Model<D>) -> Self {
        let n_patterns = 1 + model.patterns.len();
        let mut factors = vec![vec![0.0; n_patterns]];
        factors.extend(model.stages.iter().map(|s| s.factors.clone()));
        if model.stages.is_empty() {
            factors.push(vec![1.0; n_patterns]);
        }
        let stage_names =
            match model.stages.is_empty() {
                true => vec![String::from("stage 1")],
                false => model
                    .stages
                    .iter()
                    .enumerate()
                    .map(|(k, s)| {
                        if s.name.is_empty() {
                            format!("stage {}", k + 1)
                        } else {
                            s.name.clone()
                        }
                    })
                    .collect(),
            };
        let mut forces = vec![model.load.clone()];
        let mut displacements = vec![vec![]];
        let mut shifts = vec![vec![]];
        for pat in &model.patterns {
            forces.push(pat.force.clone());
            displacements.push(pat.displacement.clone());
            shifts.push(obstacle_shifts::<D>(&model.pairs, &pat.motion));
        }
        LoadPath { factors, forces, displacements, shifts, stage_names }
    }

    pub fn n_stages(&self) -> usize {
        self.factors.len() - 1
    }

    /// Every prescribed DOF of the path (eliminated like a support).
    pub fn prescribed_dofs(&self) -> Vec<usize> {
        let mut dofs: Vec<usize> = self.displacements.iter().flatten().map(|&(d, _)| d).collect();
        dofs.sort_unstable();
        dofs.dedup();
        dofs
    }

    /// The loads of stage k (0-based) over `n_dofs` DOFs and `n_pairs` pairs.
    pub fn stage(&self, k: usize, n_dofs: usize, n_pairs: usize) -> StageLoad {
        let (start, end) = (&self.factors[k], &self.factors[k + 1]);
        let mut force_start = vec![0.0; n_dofs];
        let mut force_change = vec![0.0; n_dofs];
        for (j, f) in self.forces.iter().enumerate() {
            for (d, v) in f.iter().enumerate() {
                force_start[d] += start[j] * v;
                force_change[d] += (end[j] - start[j]) * v;
            }
        }
        let mut prescribed: Vec<(usize, f64, f64)> = vec![];
        for (j, disp) in self.displacements.iter().enumerate() {
            prescribed
                .extend(disp.iter().map(|&(d, v)| (d, start[j] * v, (end[j] - start[j]) * v)));
        }
        let mut shift_start = vec![[0.0; 3]; n_pairs];
        let mut shift_change = vec![[0.0; 3]; n_pairs];
        for (j, shift) in self.shifts.iter().enumerate() {
            for (p, c) in shift.iter().enumerate() {
                for i in 0..3 {
                    shift_start[p][i] += start[j] * c[i];
                    shift_change[p][i] += (end[j] - start[j]) * c[i];
                }
            }
        }
        StageLoad { force_start, force_change, prescribed, shift_start, shift_change }
    }
}

/// (c_n, c_t) = (−n·m, −t·m) of every pair whose contact's obstacle moves by m (eqs. 21, 25
/// with the target translated); empty when the pattern moves nothing.
fn obstacle_shifts<D: Dim>(pairs: &[PairInput], motion: &[(usize, [f64; 3])]) -> Vec<Shift> {
    if motion.is_empty() {
        return vec![];
    }
    pairs
        .iter()
        .map(|p| match motion.iter().find(|(c, _)| *c == p.contact) {
            Some((_, m)) => {
                let frame = D::pair_frame(p.normal, p.tangents);
                let dot = |a: [f64; 3]| a[0] * m[0] + a[1] * m[1] + a[2] * m[2];
                let mut shift = [-dot(frame.normal), 0.0, 0.0];
                for k in 0..D::N - 1 {
                    shift[k + 1] = -dot(frame.tangents[k]); // along the pair's own tangents
                }
                shift
            }
            None => [0.0; 3],
        })
        .collect()
}
