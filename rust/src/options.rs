//! The solver options, declared once.
//!
//! [`SPECS`] is the one declaration of every knob: its key (the same in a case's `[solver]`
//! table, in the engine's `options` dict and here), its kind, its default, the values it
//! allows and what it means. [`Options::default`] takes its defaults from there, [`Options::set`]
//! reads a value by key and checks it against its spec, and the bindings hand `SPECS` to Python
//! (`_engine.option_specs()`), whose case schema builds its `[solver]` table from them.

use crate::bail;
use crate::error::Result;

/// What a value of an option is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kind {
    /// A real number.
    Real,
    /// A count (a non-negative integer).
    Count,
    /// A switch.
    Flag,
    /// One of these names (the spec's default: the index of its name).
    Choice(&'static [&'static str]),
}

/// One end of an option's allowed range: the value and whether it is allowed itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct End {
    pub value: f64,
    pub inclusive: bool,
}

const fn at_least(value: f64) -> Option<End> {
    Some(End { value, inclusive: true })
}
const fn above(value: f64) -> Option<End> {
    Some(End { value, inclusive: false })
}
const fn below(value: f64) -> Option<End> {
    Some(End { value, inclusive: false })
}
const fn at_most(value: f64) -> Option<End> {
    Some(End { value, inclusive: true })
}

/// The declaration of one option.
#[derive(Debug, Clone, Copy)]
pub struct Spec {
    pub key: &'static str,
    pub kind: Kind,
    /// The default (a flag: 0 or 1).
    pub default: f64,
    pub min: Option<End>,
    pub max: Option<End>,
    pub doc: &'static str,
}

/// Default of `group_tol`: chosen by measurement (bench/results.md). Largest plastic strain
/// difference to the event-by-event run at δ = 0.01 / 0.02 / 0.03 / 0.05: thick cylinder (H' = 0)
/// 0.45 / 0.39 / 0.15 / 0.14 %, Hertz load–unload 0.74 / 1.08 / 1.07 / 1.40 % (its stresses
/// 0.05 / 0.07 / 0.10 / 0.42 %); elastoplastic Hertz p0 unchanged to 1e-5; the 24.5k Hertz runs
/// ~27 % faster at 0.03 than at 0.01.
pub const DEFAULT_GROUP_TOL: f64 = 0.03;
/// Default of `tangent_turn` (radians).
pub const DEFAULT_TANGENT_TURN: f64 = 0.05;

/// Default of `slip_turn` (radians): see rust/src/contact.rs for its measured error.
pub const DEFAULT_SLIP_TURN: f64 = 0.1;

/// Default of `near_hops`: the element layers around the contact DOFs in the condensed
/// factorization's first region (`factor::condensed`).
pub const DEFAULT_NEAR_HOPS: usize = 8;

/// Which backend factorizes K (`crate::factor`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Factorization {
    /// faer's supernodal Cholesky in-process.
    Faer,
    /// PETSc's MUMPS, distributed over the MPI ranks of `mpirun`.
    Mumps,
    /// faer's Cholesky of the region near the contact, the far field's kept (`factor::condensed`).
    Condensed,
}

impl Factorization {
    /// The names a case gives, in the order of the variants.
    pub const NAMES: &'static [&'static str] = &["faer", "mumps", "condensed"];
    const ALL: [Factorization; 3] =
        [Factorization::Faer, Factorization::Mumps, Factorization::Condensed];
}

