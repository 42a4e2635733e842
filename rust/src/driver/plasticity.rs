//! Plasticity in the loop (eqs. 5–11, 59): the elements' stresses over an increment, and the
//! equilibrium correction after it.
//!
//! The trial moves every element with the tangent K holds (`tangents`), which is exact for the
//! elastic ones. With `drift_control` (the default) the stress of every element that is plastic,
//! or (a plastic window) crosses its yield surface inside the increment, is integrated along
//! its strain instead (`stress_integration`: the elastic–plastic split, Prandtl–Reuss with error
//! control); one correction solve at fixed load, with the tangents brought up to date, then
//! restores equilibrium, so that every event is in equilibrium to round-off. (Keeping the
//! linear stresses while they stay within a tolerance of the surface saves corrections but
//! biases the path: measured on the elastoplastic Hertz at 8.6k DOFs, p0 −0.24 %, −0.05 % and
//! −0.03 % for tolerances 1e-3, 1e-4 and 1e-5 of σy.) `drift_control = false` is the paper
//! exactly: the tangent's linear increment, no correction.
//!
//! A plastic window is re-integrated from its start until balanced; one whose rounds stall is
//! handed back (`Restored::Unbalanced`) with the window the caller passed in, to be retaken.

use super::checks::{full_residual, Correction, FORCE_ROUND_OFF, GAP_ROUND_OFF};
use super::clock::Phase;
use super::engine::Engine;
use super::problem::{Problem, PARALLEL_CHUNK};
use super::selection::{pair_state, trial_of, Selection, STAGE_END, ZERO_SCALE};
use super::slip_direction::direct_new_slips;
use super::state::{IncrementStart, State, TrialIncrement};
use super::switching::{contact_forces, jumps_kept, keep_jumps, switch_keeping};
use super::tangents::Renewal;
use super::trial::{self, Solve};
use crate::dim::Dim;
use crate::error::Result;
use crate::events::{self, Candidate};
use crate::material::{von_mises, yield_scale};
use crate::model::EventKind;
use crate::stress_integration::{integrate, Integrated, PointState};
use rayon::prelude::*;

/// A grouped increment is re-integrated until its state is out of balance by at most this ×
/// the load (relative residual). Measured on the thick cylinder (H' = 0, δ = 0.01, 2.7k and
/// 4.9k DOFs), the largest difference of plastic strain to the event-by-event run: 1.75 % with
/// one linear correction, 1.45 % (tol 1e-3), 0.47 % (1e-4), 0.33 % (1e-5); on the
/// elastoplastic Hertz (24.5k DOFs) 1e-4 moves p0 by 0.003 %.
const REINTEGRATION_TOL: f64 = 1e-4;
/// After this many rounds a window within `RETAKE_TOL` is kept; one further out goes on while
/// its rounds converge fast enough to reach `RETAKE_TOL` within `MAX_ROUNDS` (`stalls`), else
/// it is retaken.
const MAX_REINTEGRATIONS: usize = 4;
const MAX_ROUNDS: usize = 10;
/// A window still out of balance by more than this × the load after its re-integration rounds
/// (`MAX_REINTEGRATIONS`, more while they converge: `stalls`) is retaken: ten times the balance
/// a window is re-integrated to (`REINTEGRATION_TOL`). Measured at δ = 0.01: the elastoplastic
/// Hertz at 24.5k DOFs leaves 8 of its 54 windows between 1.1e-4 and 1.6e-4 after four rounds,
/// none above; asked for 1.1× its limit load, the thick sphere's windows before the limit end
/// their fourth round at up to 2e-2 and still converge (ratios ~0.5), the one past it stalls at
/// 0.37.
const RETAKE_TOL: f64 = 1e-3;

/// A stage ends with its plastic elements this close to their yield surfaces (relative; a
/// reload of an elastic release then meets them at the stage's end: `selection::STAGE_END`),
/// settled in at most `SETTLE_ROUNDS` rounds (each leaves about the square of the last drift).
const SETTLED_DRIFT: f64 = 1e-12;
const SETTLE_ROUNDS: usize = 3;

