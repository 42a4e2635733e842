//! Stopping a run from outside, in every phase: a request (Ctrl-C: the front end's signal
//! handler calls [`request`], which only stores an atomic flag, safe in a handler) is seen at
//! the next checkpoint of whatever loop runs, and the run ends there as an interrupted stop with
//! its results so far. The event loop checks after every increment; the loops that can run long
//! inside one (Lemke's pivots, the rate problem's passes, a correction's steps, zero-length
//! turns) call [`checkpoint`].
//!
//! Tests interrupt a given phase deterministically: [`arm`] names a checkpoint and how many
//! times it is passed before a hook (the front end's: a real SIGINT) fires there.
//!
//! Progress inside a long phase: a front end may set a [`pulse`], which checkpoints call when
//! no increment has ended ([`touch`]) for its interval.

use crate::error::{Error, ErrorKind, Result};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// The places a long loop checks for a request.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Checkpoint {
    /// One pivot of Lemke's method (a rate problem's LCP).
    LcpPivot,
    /// One solve of a rate problem (a pass of its facets).
    RateProblem,
    /// One step of an equilibrium correction at fixed load.
    Correction,
    /// One re-solve after the held directions of slips at zero force turned.
    UnloadedTurn,
}

impl Checkpoint {
    pub fn name(self) -> &'static str {
        match self {
            Checkpoint::LcpPivot => "lcp_pivot",
            Checkpoint::RateProblem => "rate_problem",
            Checkpoint::Correction => "correction",
            Checkpoint::UnloadedTurn => "unloaded_turn",
        }
    }

    pub fn named(name: &str) -> Option<Checkpoint> {
        [
            Checkpoint::LcpPivot,
            Checkpoint::RateProblem,
            Checkpoint::Correction,
            Checkpoint::UnloadedTurn,
        ]
        .into_iter()
        .find(|c| c.name() == name)
    }
}

/// Ask the running engine to stop at its next checkpoint (async-signal-safe).
pub fn request() {
    REQUESTED.store(true, Ordering::SeqCst);
}

/// Forget a request (a new run starts, or the front end took it).
pub fn clear() {
    REQUESTED.store(false, Ordering::SeqCst);
}

pub fn requested() -> bool {
    REQUESTED.load(Ordering::SeqCst)
}

/// A test trigger: at the `after`-th pass of `at`, `fire` is called once.
struct Armed {
    at: Checkpoint,
    after: usize,
    fire: fn(),
}

static ARMED: Mutex<Option<Armed>> = Mutex::new(None);
static PASSES: AtomicUsize = AtomicUsize::new(0);

/// Arm the test trigger (None: disarm).
pub fn arm(trigger: Option<(Checkpoint, usize, fn())>) {
    PASSES.store(0, Ordering::SeqCst);
    *ARMED.lock().unwrap_or_else(|e| e.into_inner()) =
        trigger.map(|(at, after, fire)| Armed { at, after, fire });
}

/// A progress report from inside a long phase, and how often (s).
type Pulse = Box<dyn FnMut() + Send>;
struct Pulsing {
    pulse: Pulse,
    interval: f64,
    last: Instant,
}

static PULSE: Mutex<Option<Pulsing>> = Mutex::new(None);

/// Call `pulse` from checkpoints when no increment has ended for `interval` seconds (None: stop).
pub fn pulse(pulse: Option<(Pulse, f64)>) {
    *PULSE.lock().unwrap_or_else(|e| e.into_inner()) =
        pulse.map(|(pulse, interval)| Pulsing { pulse, interval, last: Instant::now() });
}

/// An increment ended (it reported its progress itself).
pub fn touch() {
    if let Some(p) = PULSE.lock().unwrap_or_else(|e| e.into_inner()).as_mut() {
        p.last = Instant::now();
    }
}

/// A long loop passes `at`: the test trigger and the pulse, if due; Err(Interrupted) if a stop
/// was requested.
pub fn checkpoint(at: Checkpoint) -> Result<()> {
    if let Some(p) = PULSE
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .as_mut()
        .filter(|p| p.last.elapsed().as_secs_f64() >= p.interval)
    {
        p.last = Instant::now();
        (p.pulse)();
    }
    let mut armed = ARMED.lock().unwrap_or_else(|e| e.into_inner());
    if armed.as_ref().is_some_and(|a| a.at == at)
        && PASSES.fetch_add(1, Ordering::SeqCst) + 1
            >= armed.as_ref().map_or(usize::MAX, |a| a.after)
    {
        let fire = armed.take().map(|a| a.fire);
        drop(armed);
        fire.into_iter().for_each(|f| f());
    } else {
        drop(armed);
    }
    if requested() {
        return Err(Error::new(ErrorKind::Interrupted, format!("interrupted in {}", at.name())));
    }
    Ok(())
}
