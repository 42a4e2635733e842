//! Is every body held? A free rigid-body mode that no closed pair resists makes the small
//! system singular: say which body, which motion, and why — a missing support (free body), or
//! friction that cannot hold the tangential load (gross sliding: the body's closed pairs all
//! slip, and sticking would hold it).

use super::engine::Engine;
use super::state::State;
use super::trial::{OutOfBalance, Row};
use crate::bail;
use crate::contact::Status;
use crate::error::Result;
use crate::rigid_modes::describe;
use nalgebra::DMatrix;

/// A singular value of Cᵀ N below this × the largest is a motion no closed pair resists.
const FREE_MOTION: f64 = 1e-9;

impl Engine<'_> {
    /// Check, per body with free rigid modes, that the closed pairs' rows Cᵀ N (columns m.. of
    /// the small system `a`) have full column rank.
    pub fn check_restrained(&self, state: &State, a: &DMatrix<f64>, rows: &[Row], oob: &OutOfBalance) -> Result<()> {
        let nm = self.modes.len();
        let m = rows.len();
        let mut bodies: Vec<usize> = self.modes.iter().map(|md| md.body).collect();
        bodies.dedup();
        for body in bodies {
            let idx: Vec<usize> = (0..nm).filter(|&k| self.modes[k].body == body).collect();
            let rows_n: Vec<Vec<f64>> = (0..m).map(|i| idx.iter().map(|&k| a[(i, m + k)]).collect()).collect();
            let free = free_motions(&rows_n, idx.len());
            if free.is_empty() {
                continue;
            }
            let words: Vec<String> = free.iter().map(|v| self.describe_motion(&idx, v)).collect();
            let slip_rows: Vec<Vec<f64>> = self.slipping_pairs_of(body, state).map(|p| idx.iter().map(|&k| self.pairs[p].w_t.dot(&self.mode_vectors[k])).collect()).collect();
            if !slip_rows.is_empty() && free_motions(&[rows_n.as_slice(), slip_rows.as_slice()].concat(), idx.len()).is_empty() {
                return Err(self.gross_sliding(body, state, &idx, &free[0], &words[0], oob));
            }
            let closed = rows.iter().filter(|r| matches!(r, Row::Normal(p) if self.body_of_pair(*p) == body)).count();
            bail!(FreeBody, "{} is free to move ({}): it has no support in that direction and its {closed} closed contact pair(s) do not hold it; add a support (fix/symmetry) or start a contact closed (gap 0)", self.model.body_name(self.body_first_element[body]), words.join("; "));
        }
        Ok(())
    }

    fn body_of_pair(&self, p: usize) -> usize {
        self.body_of_node[self.global_pairs()[p].node_a]
    }

    fn slipping_pairs_of<'a>(&'a self, body: usize, state: &'a State) -> impl Iterator<Item = usize> + 'a {
        (0..self.pairs.len()).filter(move |&p| matches!(state.status[p], Status::Slip { .. }) && self.pairs[p].frictional() && self.body_of_pair(p) == body)
    }

    /// Words for a combination `v` of the body's modes `idx`.
    fn describe_motion(&self, idx: &[usize], v: &[f64]) -> String {
        let mut w = [0.0; 3];
        for (c, &k) in idx.iter().enumerate() {
            for (wl, ml) in w.iter_mut().zip(self.modes[k].weights) {
                *wl += v[c] * ml;
            }
        }
        describe(w[0], w[1], w[2])
    }

    /// The gross-sliding error: the load along the free motion against the friction capacity
    /// μ Σ λ_n of the body's closed pairs.
    fn gross_sliding(&self, body: usize, state: &State, idx: &[usize], v: &[f64], words: &str, oob: &OutOfBalance) -> crate::error::Error {
        // −Nᵀ r along the motion is the out-of-balance force that nothing holds; its sign
        // gives the direction of sliding.
        let push: f64 = idx.iter().zip(v).map(|(&k, c)| -c * oob.mode_rhs[k]).sum();
        let load: f64 = idx.iter().zip(v).map(|(&k, c)| c * self.mode_load[k]).sum::<f64>() * state.load_fraction;
        let (mut capacity, mut n) = (0.0, 0);
        for p in (0..self.pairs.len()).filter(|&p| state.status[p].is_closed() && self.body_of_pair(p) == body) {
            capacity += self.pairs[p].mu * state.lambda_n[p];
            n += 1;
        }
        let sense = if push >= 0.0 { "+" } else { "−" };
        crate::fail!(GrossSliding, "{} slides as a whole at load fraction {:.6} ({sense}{words}): the tangential load {:.4e} exceeds the friction capacity μΣλ_n = {capacity:.4e} of its {n} closed pair(s), all slipping; lower the tangential load, raise mu, or add a support", self.model.body_name(self.body_first_element[body]), state.load_fraction, load.abs())
    }
}

/// Right singular vectors of `rows` (k columns) with (near-)zero singular values: the motions
/// the rows do not resist.
fn free_motions(rows: &[Vec<f64>], k: usize) -> Vec<Vec<f64>> {
    // Padded with zero rows so that the SVD returns the full right singular basis.
    let mut g = DMatrix::<f64>::zeros(rows.len().max(k), k);
    for (i, r) in rows.iter().enumerate() {
        for c in 0..k {
            g[(i, c)] = r[c];
        }
    }
    let svd = g.svd(false, true);
    let smax = svd.singular_values.iter().fold(0.0f64, |x, v| x.max(*v));
    let v_t = svd.v_t.as_ref().expect("requested");
    (0..svd.singular_values.len())
        .filter(|&j| smax == 0.0 || svd.singular_values[j] <= FREE_MOTION * smax)
        .map(|j| (0..k).map(|c| v_t[(j, c)]).collect())
        .collect()
}
