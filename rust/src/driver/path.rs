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

use super::engine::{since, Engine};
use super::space::Space;
use super::state::State;
use crate::model::{Model, PairInput};
use nalgebra::Vector3;
use std::time::Instant;

/// The loads of one stage, linear in its fraction s ∈ [0, 1].
pub(super) struct StageLoad {
    /// P_start and ΔP over all DOFs.
    force_start: Vec<f64>,
    force_change: Vec<f64>,
    /// Prescribed DOFs: (DOF, ū_start, Δū).
    pub prescribed: Vec<(usize, f64, f64)>,
    /// Per pair: (c_n, c_t) at the stage's start and their change over it.
    shift_start: Vec<[f64; 2]>,
    shift_change: Vec<[f64; 2]>,
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

    /// P at the stage's end.
    pub fn force_end(&self) -> Vec<f64> {
        (0..self.force_start.len()).map(|d| self.force(d, 1.0)).collect()
    }

    /// ū(s) at every prescribed DOF.
    pub fn prescribed_at(&self, s: f64) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.prescribed.iter().map(move |&(d, start, change)| (d, start + s * change))
    }

    /// (c_n, c_t)(s) of pair p.
    pub fn shift(&self, p: usize, s: f64) -> [f64; 2] {
        let (a, b) = (self.shift_start[p], self.shift_change[p]);
        [a[0] + s * b[0], a[1] + s * b[1]]
    }
}

/// Every pattern and the factors of every stage.
pub(super) struct LoadPath {
    /// Factors at t = 0, 1, …, n_stages (`load` first, then `Model::patterns`).
    factors: Vec<Vec<f64>>,
    forces: Vec<Vec<f64>>,
    displacements: Vec<Vec<(usize, f64)>>,
    /// Per pattern: the (c_n, c_t) of every pair at factor 1.
    shifts: Vec<Vec<[f64; 2]>>,
    pub stage_names: Vec<String>,
}

