//! The evolving state of the procedure (eqs. 59–62), one trial increment (eq. 44), and the
//! element state at the start of an increment whose stresses were integrated.

use crate::contact::{Pair, Shift, Status};
use crate::dim::{Dim, InSpace};
use crate::events::Noise;
use crate::material::Voigt;
use std::collections::HashMap;

/// Everything that changes along the load path: accumulated displacement, stresses and
/// contact forces, and the statuses (open / stick / slip per pair, elastic / plastic per
/// element). What only space has (the second tangent, the facets) is `space`, which in the plane
/// holds nothing (`Dim::OnlyInSpace`).
#[derive(Clone)]
pub(super) struct State<D: Dim> {
    /// The stage (0-based) and the fraction s of it applied (the paper's load fraction for a
    /// single stage); path time t = stage + s.
    pub stage: usize,
    pub load_fraction: f64,
    /// Displacement over the DOFs the loop carries (`Space`).
    pub u: Vec<f64>,
    /// The six stress components per element (2D: yz = xz = 0; empty in the reduced elastic
    /// space).
    pub stress: Vec<Voigt>,
    pub plastic_strain: Vec<f64>,
    pub lambda_n: Vec<f64>,
    /// λ_t along the first tangent (t in the plane, t1 in space).
    pub lambda_t: Vec<f64>,
    /// Rigid-body amplitudes (tracked in the reduced elastic space only).
    pub alpha: Vec<f64>,
    pub status: Vec<Status>,
    /// RTD at which each stick pair stuck: its tangential constraint holds RTD there (eq. 39).
    pub rtd_stick: Vec<f64>,
    pub plastic: Vec<bool>,
    /// Per pair: the gap and RTD shift (c_n, c_t1, c_t2) of its obstacle's motion (`path`).
    pub shift: Vec<Shift>,
    /// The pairs' state in space.
    pub space: D::OnlyInSpace<PairsInSpace>,
}

/// What a pair's state holds only in space, per pair.
#[derive(Clone, Debug)]
pub(super) struct PairsInSpace {
    /// λ_t and the stuck RTD along the second tangent t2.
    pub lambda_t2: Vec<f64>,
    pub rtd_stick2: Vec<f64>,
    /// The held direction e (along t1, t2; unit) of a slipping pair's friction force,
    /// λ_t = μ λ_n e (`contact`'s module text).
    pub slip_dir: Vec<[f64; 2]>,
    /// A slipping pair whose facet the rate problem laid (`rate_problem::hold_slip_directions`):
    /// it holds its cross row from zero normal force on, as the rate problem's facet did.
    pub facet_laid: Vec<bool>,
    /// A slipping pair at the vertex `slip_dir` = m of two facets (`coulomb`): its force is
    /// μ λ_n / cos(slip_turn) along m, both facets hold, it slips within slip_turn of −m.
    pub vertex: Vec<bool>,
    /// Reduced space: the contact force jumps (Δλ_n, Δλ_t1, Δλ_t2) not yet rebalanced. The full
    /// space reads their out-of-balance force W Δλ from its residual; the reduced one carries it
    /// here for the trials, and an increment by S leaves (1 − S) of it, as of any out-of-balance
    /// force (`switching::keep_jumps`). Zero elsewhere.
    pub jumps: Vec<[f64; 3]>,
}

impl PairsInSpace {
    fn new(n_pairs: usize) -> Self {
        PairsInSpace {
            lambda_t2: vec![0.0; n_pairs],
            rtd_stick2: vec![0.0; n_pairs],
            slip_dir: vec![[0.0; 2]; n_pairs],
            facet_laid: vec![false; n_pairs],
            vertex: vec![false; n_pairs],
            jumps: vec![[0.0; 3]; n_pairs],
        }
    }
}

