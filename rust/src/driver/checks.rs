//! Checks at every event: equilibrium (eq. 36 with Δ = 0), the contact conditions (eqs. 22–24,
//! 1–2), and the limit-load stop (a plastic mechanism).

use super::engine::Engine;
use super::selection::Selection;
use super::space::Space;
use super::state::{State, TrialIncrement};
use crate::bail;
use crate::dim::Dim;
use crate::error::Result;
use crate::model::StopReason;

/// Gap tolerance: × max|u| (round-off of the solves) + × the length scale (of coordinates).
pub(super) const GAP_ROUND_OFF: f64 = 1e-8;
const GAP_COORDINATE: f64 = 1e-12;
/// Force tolerance: × Σ|load|.
pub(super) const FORCE_ROUND_OFF: f64 = 1e-9;
/// The correction moves gaps by up to its displacement and forces by up to its force size;
/// these multiples of the last correction are allowed on top (see `Correction`).
const CORRECTION_GAP_ALLOWANCE: f64 = 2.0;
const CORRECTION_FORCE_ALLOWANCE: f64 = 4.0;

/// The size of the last equilibrium correction (displacement, force): the correction moves
/// nodes and contact forces by that much with no event of its own, so the contact checks
/// allow for it (`check_contact`).
#[derive(Clone, Copy, Default)]
pub(super) struct Correction {
    pub displacement: f64,
    pub force: f64,
}

impl Correction {
    /// Grow by `s` × a correction increment.
    pub fn include(&mut self, c: &TrialIncrement, s: f64) {
        let largest = |v: &[f64]| v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        self.displacement = self.displacement.max(s * largest(&c.du));
        self.force = self
            .force
            .max(s * largest(&c.dlambda_n).max(largest(&c.dlambda_t)).max(largest(&c.dlambda_t2)));
    }
}

/// |P(s) − P_σ + Wλ| / |P| over all DOFs, from the stresses of a full state, and the internal
/// force P_σ it used (reused by the next trial from the same stresses).
pub(super) fn full_residual<D: Dim>(eng: &Engine<D>, state: &State<D>) -> (f64, Vec<f64>) {
    let problem = &eng.problem;
    let internal = problem.internal_force(&state.stress);
    let r = eng.loads.residual_from(problem, &internal, state, state.load_fraction);
    (r.iter().map(|v| v * v).sum::<f64>().sqrt() / problem.scales.load_norm, internal)
}

/// The relative equilibrium residual of the loop's state, and the internal force it used (full
/// space). In the reduced space u = K#(φP + Wλ) + Nα is in equilibrium exactly when φP + Wλ
/// is orthogonal to the free rigid modes (K K# y = y for y ⊥ N): only that part is measured
/// here; snapshots check in full. (With stages, P(s) is the stage's load and K#P the sum of the
/// stages' K# loads.)
pub(super) fn equilibrium_residual<D: Dim>(
    eng: &Engine<D>,
    state: &State<D>,
) -> (f64, Option<Vec<f64>>) {
    let problem = &eng.problem;
    if let Space::Full = problem.space {
        let (r, internal) = full_residual(eng, state);
        return (r, Some(internal));
    }
    let r2: f64 = (0..problem.bodies.mode_vectors.len())
        .map(|k| {
            (eng.loads.mode_force_at(k, state.load_fraction) + problem.mode_contact_force(state, k))
                .powi(2)
        })
        .sum();
    (r2.sqrt() / problem.scales.load_norm, None)
}

/// An error unless the residual is within `equilibrium_tol`.
pub(super) fn check_equilibrium<D: Dim>(
    eng: &Engine<D>,
    residual: f64,
    phi: f64,
    step: usize,
) -> Result<()> {
    let tol = eng.problem.model.options.equilibrium_tol;
    if residual > tol {
        bail!(Equilibrium, "equilibrium residual {residual:.3e} exceeds {tol:.1e} at load fraction {phi:.6} (step {step}): the linear system is ill-conditioned; check for nearly unsupported bodies or extreme element size ratios");
    }
    Ok(())
}

