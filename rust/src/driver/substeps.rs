//! Contact events inside a grouped plastic increment, in the contact space.
//!
//! A grouped increment (δ > 0) holds K fixed from its trial to the end of its plastic window;
//! its stresses are integrated and balanced once, at that end (`plasticity`). Over that stretch
//! the path is linear in K, as in an elastic run, so a contact event inside it (stick↔slip, a
//! separation, a closure away from plastic elements) needs only the paper's small system
//! (eqs. 43–44) at the contact DOFs: from a state the increment reached linearly the remaining
//! load is (c'/c) r of the trial's (`TrialBase`), so K# r at the contact slots is the trial's
//! scaled and the flexibility gives the rest. The events switch one after another in load
//! order, exactly as between full trials (with the anti-cycling rule), each with its step
//! record; the increment then ends at its window, or at a closure next to a plastic element,
//! with one backward sweep for Δu = K⁻¹(f r + W Δλ) + N Δα over all DOFs, and the usual
//! integration and correction. (The full-space loop would solve, integrate and correct at
//! every one of them: on the elastoplastic Hertz at 24.5k DOFs 297 increments become 64, with
//! 183 sub-steps.)
//!
//! Not with prescribed displacements changing in the stage (their DOFs' increments follow the
//! full state), nor when every event is a snapshot (each would need the full fields).

use super::anticycling::AntiCycling;
use super::engine::Engine;
use super::recording::Recorder;
use super::restraint::Hold;
use super::selection::Selection;
use super::state::{State, TrialIncrement};
use super::switch_statuses;
use super::trial::TrialBase;
use crate::error::Result;
use crate::events::Candidate;
use crate::model::EventKind;

/// At most this many contact sub-steps per increment (zero-length cycles are broken by the
/// anti-cycling rule; past it the increment simply ends there).
const MAX_SUBSTEPS: usize = 10_000;
/// The whole increment reproduces the sub-steps' contact path to this, relative to its largest
/// displacement. Measured: 1e-13 on the elastoplastic Hertz; up to 2.2e-6 at the two DOFs of
/// one slipping pair of the paper's block (quick mesh, μ = 0.2), a punch held by contact alone.
/// That is round-off, amplified: K# of a free body is its compliance relative to the pinned
/// DOF, there ~1e4 per unit force at the contact slots (a row sums to 2.2e5), and the pair's
/// displacement increment, 8e-4 per unit load, is the difference of K#r ≈ 1.372 and K#WΔλ ≈
/// −1.371. The whole takes Δλ as the difference of the end and start forces (~50 each: 4e-14
/// apart from the sub-steps' sum of increments), which K# turns into 4.6e-9. An error in the
/// algebra would be of order one.
const PATH_CHECK: f64 = 1e-3;

