//! Ctrl-C while the event loop runs with the GIL released.
//!
//! Python's SIGINT handler only records the signal; the interpreter raises KeyboardInterrupt
//! when it next checks (`PyErr_CheckSignals`), which the engine can do only with the GIL. So for
//! the length of one `solve`, [`Watch`] puts a handler in front of Python's that also sets an
//! atomic flag and then calls Python's handler. The event loop reads the flag after every
//! increment, without the GIL, and re-attaches at once when it is set: a SIGINT that arrives
//! while `solve` runs stops the run at the next increment, however short the run. Python's own
//! record of the signal is untouched, so KeyboardInterrupt is raised exactly as before.
//!
//! The watch is set only where Python itself handles SIGINT: on the main thread, with Python's
//! handler in place. With SIG_IGN (sweep workers) or SIG_DFL the process's behaviour stays as
//! it was; off the main thread Python never raises KeyboardInterrupt anyway.
//!
//! [`TestTrigger`]: `SLIPSTEP_TEST_INTERRUPT=event=N` raises a real SIGINT in the process once
//! the run has recorded N events (`=end`: after its last increment; `=NAME:N`: at the N-th pass
//! of the engine's checkpoint NAME inside an increment, `slipstep_core::interrupt::Checkpoint`,
//! e.g. `lcp_pivot:50`), so that tests interrupt at a known place instead of racing a clock.

use pyo3::prelude::*;
use slipstep_core::interrupt::Checkpoint;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Set by the chained handler; cleared when the event loop hands the signal to Python.
static RECEIVED: AtomicBool = AtomicBool::new(false);
/// Python's handler (the previous `sa_sigaction`) and whether it takes `siginfo` (SA_SIGINFO).
static PREVIOUS: AtomicUsize = AtomicUsize::new(0);
static PREVIOUS_SIGINFO: AtomicBool = AtomicBool::new(false);
/// One watch at a time (a solve started from inside a progress callback does not chain twice).
static WATCHING: AtomicBool = AtomicBool::new(false);

/// The handler put in front of Python's: note the signal, then let Python record it.
extern "C" fn on_sigint(sig: libc::c_int, info: *mut libc::siginfo_t, context: *mut libc::c_void) {
    RECEIVED.store(true, Ordering::SeqCst);
    slipstep_core::interrupt::request(); // seen at the engine's next checkpoint, in any phase
    let previous = PREVIOUS.load(Ordering::SeqCst);
    if previous == 0 {
        return;
    }
    // SAFETY: `previous` is the handler that was installed for SIGINT when the watch began
    // (neither SIG_DFL nor SIG_IGN), called with the arguments its flags declare.
    unsafe {
        if PREVIOUS_SIGINFO.load(Ordering::SeqCst) {
            let f: extern "C" fn(libc::c_int, *mut libc::siginfo_t, *mut libc::c_void) =
                std::mem::transmute(previous);
            f(sig, info, context);
        } else {
            let f: extern "C" fn(libc::c_int) = std::mem::transmute(previous);
            f(sig);
        }
    }
}

/// The chained SIGINT handler for the length of one solve; restores Python's on drop.
pub struct Watch {
    previous: Option<libc::sigaction>,
}

impl Watch {
    /// Chain the handler if this thread is the one where Python handles signals and Python's
    /// handler is the current one; otherwise a watch that never fires.
    pub fn start(py: Python<'_>) -> Watch {
        let idle = Watch { previous: None };
        if !on_main_thread(py) || WATCHING.swap(true, Ordering::SeqCst) {
            return idle;
        }
        // SAFETY: plain sigaction calls on valid, zero-initialised structs.
        unsafe {
            let mut current: libc::sigaction = std::mem::zeroed();
            if libc::sigaction(libc::SIGINT, std::ptr::null(), &mut current) != 0
                || current.sa_sigaction == libc::SIG_DFL
                || current.sa_sigaction == libc::SIG_IGN
            {
                WATCHING.store(false, Ordering::SeqCst);
                return idle;
            }
            PREVIOUS.store(current.sa_sigaction, Ordering::SeqCst);
            PREVIOUS_SIGINFO.store(current.sa_flags & libc::SA_SIGINFO != 0, Ordering::SeqCst);
            RECEIVED.store(false, Ordering::SeqCst);
            let mut ours: libc::sigaction = std::mem::zeroed();
            ours.sa_sigaction = on_sigint as *const () as usize;
            ours.sa_flags =
                libc::SA_SIGINFO | (current.sa_flags & (libc::SA_ONSTACK | libc::SA_RESTART));
            ours.sa_mask = current.sa_mask;
            if libc::sigaction(libc::SIGINT, &ours, std::ptr::null_mut()) != 0 {
                WATCHING.store(false, Ordering::SeqCst);
                return idle;
            }
            Watch { previous: Some(current) }
        }
    }

