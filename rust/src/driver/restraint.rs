//! Is every body held? A free rigid-body mode that no closed pair resists makes the small
//! system singular: say which body, which motion, and why — a missing support (free body), or
//! friction that cannot hold the tangential load (gross sliding: the body's closed pairs all
//! slip, and sticking would hold it).
//!
//! Between increments (`hold`) the same rows tell two states the small system cannot solve
//! apart from a missing support. A body whose remaining closed pairs would not hold it even if
//! they all stuck has lost its support along the path (its last pairs separated: it lifts off
//! or tips about its last closed pair): there is no equilibrium beyond, and the run stops there
//! like at a limit load, keeping its results. A body whose closed pairs all slip along a motion
//! that sticking would hold rests on friction alone: its rigid motion along that direction,
//! which decides where the slip changes sense and which pair sticks there, is not in the small
//! system; the rate problem, which has it, decides the statuses (`switch_statuses`).

use super::loads::StageLoads;
use super::planar_sliding;
use super::problem::Problem;
use super::state::{State, TrialIncrement};
use crate::bail;
use crate::contact::SparseVec;
use crate::contact::Status;
use crate::coulomb::MeanCoulomb;
use crate::dim::Dim;
use crate::error::Result;
use crate::model::{EventKind, EventRecord, StopReason};
use crate::rigid_modes::describe;
use nalgebra::DMatrix;

/// A singular value of Cᵀ N below this × the largest is a motion no closed pair resists.
const FREE_MOTION: f64 = 1e-9;
/// T within this (relative) of μ̄N is not gross sliding: the body is at the limit, not beyond.
const CAPACITY_TIE: f64 = 1e-9;
/// Unit normals whose dot product is within this of 1 are parallel (pairs on one plane).
const PARALLEL: f64 = 1e-9;
/// A tangential load below this × Σ|load| is round-off (of a moment of the other loads, say).
const LOAD_ROUND_OFF: f64 = 1e-9;

/// How the closed pairs hold the bodies that have free rigid modes (see the module text).
pub(super) enum Hold {
    /// By supports, closed normals and sticking pairs.
    Held,
    /// A body's closed pairs all slip along a motion that sticking would hold, under a load
    /// friction can hold.
    OnFriction,
    /// A body lifts off, tips, or slides as a whole: the run's stop.
    Lost(StopReason),
}

/// How the closed pairs hold the bodies at a state; `events`: the history so far (to name the
/// last pair that separated from a body that lifts off).
pub(super) fn hold<D: Dim>(
    problem: &Problem<D>,
    loads: &StageLoads,
    state: &State<D>,
    events: &[EventRecord],
) -> Hold {
    Restraint { p: problem, loads }.hold(state, events)
}

/// Check, per body with free rigid modes, that the closed pairs' rows Cᵀ N (columns m.. of the
/// small system `a`, whose first m rows are the closed pairs' constraints) have full column
/// rank; else name the body, its free motion and why (a missing support, gross sliding).
/// `mode_rhs`: the small system's rigid-body rows −Nᵀ r; `closed_normals`: the pairs of its
/// normal rows.
/// Returns the idle free motions where slips turn (`Dim::SLIP_TURNS`), over all modes:
/// unresisted, but neither loaded nor moved by any force of the system (a pressed body turning
/// about the normal while its pairs, all slipping at zero force, have no direction yet to hold
/// it by): the caller holds them still (α along them = 0), as nothing drives them.
pub(super) fn check_restrained<D: Dim>(
    problem: &Problem<D>,
    loads: &StageLoads,
    state: &State<D>,
    a: &DMatrix<f64>,
    m: usize,
    mode_rhs: &[f64],
    closed_normals: impl Fn() -> Vec<usize>,
) -> Result<Vec<Vec<f64>>> {
    Restraint { p: problem, loads }.check_restrained(state, a, m, mode_rhs, closed_normals)
}