/// Contact conditions at an event: no penetration, λ_n ≥ 0, Coulomb's cone (for a slipping 3D
/// pair that has slipped its polygon: `Problem::friction_excess`). A violation by a pair the
/// last-resort anti-cycling rule froze is reported as an ill-posed scene.
pub(super) fn check_contact<D: Dim>(
    eng: &Engine<D>,
    state: &State<D>,
    frozen: &[bool],
    correction: Correction,
) -> Result<()> {
    let problem = &eng.problem;
    let umax = eng.loads.largest_displacement(problem, &state.u, state.load_fraction);
    let gap_tol = GAP_ROUND_OFF * umax
        + GAP_COORDINATE * problem.scales.length
        + CORRECTION_GAP_ALLOWANCE * correction.displacement;
    let force_tol =
        FORCE_ROUND_OFF * problem.scales.force + CORRECTION_FORCE_ALLOWANCE * correction.force;
    let phi = state.load_fraction;
    for (p, pair) in problem.pairs.iter().enumerate() {
        let g = problem.gap(state, p);
        let ln = state.lambda_n[p];
        let lt = state.lambda_t[p].hypot(state.lambda_t_of(p)[1]);
        let closed = state.status[p].is_closed();
        // a frozen pair has no event to bring it back: held to round-off, not to a correction's allowance
        let force_tol = if frozen[p] { FORCE_ROUND_OFF * problem.scales.force } else { force_tol };
        let violation = if g < -gap_tol {
            format!("penetrates by {:.3e}", -g)
        } else if closed && ln < -force_tol {
            format!("carries a tensile force {ln:.3e}")
        } else if closed && problem.friction_excess(state, p) > force_tol {
            format!("violates Coulomb's law (|λ_t| = {lt:.3e} beyond its cone by {:.3e}, μλ_n = {:.3e})", problem.friction_excess(state, p), problem.pairs[p].friction.capacity(ln))
        } else {
            continue;
        };
        let name = problem.model.pair_name(p);
        if frozen[p] {
            bail!(IllPosed, "{name} {violation} at load fraction {phi:.6}: its statuses cycled at zero load increment, the complementarity (rate) problem found no admissible set, and the last-resort anti-cycling rule froze it; the scene may be ill-posed for mu = {}: lower mu, or load it differently", pair.friction.mu);
        }
        if correction.displacement > 0.0 || correction.force > 0.0 {
            // The equilibrium correction after a plastic return moves contact forces with no
            // event of its own; beyond its allowance that is the drift control's limit.
            bail!(Equilibrium, "{name} {violation} at load fraction {phi:.6} after the equilibrium correction of the plastic drift: lower solver.max_stress_step (default 0.05) or refine the mesh");
        }
        bail!(Internal, "{name} {violation} at load fraction {phi:.6}: an event was missed (a bug; please report it with the case)");
    }
    Ok(())
}

/// The limit-load stop: with a plastic mechanism the tangent turns (nearly) singular and the
/// trial displacement explodes while the factorization still succeeds. The current stiffness
/// |R|²/(R·Δu) of the stage's remaining force R is compared with the stage's first increment's
/// (a new stage, e.g. unloading, starts a new reference). Only trials the load advances along
/// are measured: one whose statuses switch at once (a zero-length increment, as after a pair
/// closes and slips at one instant, with every element still on its plastic tangent) is no
/// response of the body.
#[derive(Default)]
pub(super) struct LimitLoad {
    initial_stiffness: Option<f64>,
}

impl LimitLoad {
    pub fn check<D: Dim>(
        &mut self,
        eng: &Engine<D>,
        state: &State<D>,
        trial: &TrialIncrement,
        sel: &Selection,
    ) -> Option<StopReason> {
        let problem = &eng.problem;
        if problem.is_reduced() || sel.zero_length() {
            return None;
        }
        let fixed = &problem.dofs.fixed;
        let remaining: Vec<f64> = eng
            .loads
            .load
            .force_change()
            .iter()
            .enumerate()
            .map(|(d, v)| if fixed[d] { 0.0 } else { v * (1.0 - state.load_fraction) })
            .collect();
        let r2: f64 = remaining.iter().map(|v| v * v).sum();
        let work: f64 = remaining.iter().zip(&trial.du).map(|(a, b)| a * b).sum();
        if r2 <= 0.0 {
            return None;
        }
        // Non-positive work of the remaining load: the tangent has lost positive definiteness
        // along the path (past the limit): zero stiffness.
        let stiffness = if work > 0.0 { r2 / work } else { 0.0 };
        let first = *self.initial_stiffness.get_or_insert(stiffness);
        let ratio = stiffness / first;
        (stiffness < problem.model.options.limit_stiffness * first).then_some(
            StopReason::LimitLoad { load_fraction: state.time(), stiffness_ratio: ratio },
        )
    }
}