/// Contact events of one correction within this (relative, plus an absolute slack) of its
/// first switch together; at most this many sub-steps per correction (each switches at
/// least one pair; past it the rest is taken as one step).
const CORRECTION_TIE: f64 = 1e-9;
const CORRECTION_TIE_SLACK: f64 = 1e-14;
const MAX_CORRECTION_EVENTS: usize = 32;

/// What restoring equilibrium after an increment did; `W` is the plastic window the caller
/// passed in, handed back when it must be retaken.
pub(super) enum Restored<W> {
    /// The increment kept the tangent's linear stresses: in equilibrium already, and the last
    /// correction's allowance for the contact checks still holds.
    Linear,
    /// Corrected; the increment's start (which elements yielded inside: `window`).
    Corrected(Corrected, IncrementStart),
    /// A plastic window its re-integration could not balance: the caller retakes it from the
    /// increment's start.
    Unbalanced(W, IncrementStart),
}

/// What an equilibrium correction did: its size and the contact events it took, in order.
#[derive(Default)]
pub(super) struct Corrected {
    pub size: Correction,
    pub events: Vec<Candidate>,
}

impl Corrected {
    /// Grown by a further correction.
    fn absorb(&mut self, other: Corrected) {
        self.size.displacement = self.size.displacement.max(other.size.displacement);
        self.size.force = self.size.force.max(other.size.force);
        self.events.extend(other.events);
    }
}

/// Yield-surface drift: max |σe − σy(εp)| / σy(εp) over plastic elements.
pub(super) fn drift<D: Dim>(problem: &Problem<D>, state: &State<D>) -> f64 {
    (0..state.plastic.len())
        .filter(|&e| state.plastic[e])
        .map(|e| {
            let sy = problem.sections[e].material.current_yield(state.plastic_strain[e]);
            (von_mises(&state.stress[e]) - sy).abs() / sy
        })
        .fold(0.0, f64::max)
}

/// The stress of each element that is plastic at the increment's start, or (a plastic window)
/// whose elastic path crosses its yield surface inside the increment, integrated over the
/// increment's strain from `state` (before the advance). An elastic path that meets the
/// surface within `STAGE_END` of the stage's end ties with the end, as a yield event does
/// (`selection`): it belongs to the next stage.
pub(super) fn integrate_stresses<D: Dim>(
    problem: &Problem<D>,
    state: &State<D>,
    trial: &TrialIncrement,
    sel: &Selection,
) -> Vec<(usize, Integrated)> {
    let scale = sel.scale;
    if !problem.model.options.drift_control || scale <= ZERO_SCALE {
        return vec![]; // a zero-length increment changes no stress (and gets no correction)
    }
    let (phi0, phi1) = (state.load_fraction, sel.phi);
    let crosses =
        |e: usize, sy: f64| match yield_scale(&state.stress[e], &(trial.dstress[e] * scale), sy) {
            Some(r) => r < 1.0 && phi0 + r * (phi1 - phi0) < 1.0 - STAGE_END,
            None => false,
        };
    (0..state.stress.len())
        .into_par_iter()
        .with_min_len(PARALLEL_CHUNK)
        .filter_map(|e| {
            let (section, plastic) = (&problem.sections[e], state.plastic[e]);
            let m = &section.material;
            let sy = m.current_yield(state.plastic_strain[e]);
            if !m.is_plastic() || !(plastic || (sel.plastic_inside && crosses(e, sy))) {
                return None;
            }
            // back onto the surface first if the last correction left it beyond
            let stress = if plastic {
                section.not_beyond_surface(&state.stress[e], sy)
            } else {
                state.stress[e]
            };
            let start = PointState { stress, plastic_strain: state.plastic_strain[e], plastic };
            Some((e, integrate(section, &start, &(problem.elements.strain(e, &trial.du) * scale))))
        })
        .collect()
}