impl<D: Dim> State<D> {
    /// The start of the path (paper §4): zero load; pairs with zero initial gap (receding or
    /// conforming contact) start closed, in stick when frictional.
    pub fn initial(
        pairs: &[Pair],
        n_dofs: usize,
        n_elements: usize,
        n_modes: usize,
        gap_tol: f64,
    ) -> Self {
        let n_pairs = pairs.len();
        State {
            stage: 0,
            load_fraction: 0.0,
            u: vec![0.0; n_dofs],
            stress: vec![Voigt::zeros(); n_elements],
            plastic_strain: vec![0.0; n_elements],
            lambda_n: vec![0.0; n_pairs],
            lambda_t: vec![0.0; n_pairs],
            alpha: vec![0.0; n_modes],
            status: pairs
                .iter()
                .map(|p| if p.gap0 <= gap_tol { p.closed_status() } else { Status::Open })
                .collect(),
            rtd_stick: vec![0.0; n_pairs],
            plastic: vec![false; n_elements],
            shift: vec![[0.0; 3]; n_pairs],
            space: D::OnlyInSpace::new(|| PairsInSpace::new(n_pairs)),
        }
    }

    /// The pairs' state in space; None in the plane.
    pub fn space(&self) -> Option<&PairsInSpace> {
        self.space.get()
    }

    pub fn space_mut(&mut self) -> Option<&mut PairsInSpace> {
        self.space.get_mut()
    }

    /// λ_t of pair p along (t1, t2) (t2: 0 in the plane).
    pub fn lambda_t_of(&self, p: usize) -> [f64; 2] {
        [self.lambda_t[p], self.space.get().map_or(0.0, |s| s.lambda_t2[p])]
    }

    /// Set λ_t of pair p along (t1, t2) (in the plane only the first).
    pub fn set_lambda_t(&mut self, p: usize, lambda_t: [f64; 2]) {
        self.lambda_t[p] = lambda_t[0];
        if let Some(s) = self.space.get_mut() {
            s.lambda_t2[p] = lambda_t[1];
        }
    }

    /// (λ_n, λ_t1, λ_t2) of pair p.
    pub fn contact_force(&self, p: usize) -> [f64; 3] {
        let [t1, t2] = self.lambda_t_of(p);
        [self.lambda_n[p], t1, t2]
    }

    /// The held direction e of pair p's friction, and whether it is at a vertex (`PairsInSpace`);
    /// ([0, 0], false) in the plane.
    pub fn slip_dir(&self, p: usize) -> [f64; 2] {
        self.space.get().map_or([0.0; 2], |s| s.slip_dir[p])
    }

    pub fn at_vertex(&self, p: usize) -> bool {
        self.space.get().is_some_and(|s| s.vertex[p])
    }

    /// Pair p's friction on the facet (or vertex) e (space only; nothing in the plane).
    pub fn set_facet(&mut self, p: usize, e: [f64; 2], vertex: bool) {
        if let Some(s) = self.space.get_mut() {
            (s.slip_dir[p], s.vertex[p]) = (e, vertex);
        }
    }

    /// The RTD pair p stuck at along (t1, t2) (t2: 0 in the plane).
    pub fn rtd_stick_of(&self, p: usize) -> [f64; 2] {
        [self.rtd_stick[p], self.space.get().map_or(0.0, |s| s.rtd_stick2[p])]
    }

    /// Pair p sticks at the RTD `rtd` along (t1, t2) (in the plane only the first).
    pub fn stick_at(&mut self, p: usize, rtd: [f64; 2]) {
        self.rtd_stick[p] = rtd[0];
        if let Some(s) = self.space.get_mut() {
            s.rtd_stick2[p] = rtd[1];
        }
    }

    pub fn facet_laid(&self, p: usize) -> bool {
        self.space.get().is_some_and(|s| s.facet_laid[p])
    }

    /// Path time t = stage + s.
    pub fn time(&self) -> f64 {
        self.stage as f64 + self.load_fraction
    }

