//! What goes into the engine (a scene reduced to arrays) and what comes out (the event
//! history and field snapshots). No Python types: the bindings translate.

use crate::bail;
use crate::error::Result;
use crate::material::{Material, Plane};
use crate::mesh::Mesh;

/// A candidate contact pair as given by the front end (see `contact::Pair`).
#[derive(Debug, Clone)]
pub struct PairInput {
    pub node_a: usize,
    pub node_b: Option<usize>,
    pub normal: [f64; 2],
    pub gap: f64,
    pub mu: f64,
}

#[derive(Debug, Clone)]
pub enum SnapshotRequest {
    /// A snapshot at the start and after every event.
    EveryEvent,
    /// Snapshots at exactly these load fractions (interpolated on the piecewise-linear path);
    /// the final state is always added.
    Fractions(Vec<f64>),
}

#[derive(Debug, Clone)]
pub struct Options {
    pub snapshots: SnapshotRequest,
    /// Events whose scale factors lie within S_min·(1 + tie_tol) are applied together.
    pub tie_tol: f64,
    /// Event grouping δ, the speed–accuracy knob (0 = the paper's procedure): besides the ties,
    /// the friction (stick↔slip) and plasticity (yield, unload) events predicted at load
    /// fractions φ ≤ φ_min (1 + δ) are taken early, at φ_min, in the same increment (see
    /// `driver`).
    pub group_tol: f64,
    /// Upper bound on the number of increments (0 = automatic: 50 per pair and element + 1000).
    pub max_steps: usize,
    /// Largest relative equilibrium residual accepted at an event.
    pub equilibrium_tol: f64,
    /// How many times a pair may change status within one zero-length run of events before
    /// it is frozen until the load advances (anti-cycling rule, see `driver`).
    pub max_zero_length_switches: usize,
    /// Drift control for plastic elements (false = the paper exactly).
    pub drift_control: bool,
    /// With drift control: largest stress change of a plastic element per increment, × σy.
    pub max_stress_step: f64,
    /// Stop at the first yield event (the load capacity at the onset of plasticity).
    pub stop_at_first_yield: bool,
    /// Elastic runs keep only contact-DOF values between events (see `driver`); false forces
    /// the general path (for cross-checks).
    pub reduced_elastic: bool,
    /// Stop at a limit load: when the current stiffness of the remaining load falls below this
    /// fraction of the initial one (plastic collapse).
    pub limit_stiffness: f64,
}

impl Options {
    /// Reject option values that would make the run meaningless (NaN tolerances, snapshot
    /// fractions outside (0, 1]), naming the option and the fix.
    pub fn validate(&self) -> Result<()> {
        if !(self.tie_tol.is_finite() && self.tie_tol >= 0.0) {
            bail!("options.tie_tol = {} is not allowed: give a finite tolerance >= 0 (default 1e-9)", self.tie_tol);
        }
        if !(self.group_tol.is_finite() && (0.0..1.0).contains(&self.group_tol)) {
            bail!("options.group_tol = {} is not allowed: give a relative load window in [0, 1) (0 = the exact event procedure, the default; 1e-3 to 1e-1 trade accuracy for speed)", self.group_tol);
        }
        if !(self.equilibrium_tol.is_finite() && self.equilibrium_tol > 0.0) {
            bail!("options.equilibrium_tol = {} is not allowed: give a finite tolerance > 0 (default 1e-9)", self.equilibrium_tol);
        }
        if !(self.limit_stiffness.is_finite() && (0.0..1.0).contains(&self.limit_stiffness)) {
            bail!("options.limit_stiffness = {} is not allowed: give a fraction in [0, 1) of the initial stiffness (0 disables the limit-load stop; default 1e-3)", self.limit_stiffness);
        }
        if !(self.max_stress_step.is_finite() && self.max_stress_step > 0.0) {
            bail!("options.max_stress_step = {} is not allowed: give a finite fraction of Sy > 0 (default 0.05)", self.max_stress_step);
        }
        if let SnapshotRequest::Fractions(f) = &self.snapshots {
            if let Some(bad) = f.iter().find(|v| !(v.is_finite() && **v > 0.0 && **v <= 1.0)) {
                bail!("options.fractions: {bad} is not allowed: snapshot load fractions must lie in (0, 1]");
            }
        }
        Ok(())
    }
}

impl Default for Options {
    fn default() -> Self {
        Options {
            snapshots: SnapshotRequest::EveryEvent,
            tie_tol: 1e-9,
            group_tol: 0.0,
            max_steps: 0,
            equilibrium_tol: 1e-9,
            max_zero_length_switches: 4,
            drift_control: true,
            max_stress_step: 0.05,
            stop_at_first_yield: false,
            reduced_elastic: true,
            limit_stiffness: 1e-3,
        }
    }
}