/// 3D: the stage fraction in (φ, 1] at which the load of a body held by friction alone
/// (`friction_held`) reaches the limit of its pairs (`planar_sliding`): its force in the
/// contact plane and moment about the normal, linear in the trial's scale as the pairs' normal
/// forces λ_n + S Δλ_n are, meet what friction forces within μλ_n can balance, whatever the
/// pairs' statuses and slip directions; no equilibrium exists beyond (the increment is cut
/// there, `friction_stop` stops the run). With no moment this is |T| = μN. None when no body
/// is so held or its load stays inside.
pub(super) fn friction_limit<D: Dim>(
    problem: &Problem<D>,
    loads: &StageLoads,
    state: &State<D>,
    trial: &TrialIncrement,
) -> Option<f64> {
    let r = Restraint { p: problem, loads };
    let phi = state.load_fraction;
    let limit = r
        .friction_held(state)
        .filter_map(|plane| {
            let contact = plane.contact(problem, |p| [state.lambda_n[p], trial.dlambda_n[p]]);
            let (start, end) = (r.wrench(&plane, phi), r.wrench(&plane, 1.0));
            let change = [end[0] - start[0], end[1] - start[1], end[2] - start[2]];
            planar_sliding::first_reach(&contact, start, change)
                .map(|l| phi + l.scale * (1.0 - phi))
        })
        .filter(|&s| s > phi && s <= 1.0)
        .reduce(f64::min);
    limit
}

/// The run's stop where the load of a body held by friction alone has reached the limit of
/// its pairs (`friction_limit`'s fraction reached): it slides as a whole, turning about a
/// centre in the contact plane when the load has a moment about it.
pub(super) fn friction_stop<D: Dim>(
    problem: &Problem<D>,
    loads: &StageLoads,
    state: &State<D>,
) -> Option<StopReason> {
    let r = Restraint { p: problem, loads };
    let stop = r.friction_held(state).find_map(|plane| {
        let contact = plane.contact(problem, |p| [state.lambda_n[p], 0.0]);
        let load = r.wrench(&plane, state.load_fraction);
        let limit = planar_sliding::proportional(&contact, load)?;
        let size = load[0].hypot(load[1]) + load[2].abs() * plane.size;
        (limit.scale <= 1.0 + CAPACITY_TIE && size > LOAD_ROUND_OFF * problem.scales.force).then(|| {
            let name = problem.model.body_name(problem.bodies.first_element[plane.body]);
            let what = format!("{name} slides as a whole{}", r.limit_words(&plane, &contact, load, &limit, state));
            StopReason::SupportLost { load_fraction: state.time(), stage: problem.model.stage_label(state.stage), what, fix: "lower the tangential load or its moment about the contact normal, raise mu, or add a support (fix/symmetry)".into() }
        })
    });
    stop
}

/// A body's load against the friction of its closed pairs, for the check of gross sliding
/// (`Restraint::sliding_load`): T, the tangential load; N, the normal load along their mean
/// normal; μ̄N, what their friction holds together (`MeanCoulomb`); `under`: which load it is,
/// in the message's words.
struct SlidingLoad {
    tangential: f64,
    normal: f64,
    capacity: f64,
    under: &'static str,
}

/// A body held by friction alone on one plane (`Restraint::friction_held`): its closed pairs,
/// the plane's unit normal n (towards the body) and basis (t1, t2, t1 × t2 = n), the centre of
/// its pairs and their largest distance from it, the unit of `planar_sliding`'s lengths.
struct FrictionPlane {
    body: usize,
    pairs: Vec<usize>,
    normal: [f64; 3],
    basis: [[f64; 3]; 2],
    centre: [f64; 3],
    size: f64,
}

impl FrictionPlane {
    fn new<D: Dim>(problem: &Problem<D>, body: usize, pairs: Vec<usize>, normal: [f64; 3]) -> Self {
        let basis = crate::contact::Frame::in_space(normal, None).tangents;
        let points: Vec<[f64; 3]> = pairs.iter().map(|&p| contact_point(problem, p)).collect();
        let centre = points
            .iter()
            .fold([0.0; 3], |c, x| [c[0] + x[0], c[1] + x[1], c[2] + x[2]])
            .map(|c| c / points.len() as f64);
        let size = points
            .iter()
            .map(|x| norm(&[x[0] - centre[0], x[1] - centre[1], x[2] - centre[2]]))
            .fold(0.0, f64::max);
        FrictionPlane {
            body,
            pairs,
            normal,
            basis,
            centre,
            size: if size > 0.0 { size } else { 1.0 },
        }
    }

