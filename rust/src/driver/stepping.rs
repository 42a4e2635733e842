//! How increments are taken: event by event (the paper), or grouped past the first predicted
//! yield by δ = `group_tol` of the load (a plastic window, `window`), or event by event again
//! while a window its re-integration could not balance is retaken, up to where it ended.
//!
//! The loop holds one `Stepping` value and passes it to every phase that depends on it (the
//! selection's window bound, the trial's kept base for contact sub-steps, the tangents that
//! may wait, the re-integration rounds).

use crate::model::Options;

#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Stepping {
    /// One event per increment (δ = 0, no drift control, a stop at the first yield, the
    /// reduced elastic space).
    EventByEvent,
    /// Plastic windows of δ.
    Grouped { delta: f64 },
    /// A window is retaken event by event up to path time `until`; grouped (δ) after.
    Retaking { until: f64, delta: f64 },
}

impl Stepping {
    /// Grouped increments need integrated stresses (drift control) and a full-space loop, and
    /// not a stop at the first yield (that needs the yield's exact load).
    pub fn new(options: &Options, reduced: bool) -> Self {
        let delta = options.group_tol;
        match delta > 0.0 && options.drift_control && !options.stop_at_first_yield && !reduced {
            true => Stepping::Grouped { delta },
            false => Stepping::EventByEvent,
        }
    }

    /// δ when this increment is a plastic window.
    pub fn window(self) -> Option<f64> {
        match self {
            Stepping::Grouped { delta } => Some(delta),
            Stepping::EventByEvent | Stepping::Retaking { .. } => None,
        }
    }

    /// At path time t: grouped again once a retaken window is behind.
    pub fn at(self, t: f64) -> Self {
        match self {
            Stepping::Retaking { until, delta } if t >= until => Stepping::Grouped { delta },
            other => other,
        }
    }

    /// A window that ended at path time t is taken back: event by event up to there.
    pub fn retake_until(self, t: f64) -> Self {
        match self {
            Stepping::Grouped { delta } | Stepping::Retaking { delta, .. } => {
                Stepping::Retaking { until: t, delta }
            }
            Stepping::EventByEvent => Stepping::EventByEvent,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_retaken_window_is_event_by_event_until_its_end() {
        let options = Options { group_tol: 0.03, ..Options::default() };
        let grouped = Stepping::new(&options, false);
        assert_eq!(grouped.window(), Some(0.03));
        let retaking = grouped.retake_until(0.4);
        assert_eq!(retaking.window(), None);
        assert_eq!(retaking.at(0.39).window(), None);
        assert_eq!(retaking.at(0.4), grouped);
        // the paper's settings and the reduced space never group
        assert_eq!(
            Stepping::new(&Options { group_tol: 0.0, ..options.clone() }, false),
            Stepping::EventByEvent
        );
        assert_eq!(
            Stepping::new(&Options { drift_control: false, ..options.clone() }, false),
            Stepping::EventByEvent
        );
        assert_eq!(
            Stepping::new(&Options { stop_at_first_yield: true, ..options.clone() }, false),
            Stepping::EventByEvent
        );
        assert_eq!(Stepping::new(&options, true), Stepping::EventByEvent);
    }
}
