//! The stiffness the loop solves with: K = Σ w Bᵀ D B (eq. 36; w = t A, or 2π r̄ A in
//! axisymmetry) with the tangents K holds (`tangents`), its SPD factor K_f, the low-rank terms
//! of the tangents changed since (`low_rank`), the contact flexibility read from the factor,
//! and the products with K# the loop needs: full solves, split solves around the contact
//! forces, flexibility lookups, and the cached forward sweep of the stage's load.
//!
//! A tangent change is a term of rank one or two per element on the last factor, until those
//! terms have cost as much as a refactorization (counted in floating-point operations from the
//! factor's structure, so the choice is the same on every machine).

use super::clock::{seconds, Clock, Phase};
use super::problem::Problem;
use super::state::State;
use super::tangents::{Renewal, Tangents};
use crate::dim::Dim;
use crate::element::Element;
use crate::error::Result;
use crate::factor::Factor;
use crate::linalg::{DofMap, ElementScatter, StiffnessPattern};
use crate::low_rank::{Column, Cost, LowRank};
use crate::on_elements;
use faer::sparse::SparseColMat;

/// Measurements of one solve pair taken for the timing unit (the best is kept).
const SOLVE_PAIR_SAMPLES: usize = 3;
/// An out-of-balance force within this of c ΔP (relative, 2-norms) is c ΔP (`forward_sweep`):
/// a state balanced to round-off. Corrected states are balanced to ~1e-13 of the load
/// (`max_equilibrium_residual` of the runs), the loop accepts 1e-9 (`equilibrium_tol`).
const BALANCED: f64 = 1e-12;

/// Plastic runs keep K with every element elastic (the first assembly) and where each
/// element's entries sit in it: a refactorization re-adds w Bᵀ (D_ep − D) B of the plastic
/// elements only.
struct ElasticK {
    values: Vec<f64>,
    scatter: ElementScatter,
}

/// L⁻¹ ΔP_eq of stage `stage` with the factor of factorization number `factorization`.
struct LoadSweep {
    stage: usize,
    factorization: usize,
    load: Vec<f64>,
    sweep: Vec<f64>,
}

pub(super) struct Stiffness {
    pub solver: Factor,
    pattern: StiffnessPattern,
    elastic: Option<ElasticK>,
    pub tangents: Tangents,
    /// K = K_f + the low-rank terms of the elements whose tangent changed since, what those
    /// terms have cost so far (flops), and how many updates took them.
    pub low_rank: LowRank,
    low_rank_spent: f64,
    pub n_low_rank_updates: usize,
    /// The work of a factorization and of a solve pair (from the factor's structure).
    cost: Cost,
    /// K# restricted to the contact DOFs that are equations (t × t, by slot), read from the
    /// trailing block of the factor after every factorization (`flexibility_factored`) and
    /// corrected for the low-rank terms: every Cᵀ K# E entry of the small system is a lookup
    /// here, no triangular solve per contact pair.
    pub flexibility: faer::Mat<f64>,
    flexibility_factored: faer::Mat<f64>,
    /// The forward sweep of the current stage's load change, for the factor it was swept with
    /// (a balanced state's trial is that sweep scaled).
    load_sweep: Option<LoadSweep>,
    /// One forward + backward substitution with one right-hand side on the first factor, best
    /// of a few (the timing unit of an event's cost).
    pub solve_pair: f64,
}

impl Stiffness {
    /// K with every element elastic, factored, and its flexibility.
    pub fn new<D: Dim>(problem: &Problem<D>, clock: &Clock) -> Result<Self> {
        let tangents = Tangents::elastic(problem);
        let map = &problem.dofs.map;
        let (pattern, k, elastic) = {
            let _t = clock.time(Phase::Assembly);
            let pattern = on_elements!(&problem.elements, els => StiffnessPattern::new(els, map))?;
            let d: Vec<_> = tangents
                .held
                .iter()
                .zip(&problem.sections)
                .map(|(t, s)| s.element_matrix(t))
                .collect();
            let k = on_elements!(&problem.elements, els => pattern.assemble(els, &d, map))?;
            let plastic_run = problem.sections.iter().any(|s| s.material.is_plastic());
            let elastic = (plastic_run && !problem.is_reduced()).then(|| ElasticK {
                values: k.val().to_vec(),
                scatter: on_elements!(&problem.elements, els => pattern.element_scatter(els, map)),
            });
            (pattern, k, elastic)
        };
        let solver = {
            let _t = clock.time(Phase::Factorization);
            Factor::of_options(&problem.model.options, &k, map, problem.dofs.slot_dofs.len())?
        };
        let mut stiffness = Stiffness {
            solver,
            pattern,
            elastic,
            tangents,
            low_rank: LowRank::default(),
            low_rank_spent: 0.0,
            n_low_rank_updates: 0,
            cost: Cost::default(),
            flexibility: faer::Mat::zeros(0, 0),
            flexibility_factored: faer::Mat::zeros(0, 0),
            load_sweep: None,
            solve_pair: 0.0,
        };
        stiffness.factored(clock);
        stiffness.solve_pair = stiffness.measure_solve_pair(map);
        Ok(stiffness)
    }