#[derive(Debug, Clone)]
pub struct Model {
    pub mesh: Mesh,
    pub element_material: Vec<usize>,
    pub materials: Vec<Material>,
    pub plane: Plane,
    pub thickness: f64,
    /// DOFs with u = 0 (2·node + component).
    pub fixed_dofs: Vec<usize>,
    /// Total nodal load at load fraction 1 (length 2·nodes).
    pub load: Vec<f64>,
    pub pairs: Vec<PairInput>,
    pub options: Options,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EventKind {
    Close,
    Separate,
    StickToSlip,
    SlipToStick,
    /// Anti-cycling: the pair was frozen in its status for the rest of a zero-length run.
    Frozen,
    /// An elastic element reaches the yield surface (S_p, eq. 16).
    Yield,
    /// A plastic element unloads elastically.
    Unload,
    /// Anti-cycling for an element.
    FrozenElement,
}

impl EventKind {
    pub fn name(self) -> &'static str {
        match self {
            EventKind::Close => "close",
            EventKind::Separate => "separate",
            EventKind::StickToSlip => "stick_to_slip",
            EventKind::SlipToStick => "slip_to_stick",
            EventKind::Frozen => "frozen",
            EventKind::Yield => "yield",
            EventKind::Unload => "unload",
            EventKind::FrozenElement => "frozen_element",
        }
    }

    pub fn is_element_event(self) -> bool {
        matches!(self, EventKind::Yield | EventKind::Unload | EventKind::FrozenElement)
    }
}

#[derive(Debug, Clone)]
pub struct EventRecord {
    pub step: usize,
    pub load_fraction: f64,
    pub kind: EventKind,
    pub entity: usize,
}

#[derive(Debug, Clone)]
pub struct StepRecord {
    pub load_fraction: f64,
    pub scale: f64,
    pub residual: f64,
    pub n_closed: usize,
    pub n_stick: usize,
    pub n_slip: usize,
    pub normal_force: f64,
    pub n_plastic: usize,
    /// Max |σe − σy(εp)| / σy(εp) over plastic elements at the end of the step, before return.
    pub drift: f64,
}

#[derive(Debug, Clone)]
pub struct Snapshot {
    pub load_fraction: f64,
    /// Displacement, 2 per node.
    pub u: Vec<f64>,
    /// σx, σy, σz, τxy per element.
    pub stress: Vec<[f64; 4]>,
    pub plastic_strain: Vec<f64>,
    pub plastic: Vec<i8>,
    pub lambda_n: Vec<f64>,
    pub lambda_t: Vec<f64>,
    pub status: Vec<i8>,
    pub gap: Vec<f64>,
    pub rtd: Vec<f64>,
}

#[derive(Debug, Clone, Default)]
pub struct Timings {
    pub assembly: f64,
    pub factorization: f64,
    /// Reading the contact flexibility from the factor's trailing block (dense, per factor).
    pub flexibility: f64,
    /// Triangular solves (trial, corrections, snapshots).
    pub solves: f64,
    /// The small dense contact systems (also counted in `events`).
    pub dense: f64,
    /// Event bookkeeping: scale factors, advancing, checks, the small dense systems.
    pub events: f64,
    /// One forward + backward substitution with one right-hand side on the first factor
    /// (the unit of the amortized cost of an event).
    pub solve_pair: f64,
}

#[derive(Debug, Clone)]
pub struct RunResult {
    pub events: Vec<EventRecord>,
    pub steps: Vec<StepRecord>,
    pub snapshots: Vec<Snapshot>,
    pub closure_fraction: Vec<f64>,
    pub predicted_closure: Vec<f64>,
    pub max_equilibrium_residual: f64,
    pub max_drift: f64,
    pub n_factorizations: usize,
    pub n_solves: usize,
    pub interrupted: bool,
    /// Why the run stopped before load fraction 1 other than Ctrl-C (e.g. the event bound).
    pub stop_reason: Option<String>,
    pub timings: Timings,
}

/// What the driver reports while it runs; the callback returns `false` to stop (Ctrl-C).
#[derive(Debug, Clone, Copy)]
pub struct Progress {
    pub steps: usize,
    pub events: usize,
    pub load_fraction: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_with_nan_or_out_of_range_values_are_refused() {
        assert!(Options::default().validate().is_ok());
        let bad = [
            Options { tie_tol: f64::NAN, ..Options::default() },
            Options { tie_tol: -1.0, ..Options::default() },
            Options { group_tol: f64::NAN, ..Options::default() },
            Options { group_tol: 1.0, ..Options::default() },
            Options { equilibrium_tol: f64::NAN, ..Options::default() },
            Options { max_stress_step: 0.0, ..Options::default() },
            Options { snapshots: SnapshotRequest::Fractions(vec![0.5, f64::NAN]), ..Options::default() },
            Options { snapshots: SnapshotRequest::Fractions(vec![0.0]), ..Options::default() },
            Options { snapshots: SnapshotRequest::Fractions(vec![1.5]), ..Options::default() },
        ];
        for o in bad {
            let err = o.validate().unwrap_err().0;
            assert!(err.starts_with("options.") && err.contains("is not allowed"), "{err}");
        }
    }
}