impl LoadPath {
    pub fn new(model: &Model) -> Self {
        let n_patterns = 1 + model.patterns.len();
        let mut factors = vec![vec![0.0; n_patterns]];
        factors.extend(model.stages.iter().map(|s| s.factors.clone()));
        if model.stages.is_empty() {
            factors.push(vec![1.0; n_patterns]);
        }
        let stage_names = match model.stages.is_empty() {
            true => vec![String::from("stage 1")],
            false => model.stages.iter().enumerate().map(|(k, s)| if s.name.is_empty() { format!("stage {}", k + 1) } else { s.name.clone() }).collect(),
        };
        let mut forces = vec![model.load.clone()];
        let mut displacements = vec![vec![]];
        let mut shifts = vec![vec![]];
        for pat in &model.patterns {
            forces.push(pat.force.clone());
            displacements.push(pat.displacement.clone());
            shifts.push(obstacle_shifts(&model.pairs, &pat.motion));
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
            prescribed.extend(disp.iter().map(|&(d, v)| (d, start[j] * v, (end[j] - start[j]) * v)));
        }
        let mut shift_start = vec![[0.0; 2]; n_pairs];
        let mut shift_change = vec![[0.0; 2]; n_pairs];
        for (j, shift) in self.shifts.iter().enumerate() {
            for (p, c) in shift.iter().enumerate() {
                for i in 0..2 {
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
fn obstacle_shifts(pairs: &[PairInput], motion: &[(usize, [f64; 2])]) -> Vec<[f64; 2]> {
    if motion.is_empty() {
        return vec![];
    }
    pairs
        .iter()
        .map(|p| match motion.iter().find(|(c, _)| *c == p.contact) {
            Some((_, m)) => {
                let (n, t) = (p.normal, [-p.normal[1], p.normal[0]]);
                [-(n[0] * m[0] + n[1] * m[1]), -(t[0] * m[0] + t[1] * m[1])]
            }
            None => [0.0, 0.0],
        })
        .collect()
}

impl Engine<'_> {
    /// Start stage k (0-based) at s = 0: its loads, the free rigid modes' share of them, and in
    /// the reduced space K# of its effective load (one solve per stage).
    pub fn begin_stage(&mut self, k: usize, state: &mut State) {
        self.stage = self.path.stage(k, self.map.role.len(), self.global_pairs().len());
        state.stage = k;
        state.load_fraction = 0.0;
        let free = |f: &[f64], d: usize| if self.fixed[d] { 0.0 } else { f[d] };
        let (start, change) = (self.stage.force_start(), self.stage.force_change());
        let mode_force = self
            .modes
            .iter()
            .map(|m| {
                let dot = |f: &[f64]| m.vector.iter().enumerate().map(|(d, a)| a * free(f, d)).sum::<f64>();
                [dot(start), dot(change)]
            })
            .collect();
        self.mode_force = mode_force;
        if self.is_reduced() {
            self.solve_stage_load();
        }
    }

    /// Nᵀ P(s) of free rigid mode k.
    pub fn mode_force_at(&self, k: usize, s: f64) -> f64 {
        self.mode_force[k][0] + s * self.mode_force[k][1]
    }

    /// The stage's effective load over the free DOFs: ΔP − K_fp Δū.
    fn stage_effective_load(&self) -> Vec<f64> {
        let mut load: Vec<f64> = self.stage.force_change().iter().enumerate().map(|(d, v)| if self.fixed[d] { 0.0 } else { *v }).collect();
        let changes: Vec<(usize, f64)> = self.stage.prescribed.iter().map(|&(d, _, c)| (d, c)).collect();
        if let Some(f) = self.prescribed_force(&changes) {
            load.iter_mut().zip(&f).for_each(|(l, x)| *l += x);
        }
        load
    }

    /// Reduced space: u_stage = K#(ΔP − K_fp Δū) over all DOFs and at the reduced DOFs; the
    /// completed stages' share is accumulated (u = Σ u_stage + s u_stage + K#Wλ + Nα).
    fn solve_stage_load(&mut self) {
        let load = self.stage_effective_load();
        let t0 = Instant::now();
        let u_stage = self.apply_ginv(std::slice::from_ref(&load)).pop().unwrap();
        if let Space::Reduced(r) = &mut self.space {
            if !r.u_load.is_empty() {
                r.u_done.resize(r.u_load.len(), 0.0);
                r.u_done.iter_mut().zip(&r.u_load).for_each(|(a, b)| *a += b);
                r.u_done_max = r.u_done.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            }
            r.u_load_reduced = r.dofs.iter().map(|&d| u_stage[d]).collect();
            r.u_load_max = u_stage.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            r.u_load = u_stage;
        }
        self.timings.solves += since(t0);
    }

    /// ū(target) − u at every prescribed DOF (full space; residual form, so no drift).
    pub fn prescribed_increment(&self, state: &State, target: f64) -> Vec<(usize, f64)> {
        if self.is_reduced() {
            return vec![];
        }
        self.stage.prescribed_at(target).map(|(d, v)| (d, v - state.u[d])).collect()
    }

    /// −K_fp Δū over all DOFs (zero at held ones): the force on the free DOFs of the elements
    /// that touch prescribed increments Δū, with their current tangents. None when Δū = 0.
    pub fn prescribed_force(&self, increments: &[(usize, f64)]) -> Option<Vec<f64>> {
        if increments.iter().all(|&(_, v)| v == 0.0) {
            return None;
        }
        let mut du = vec![0.0; self.map.role.len()];
        increments.iter().for_each(|&(d, v)| du[d] = v);
        let mut f = vec![0.0; du.len()];
        let (plane, thickness) = (self.model.plane, self.model.thickness);
        for &e in &self.prescribed_elements {
            let el = &self.elements[e];
            let s = self.tangents[e].stress_increment(plane, &el.strain(&du));
            let fe = el.internal_force(&Vector3::new(s[0], s[1], s[3]), thickness);
            for (k, &d) in el.dofs().iter().enumerate() {
                if !self.fixed[d] {
                    f[d] -= fe[k];
                }
            }
        }
        Some(f)
    }

    /// (c_n, c_t)(target) − (c_n, c_t) of every pair (residual form).
    pub fn shift_increment(&self, state: &State, target: f64) -> Vec<[f64; 2]> {
        (0..state.shift.len())
            .map(|p| {
                let c = self.stage.shift(p, target);
                [c[0] - state.shift[p][0], c[1] - state.shift[p][1]]
            })
            .collect()
    }

    /// The gap of pair p with its obstacle's motion: gap₀ + w_nᵀu + c_n.
    pub fn gap(&self, state: &State, p: usize) -> f64 {
        self.pairs[p].gap(&state.u) + state.shift[p][0]
    }

    /// The RTD of pair p with its obstacle's motion: w_tᵀu + c_t.
    pub fn rtd(&self, state: &State, p: usize) -> f64 {
        self.pairs[p].rtd(&state.u) + state.shift[p][1]
    }

    /// Scales of the whole path: max over stages of |ΔP − K_fp Δū| over the free DOFs, and
    /// of Σ|ΔP| (+ Σ|K_fp Δū|); an obstacle motion Δc counts as the force E t |Δc| per pair
    /// (the order of what moving a surface node by Δc takes). (norm, sum)
    pub fn path_force_scales(&mut self) -> (f64, f64) {
        let young = self.material.iter().map(|m| m.young).fold(0.0f64, f64::max);
        let (mut norm, mut sum) = (0.0f64, 0.0f64);
        for k in 0..self.path.n_stages() {
            self.stage = self.path.stage(k, self.map.role.len(), self.global_pairs().len());
            let mut total: f64 = self.stage.force_change().iter().map(|v| v.abs()).sum();
            let mut effective = self.stage_effective_load();
            let changes: Vec<(usize, f64)> = self.stage.prescribed.iter().map(|&(d, _, c)| (d, c)).collect();
            if let Some(f) = self.prescribed_force(&changes) {
                total += f.iter().map(|v| v.abs()).sum::<f64>();
            }
            for p in 0..self.global_pairs().len() {
                let c = self.stage.shift(p, 1.0);
                let c0 = self.stage.shift(p, 0.0);
                let moved = young * self.model.thickness * (c[0] - c0[0]).hypot(c[1] - c0[1]);
                total += moved;
                effective.push(moved);
            }
            norm = norm.max(effective.iter().map(|v| v * v).sum::<f64>().sqrt());
            sum = sum.max(total);
        }
        (norm, sum)
    }
}
