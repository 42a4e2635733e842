//! Plasticity in the loop: each element's tangent D or D_ep (eq. 11) at the increment's start,
//! and drift control after it: plastic elements return to their yield surface and one
//! correction solve at fixed load restores equilibrium, so that every event is in equilibrium
//! to round-off (`drift_control = false` is the paper without either).

use super::engine::Engine;
use super::selection::Selection;
use super::state::State;
use crate::error::Result;
use crate::material::{von_mises, Plane};
use nalgebra::Vector4;

/// The size of the last equilibrium correction (displacement, force): the correction moves
/// nodes and contact forces by that much with no event of its own, so the contact checks
/// allow for it (see `Engine::check_contact`).
#[derive(Clone, Copy, Default)]
pub(super) struct Correction {
    pub displacement: f64,
    pub force: f64,
}

impl Engine<'_> {
    /// Rebuild the tangents of plastic elements at the current stress (the paper's D_ep at the
    /// increment's start) and of elements whose plastic flag changed; K is refactorized only
    /// if one of them differs (not after a zero-length increment without a yield/unload).
    pub fn update_tangents(&mut self, state: &State) -> Result<()> {
        if !self.is_reduced() {
            for e in 0..self.elements.len() {
                let was_plastic = self.tangents[e].flow.is_some();
                if state.plastic[e] || was_plastic {
                    let tangent = self.material[e].tangent(&state.stress[e], state.plastic[e]);
                    if tangent.d4 != self.tangents[e].d4 || state.plastic[e] != was_plastic {
                        self.tangents[e] = tangent;
                        self.tangents_changed = true;
                    }
                }
            }
        }
        if self.tangents_changed {
            self.factor()?;
        }
        Ok(())
    }

    /// Yield-surface drift: max |σe − σy(εp)| / σy(εp) over plastic elements.
    pub fn drift(&self, state: &State) -> f64 {
        (0..state.plastic.len())
            .filter(|&e| state.plastic[e])
            .map(|e| {
                let sy = self.material[e].current_yield(state.plastic_strain[e]);
                (von_mises(&state.stress[e]) - sy).abs() / sy
            })
            .fold(0.0, f64::max)
    }

    /// Drift control after an increment: return plastic elements to the yield surface, then
    /// correct equilibrium at fixed load. A zero-length increment of contact events only
    /// changed no stress: the last correction (and its allowance) still holds, and skipping
    /// it keeps the tangents, so K needs no refactorization. Returns the correction's size.
    pub fn control_drift(&mut self, state: &mut State, sel: &Selection, drift: f64, last: Correction) -> Result<Correction> {
        let stresses_kept = sel.zero_length() && !sel.group.iter().any(|c| c.kind.is_element_event());
        if stresses_kept {
            return Ok(last);
        }
        if !(self.model.options.drift_control && drift > 0.0) {
            return Ok(Correction::default());
        }
        self.return_to_yield_surface(state);
        let correction = self.trial(state, sel.phi, None)?;
        let largest = |v: &[f64]| v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let size = Correction { displacement: largest(&correction.du), force: largest(&correction.dlambda_n).max(largest(&correction.dlambda_t)) };
        state.advance(&correction, 1.0);
        state.load_fraction = sel.phi;
        Ok(size)
    }

    /// Scale the stress of plastic elements back onto the yield surface: the deviator at fixed
    /// mean stress in plane strain and axisymmetry (all four components), the in-plane stress
    /// (keeping σz = 0) in plane stress.
    fn return_to_yield_surface(&self, state: &mut State) {
        for e in 0..state.plastic.len() {
            if !state.plastic[e] {
                continue;
            }
            let sy = self.material[e].current_yield(state.plastic_strain[e]);
            let s = state.stress[e];
            let factor = sy / von_mises(&s);
            if factor > 1.0 && self.model.options.group_tol > 0.0 {
                // Yielded early by grouping and still inside the surface: flowing from there
                // is the O(δ) error grouping accepts; lifting it onto the surface would add
                // stress that no load put there.
                continue;
            }
            state.stress[e] = match self.model.plane {
                Plane::Stress => s * factor,
                Plane::Strain | Plane::Axisymmetric => {
                    let p = (s[0] + s[1] + s[2]) / 3.0;
                    let mean = Vector4::new(p, p, p, 0.0);
                    mean + (s - mean) * factor
                }
            };
        }
    }
}