    /// Assemble K with the current tangents and factor it.
    fn factor<D: Dim>(&mut self, problem: &Problem<D>, clock: &Clock) -> Result<()> {
        let k = {
            let _t = clock.time(Phase::Assembly);
            self.assemble(problem)?
        };
        {
            let _t = clock.time(Phase::Factorization);
            self.solver.factor(&k, &problem.dofs.map)?;
        }
        self.factored(clock);
        Ok(())
    }

    /// After a factorization: the contact flexibility read from the factor, and K_f holds
    /// every element's current tangent (no low-rank terms).
    fn factored(&mut self, clock: &Clock) {
        {
            let _t = clock.time(Phase::Flexibility);
            self.flexibility_factored = self.solver.trailing_inverse();
            self.flexibility.clone_from(&self.flexibility_factored);
        }
        // (The condensed backend's work changes when its near region grows.)
        self.cost = Cost::of(self.solver.work());
        self.tangents.factored();
        self.low_rank.clear();
        self.low_rank_spent = 0.0;
    }

    /// K with the current tangents. Plastic runs keep the elastic K and re-add
    /// w Bᵀ (D_ep − D) B of the elements that are plastic now.
    fn assemble<D: Dim>(&self, problem: &Problem<D>) -> Result<SparseColMat<usize, f64>> {
        if let Some(elastic) = &self.elastic {
            let mut values = elastic.values.clone();
            for (e, t) in self.tangents.held.iter().enumerate() {
                if t.flow.is_some() {
                    let section = &problem.sections[e];
                    let softening = section.element_matrix(t) - section.elastic_matrix();
                    on_elements!(&problem.elements, els => elastic.scatter.add(e, &els[e].stiffness(&softening), &mut values));
                }
            }
            return Ok(self.pattern.with_values(values));
        }
        let d: Vec<_> = self
            .tangents
            .held
            .iter()
            .zip(&problem.sections)
            .map(|(t, s)| s.element_matrix(t))
            .collect();
        on_elements!(&problem.elements, els => self.pattern.assemble(els, &d, &problem.dofs.map))
    }

    /// The timing unit: one forward + backward substitution, best of a few (not counted as
    /// solves).
    fn measure_solve_pair(&mut self, map: &DofMap) -> f64 {
        let mut best = f64::INFINITY;
        for _ in 0..SOLVE_PAIR_SAMPLES {
            let mut b = vec![1.0; map.n_equations];
            let ((), t) = seconds(|| self.solver.solve_in_place(&mut b, 1));
            best = best.min(t);
            self.solver.n_solves -= 1;
        }
        best
    }

    /// Bring every element's tangent in K up to date with the state (full space; `renewal`
    /// says which, `tangents`), then K follows: low-rank terms on the last factor, or a
    /// refactorization once those would cost more.
    pub fn update<D: Dim>(
        &mut self,
        problem: &Problem<D>,
        state: &State<D>,
        renewal: Renewal,
        clock: &Clock,
    ) -> Result<()> {
        if problem.is_reduced() {
            return Ok(());
        }
        let Some(changed) = self.tangents.renew(problem, state, renewal) else { return Ok(()) };
        if changed.is_empty() {
            return Ok(());
        }
        let map = &problem.dofs.map;
        let columns: Vec<Column> =
            changed.iter().flat_map(|&e| self.tangents.columns(problem, e, map)).collect();
        let extra = self.cost.update(self.low_rank.rank(), columns.len());
        if self.low_rank_spent + extra > self.cost.factorization {
            return self.factor(problem, clock);
        }
        self.low_rank_spent += extra;
        let _t = clock.time(Phase::LowRank);
        self.low_rank.update(&mut self.solver, map.n_equations, &changed, columns);
        self.flexibility = self.flexibility_factored.clone();
        if !self.low_rank.is_empty() {
            let t = self.flexibility.nrows();
            self.flexibility += self.low_rank.trailing_correction(t);
        }
        self.n_low_rank_updates += 1;
        Ok(())
    }