/// Every option, in the order the key tables list them.
pub const SPECS: &[Spec] = &[
    Spec { key: "tie_tol", kind: Kind::Real, default: 1e-9, min: at_least(0.0), max: None, doc: "events whose scale factors lie within S_min (1 + tie_tol) are applied together" },
    Spec { key: "group_tol", kind: Kind::Real, default: DEFAULT_GROUP_TOL, min: at_least(0.0), max: below(1.0), doc: "grouped plastic increments, the speed-accuracy knob (0 = the paper's procedure, event by event): an increment of a plastic run runs on past the first yield it predicts by group_tol of the load fraction reached; every element that yields inside it gets the exact split of its strain increment" },
    Spec { key: "max_events", kind: Kind::Count, default: 0.0, min: at_least(0.0), max: None, doc: "stop after this many increments (0 = an automatic bound: 50 per pair and element + 1000)" },
    Spec { key: "equilibrium_tol", kind: Kind::Real, default: 1e-9, min: above(0.0), max: None, doc: "largest relative equilibrium residual accepted at an event" },
    Spec { key: "drift_control", kind: Kind::Flag, default: 1.0, min: None, max: None, doc: "plasticity: integrate the stresses of plastic elements along each increment and restore equilibrium with a correction (false = the paper exactly: D_ep at the increment's start, linear stresses)" },
    Spec { key: "max_stress_step", kind: Kind::Real, default: 0.05, min: above(0.0), max: None, doc: "plasticity with drift control: largest von Mises stress change of a plastic element per increment, x Sy" },
    Spec { key: "tangent_turn", kind: Kind::Real, default: DEFAULT_TANGENT_TURN, min: at_least(0.0), max: at_most(std::f64::consts::FRAC_PI_2), doc: "plasticity with drift control: a plastic element's tangent in the stiffness is renewed when its flow direction has turned by more than this angle (radians; 0 = at every increment, as the paper)" },
    Spec { key: "slip_turn", kind: Kind::Real, default: DEFAULT_SLIP_TURN, min: above(0.0), max: at_most(std::f64::consts::FRAC_PI_2), doc: "3D friction: once a pair slips, its friction is on the polygon of N sides circumscribed about the round Coulomb cone, laid at the slip's onset (N even, the sides pi/N <= this angle (radians) from its vertices); a slipping pair moving from a side to a vertex or on to the next side is a slip_turn event: the force lags the slip by at most this angle and exceeds the round cone by at most 1/cos(angle) - 1 of mu lambda_n" },
    Spec { key: "stop_at_first_yield", kind: Kind::Flag, default: 0.0, min: None, max: None, doc: "plasticity: end the run right after the first yield event" },
    Spec { key: "limit_stiffness", kind: Kind::Real, default: 1e-3, min: at_least(0.0), max: below(1.0), doc: "stop at a limit load when the current stiffness of the remaining load falls below this fraction of the initial one (0 = never)" },
    Spec { key: "max_zero_length_switches", kind: Kind::Count, default: 4.0, min: at_least(1.0), max: None, doc: "switches of one pair or element within a zero-length run of events before the rate problem sets the statuses (anti-cycling)" },
    Spec { key: "reduced_elastic", kind: Kind::Flag, default: 1.0, min: None, max: None, doc: "elastic runs carry only the contact DOFs between events (false: the general path, for cross-checks)" },
    Spec { key: "factorization", kind: Kind::Choice(Factorization::NAMES), default: 0.0, min: None, max: None, doc: "the factorization of the stiffness: \"faer\" (in-process sparse Cholesky) or \"mumps\" (PETSc's MUMPS, the factor distributed over the MPI ranks of `mpirun -n N slipstep run ...`, for scenes whose factor outgrows one process; needs PETSc with MUMPS, Debian's python3-petsc4py; every rank runs the same event loop, rank 0 writes the results) or \"condensed\" (faer's Cholesky of the region near the contact, the far field's factor and its condensed coupling kept between refactorizations: plastic runs refactorize only that region)" },
    Spec { key: "near_hops", kind: Kind::Count, default: DEFAULT_NEAR_HOPS as f64, min: at_least(0.0), max: None, doc: "factorization = \"condensed\": the region refactorized holds the equations within this many element layers of the contact DOFs; it grows by as many layers, and by at least half its size, around any element outside it whose tangent changes" },
];

/// The spec of `key`.
pub fn spec(key: &str) -> Option<&'static Spec> {
    SPECS.iter().find(|s| s.key == key)
}

/// A value given for an option.
#[derive(Debug, Clone)]
pub enum Value {
    Real(f64),
    Count(i64),
    Flag(bool),
    Choice(String),
}

#[derive(Debug, Clone)]
pub enum SnapshotRequest {
    /// A snapshot at the start and after every event.
    EveryEvent,
    /// Snapshots at exactly these path times t (stage k runs over [k − 1, k]; interpolated on
    /// the piecewise-linear path); the final state is always added.
    Times(Vec<f64>),
}

/// The solver options of a run (see [`SPECS`] for each one's meaning and default).
#[derive(Debug, Clone)]
pub struct Options {
    pub snapshots: SnapshotRequest,
    pub tie_tol: f64,
    pub group_tol: f64,
    pub max_events: usize,
    pub equilibrium_tol: f64,
    pub drift_control: bool,
    pub max_stress_step: f64,
    pub tangent_turn: f64,
    pub slip_turn: f64,
    pub stop_at_first_yield: bool,
    pub limit_stiffness: f64,
    pub max_zero_length_switches: usize,
    pub reduced_elastic: bool,
    pub factorization: Factorization,
    pub near_hops: usize,
}

impl Default for Options {
    /// Every option at its declared default, snapshots at every event.
    fn default() -> Self {
        let mut o = Options {
            snapshots: SnapshotRequest::EveryEvent,
            tie_tol: 0.0,
            group_tol: 0.0,
            max_events: 0,
            equilibrium_tol: 0.0,
            drift_control: false,
            max_stress_step: 0.0,
            tangent_turn: 0.0,
            slip_turn: 0.0,
            stop_at_first_yield: false,
            limit_stiffness: 0.0,
            max_zero_length_switches: 0,
            reduced_elastic: false,
            factorization: Factorization::Faer,
            near_hops: 0,
        };
        for s in SPECS {
            o.field(s.key).expect("every spec names a field").set(s.default);
        }
        o
    }
}