/// Put the integrated states in place and note where elements crossed their surfaces.
pub(super) fn place_integrated<D: Dim>(
    state: &mut State<D>,
    integrated: &[(usize, Integrated)],
    start: &mut IncrementStart,
) {
    for (e, out) in integrated {
        state.stress[*e] = out.end.stress;
        state.plastic_strain[*e] = out.end.plastic_strain;
        state.plastic[*e] = out.end.plastic;
        if let Some(at) = out.yielded_at {
            start.yielded_at.insert(*e, at);
        }
    }
}

/// Equilibrium after an increment whose stresses were integrated (`start`: its start; None
/// when nothing was): the tangents follow the state (`renewal`), then the correction at fixed
/// load (`correct_at_fixed_load`), in a plastic window (`window`) re-integrated until balanced
/// (`converge`). A correction that leaves plastic elements more than max_stress_step² off
/// their yield surfaces (the second-order drift of a fresh tangent over a bounded stress step:
/// only waiting yields, `tangents`, do that), and every stage's end, then settle on the
/// surfaces (`settle_on_surfaces`).
pub(super) fn restore_equilibrium<W, D: Dim>(
    eng: &mut Engine<D>,
    state: &mut State<D>,
    sel: &Selection,
    start: Option<IncrementStart>,
    window: Option<W>,
    renewal: Renewal,
) -> Result<Restored<W>> {
    let Some(mut start) = start else { return Ok(Restored::Linear) };
    let _t = eng.clock.time(Phase::Corrections);
    eng.stiffness.update(&eng.problem, state, renewal, eng.clock)?;
    let mut corrected = match converge(eng, state, sel.phi, &mut start, window)? {
        Ok(corrected) => corrected,
        Err(window) => return Ok(Restored::Unbalanced(window, start)),
    };
    let bound = eng.problem.model.options.max_stress_step.powi(2);
    if sel.last || drift(&eng.problem, state) > bound {
        corrected.absorb(settle_on_surfaces(eng, state, sel.phi, sel.last)?);
    }
    Ok(Restored::Corrected(corrected, start))
}

/// The increment's correction; in a plastic window then every element that was or became
/// plastic, or is beyond its surface, integrated again from the increment's start over its
/// whole strain (trial and corrections: `reintegrate`), and while that state is out of balance
/// by more than `REINTEGRATION_TOL` of the load, corrected again. The last linear stresses
/// are kept (in equilibrium to round-off), with their plastic strains and flags; an elastic
/// element they leave beyond its surface has yielded. Err(window) for a window whose rounds
/// stall (`stalls`).
fn converge<W, D: Dim>(
    eng: &mut Engine<D>,
    state: &mut State<D>,
    phi: f64,
    start: &mut IncrementStart,
    window: Option<W>,
) -> Result<std::result::Result<Corrected, W>> {
    let mut corrected = correct_at_fixed_load(eng, state, phi, None)?;
    if let Some(window) = window {
        let mut previous = None;
        for round in 1..=MAX_ROUNDS {
            let linear =
                (state.stress.clone(), state.plastic_strain.clone(), state.plastic.clone());
            reintegrate(&eng.problem, state, start);
            let (residual, internal) = full_residual(eng, state);
            if residual <= REINTEGRATION_TOL {
                (state.stress, state.plastic_strain, state.plastic) = linear;
                break;
            }
            if residual > RETAKE_TOL && stalls(residual, previous, MAX_ROUNDS - round) {
                return Ok(Err(window));
            }
            corrected.absorb(correct_at_fixed_load(eng, state, phi, Some(internal))?);
            if round >= MAX_REINTEGRATIONS && residual <= RETAKE_TOL {
                break;
            }
            previous = Some(residual);
        }
    }
    flag_beyond_surfaces(&eng.problem, state, start);
    Ok(Ok(corrected))
}