    /// x = K# y over all DOFs (fixed and pinned DOFs get 0), for each y in `ys`.
    pub fn apply_ginv(&mut self, map: &DofMap, ys: &[Vec<f64>]) -> Vec<Vec<f64>> {
        let (n, k) = (map.n_equations, ys.len());
        let mut b: Vec<f64> = ys.iter().flat_map(|y| map.to_equations(y)).collect();
        if k > 0 {
            self.solver.solve_in_place(&mut b, k);
        }
        (0..k).map(|c| map.from_equations(&b[c * n..(c + 1) * n])).collect()
    }

    /// K# y at the contact slots for a force y = Σ v e_d on contact DOFs (a column of the
    /// flexibility matrix per entry); `contact_slot`: the slot of every DOF.
    pub fn flexibility_times(&self, contact_slot: &[usize], y: &[(usize, f64)]) -> Vec<f64> {
        let mut out = vec![0.0; self.flexibility.nrows()];
        for &(d, v) in y {
            let slot = contact_slot[d];
            if slot == usize::MAX || v == 0.0 {
                continue;
            }
            let col = self.flexibility.col(slot);
            out.iter_mut().zip(col.iter()).for_each(|(o, g)| *o += v * g);
        }
        out
    }

    /// The forward sweep L⁻¹ r of an out-of-balance force r over the equations. From a balanced
    /// state r is c ΔP (c the stage fraction left, ΔP the stage's load change over the
    /// equations, `stage_load`) up to round-off: the sweep of ΔP is kept per stage and factor
    /// (one forward sweep per factor instead of one per trial), the rest is dropped (it would
    /// leave L⁻¹ r as it is), and the trial costs one backward sweep. A rest above `BALANCED` ×
    /// c‖ΔP‖ (an integrated increment not yet corrected, prescribed displacements) is swept whole.
    pub fn forward_sweep(
        &mut self,
        r_eq: &[f64],
        c: f64,
        stage: usize,
        stage_load: impl FnOnce() -> Vec<f64>,
    ) -> Vec<f64> {
        if c > 0.0 {
            let ls = self.stage_sweep(stage, stage_load);
            let (mut rest, mut load) = (0.0, 0.0);
            for (r, p) in r_eq.iter().zip(&ls.load) {
                rest += (r - c * p) * (r - c * p);
                load += c * c * p * p;
            }
            if rest <= BALANCED * BALANCED * load {
                return ls.sweep.iter().map(|w| c * w).collect();
            }
        }
        self.solver.forward(r_eq)
    }

    /// The current stage load's forward sweep, swept anew unless the cache holds it for this
    /// factor.
    fn stage_sweep(&mut self, stage: usize, stage_load: impl FnOnce() -> Vec<f64>) -> &LoadSweep {
        let factorization = self.solver.n_factorizations;
        if !self
            .load_sweep
            .as_ref()
            .is_some_and(|ls| ls.stage == stage && ls.factorization == factorization)
        {
            self.load_sweep = None;
        }
        let solver = &mut self.solver;
        self.load_sweep.get_or_insert_with(|| {
            let load = stage_load();
            let sweep = solver.forward(&load);
            LoadSweep { stage, factorization, load, sweep }
        })
    }

    /// K⁻¹(r + f) over the equations from the forward sweep `w` of r and a force f at the
    /// contact slots (`force_slots`): w_t += T⁻¹ f, one backward sweep, and with low-rank terms
    /// K⁻¹ y = K_f⁻¹ y − Z C⁻¹ Zᵀ y, whose coefficients for r are `r_coefficients`.
    pub fn backward_with_forces(
        &mut self,
        mut w: Vec<f64>,
        force_slots: &[f64],
        r_coefficients: impl FnOnce() -> Vec<f64>,
    ) -> Vec<f64> {
        self.solver.add_trailing_force(&mut w, force_slots);
        let mut x = self.solver.backward(w);
        if !self.low_rank.is_empty() {
            let mut c = r_coefficients();
            let from_forces = self.low_rank.trailing_coefficients(force_slots);
            c.iter_mut().zip(&from_forces).for_each(|(a, b)| *a += b);
            self.low_rank.subtract(&mut x, &c);
            self.count_low_rank_solve();
        }
        x
    }

    /// A solve with low-rank terms costs 4 n k more: counted towards the next refactorization.
    fn count_low_rank_solve(&mut self) {
        if !self.low_rank.is_empty() {
            self.low_rank_spent += self.cost.per_solve(self.low_rank.rank());
        }
    }
}