impl Engine<'_> {
    /// Whether the selection's events are taken as contact sub-steps: a grouped plastic
    /// increment ended early by contact events only.
    pub fn takes_substeps(&self, sel: &Selection, every_event: bool, state: &State) -> bool {
        sel.plastic_inside && !sel.last && !every_event && !sel.group.is_empty() && sel.phi < sel.bound_phi
            && sel.group.iter().all(|c| self.inside_substeps(c, state))
            && self.stage.prescribed_changes().iter().all(|&(_, v)| v == 0.0)
            && self.trial_base.is_some()
    }

    /// Stick↔slip and separation are taken as sub-steps, and a closure whose nodes' elements are
    /// all elastic; a closure next to a plastic element ends the increment, as an element event
    /// does: a new contact at the edge of a plastic zone concentrates stress where the held
    /// tangent is furthest from the material's. Measured: on the sphere on a flat (H' = 0,
    /// 50 ω_c) every closure as a sub-step moved a contact-edge element's stress path from
    /// 0.085 % to 1.5 % of the peak stress (with this rule: 0.086 %); on the elastoplastic
    /// Hertz at 24.5k DOFs, whose contact edge stays elastic, the rule takes every closure and
    /// the engine goes 2.77 → 2.61 s (δ = 0.01), 2.24 → 1.78 s (δ = 0.03).
    fn inside_substeps(&self, c: &Candidate, state: &State) -> bool {
        match c.kind {
            EventKind::StickToSlip | EventKind::SlipToStick | EventKind::Separate => true,
            EventKind::Close => self.pairs[c.entity].w_n.entries.iter().all(|&(d, _)| self.node_elements[d / 2].iter().all(|&e| !state.plastic[e])),
            _ => false,
        }
    }

    /// Switch the selection's contact events and go on event by event in the contact space up
    /// to the increment's bound; then the whole increment from `state` as one trial increment
    /// (scaled to the remaining load) and its selection, for `advance`, and the largest force
    /// jump of a switch (a jump ends the sub-steps: the correction must rebalance it).
    pub fn contact_substeps(&mut self, state: &mut State, sub: TrialIncrement, sel: Selection, cycles: &mut AntiCycling, rec: &mut Recorder) -> Result<(TrialIncrement, Selection, f64)> {
        // The trial's first yield is the exact onset only if no contact event switches before
        // it (else the yields keep where the integration puts them).
        let first_yield = sel.first_yield.filter(|&(_, phi)| phi <= sel.phi);
        let start = state.clone();
        let base = self.trial_base.take().expect("takes_substeps checked the trial");
        self.substep = Some(base.clone());
        let walked = self.walk_contact_events(state, sub, sel, cycles, rec);
        self.substep = None;
        let (sel, jump) = walked?;
        let whole = self.whole_increment(&start, state, &base);
        self.check_contact_path(&start, state, &whole)?;
        let (phi, bound_phi) = (state.load_fraction, sel.bound_phi);
        let scale = scale_between(&start, state);
        let (status, rtd_stick) = (std::mem::take(&mut state.status), std::mem::take(&mut state.rtd_stick));
        *state = State { status, rtd_stick, ..start };
        let rebalance = jump > self.noise.force;
        let last = sel.last && !rebalance;
        let ending = if rebalance || sel.group.iter().all(|c| self.inside_substeps(c, state)) { vec![] } else { sel.group };
        let predicted_closures = if last { sel.predicted_closures } else { vec![] };
        Ok((whole, Selection { scale, last, phi, group: ending, predicted_closures, plastic_inside: true, bound_phi, first_yield }, jump))
    }

    /// The sub-steps themselves: the contact state advanced to each selection, its events
    /// switched and recorded, the next contact-space trial and selection, until the bound, the
    /// stage's end, a closure (left for the increment's end) or a force jump. Returns the last
    /// selection (its bound the increment's) and the jump.
    fn walk_contact_events(&mut self, state: &mut State, mut sub: TrialIncrement, mut sel: Selection, cycles: &mut AntiCycling, rec: &mut Recorder) -> Result<(Selection, f64)> {
        let bound_phi = sel.bound_phi;
        for _ in 0..MAX_SUBSTEPS {
            let projected = self.advance_contact(state, &sub, &sel);
            let jump = switch_statuses(self, state, &sel, cycles, rec).max(projected);
            if jump > self.noise.force {
                return Ok((sel, jump));
            }
            rec.substep(state, sel.scale);
            if rec.steps.len() >= rec.max_steps || matches!(self.hold(state, &rec.events), Hold::Lost(_)) {
                break; // the loop's event bound (or `support_lost`) stops the run at its next increment
            }
            sub = self.trial(state, 1.0, None)?;
            let remaining = 1.0 - state.load_fraction;
            let bound = if bound_phi >= 1.0 { f64::INFINITY } else if remaining > 0.0 { ((bound_phi - state.load_fraction) / remaining).max(0.0) } else { 0.0 };
            sel = self.select_contact(state, &sub, cycles, bound);
            if sel.group.is_empty() || sel.last || !sel.group.iter().all(|c| self.inside_substeps(c, state)) {
                let projected = self.advance_contact(state, &sub, &sel);
                return Ok((sel, projected));
            }
        }
        Ok((Selection { group: vec![], ..sel }, 0.0))
    }

    /// The whole increment must reproduce the sub-steps' path at the contact slots (the same
    /// linear problem, solved once in full) to `PATH_CHECK` of the increment's largest
    /// displacement; anything larger is an error in this module, not round-off.
    fn check_contact_path(&self, start: &State, end: &State, whole: &TrialIncrement) -> Result<()> {
        let scale = scale_between(start, end);
        let mut worst = 0.0f64;
        for (d, _) in self.contact_slot.iter().enumerate().filter(|(_, &slot)| slot != usize::MAX) {
            worst = worst.max((scale * whole.du[d] - (end.u[d] - start.u[d])).abs());
        }
        let largest = scale * whole.du.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if worst > PATH_CHECK * largest {
            crate::bail!(Internal, "contact sub-steps: the increment's displacement differs from its sub-steps' by {:.1e} (of {largest:.1e}) at load fraction {:.6}", worst, end.load_fraction);
        }
        Ok(())
    }

    /// The contact state along a sub-step: u (exact at the contact DOFs, where a sub-step's
    /// increment lives), λ, α and the obstacle shifts; the rest follows at the increment's end.
    /// Returns the force jump of putting slipping pairs back on their cones (`project_onto_cone`):
    /// the sub-steps' scaled load does not hold it, so a jump ends them.
    fn advance_contact(&self, state: &mut State, inc: &TrialIncrement, sel: &Selection) -> f64 {
        let s = sel.scale;
        state.u.iter_mut().zip(&inc.du).for_each(|(u, d)| *u += s * d);
        state.advance_forces(inc, s);
        state.load_fraction = sel.phi;
        self.project_onto_cone(state)
    }

    /// The increment from `start` to the contact state `end` over all DOFs, as a trial
    /// increment for the remaining load of `start` (so that its scale takes `start` to `end`):
    /// Δu = K⁻¹(f r + W Δλ) + N Δα with f = 1 − c_end / c, then the stresses with K's tangents.
    fn whole_increment(&mut self, start: &State, end: &State, base: &TrialBase) -> TrialIncrement {
        let scale = scale_between(start, end);
        let per = |v: f64| if scale > 0.0 { v / scale } else { 0.0 };
        let dlambda_n: Vec<f64> = end.lambda_n.iter().zip(&start.lambda_n).map(|(a, b)| a - b).collect();
        let dlambda_t: Vec<f64> = end.lambda_t.iter().zip(&start.lambda_t).map(|(a, b)| a - b).collect();
        let mut force_slots = vec![0.0; self.flexibility.nrows()];
        for (p, pair) in self.pairs.iter().enumerate() {
            for (w, dl) in [(&pair.w_n, dlambda_n[p]), (&pair.w_t, dlambda_t[p])] {
                for &(d, v) in &w.entries {
                    if self.contact_slot[d] != usize::MAX {
                        force_slots[self.contact_slot[d]] += dl * v;
                    }
                }
            }
        }
        let mut du = self.displacement_from(base, scale, &force_slots);
        let dalpha: Vec<f64> = end.alpha.iter().zip(&start.alpha).map(|(a, b)| a - b).collect();
        for (mode, a) in self.mode_vectors.iter().zip(&dalpha) {
            du.iter_mut().zip(mode).for_each(|(x, v)| *x += a * v);
        }
        du.iter_mut().for_each(|x| *x = per(*x));
        let (dstress, dplastic, dstrain) = self.stress_increment(&du);
        TrialIncrement {
            du,
            dstress,
            dplastic,
            dstrain,
            dlambda_n: dlambda_n.into_iter().map(per).collect(),
            dlambda_t: dlambda_t.into_iter().map(per).collect(),
            dalpha: dalpha.into_iter().map(per).collect(),
            dshift: end.shift.iter().zip(&start.shift).map(|(a, b)| [per(a[0] - b[0]), per(a[1] - b[1])]).collect(),
        }
    }
}

/// The scale of `start`'s trial for the remaining load that takes it to `end` (0 at a stage's end).
fn scale_between(start: &State, end: &State) -> f64 {
    let c = 1.0 - start.load_fraction;
    if c > 0.0 { (end.load_fraction - start.load_fraction) / c } else { 0.0 }
}
