//! The current stage's loads inside the engine (module `path` holds the path itself): starting
//! a stage, the trial's prescribed displacement increments and their force −K_fp Δū, the
//! obstacle shifts Δc, gaps and RTDs with the obstacle's motion, and the force scales of the
//! whole path that the tolerances use.

use super::engine::{since, Engine};
use super::path::StageLoad;
use super::space::Space;
use super::state::State;
use crate::element::Element;
use std::time::Instant;

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

    /// A stage's effective load over the free DOFs, ΔP − K_fp Δū, and its part −K_fp Δū.
    fn effective_load(&self, stage: &StageLoad) -> (Vec<f64>, Option<Vec<f64>>) {
        let mut load: Vec<f64> = stage.force_change().iter().enumerate().map(|(d, v)| if self.fixed[d] { 0.0 } else { *v }).collect();
        let held = self.prescribed_force(&stage.prescribed_changes());
        if let Some(f) = &held {
            load.iter_mut().zip(f).for_each(|(l, x)| *l += x);
        }
        (load, held)
    }

    /// Reduced space: u_stage = K#(ΔP − K_fp Δū) over all DOFs and at the reduced DOFs; the
    /// completed stages' share is accumulated (u = Σ u_stage + s u_stage + K#Wλ + Nα).
    fn solve_stage_load(&mut self) {
        let (load, _) = self.effective_load(&self.stage);
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
        for &e in &self.prescribed_elements {
            let el = &self.elements[e];
            let s = self.sections[e].stress_increment(&self.tangents[e], &el.strain(&du));
            let fe = el.internal_force(&s);
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
    /// (the order of what moving a surface node by Δc takes; t = `Model::depth`). (norm, sum)
    pub fn path_force_scales(&self) -> (f64, f64) {
        let young = self.sections.iter().map(|s| s.material.young).fold(0.0f64, f64::max);
        let (mut norm, mut sum) = (0.0f64, 0.0f64);
        for k in 0..self.path.n_stages() {
            let stage = self.path.stage(k, self.map.role.len(), self.global_pairs().len());
            let mut total: f64 = stage.force_change().iter().map(|v| v.abs()).sum();
            let (mut effective, held) = self.effective_load(&stage);
            if let Some(f) = held {
                total += f.iter().map(|v| v.abs()).sum::<f64>();
            }
            for p in 0..self.global_pairs().len() {
                let c = stage.shift(p, 1.0);
                let c0 = stage.shift(p, 0.0);
                let moved = young * self.model.depth() * (c[0] - c0[0]).hypot(c[1] - c0[1]);
                total += moved;
                effective.push(moved);
            }
            norm = norm.max(effective.iter().map(|v| v * v).sum::<f64>().sqrt());
            sum = sum.max(total);
        }
        (norm, sum)
    }
}