    /// In-plane coordinates of a point about the centre, in units of `size`.
    fn coordinates(&self, x: [f64; 3]) -> [f64; 2] {
        let d = [x[0] - self.centre[0], x[1] - self.centre[1], x[2] - self.centre[2]];
        [along(&d, &self.basis[0]) / self.size, along(&d, &self.basis[1]) / self.size]
    }

    /// The point of in-plane coordinates `c`.
    fn point(&self, c: [f64; 2]) -> [f64; 3] {
        let [a, b] = self.basis;
        [0, 1, 2].map(|k| self.centre[k] + self.size * (c[0] * a[k] + c[1] * b[k]))
    }

    /// The pairs' positions and capacities μ λ_n (at S = 0 and its rate) from `normal_force`
    /// (λ_n and Δλ_n of a pair).
    fn contact<D: Dim>(
        &self,
        problem: &Problem<D>,
        normal_force: impl Fn(usize) -> [f64; 2],
    ) -> planar_sliding::Contact {
        let at = self.pairs.iter().map(|&p| self.coordinates(contact_point(problem, p))).collect();
        let capacity = self
            .pairs
            .iter()
            .map(|&p| {
                let ([ln, dln], law) = (normal_force(p), problem.pairs[p].friction);
                [law.capacity(ln), law.capacity_rate(dln)]
            })
            .collect();
        planar_sliding::Contact { at, capacity }
    }
}

/// Where pair p acts on its contactor: its node, or the weighted mean of its contactor nodes.
fn contact_point<D: Dim>(problem: &Problem<D>, p: usize) -> [f64; 3] {
    let input = &problem.model.pairs[p];
    let mesh = &problem.model.mesh;
    let contactor: Vec<(usize, f64)> =
        input.weights.iter().copied().filter(|&(_, c)| c > 0.0).collect();
    if contactor.is_empty() {
        return mesh.point(input.node_a);
    }
    let total: f64 = contactor.iter().map(|c| c.1).sum();
    contactor.iter().fold([0.0; 3], |x, &(i, c)| {
        let y = mesh.point(i);
        [0, 1, 2].map(|k| x[k] + c / total * y[k])
    })
}

/// The bodies of a problem under the current stage's loads.
struct Restraint<'a, D: Dim> {
    p: &'a Problem<'a, D>,
    loads: &'a StageLoads,
}