    /// A SIGINT arrived since the last call (and Python has recorded it too).
    pub fn take(&self) -> bool {
        self.previous.is_some() && RECEIVED.swap(false, Ordering::SeqCst)
    }
}

impl Drop for Watch {
    fn drop(&mut self) {
        let Some(previous) = self.previous.take() else { return };
        // SAFETY: as in `start`. Python's handler goes back only if ours is still the one in
        // place (a callback may have installed another with signal.signal meanwhile).
        unsafe {
            let mut current: libc::sigaction = std::mem::zeroed();
            if libc::sigaction(libc::SIGINT, std::ptr::null(), &mut current) == 0
                && current.sa_sigaction == on_sigint as *const () as usize
            {
                libc::sigaction(libc::SIGINT, &previous, std::ptr::null_mut());
            }
        }
        WATCHING.store(false, Ordering::SeqCst);
    }
}

/// Python runs signal handlers on its main thread only.
fn on_main_thread(py: Python<'_>) -> bool {
    let check = || -> PyResult<bool> {
        let threading = py.import("threading")?;
        Ok(threading.call_method0("current_thread")?.is(&threading.call_method0("main_thread")?))
    };
    check().unwrap_or(false)
}

/// `SLIPSTEP_TEST_INTERRUPT=event=N` (or `=end`): one real SIGINT once N events are recorded
/// (or once the engine has returned).
pub struct TestTrigger {
    at_event: Option<usize>,
    at_end: bool,
}

impl TestTrigger {
    pub const VARIABLE: &'static str = "SLIPSTEP_TEST_INTERRUPT";
    /// `SLIPSTEP_TEST_PANIC=NAME:N`: a panic at the N-th pass of checkpoint NAME, as an engine bug
    /// would (tests of the failure path: an InternalError with the results so far).
    pub const PANIC: &'static str = "SLIPSTEP_TEST_PANIC";

    pub fn from_env() -> TestTrigger {
        let value = std::env::var(Self::VARIABLE).unwrap_or_default();
        let at_event = value.strip_prefix("event=").and_then(|n| n.trim().parse().ok());
        let at_checkpoint = |value: &str| {
            value.split_once(':').and_then(|(name, n)| {
                Some((Checkpoint::named(name.trim())?, n.trim().parse().ok()?))
            })
        };
        let panic = std::env::var(Self::PANIC)
            .ok()
            .and_then(|v| at_checkpoint(&v))
            .map(|(at, after)| (at, after, panic_here as fn()));
        slipstep_core::interrupt::arm(
            at_checkpoint(&value).map(|(at, after)| (at, after, raise_sigint as fn())).or(panic),
        );
        TestTrigger { at_event, at_end: value.trim() == "end" }
    }

    /// After an increment: SIGINT (once) when the run has reached the trigger's event count.
    pub fn after_increment(&mut self, events: usize) {
        if self.at_event.is_some_and(|n| events >= n) {
            self.at_event = None;
            raise_sigint();
        }
    }

    /// After the engine has returned.
    pub fn at_end(&self) {
        if self.at_end {
            raise_sigint();
        }
    }
}

fn panic_here() {
    panic!("a test panic ({})", TestTrigger::PANIC);
}

fn raise_sigint() {
    // SAFETY: raise() delivers the signal to this thread before it returns.
    unsafe {
        libc::raise(libc::SIGINT);
    }
}