impl Options {
    /// Set option `key` from a value given by the caller, checked against its spec: an unknown
    /// key, a value of another kind or outside the allowed range is an input error naming the
    /// key, the range and the default.
    pub fn set(&mut self, key: &str, value: Value) -> Result<()> {
        let Some(spec) = spec(key) else {
            let keys: Vec<&str> = SPECS.iter().map(|s| s.key).collect();
            bail!(Input, "options.{key} is not an option: the options are {}", keys.join(", "));
        };
        let v = match (spec.kind, value) {
            (Kind::Real, Value::Real(x)) => x,
            (Kind::Real | Kind::Count, Value::Count(n)) => n as f64,
            (Kind::Flag, Value::Flag(b)) => f64::from(u8::from(b)),
            (Kind::Choice(names), Value::Choice(name)) => {
                match names.iter().position(|n| *n == name) {
                    Some(i) => i as f64,
                    None => bail!(
                        Input,
                        "options.{key} = {name:?} is not allowed: give {} (default {})",
                        spec.kind_text(),
                        spec.default_text()
                    ),
                }
            }
            _ => bail!(
                Input,
                "options.{key}: give {} (default {})",
                spec.kind_text(),
                spec.default_text()
            ),
        };
        spec.check(v)?;
        self.field(key).expect("every spec names a field").set(v);
        Ok(())
    }

    /// Every option within its spec's range (for options built in Rust, field by field).
    pub fn validate(&self) -> Result<()> {
        let mut o = self.clone();
        SPECS
            .iter()
            .try_for_each(|s| s.check(o.field(s.key).expect("every spec names a field").get()))
    }

    /// Snapshot times must lie on the path, in (0, number of stages].
    pub(crate) fn validate_times(&self, n_stages: usize) -> Result<()> {
        if let SnapshotRequest::Times(f) = &self.snapshots {
            if let Some(bad) =
                f.iter().find(|v| !(v.is_finite() && **v > 0.0 && **v <= n_stages as f64))
            {
                bail!(Input, "options.times: {bad} is not allowed: snapshot times must lie in (0, {n_stages}] (stage k runs over t in [k-1, k])");
            }
        }
        Ok(())
    }

    /// The field of `key`, as a number (a flag: 0 or 1).
    fn field(&mut self, key: &str) -> Option<Field<'_>> {
        Some(match key {
            "tie_tol" => Field::Real(&mut self.tie_tol),
            "group_tol" => Field::Real(&mut self.group_tol),
            "max_events" => Field::Count(&mut self.max_events),
            "equilibrium_tol" => Field::Real(&mut self.equilibrium_tol),
            "drift_control" => Field::Flag(&mut self.drift_control),
            "max_stress_step" => Field::Real(&mut self.max_stress_step),
            "tangent_turn" => Field::Real(&mut self.tangent_turn),
            "slip_turn" => Field::Real(&mut self.slip_turn),
            "stop_at_first_yield" => Field::Flag(&mut self.stop_at_first_yield),
            "limit_stiffness" => Field::Real(&mut self.limit_stiffness),
            "max_zero_length_switches" => Field::Count(&mut self.max_zero_length_switches),
            "reduced_elastic" => Field::Flag(&mut self.reduced_elastic),
            "factorization" => Field::Factorization(&mut self.factorization),
            "near_hops" => Field::Count(&mut self.near_hops),
            _ => return None,
        })
    }
}

