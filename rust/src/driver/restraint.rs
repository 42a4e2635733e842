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
/// T within this (relative) of μN is not gross sliding: the body is at the limit, not beyond.
const CAPACITY_TIE: f64 = 1e-9;
/// A tangential load below this × Σ|load| is round-off (of a moment of the other loads, say).
const LOAD_ROUND_OFF: f64 = 1e-9;

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
            let held_if_stuck = !slip_rows.is_empty() && free_motions(&[rows_n.as_slice(), slip_rows.as_slice()].concat(), idx.len()).is_empty();
            let name = self.model.body_name(self.body_first_element[body]);
            if held_if_stuck {
                let (t, n, mu) = self.tangential_and_normal_load(body, state, &idx, &free[0]);
                if t > mu * n * (1.0 + CAPACITY_TIE) && t > LOAD_ROUND_OFF * self.scales.force {
                    return Err(self.gross_sliding(&name, state, (t, n, mu), &words[0], &idx, &free[0], oob));
                }
                bail!(FreeBody, "{name} is free to move ({}): its {} closed contact pair(s) slip or are frictionless, so they do not hold it in that direction, and no support does; add a support (fix/symmetry) there", words.join("; "), slip_rows.len());
            }
            let closed = rows.iter().filter(|r| matches!(r, Row::Normal(p) if self.body_of_pair(*p) == body)).count();
            bail!(FreeBody, "{name} is free to move ({}): it has no support in that direction and its {closed} closed contact pair(s) do not hold it; add a support (fix/symmetry) or start a contact closed (gap 0)", words.join("; "));
        }
        Ok(())
    }

    fn body_of_pair(&self, p: usize) -> usize {
        self.body_of_node[self.global_pairs()[p].node_a]
    }

    fn slipping_pairs_of<'a>(&'a self, body: usize, state: &'a State) -> impl Iterator<Item = usize> + 'a {
        // Frictionless closed pairs (Slip with μ = 0) slip too: they hold no tangential load.
        (0..self.pairs.len()).filter(move |&p| matches!(state.status[p], Status::Slip { .. }) && !self.pairs[p].tangent_held && self.body_of_pair(p) == body)
    }

    /// Words for a combination `v` of the body's modes `idx`.
    fn describe_motion(&self, idx: &[usize], v: &[f64]) -> String {
        let w = self.motion_weights(idx, v);
        describe(w[0], w[1], w[2])
    }

    /// (translation x, translation y, rotation) of a combination `v` of the body's modes `idx`.
    fn motion_weights(&self, idx: &[usize], v: &[f64]) -> [f64; 3] {
        let mut w = [0.0; 3];
        for (c, &k) in idx.iter().enumerate() {
            for (wl, ml) in w.iter_mut().zip(self.modes[k].weights) {
                *wl += v[c] * ml;
            }
        }
        w
    }

    /// Under the stage's end load: the body's load T along the sliding translation, N along the mean
    /// normal of its closed pairs, and their mean μ.
    fn tangential_and_normal_load(&self, body: usize, state: &State, idx: &[usize], v: &[f64]) -> (f64, f64, f64) {
        let closed: Vec<usize> = (0..self.pairs.len()).filter(|&p| state.status[p].is_closed() && self.body_of_pair(p) == body).collect();
        let mean = |f: &dyn Fn(&crate::contact::Pair) -> f64| closed.iter().map(|&p| f(&self.global_pairs()[p])).sum::<f64>() / closed.len().max(1) as f64;
        let (normal, mu) = ([mean(&|p| p.normal[0]), mean(&|p| p.normal[1])], mean(&|p| p.mu));
        let load = self.stage.force_end();
        let load_along = |dir: [f64; 2]| -> f64 {
            let len = dir[0].hypot(dir[1]).max(f64::MIN_POSITIVE);
            (0..self.body_of_node.len()).filter(|&i| self.body_of_node[i] == body).map(|i| (load[2 * i] * dir[0] + load[2 * i + 1] * dir[1]) / len).sum()
        };
        (load_along(self.translation_of(idx, v)).abs(), load_along(normal).abs(), mu)
    }

    /// The gross-sliding error: T against μN under the full load (see above).
    #[allow(clippy::too_many_arguments)]
    fn gross_sliding(&self, name: &str, state: &State, (t, n, mu): (f64, f64, f64), words: &str, idx: &[usize], v: &[f64], oob: &OutOfBalance) -> crate::error::Error {
        // −Nᵀ r along the motion is the out-of-balance force nothing holds: the sense of sliding.
        let push: f64 = idx.iter().zip(v).map(|(&k, c)| -c * oob.mode_rhs[k]).sum();
        let sense = if push >= 0.0 { "+" } else { "−" };
        crate::fail!(GrossSliding, "{name} slides as a whole at load fraction {:.6} of {} ({sense}{words}): its closed pairs all slip; under the stage's full load the tangential load T = {t:.4e} exceeds the friction capacity μN = {:.4e} (N = {n:.4e} along the contact normal): lower the tangential load, raise mu, or add a support", state.load_fraction, self.path.stage_names[state.stage], mu * n)
    }

    /// The translation part (x, y) of a combination `v` of the body's modes `idx`.
    fn translation_of(&self, idx: &[usize], v: &[f64]) -> [f64; 2] {
        let w = self.motion_weights(idx, v);
        [w[0], w[1]]
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