impl<D: Dim> Restraint<'_, D> {
    fn hold(&self, state: &State<D>, events: &[EventRecord]) -> Hold {
        let mut hold = Hold::Held;
        for (body, idx) in self.bodies_with_modes() {
            let slides = free_motions(&self.closed_rows(state, &idx, false), idx.len());
            if slides.is_empty() {
                continue;
            }
            let name = self.p.model.body_name(self.p.bodies.first_element[body]);
            let free = free_motions(&self.closed_rows(state, &idx, true), idx.len());
            let (what, fix) = if !free.is_empty() {
                (
                    self.lifted_or_tipped(&name, state, body, &idx, &free, events),
                    "lower the load, or add a support (fix/symmetry) that holds the body",
                )
            } else if let Some(load) = self.beyond_capacity(body, state, &idx, &slides[0]) {
                let push: f64 =
                    idx.iter().zip(&slides[0]).map(|(&k, c)| c * self.loads.mode_force[k][1]).sum();
                (
                    format!(
                        "{name} slides as a whole {}",
                        self.sliding(Some(push), &self.describe_motion(&idx, &slides[0]), &load)
                    ),
                    "lower the tangential load, raise mu, or add a support (fix/symmetry)",
                )
            } else {
                hold = Hold::OnFriction;
                continue;
            };
            return Hold::Lost(StopReason::SupportLost {
                load_fraction: state.time(),
                stage: self.p.model.stage_label(state.stage),
                what,
                fix: fix.into(),
            });
        }
        hold
    }

    /// The bodies with free rigid modes, and the indices of their modes.
    fn bodies_with_modes(&self) -> Vec<(usize, Vec<usize>)> {
        let mut bodies: Vec<usize> = self.p.bodies.modes.iter().map(|md| md.body).collect();
        bodies.dedup();
        bodies
            .into_iter()
            .map(|b| {
                (
                    b,
                    (0..self.p.bodies.modes.len())
                        .filter(|&k| self.p.bodies.modes[k].body == b)
                        .collect(),
                )
            })
            .collect()
    }

    /// The rows w·N_k (k in `idx`) of the closed pairs' constraints: their normals and the
    /// tangents of the sticking frictional pairs (`if_stuck`: of every frictional one).
    fn closed_rows(&self, state: &State<D>, idx: &[usize], if_stuck: bool) -> Vec<Vec<f64>> {
        let row = |w: &SparseVec| {
            idx.iter().map(|&k| w.dot(&self.p.bodies.mode_vectors[k])).collect::<Vec<f64>>()
        };
        let mut rows = vec![];
        for (p, pair) in
            self.p.pairs.iter().enumerate().filter(|(p, _)| state.status[*p].is_closed())
        {
            rows.push(row(&pair.w_n));
            if pair.frictional() && (if_stuck || state.status[p] == Status::Stick) {
                rows.extend(pair.free_tangents().map(|(_, t)| row(&t.w)));
            } else if let Some(cross) = self.p.cross_direction(state, p) {
                rows.push(row(&pair.along_tangent(cross))); // a 3D slip holds across its direction
            }
        }
        rows
    }

    /// How a body no closed pair would hold even sticking left its support: lifted off (the
    /// last pair it left named), tipped about its one closed pair, or free along `free`.
    fn lifted_or_tipped(
        &self,
        name: &str,
        state: &State<D>,
        body: usize,
        idx: &[usize],
        free: &[Vec<f64>],
        events: &[EventRecord],
    ) -> String {
        let closed: Vec<usize> = (0..self.p.pairs.len())
            .filter(|&p| state.status[p].is_closed() && self.p.body_of_pair(p) == body)
            .collect();
        let last_left = events
            .iter()
            .rev()
            .find(|e| e.kind == EventKind::Separate && self.p.body_of_pair(e.entity) == body);
        match closed.as_slice() {
            [] => format!("{name} lifts off: its last closed pair{} separated, and the load moves it away from the contact", last_left.map_or(String::new(), |e| format!(" ({})", self.p.model.pair_name(e.entity)))),
            [p] => format!("{name} tips about {}, its last closed pair: the other pairs separated, and the load turns the body about that point", self.p.model.pair_name(*p)),
            _ => {
                let words: Vec<String> = free.iter().map(|v| self.describe_motion(idx, v)).collect();
                format!("{name} is free to move ({}): its {} closed pairs do not hold it in that direction, even sticking", words.join("; "), closed.len())
            }
        }
    }

    fn check_restrained(
        &self,
        state: &State<D>,
        a: &DMatrix<f64>,
        m: usize,
        mode_rhs: &[f64],
        closed_normals: impl Fn() -> Vec<usize>,
    ) -> Result<Vec<Vec<f64>>> {
        let mut idle = vec![];
        for (body, idx) in self.bodies_with_modes() {
            let rows_n: Vec<Vec<f64>> =
                (0..m).map(|i| idx.iter().map(|&k| a[(i, m + k)]).collect()).collect();
            let free = free_motions(&rows_n, idx.len());
            if free.is_empty() {
                continue;
            }
            if D::SLIP_TURNS && free.iter().all(|v| self.is_idle(a, m, mode_rhs, &idx, v)) {
                idle.extend(free.iter().map(|v| {
                    let mut all = vec![0.0; mode_rhs.len()];
                    idx.iter().zip(v).for_each(|(&k, c)| all[k] = *c);
                    all
                }));
                continue;
            }
            let words: Vec<String> = free.iter().map(|v| self.describe_motion(&idx, v)).collect();
            let slip_rows = self.slip_rows(state, body, &idx);
            let held_if_stuck = !slip_rows.is_empty()
                && free_motions(&[rows_n.as_slice(), slip_rows.as_slice()].concat(), idx.len())
                    .is_empty();
            let name = self.p.model.body_name(self.p.bodies.first_element[body]);
            if held_if_stuck {
                if let Some(load) = self.beyond_capacity(body, state, &idx, &free[0]) {
                    // −Nᵀ r along the motion is the out-of-balance force nothing holds.
                    let push: f64 = idx.iter().zip(&free[0]).map(|(&k, c)| -c * mode_rhs[k]).sum();
                    // where slips turn, the free motions together (the load in the contact
                    // plane picks the direction)
                    let (push, motion) = if D::SLIP_TURNS && free.len() > 1 {
                        (None, words.join("; "))
                    } else {
                        (Some(push), words[0].clone())
                    };
                    bail!(GrossSliding, "{name} slides as a whole at load fraction {:.6} of {} {}: lower the tangential load, raise mu, or add a support", state.load_fraction, self.p.path.stage_names[state.stage], self.sliding(push, &motion, &load));
                }
                bail!(FreeBody, "{name} is free to move ({}): its {} closed contact pair(s) slip or are frictionless, so they do not hold it in that direction, and no support does; add a support (fix/symmetry) there", words.join("; "), slip_rows.len());
            }
            if let Some(what) = self.left_at_once(state, body, &words) {
                bail!(FreeBody, "{name} {what}, and nothing else holds it; add a support (fix/symmetry) that does, or change the load");
            }
            let closed =
                closed_normals().into_iter().filter(|&p| self.p.body_of_pair(p) == body).count();
            bail!(FreeBody, "{name} is free to move ({}): it has no support in that direction and its {closed} closed contact pair(s) do not hold it; add a support (fix/symmetry) or start a contact closed (gap 0)", words.join("; "));
        }
        Ok(idle)
    }

    /// The rows w_t·N_k (k in `idx`) of the tangents of the body's slipping pairs: in the plane
    /// a pair's one tangent, held or not; in space its free ones.
    fn slip_rows(&self, state: &State<D>, body: usize, idx: &[usize]) -> Vec<Vec<f64>> {
        let tangents = |p: usize| {
            let pair = &self.p.pairs[p];
            match pair.tangents.as_slice() {
                [t] => vec![&t.w],
                _ => pair.free_tangents().map(|(_, t)| &t.w).collect(),
            }
        };
        self.slipping_pairs_of(body, state)
            .flat_map(tangents)
            .map(|w| idx.iter().map(|&k| w.dot(&self.p.bodies.mode_vectors[k])).collect())
            .collect()
    }

    /// Whether a free motion `v` of the body's modes `idx` is idle: no load along it (−Nᵀ r
    /// at round-off) and no force column of the small system with a share along it (Nᵀ E).
    fn is_idle(
        &self,
        a: &DMatrix<f64>,
        m: usize,
        mode_rhs: &[f64],
        idx: &[usize],
        v: &[f64],
    ) -> bool {
        let along =
            |row: &dyn Fn(usize) -> f64| idx.iter().zip(v).map(|(&k, c)| c * row(k)).sum::<f64>();
        let loaded = along(&|k| mode_rhs[k]).abs() > LOAD_ROUND_OFF * self.p.scales.force;
        let moved = (0..m).any(|j| {
            let size = idx.iter().map(|&k| a[(m + k, j)].abs()).fold(0.0, f64::max);
            along(&|k| a[(m + k, j)]).abs() > FREE_MOTION * size.max(f64::MIN_POSITIVE)
        });
        !loaded && !moved
    }

    /// Before any load (t = 0), a body some of whose pairs started closed (gap 0) and separated
    /// at once: how it leaves its support (lifts off, along the load's direction; tips about its
    /// one closed pair; or moves along `words`), naming the contacts. None otherwise.
    fn left_at_once(&self, state: &State<D>, body: usize, words: &[String]) -> Option<String> {
        if state.time() != 0.0 {
            return None;
        }
        let touching = self.p.scales.touching();
        let of_body: Vec<usize> =
            (0..self.p.pairs.len()).filter(|&p| self.p.body_of_pair(p) == body).collect();
        let mut left: Vec<usize> = of_body
            .iter()
            .filter(|&&p| self.p.pairs[p].gap0 <= touching && !state.status[p].is_closed())
            .map(|&p| self.p.model.pairs[p].contact)
            .collect();
        left.sort_unstable();
        left.dedup();
        let names: Vec<String> = left
            .iter()
            .map(|&c| {
                self.p
                    .model
                    .names
                    .contacts
                    .get(c)
                    .map_or_else(|| "the contact".to_string(), |n| format!("contact '{n}'"))
            })
            .collect();
        let contacts = names.join(" and ");
        let closed: Vec<usize> =
            of_body.into_iter().filter(|&p| state.status[p].is_closed()).collect();
        let at = "at the first instant (t = 0)";
        match closed.as_slice() {
            _ if names.is_empty() => None,
            [] => {
                let force = self.body_load(body);
                let size = norm(&force);
                let direction: Vec<String> = force.iter().map(|f| format!("{:.3}", f / size)).collect();
                let pull = if size > LOAD_ROUND_OFF * self.p.scales.force { format!("pulls the body away from it along ({})", direction.join(", ")) } else { "turns the body off it".to_string() };
                Some(format!("lifts off {at}: {contacts} {} closed (gap 0), but the load {pull}", if names.len() == 1 { "starts" } else { "start" }))
            }
            [p] => Some(format!("tips about {} {at}: the other pairs of {contacts} start closed (gap 0) but separate at once, and the load turns the body about that point", self.p.model.pair_name(*p))),
            _ => Some(format!("is free to move ({}) {at}: pairs of {contacts} start closed (gap 0) but separate at once, and its {} closed pairs do not hold it in that direction", words.join("; "), closed.len())),
        }
    }

    fn slipping_pairs_of<'a>(
        &'a self,
        body: usize,
        state: &'a State<D>,
    ) -> impl Iterator<Item = usize> + 'a {
        // Frictionless closed pairs (Slip with μ = 0) slip too: they hold no tangential load.
        (0..self.p.pairs.len()).filter(move |&p| {
            matches!(state.status[p], Status::Slip { .. })
                && !self.p.pairs[p].tangent_held()
                && self.p.body_of_pair(p) == body
        })
    }

    /// Words for a combination `v` of the body's modes `idx`.
    fn describe_motion(&self, idx: &[usize], v: &[f64]) -> String {
        describe(&self.motion_weights(idx, v))
    }

    /// The weights of the elementary motions (translations, rotations: `rigid_modes`) of a
    /// combination `v` of the body's modes `idx`.
    fn motion_weights(&self, idx: &[usize], v: &[f64]) -> Vec<f64> {
        let mut w = vec![0.0; D::RIGID_MODES];
        for (c, &k) in idx.iter().enumerate() {
            for (wl, ml) in w.iter_mut().zip(&self.p.bodies.modes[k].weights) {
                *wl += v[c] * ml;
            }
        }
        w
    }

    /// The body's load against the friction of its closed pairs (`SlidingLoad`): where it can
    /// turn about their normal (`Dim::TURNS_ABOUT_A_NORMAL`: a turn has no translation to read
    /// T along) its part in the contact plane at the fraction checked, else its part along the
    /// sliding translation under the stage's end load.
    fn sliding_load(&self, body: usize, state: &State<D>, idx: &[usize], v: &[f64]) -> SlidingLoad {
        let closed: Vec<usize> = (0..self.p.pairs.len())
            .filter(|&p| state.status[p].is_closed() && self.p.body_of_pair(p) == body)
            .collect();
        let pairs = self.p.global_pairs();
        let normal: Vec<f64> = (0..D::N)
            .map(|k| {
                closed.iter().map(|&p| pairs[p].normal[k]).sum::<f64>() / closed.len().max(1) as f64
            })
            .collect();
        let friction = MeanCoulomb::of(closed.iter().map(|&p| &pairs[p].friction));
        let ((tangential, n), under) = if D::TURNS_ABOUT_A_NORMAL {
            (
                self.load_in_contact_plane(body, state, &normal),
                "under the load at that fraction (the stage's, where none is applied yet)",
            )
        } else {
            let force = self.body_load(body);
            let t = along(&force, &self.translation_of(idx, v)).abs();
            ((t, along(&force, &normal).abs()), "under the stage's full load")
        };
        SlidingLoad { tangential, normal: n, capacity: friction.capacity(n), under }
    }

    /// (T, N) of a body's load on the plane of the mean `normal` of its closed pairs: the load
    /// at the fraction checked (its remaining change where it is zero there, as before any
    /// load: the ratio of T to N is what friction holds or not), T its size in the plane.
    fn load_in_contact_plane(&self, body: usize, state: &State<D>, normal: &[f64]) -> (f64, f64) {
        let now = self.body_load_at(body, state.load_fraction);
        let force = if norm(&now) > LOAD_ROUND_OFF * self.p.scales.force {
            now
        } else {
            self.body_load(body).iter().zip(&now).map(|(e, s)| e - s).collect()
        };
        let n = along(&force, normal);
        let unit =
            normal.iter().map(|c| c / norm(normal).max(f64::MIN_POSITIVE)).collect::<Vec<f64>>();
        let tangential: Vec<f64> = force.iter().zip(&unit).map(|(f, u)| f - n * u).collect();
        (norm(&tangential), n.abs())
    }

    /// 3D bodies held by nothing but their closed pairs (all six rigid modes free: no support
    /// takes a share of the load), all frictional and on one plane (parallel normals). Their
    /// friction forces lie in that plane and are bounded by μ λ_n each whatever their statuses,
    /// so a load in the plane beyond what such forces balance (`planar_sliding`; without a
    /// moment: T beyond μN) has no equilibrium.
    fn friction_held<'s>(
        &'s self,
        state: &'s State<D>,
    ) -> impl Iterator<Item = FrictionPlane> + 's {
        self.bodies_with_modes()
            .into_iter()
            .filter(|(_, idx)| D::TURNS_ABOUT_A_NORMAL && idx.len() == D::RIGID_MODES)
            .filter_map(move |(body, _)| {
                let closed: Vec<usize> = (0..self.p.pairs.len())
                    .filter(|&p| state.status[p].is_closed() && self.p.body_of_pair(p) == body)
                    .collect();
                let normal = |p: usize| self.p.global_pairs()[p].normal;
                let n = normal(*closed.first()?);
                let on_plane = |p: &usize| {
                    let m = normal(*p);
                    n[0] * m[0] + n[1] * m[1] + n[2] * m[2] >= 1.0 - PARALLEL
                };
                if !closed.iter().all(|&p| self.p.pairs[p].frictional())
                    || !closed.iter().all(on_plane)
                {
                    return None;
                }
                Some(FrictionPlane::new(self.p, body, closed, n))
            })
    }

    /// A body's load at stage fraction s on its friction plane: the force along the plane's
    /// basis and the moment about the normal through its centre, over its size.
    fn wrench(&self, plane: &FrictionPlane, s: f64) -> planar_sliding::Wrench {
        let nodes =
            (0..self.p.bodies.of_node.len()).filter(|&i| self.p.bodies.of_node[i] == plane.body);
        let n = plane.normal;
        nodes.fold([0.0; 3], |w, i| {
            let f: Vec<f64> = (0..3).map(|k| self.loads.load.force(3 * i + k, s)).collect();
            let x = self.p.model.mesh.point(i);
            let r = [0, 1, 2].map(|k| x[k] - plane.centre[k]);
            let moment = n[0] * (r[1] * f[2] - r[2] * f[1])
                + n[1] * (r[2] * f[0] - r[0] * f[2])
                + n[2] * (r[0] * f[1] - r[1] * f[0]);
            [
                w[0] + along(&f, &plane.basis[0]),
                w[1] + along(&f, &plane.basis[1]),
                w[2] + moment / plane.size,
            ]
        })
    }

    /// ": …" of a body at the limit of its friction plane: the centre it turns about and the
    /// load's moment there against the pairs' friction moment, or (a translation) its
    /// tangential load against μN.
    fn limit_words(
        &self,
        plane: &FrictionPlane,
        contact: &planar_sliding::Contact,
        load: planar_sliding::Wrench,
        limit: &planar_sliding::Limit,
        state: &State<D>,
    ) -> String {
        let (t, n_load) = self.resultants(plane.body, &plane.normal, state.load_fraction);
        let t = t[0].hypot(t[1]);
        let capacity: f64 = contact.capacity.iter().map(|c| c[0]).sum();
        let Some(c) = limit.centre() else {
            return format!(": its tangential load T = {t:.4e} has reached the friction capacity of its closed pairs, μN = {capacity:.4e} (N = {n_load:.4e} along the contact normal)");
        };
        // moments about the centre: the load's, and the pairs' friction against their velocities
        let moment = (load[2] - (c[0] * load[1] - c[1] * load[0])) * plane.size;
        let resisted: f64 = contact
            .at
            .iter()
            .zip(&contact.capacity)
            .map(|(r, k)| k[0] * (r[0] - c[0]).hypot(r[1] - c[1]))
            .sum::<f64>()
            * plane.size;
        let x = plane.point(c);
        format!(", turning about ({:.4}, {:.4}, {:.4}) in the contact plane: its load there, the tangential force T = {t:.4e} and the moment {moment:.4e} about that point along the contact normal, has reached the limit of its closed pairs' friction, all slipping about that point (their moment there Σ μλ_n r = {resisted:.4e}; μN = {capacity:.4e}, N = {n_load:.4e})", x[0], x[1], x[2])
    }

    /// A body's load at stage fraction s resolved on the unit normal n: its components in a
    /// basis of the contact plane, and the compressive part along −n.
    fn resultants(&self, body: usize, n: &[f64; 3], s: f64) -> ([f64; 2], f64) {
        let f = self.body_load_at(body, s);
        let [t1, t2] = crate::contact::Frame::in_space(*n, None).tangents;
        ([along(&f, &t1), along(&f, &t2)], -along(&f, n))
    }

    /// The resultant (x, y[, z]) of the stage's end load on a body.
    fn body_load(&self, body: usize) -> Vec<f64> {
        self.body_load_at(body, 1.0)
    }

    /// The resultant (x, y[, z]) of the load on a body at stage fraction s.
    fn body_load_at(&self, body: usize, s: f64) -> Vec<f64> {
        let dim = D::N;
        let nodes = (0..self.p.bodies.of_node.len()).filter(|&i| self.p.bodies.of_node[i] == body);
        nodes.fold(vec![0.0; dim], |f, i| {
            (0..dim).map(|k| f[k] + self.loads.load.force(dim * i + k, s)).collect()
        })
    }

    /// The body's `sliding_load` when T exceeds the capacity μ̄N: gross sliding.
    fn beyond_capacity(
        &self,
        body: usize,
        state: &State<D>,
        idx: &[usize],
        v: &[f64],
    ) -> Option<SlidingLoad> {
        let load = self.sliding_load(body, state, idx, v);
        let t = load.tangential;
        (t > load.capacity * (1.0 + CAPACITY_TIE) && t > LOAD_ROUND_OFF * self.p.scales.force)
            .then_some(load)
    }

    /// "(±motion): …" of gross sliding, the sense that of `push`, the load along the motion
    /// (None: motions named together, no sense).
    fn sliding(&self, push: Option<f64>, words: &str, load: &SlidingLoad) -> String {
        let sense = match push {
            Some(p) if p >= 0.0 => "+",
            Some(_) => "−",
            None => "",
        };
        let SlidingLoad { tangential: t, normal: n, capacity, under } = load;
        format!("({sense}{words}): its closed pairs all slip; {under} the tangential load T = {t:.4e} exceeds the friction capacity μN = {capacity:.4e} (N = {n:.4e} along the contact normal)")
    }

    /// The translation part (x, y[, z]) of a combination `v` of the body's modes `idx`.
    fn translation_of(&self, idx: &[usize], v: &[f64]) -> Vec<f64> {
        let mut w = self.motion_weights(idx, v);
        w.truncate(D::N);
        w
    }
}

/// |v| (hypot in 2D).
fn norm(v: &[f64]) -> f64 {
    match v {
        [x, y] => x.hypot(*y),
        _ => v.iter().map(|c| c * c).sum::<f64>().sqrt(),
    }
}

/// The component of `force` along `dir` (not necessarily unit).
fn along(force: &[f64], dir: &[f64]) -> f64 {
    force.iter().zip(dir).map(|(f, d)| f * d).sum::<f64>() / norm(dir).max(f64::MIN_POSITIVE)
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