/// A field of [`Options`] seen as a number.
enum Field<'a> {
    Real(&'a mut f64),
    Count(&'a mut usize),
    Flag(&'a mut bool),
    Factorization(&'a mut Factorization),
}

impl Field<'_> {
    fn get(&self) -> f64 {
        match self {
            Field::Real(x) => **x,
            Field::Count(x) => **x as f64,
            Field::Flag(x) => f64::from(u8::from(**x)),
            Field::Factorization(x) => {
                Factorization::ALL.iter().position(|f| f == *x).expect("every variant is listed")
                    as f64
            }
        }
    }

    fn set(self, v: f64) {
        match self {
            Field::Real(x) => *x = v,
            Field::Count(x) => *x = v as usize,
            Field::Flag(x) => *x = v != 0.0,
            Field::Factorization(x) => *x = Factorization::ALL[v as usize],
        }
    }
}

impl Spec {
    /// A value within the spec's range (and whole, for a count), or the input error naming the
    /// key, the range and the default.
    pub fn check(&self, v: f64) -> Result<()> {
        let above_min = self.min.is_none_or(|e| v > e.value || (e.inclusive && v == e.value));
        let below_max = self.max.is_none_or(|e| v < e.value || (e.inclusive && v == e.value));
        let whole = self.kind != Kind::Count || v.fract() == 0.0;
        let named = match self.kind {
            Kind::Choice(names) => v.fract() == 0.0 && v >= 0.0 && v < names.len() as f64,
            _ => true,
        };
        if !(v.is_finite() && above_min && below_max && whole && named) {
            bail!(
                Input,
                "options.{} = {v} is not allowed: give {} (default {})",
                self.key,
                self.kind_text(),
                self.default_text()
            );
        }
        Ok(())
    }

    /// "a number in [0, 1)", "a count >= 1", "true or false".
    pub fn kind_text(&self) -> String {
        let what = match self.kind {
            Kind::Real => "a number",
            Kind::Count => "a count",
            Kind::Flag => return "true or false".into(),
            Kind::Choice(names) => {
                return format!(
                    "one of {}",
                    names.iter().map(|n| format!("{n:?}")).collect::<Vec<_>>().join(", ")
                )
            }
        };
        match (self.min, self.max) {
            (Some(lo), Some(hi)) => format!(
                "{what} in {}{}, {}{}",
                if lo.inclusive { "[" } else { "(" },
                lo.value,
                hi.value,
                if hi.inclusive { "]" } else { ")" }
            ),
            (Some(lo), None) => {
                format!("{what} {} {}", if lo.inclusive { ">=" } else { ">" }, lo.value)
            }
            (None, Some(hi)) => {
                format!("{what} {} {}", if hi.inclusive { "<=" } else { "<" }, hi.value)
            }
            (None, None) => format!("a finite {}", &what[2..]),
        }
    }

    /// The default as a case file writes it.
    pub fn default_text(&self) -> String {
        match self.kind {
            Kind::Flag => (self.default != 0.0).to_string(),
            Kind::Count => format!("{}", self.default as usize),
            Kind::Real => format!("{:?}", self.default),
            Kind::Choice(names) => format!("{:?}", names[self.default as usize]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_spec_names_a_field_and_its_default_is_allowed() {
        let defaults = Options::default();
        defaults.validate().unwrap();
        let mut o = defaults.clone();
        for s in SPECS {
            assert_eq!(o.field(s.key).unwrap().get(), s.default, "{}", s.key);
        }
        assert_eq!(defaults.group_tol, DEFAULT_GROUP_TOL);
        assert!(defaults.drift_control && !defaults.stop_at_first_yield);
    }

    #[test]
    fn values_outside_their_range_or_of_another_kind_are_refused_naming_the_key() {
        let bad = [
            ("tie_tol", Value::Real(f64::NAN)),
            ("tie_tol", Value::Real(-1.0)),
            ("group_tol", Value::Real(1.0)),
            ("equilibrium_tol", Value::Real(0.0)),
            ("max_stress_step", Value::Real(0.0)),
            ("tangent_turn", Value::Real(2.0)),
            ("max_events", Value::Count(-1)),
            ("max_zero_length_switches", Value::Count(0)),
            ("drift_control", Value::Real(1.0)),
            ("group_tol", Value::Flag(true)),
            ("factorization", Value::Choice("cholmod".into())),
            ("factorization", Value::Real(1.0)),
            ("no_such_option", Value::Real(1.0)),
        ];
        for (key, value) in bad {
            let err = Options::default().set(key, value).unwrap_err().message;
            assert!(err.starts_with(&format!("options.{key}")), "{err}");
        }
        let mut o = Options::default();
        o.set("group_tol", Value::Real(0.0)).unwrap();
        o.set("max_events", Value::Count(10)).unwrap();
        o.set("tie_tol", Value::Count(0)).unwrap();
        o.set("drift_control", Value::Flag(false)).unwrap();
        assert!(o.group_tol == 0.0 && o.max_events == 10 && o.tie_tol == 0.0 && !o.drift_control);
        assert_eq!(o.factorization, Factorization::Faer);
        o.set("factorization", Value::Choice("mumps".into())).unwrap();
        assert_eq!(o.factorization, Factorization::Mumps);
        o.set("factorization", Value::Choice("condensed".into())).unwrap();
        assert_eq!(o.factorization, Factorization::Condensed);
        assert_eq!(o.near_hops, DEFAULT_NEAR_HOPS);
        assert_eq!(
            spec("factorization").unwrap().kind_text(),
            "one of \"faer\", \"mumps\", \"condensed\""
        );
        assert_eq!(spec("group_tol").unwrap().kind_text(), "a number in [0, 1)");
        assert_eq!(spec("equilibrium_tol").unwrap().kind_text(), "a number > 0");
    }
}