/// Whether the rounds of a window out of balance by more than `RETAKE_TOL` stall: at the
/// contraction of its last round (residual over the round before's), reaching `RETAKE_TOL` would
/// take more than the rounds left. Rounds contract at a near-constant ratio: 0.5–0.75 on the
/// Hertz, the paper block and the thick sphere, 0.98 past a limit load.
fn stalls(residual: f64, previous: Option<f64>, rounds_left: usize) -> bool {
    let Some(previous) = previous else { return rounds_left == 0 };
    let ratio = residual / previous;
    ratio >= 1.0 || (RETAKE_TOL / residual).ln() / ratio.ln() > rounds_left as f64
}

/// An elastic element the last correction left beyond its yield surface yielded in this
/// increment (where the integration put its crossing, else at the end): plastic from here
/// (its next increment starts on the surface).
fn flag_beyond_surfaces<D: Dim>(
    problem: &Problem<D>,
    state: &mut State<D>,
    start: &mut IncrementStart,
) {
    for e in 0..state.plastic.len() {
        let m = &problem.sections[e].material;
        if m.is_plastic()
            && !state.plastic[e]
            && von_mises(&state.stress[e]) > m.current_yield(state.plastic_strain[e])
        {
            state.plastic[e] = true;
            start.yielded_at.entry(e).or_insert(1.0);
        }
    }
}

/// Every element that was plastic at the increment's start, is plastic now or is beyond its
/// yield surface now: its start state integrated over the increment's whole strain so far.
fn reintegrate<D: Dim>(problem: &Problem<D>, state: &mut State<D>, start: &mut IncrementStart) {
    let du: Vec<f64> = state.u.iter().zip(&start.u).map(|(a, b)| a - b).collect();
    let now: &State<D> = state;
    let integrated: Vec<(usize, Integrated)> = (0..now.stress.len())
        .into_par_iter()
        .with_min_len(PARALLEL_CHUNK)
        .filter_map(|e| {
            let section = &problem.sections[e];
            let m = &section.material;
            let beyond = || von_mises(&now.stress[e]) > m.current_yield(now.plastic_strain[e]);
            if !m.is_plastic() || !(start.plastic[e] || now.plastic[e] || beyond()) {
                return None;
            }
            let sy = m.current_yield(start.plastic_strain[e]);
            let stress = if start.plastic[e] {
                section.not_beyond_surface(&start.stress[e], sy)
            } else {
                start.stress[e]
            };
            let point = PointState {
                stress,
                plastic_strain: start.plastic_strain[e],
                plastic: start.plastic[e],
            };
            Some((e, integrate(section, &point, &problem.elements.strain(e, &du))))
        })
        .collect();
    for (e, out) in integrated {
        match out.yielded_at {
            Some(at) => start.yielded_at.insert(e, at),
            None => start.yielded_at.remove(&e),
        };
        state.stress[e] = out.end.stress;
        state.plastic_strain[e] = out.end.plastic_strain;
        state.plastic[e] = out.end.plastic;
    }
}

/// Plastic elements back onto their yield surfaces (the drift a held tangent left), then a
/// correction with every tangent renewed, which leaves only the square of that drift: a reload
/// then retraces the stage's end (elastic shakedown stays elastic), and an unload starts on the
/// surface. Repeated (at most `SETTLE_ROUNDS` times) until the drift is round-off at a stage's
/// end.
fn settle_on_surfaces<D: Dim>(
    eng: &mut Engine<D>,
    state: &mut State<D>,
    phi: f64,
    stage_end: bool,
) -> Result<Corrected> {
    let mut corrected = Corrected::default();
    for _ in 0..SETTLE_ROUNDS {
        for e in (0..state.plastic.len()).filter(|&e| state.plastic[e]) {
            let section = &eng.problem.sections[e];
            let sy = section.material.current_yield(state.plastic_strain[e]);
            state.stress[e] = section.onto_yield_surface(&state.stress[e], sy);
        }
        eng.stiffness.update(&eng.problem, state, Renewal::All, eng.clock)?;
        corrected.absorb(correct_at_fixed_load(eng, state, phi, None)?);
        if !stage_end || drift(&eng.problem, state) <= SETTLED_DRIFT {
            break;
        }
    }
    Ok(corrected)
}

