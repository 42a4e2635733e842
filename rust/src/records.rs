//! What comes out of the engine: the event history, the increments, field snapshots, why the
//! run stopped, and where the time went. No Python types: the bindings translate.

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EventKind {
    Close,
    Separate,
    StickToSlip,
    SlipToStick,
    /// 3D: a slipping pair's friction force turned by `slip_turn` off its held slip direction,
    /// which turns to it (the facet of the round cone it slips on is re-laid at the force).
    SlipTurn,
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
            EventKind::SlipTurn => "slip_turn",
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
    /// The stage (0-based), the fraction of it applied, and path time t = stage + fraction.
    pub stage: usize,
    pub load_fraction: f64,
    pub time: f64,
    pub kind: EventKind,
    pub entity: usize,
}

#[derive(Debug, Clone)]
pub struct StepRecord {
    pub stage: usize,
    pub load_fraction: f64,
    pub time: f64,
    pub scale: f64,
    pub residual: f64,
    pub n_closed: usize,
    pub n_stick: usize,
    pub n_slip: usize,
    pub normal_force: f64,
    pub n_plastic: usize,
    /// Max |σe − σy(εp)| / σy(εp) over plastic elements at the end of the step, before return.
    pub drift: f64,
    /// Per contact (index into `Names::contacts`): the resultant of its pairs' forces on their
    /// contactor nodes, Σ_p (n λ_n + t1 λ_t1 + t2 λ_t2), in global axes (z = 0 in 2D). A rigid
    /// obstacle's force on the body; a two-body contact's on its contactor body (the target body
    /// takes the opposite).
    pub contact_force: Vec<[f64; 3]>,
    /// Per contact: the moment about the origin of those forces, each pair's at its contactor
    /// point (node a, or Σ c_i x_i over a weighted row's contactor nodes), in the undeformed
    /// coordinates (small strain); 2D: (0, 0, M_z).
    pub contact_moment: Vec<[f64; 3]>,
    /// Per support group (`Names::supports`): the force its DOFs exert on the body, Σ over them
    /// per component (P_σ − P − contact forces there, as a snapshot's `reaction`); NaN where
    /// not known: a contact sub-step of a grouped plastic increment, whose stresses are only
    /// integrated at the increment's end.
    pub reaction: Vec<[f64; 3]>,
    /// Per force pattern (`load`, then `Model::patterns`): P_j · u, its nodal forces at factor 1
    /// times the displacement (the work-conjugate displacement times |P_j|'s scale; 0 for a
    /// pattern without forces); NaN at contact sub-steps.
    pub load_work: Vec<f64>,
}

#[derive(Debug, Clone)]
pub struct Snapshot {
    pub stage: usize,
    pub load_fraction: f64,
    pub time: f64,
    /// DOFs per node (2 or 3).
    pub dim: usize,
    /// Displacement, dim per node.
    pub u: Vec<f64>,
    /// The six stress components (xx, yy, zz, yz, xz, xy) per element (2D: yz = xz = 0).
    pub stress: Vec<[f64; 6]>,
    pub plastic_strain: Vec<f64>,
    pub plastic: Vec<i8>,
    pub lambda_n: Vec<f64>,
    pub lambda_t: Vec<f64>,
    pub status: Vec<i8>,
    pub gap: Vec<f64>,
    pub rtd: Vec<f64>,
    /// 3D: λ_t and the RTD along each pair's second tangent t2 (empty in 2D).
    pub lambda_t2: Vec<f64>,
    pub rtd2: Vec<f64>,
    /// Support reactions, 2 per node: P_σ − P at fixed and prescribed DOFs (the force the
    /// supports exert on the body), 0 elsewhere.
    pub reaction: Vec<f64>,
}

/// Seconds per phase of the run. Each second counts once, in the innermost phase running (a
/// refactorization inside an equilibrium correction counts as factorization), but for the
/// phases `events` includes as noted.
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
    /// Event bookkeeping: scale factors, advancing, checks, snapshots, and the small dense
    /// systems, stress integration and corrections.
    pub events: f64,
    /// Low-rank updates of the factor: solving their columns, their capacitance (`low_rank`).
    pub low_rank: f64,
    /// Integrating the stresses of plastic elements (`stress_integration`; also in `events`).
    pub integration: f64,
    /// Equilibrium corrections after integrated increments (also in `events`).
    pub corrections: f64,
    /// One forward + backward substitution with one right-hand side on the first factor
    /// (the unit of the amortized cost of an event).
    pub solve_pair: f64,
}