    /// At the start of stage k (s = 0).
    pub fn begin_stage(&mut self, k: usize) {
        self.stage = k;
        self.load_fraction = 0.0;
    }

    pub fn n_closed(&self) -> usize {
        self.status.iter().filter(|s| s.is_closed()).count()
    }

    pub fn n_stick(&self) -> usize {
        self.status.iter().filter(|s| **s == Status::Stick).count()
    }

    pub fn n_plastic(&self) -> usize {
        self.plastic.iter().filter(|&&p| p).count()
    }

    /// state += s × increment (eqs. 58–61); plastic strain grows only where it flows.
    pub fn advance(&mut self, inc: &TrialIncrement, s: f64) {
        self.u.iter_mut().zip(&inc.du).for_each(|(u, d)| *u += s * d);
        self.stress.iter_mut().zip(&inc.dstress).for_each(|(u, d)| *u += s * d);
        for e in 0..self.plastic_strain.len() {
            if self.plastic[e] {
                self.plastic_strain[e] += s * inc.dplastic[e].max(0.0);
            }
        }
        self.advance_forces(inc, s);
    }

    /// λ, α and the obstacle shifts += s × increment; (1 − s) of the unbalanced jumps remain.
    pub fn advance_forces(&mut self, inc: &TrialIncrement, s: f64) {
        if let Some(space) = self.space.get_mut() {
            for jump in space.jumps.iter_mut().filter(|j| **j != [0.0; 3]) {
                *jump = jump.map(|v| (1.0 - s) * v);
            }
            space.lambda_t2.iter_mut().zip(&inc.dlambda_t2).for_each(|(u, d)| *u += s * d);
        }
        self.lambda_n.iter_mut().zip(&inc.dlambda_n).for_each(|(u, d)| *u += s * d);
        self.lambda_t.iter_mut().zip(&inc.dlambda_t).for_each(|(u, d)| *u += s * d);
        self.alpha.iter_mut().zip(&inc.dalpha).for_each(|(u, d)| *u += s * d);
        for (c, d) in self.shift.iter_mut().zip(&inc.dshift) {
            c[0] += s * d[0];
            c[1] += s * d[1];
            c[2] += s * d[2];
        }
    }
}

/// One trial increment towards a target load fraction (eq. 44 in residual form).
pub(super) struct TrialIncrement {
    pub du: Vec<f64>,
    pub dstress: Vec<Voigt>,
    /// Equivalent plastic strain increment (negative: the element would unload).
    pub dplastic: Vec<f64>,
    pub dlambda_n: Vec<f64>,
    pub dlambda_t: Vec<f64>,
    /// 3D: along t2 (empty in 2D).
    pub dlambda_t2: Vec<f64>,
    pub dalpha: Vec<f64>,
    /// Change of every pair's obstacle shift (c_n, c_t) (`path`).
    pub dshift: Vec<Shift>,
    /// The rates below which this increment's changes are round-off (its Δu's and the forces').
    pub noise: Noise,
}

/// The state of the elements and the displacement at the start of an increment whose stresses
/// were integrated (`advance`): the re-integration starts from it (`plasticity`), a retaken
/// window returns to it (`window`), and it tells which elements yielded inside.
pub(super) struct IncrementStart {
    pub stress: Vec<Voigt>,
    pub plastic_strain: Vec<f64>,
    pub plastic: Vec<bool>,
    pub u: Vec<f64>,
    /// Where in the increment each element that crossed its surface did so (the latest
    /// integration's elastic fraction).
    pub yielded_at: HashMap<usize, f64>,
}

impl IncrementStart {
    /// The element arrays and displacement of `state`, before its increment.
    pub fn of<D: Dim>(state: &State<D>) -> Self {
        IncrementStart {
            stress: state.stress.clone(),
            plastic_strain: state.plastic_strain.clone(),
            plastic: state.plastic.clone(),
            u: state.u.clone(),
            yielded_at: Default::default(),
        }
    }
}