/// Whether pair p's slip reverses in the correction `c` at φ beyond the solves' round-off (3D):
/// its slip rate along e above what the contact checks take for round-off of a displacement,
/// `GAP_ROUND_OFF` × the state's largest one. The correction's own noise floor is relative to
/// its size, and the correction of a switch's round-off jump (a rate problem's hand-back,
/// 1e-11 of the load) moves the contact DOFs by round-off: sticking pairs for that undid the
/// rate problem's slips, the next trial slipped them again at once, and the zero-length run
/// ended on the last resort (an elastic sphere pressed on a flat at μ = 0.3, 11.8k DOFs:
/// pairs stuck by corrections of 5e-14 mm at displacements of 1e-3 mm).
fn reverses<D: Dim>(
    eng: &Engine<D>,
    state: &State<D>,
    c: &TrialIncrement,
    p: usize,
    phi: f64,
) -> bool {
    let problem = &eng.problem;
    if state.space().is_none() {
        return false;
    }
    // (Plastic runs: drift corrections are not round-off; holding these switches there left
    // pairs beyond their cones, a Berkovich block at μ = 0.5 and a Vickers block at μ = 0.1.)
    if problem.model.has_plastic_material() {
        return true;
    }
    let e = state.slip_dir(p);
    let rate = events::slip_rate(&problem.pairs[p], &trial_of(c), p);
    e[0] * rate[0] + e[1] * rate[1]
        > GAP_ROUND_OFF * eng.loads.largest_displacement(problem, &state.u, phi)
}

/// Whether pair p's friction force stays within the contact checks' round-off of a force
/// (`FORCE_ROUND_OFF` × the force scale) of its capacity (its cone, or a slipping pair's
/// facet) over the whole correction `c` with its status held (3D): then its stick → slip or
/// facet turn is no event. A correction of a rate problem's hand-back (its jumps 1e-11–1e-7 of
/// the load) slipped at once the pairs the rate problem had stuck on their cones, and turned
/// by whole radians the facets of pairs that had just closed (λ_n ~ 1e-9 of the load), and the
/// next trial undid both (the frictional Hertz sphere at 22.6k and 15.4k DOFs).
fn within_round_off<D: Dim>(
    eng: &Engine<D>,
    state: &State<D>,
    c: &TrialIncrement,
    p: usize,
) -> bool {
    let problem = &eng.problem;
    if state.space().is_none() || problem.model.has_plastic_material() {
        return false;
    }
    let law = problem.pairs[p].friction;
    let excess = problem.friction_excess(state, p);
    let change = c.dlambda_t[p].hypot(c.dlambda_t2[p]) + law.polygon_capacity(c.dlambda_n[p].abs());
    excess + change <= FORCE_ROUND_OFF * problem.scales.force
}

