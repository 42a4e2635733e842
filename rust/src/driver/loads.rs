//! The current stage's loads inside the engine (module `path` holds the path itself): starting
//! a stage, the rigid modes' share of its load, in the reduced space K# of its effective load,
//! the trial's prescribed displacement increments and obstacle shifts, the out-of-balance
//! force, and the size of displacements for round-off tolerances.

use super::clock::{Clock, Phase};
use super::path::StageLoad;
use super::problem::Problem;
use super::space::Space;
use super::state::State;
use super::stiffness::Stiffness;
use crate::contact::Shift;
use crate::dim::Dim;

/// The loads of the stage the loop is in.
pub(super) struct StageLoads {
    pub load: StageLoad,
    /// Nᵀ P_start and Nᵀ ΔP of the stage per free rigid mode (the rigid-body rows without a
    /// full vector per event).
    pub mode_force: Vec<[f64; 2]>,
    pub reduced: ReducedLoad,
}

/// Reduced space: u = Σ u_stage (completed) + s u_stage + K#(W λ) + N α.
#[derive(Default)]
pub(super) struct ReducedLoad {
    /// u_stage = K#(ΔP − K_fp Δū) of the current stage over all DOFs and over the reduced
    /// DOFs; max |u_stage| for tolerances.
    pub u_load: Vec<f64>,
    pub u_load_reduced: Vec<f64>,
    pub u_load_max: f64,
    /// Σ u_stage of the completed stages (empty in the first) and its max |·|.
    pub u_done: Vec<f64>,
    pub u_done_max: f64,
}

impl StageLoads {
    /// The loads of stage k (0-based): its forces, the free rigid modes' share of them, and in
    /// the reduced space K# of its effective load (one solve per stage), with the completed
    /// stages' (`done`) accumulated.
    pub fn begin<D: Dim>(
        problem: &Problem<D>,
        stiffness: &mut Stiffness,
        k: usize,
        done: ReducedLoad,
        clock: &Clock,
    ) -> Self {
        let load = problem.stage_load(k);
        let fixed = &problem.dofs.fixed;
        let free = |f: &[f64], d: usize| if fixed[d] { 0.0 } else { f[d] };
        let (start, change) = (load.force_start(), load.force_change());
        let mode_force = problem
            .bodies
            .modes
            .iter()
            .map(|m| {
                let dot = |f: &[f64]| {
                    m.vector.iter().enumerate().map(|(d, a)| a * free(f, d)).sum::<f64>()
                };
                [dot(start), dot(change)]
            })
            .collect();
        let mut reduced = done;
        if let Space::Reduced(r) = &problem.space {
            let (effective, _) = problem.effective_load(&load, &stiffness.tangents.held);
            let _t = clock.time(Phase::Solves);
            let u_stage = stiffness
                .apply_ginv(&problem.dofs.map, std::slice::from_ref(&effective))
                .pop()
                .unwrap_or_default();
            if !reduced.u_load.is_empty() {
                reduced.u_done.resize(reduced.u_load.len(), 0.0);
                reduced.u_done.iter_mut().zip(&reduced.u_load).for_each(|(a, b)| *a += b);
                reduced.u_done_max = reduced.u_done.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            }
            reduced.u_load_reduced = r.dofs.iter().map(|&d| u_stage[d]).collect();
            reduced.u_load_max = u_stage.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            reduced.u_load = u_stage;
        }
        StageLoads { load, mode_force, reduced }
    }

    /// Nᵀ P(s) of free rigid mode k.
    pub fn mode_force_at(&self, k: usize, s: f64) -> f64 {
        self.mode_force[k][0] + s * self.mode_force[k][1]
    }

    /// ū(target) − u at every prescribed DOF (full space; residual form, so no drift).
    pub fn prescribed_increment<D: Dim>(
        &self,
        problem: &Problem<D>,
        state: &State<D>,
        target: f64,
    ) -> Vec<(usize, f64)> {
        if problem.is_reduced() {
            return vec![];
        }
        self.load.prescribed_at(target).map(|(d, v)| (d, v - state.u[d])).collect()
    }

    /// (c_n, c_t1, c_t2)(target) − (c_n, c_t1, c_t2) of every pair (residual form).
    pub fn shift_increment<D: Dim>(&self, state: &State<D>, target: f64) -> Vec<Shift> {
        (0..state.shift.len())
            .map(|p| {
                let c = self.load.shift(p, target);
                [c[0] - state.shift[p][0], c[1] - state.shift[p][1], c[2] - state.shift[p][2]]
            })
            .collect()
    }

    /// The stage's load change over the equations, zero at held DOFs (the cached sweep's load,
    /// `Stiffness::forward_sweep`).
    pub fn change_on_equations<D: Dim>(&self, problem: &Problem<D>) -> Vec<f64> {
        let change = self.load.force_change();
        problem
            .dofs
            .map
            .dof_of_equation
            .iter()
            .map(|&d| if problem.dofs.fixed[d] { 0.0 } else { change[d] })
            .collect()
    }

    /// Out-of-balance force at stage fraction `phi`: P(φ) − P_σ + contact forces over the free
    /// DOFs (the right-hand side of eq. 43), from the internal force P_σ of the stresses.
    pub fn residual_from<D: Dim>(
        &self,
        problem: &Problem<D>,
        internal: &[f64],
        state: &State<D>,
        phi: f64,
    ) -> Vec<f64> {
        let mut r = internal.to_vec();
        for (d, v) in r.iter_mut().enumerate() {
            *v = if problem.dofs.fixed[d] { 0.0 } else { self.load.force(d, phi) - *v };
        }
        for (p, pair) in problem.global_pairs().iter().enumerate() {
            pair.add_force(state.contact_force(p), &mut r);
        }
        r
    }

    /// max |u| of a state at stage fraction s (for round-off tolerances). The reduced space
    /// carries u at the contact DOFs only: the loads' share elsewhere is bounded by
    /// max |Σ u_stage of completed stages| + s × max |u_stage|.
    pub fn largest_displacement<D: Dim>(&self, problem: &Problem<D>, u: &[f64], s: f64) -> f64 {
        let carried = u.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        match problem.space {
            Space::Reduced(_) => {
                carried.max(self.reduced.u_done_max + s.abs() * self.reduced.u_load_max)
            }
            Space::Full => carried,
        }
    }

    /// max |Δu| of an increment over a stage fraction c (as `largest_displacement`).
    pub fn largest_increment<D: Dim>(&self, problem: &Problem<D>, du: &[f64], c: f64) -> f64 {
        let carried = du.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        match problem.space {
            Space::Reduced(_) => carried.max(c.abs() * self.reduced.u_load_max),
            Space::Full => carried,
        }
    }
}