/// Why the event loop stopped.
#[derive(Debug, Clone, PartialEq)]
pub enum StopReason {
    /// The whole load is applied (S = 1 reached, paper §4 step 8).
    Completed,
    /// `Options::stop_at_first_yield`: stopped at the first yield event.
    FirstYield,
    /// The current stiffness of the remaining load fell below `Options::limit_stiffness` of
    /// the initial one: a plastic mechanism (collapse). The `load_fraction` of the stops is the
    /// path time t (= the load fraction for a single stage).
    LimitLoad { load_fraction: f64, stiffness_ratio: f64 },
    /// `Options::max_events` increments were taken; `busiest` names the entities that switched
    /// most often.
    EventBound { load_fraction: f64, max_steps: usize, busiest: String },
    /// A body held by contact lost its hold along the path: its remaining closed pairs would
    /// not hold it even sticking (it lifts off or tips), or they all slip under a tangential
    /// load beyond friction's capacity (it slides as a whole), so no equilibrium exists beyond.
    /// `stage`: "stage 'NAME'"; `what`: the body, its motion, the point it turns about; `fix`.
    SupportLost { load_fraction: f64, stage: String, what: String, fix: String },
    /// The progress callback asked to stop (Ctrl-C).
    Interrupted { load_fraction: f64 },
    /// The run failed at path time `load_fraction` (a lost equilibrium, an ill-posed scene, an
    /// engine bug): the results up to the last completed increment are kept.
    Failed { load_fraction: f64, error: crate::error::Error },
}

impl StopReason {
    pub fn name(&self) -> &'static str {
        match self {
            StopReason::Completed => "completed",
            StopReason::FirstYield => "first_yield",
            StopReason::LimitLoad { .. } => "limit_load",
            StopReason::EventBound { .. } => "event_bound",
            StopReason::SupportLost { .. } => "support_lost",
            StopReason::Interrupted { .. } => "interrupted",
            StopReason::Failed { .. } => "failed",
        }
    }

    /// A one-line explanation with the fix, for stops before the whole load.
    pub fn message(&self) -> Option<String> {
        match self {
            StopReason::LimitLoad { load_fraction, stiffness_ratio } => Some(format!("limit load reached at load fraction {load_fraction:.6}: the current stiffness fell to {stiffness_ratio:.1e} of the initial one (a plastic mechanism); the results up to there are kept: lower the load, or add hardening (H > 0)")),
            StopReason::EventBound { load_fraction, max_steps, busiest } => Some(format!("the event loop reached max_events = {max_steps} increments at load fraction {load_fraction:.6} (most switching: {busiest}); the results up to there are kept: raise solver.max_events or coarsen the mesh")),
            StopReason::SupportLost { load_fraction, stage, what, fix } => Some(format!("support lost at t = {load_fraction:.6} ({stage}): {what}; no equilibrium exists beyond this load; the results up to there are kept: {fix}")),
            StopReason::Interrupted { load_fraction } => Some(format!("interrupted at load fraction {load_fraction:.6}; the results up to there are kept")),
            StopReason::Failed { error, .. } => Some(error.message.clone()),
            StopReason::Completed | StopReason::FirstYield => None,
        }
    }
}

#[derive(Debug, Clone)]
pub struct RunResult {
    /// DOFs per node (2 or 3).
    pub dim: usize,
    pub stage_names: Vec<String>,
    pub events: Vec<EventRecord>,
    pub steps: Vec<StepRecord>,
    pub snapshots: Vec<Snapshot>,
    pub closure_fraction: Vec<f64>,
    pub predicted_closure: Vec<f64>,
    pub max_equilibrium_residual: f64,
    pub max_drift: f64,
    pub n_factorizations: usize,
    /// Factors built from a new structure: 1, or with `factorization = "condensed"` its far
    /// factor's builds (the first and one per growth of the near region).
    pub n_factor_builds: usize,
    /// Tangent changes taken as low-rank terms on the last factor instead of a refactorization.
    pub n_low_rank_updates: usize,
    pub n_solves: usize,
    /// Steps taken as contact sub-steps of a grouped plastic increment (no full-space solve).
    pub n_contact_substeps: usize,
    /// Grouped plastic increments that could not be balanced, retaken event by event.
    pub n_retaken_windows: usize,
    /// How many zero-length runs the rate problem (Lemke) resolved.
    pub n_rate_problems: usize,
    pub stop: StopReason,
    pub timings: Timings,
}

/// What the driver reports while it runs; the callback returns `false` to stop (Ctrl-C).
#[derive(Debug, Clone, Copy)]
pub struct Progress {
    pub steps: usize,
    pub events: usize,
    /// Path time t (the load fraction for a single stage).
    pub t: f64,
}