/// 3D: a pair that begins to slip in the correction `c` at a vertex of its polygon (its force
/// there, `switching::onset_facet`) while its stuck force leaves through one side of that
/// vertex only slips on that side's facet: its force slides along that side, which at the
/// vertex (its force held along m) it cannot. There its slip rate may point along its force
/// (`Coulomb::vertex_exit`: it sticks), and stuck it leaves again at once: a cycle at zero
/// scale that nothing in the correction broke (the trial's go to the rate problem), so it ran
/// out of sub-steps and its last one stepped over the events left (the elastoplastic Vickers
/// block of test_friction_facets_3d at μ = 0.1, once the pairs at the pyramid's edges followed
/// its whole motion: one pair switched 31 times at φ = 0.031 of the unloading, and a gap that
/// closed at scale 7e-12 was left penetrating by 1e-6).
fn slide_off_vertex<D: Dim>(eng: &Engine<D>, state: &mut State<D>, c: &TrialIncrement, p: usize) {
    let problem = &eng.problem;
    if !state.at_vertex(p) {
        return;
    }
    let law = problem.pairs[p].friction;
    let rate = (c.dlambda_n[p], [c.dlambda_t[p], c.dlambda_t2[p]]);
    let leaving = |d: &[f64; 2]| law.outward_rate(*d, rate) > c.noise.force;
    let sides = [1.0, -1.0].map(|side| law.facet_of(state.slip_dir(p), side));
    let [e] = sides.iter().filter(|d| leaving(d)).collect::<Vec<_>>()[..] else { return };
    crate::trace!("correction: pair {p} slips off its vertex onto the facet {e:?}");
    let before = jumps_kept(eng, state).then(|| contact_forces(state));
    state.set_facet(p, *e, false);
    let now = state.lambda_t_of(p);
    state.set_lambda_t(p, problem.slip_force(state, p, now));
    if let Some(before) = before {
        keep_jumps(state, &before);
    }
}

/// Equilibrium at fixed load φ by the procedure itself: solve the correction for the
/// out-of-balance force (eq. 44 with no load change), advance it to the first contact event
/// that would make the state inadmissible (a gap closing, a pair separating, a stuck pair
/// reaching its cone: eqs. 48–53), switch that, and solve the rest again, so that the
/// corrected state is admissible. Returns the correction's size and its events, in order.
/// `internal`: the internal force of the state's stresses if the caller has it.
pub(super) fn correct_at_fixed_load<D: Dim>(
    eng: &mut Engine<D>,
    state: &mut State<D>,
    phi: f64,
    mut internal: Option<Vec<f64>>,
) -> Result<Corrected> {
    let mut corrected = Corrected::default();
    let unfrozen = vec![false; eng.problem.pairs.len()];
    for step in 0..MAX_CORRECTION_EVENTS {
        crate::interrupt::checkpoint(crate::interrupt::Checkpoint::Correction)?;
        let mut c = trial::solve(eng, state, Solve::Balance(phi), internal.take())?;
        if direct_new_slips(eng, state, &c).0 {
            c = trial::solve(eng, state, Solve::Balance(phi), None)?; // 3D: a slip begun at zero force took its direction
        }
        let mut cands =
            events::candidates(&pair_state(&eng.problem, state, &unfrozen), &trial_of(&c), c.noise);
        // A slip that reverses inside the correction leaves its force on the cone: the state
        // stays admissible, and sticking it would only cycle with the next increment; but in 3D,
        // where a facet's turn makes corrections frequent, it would move the pair along its
        // friction force (work produced: 0.035 % of the dissipated on the coarse Mindlin sphere),
        // so there it sticks, unless its reversal is round-off of the state (`reverses`).
        cands.retain(|x| {
            x.kind != EventKind::SlipToStick || reverses(eng, state, &c, x.entity, phi)
        });
        cands.retain(|x| {
            !matches!(x.kind, EventKind::StickToSlip | EventKind::SlipTurn)
                || !within_round_off(eng, state, &c, x.entity)
        });
        let first = cands.iter().map(|x| x.scale).fold(f64::INFINITY, f64::min);
        // The last allowed step takes the rest whatever it violates (the contact checks then
        // allow for the correction's size).
        let s = if step + 1 == MAX_CORRECTION_EVENTS { 1.0 } else { first.min(1.0) };
        corrected.size.include(&c, s);
        state.advance(&c, s);
        state.load_fraction = phi;
        if s >= 1.0 {
            break;
        }
        let tie = first * (1.0 + CORRECTION_TIE) + CORRECTION_TIE_SLACK;
        for x in cands.into_iter().filter(|x| x.scale <= tie) {
            switch_keeping(eng, state, &x);
            if x.kind == EventKind::StickToSlip {
                slide_off_vertex(eng, state, &c, x.entity);
            }
            corrected.events.push(x);
        }
    }
    Ok(corrected)
}
