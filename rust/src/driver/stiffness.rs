//! K = Σ w Bᵀ D B (eq. 36; w = t A, or 2π r̄ A in axisymmetry) with the current tangents, its SPD factor, and the products with
//! K# the loop needs: full solves (K# y) and flexibility lookups at the contact DOFs.

use super::engine::{since, Engine};
use super::space::Space;
use crate::contact::SparseVec;
use crate::element::Element;
use crate::error::Result;
use crate::low_rank::Cost;
use std::time::Instant;

/// Measurements of one solve pair taken for the timing unit (the best is kept).
const SOLVE_PAIR_SAMPLES: usize = 3;

impl Engine<'_> {
    /// Assemble K with the current tangents and factor it; read the contact flexibility from
    /// the factor.
    pub fn factor(&mut self) -> Result<()> {
        let t0 = Instant::now();
        let k = self.assemble()?;
        self.tangents_changed = false;
        let t1 = Instant::now();
        self.timings.assembly += (t1 - t0).as_secs_f64();
        self.solver.factor(&k, &self.map.dof_of_equation)?;
        self.timings.factorization += since(t1);
        self.factored();
        Ok(())
    }

    /// After a factorization: the contact flexibility read from the factor; the first also
    /// measures the costs.
    pub fn factored(&mut self) {
        let t2 = Instant::now();
        self.flexibility_factored = self.solver.trailing_inverse();
        self.flexibility.clone_from(&self.flexibility_factored);
        self.timings.flexibility += since(t2);
        self.tangents_factored();
        if self.timings.solve_pair == 0.0 {
            self.cost = Cost::of(self.solver.work());
            self.measure_solve_pair();
        }
    }

    /// K with the current tangents. Plastic runs keep the elastic K and re-add
    /// w Bᵀ (D_ep − D) B of the elements that are plastic now.
    fn assemble(&mut self) -> Result<faer::sparse::SparseColMat<usize, f64>> {
        if let Space::Full(full) = &self.space {
            if let Some(scatter) = &full.scatter {
                let mut values = full.elastic_values.clone();
                for (e, t) in self.tangents.iter().enumerate() {
                    if t.flow.is_some() {
                        let section = &self.sections[e];
                        let softening = section.element_matrix(t) - section.elastic_matrix();
                        scatter.add(e, &self.elements[e].stiffness(&softening), &mut values);
                    }
                }
                return Ok(self.pattern.with_values(values));
            }
        }
        let d: Vec<_> = self.tangents.iter().zip(&self.sections).map(|(t, s)| s.element_matrix(t)).collect();
        let k = self.pattern.assemble(&self.elements, &d, &self.map)?;
        let all_elastic_now = self.tangents.iter().all(|t| t.flow.is_none());
        let plastic_run = self.sections.iter().any(|s| s.material.is_plastic());
        if let Space::Full(full) = &mut self.space {
            if all_elastic_now && plastic_run {
                full.elastic_values = k.val().to_vec();
                full.scatter = Some(self.pattern.element_scatter(&self.elements, &self.map));
            }
        }
        Ok(k)
    }

    /// The timing unit: one forward + backward substitution, best of a few.
    fn measure_solve_pair(&mut self) {
        let mut best = f64::INFINITY;
        for _ in 0..SOLVE_PAIR_SAMPLES {
            let mut b = vec![1.0; self.map.n_equations];
            let t = Instant::now();
            self.solver.solve_in_place(&mut b, 1);
            best = best.min(since(t));
            self.solver.n_solves -= 1;
        }
        self.timings.solve_pair = best;
    }

    /// x = K# y over all DOFs (fixed and pinned DOFs get 0), for each y in `ys`.
    pub fn apply_ginv(&mut self, ys: &[Vec<f64>]) -> Vec<Vec<f64>> {
        let (n, k) = (self.map.n_equations, ys.len());
        let mut b: Vec<f64> = ys.iter().flat_map(|y| self.map.to_equations(y)).collect();
        if k > 0 {
            self.solver.solve_in_place(&mut b, k);
        }
        (0..k).map(|c| self.map.from_equations(&b[c * n..(c + 1) * n])).collect()
    }

    /// K# y at the contact slots for a force y = Σ v e_d on contact DOFs (a column of the
    /// flexibility matrix per entry).
    pub fn flexibility_times(&self, y: &[(usize, f64)]) -> Vec<f64> {
        let mut out = vec![0.0; self.flexibility.nrows()];
        for &(d, v) in y {
            let slot = self.contact_slot[d];
            if slot == usize::MAX || v == 0.0 {
                continue;
            }
            let col = self.flexibility.col(slot);
            out.iter_mut().zip(col.iter()).for_each(|(o, g)| *o += v * g);
        }
        out
    }

    /// cᵀ x for a constraint vector c and x given at the contact slots.
    pub fn dot_slots(&self, c: &SparseVec, x: &[f64]) -> f64 {
        c.entries
            .iter()
            .map(|&(d, v)| match self.contact_slot[d] {
                usize::MAX => 0.0,
                slot => v * x[slot],
            })
            .sum()
    }
}
