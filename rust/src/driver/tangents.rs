//! Which tangent each element gives K: D or D_ep (eq. 11), and when it is renewed.
//!
//! The paper takes D_ep of every plastic element at each increment's start, so K changes at
//! every increment. Here an element's tangent changes when it yields or unloads, and a plastic
//! element's when its flow direction D a has turned by more than `Options::tangent_turn` since
//! the tangent K holds (0: at every increment, as the paper). The stresses themselves are
//! integrated (`stress_integration`), so a tangent that lags changes no stress; it changes the
//! trial's displacement, which the equilibrium correction completes. (How K follows a change,
//! by low-rank terms or a refactorization: `stiffness`.)

use super::problem::{Problem, PARALLEL_CHUNK};
use super::state::State;
use crate::dim::Dim;
use crate::element::{Cst, Element, Elements, Tet4};
use crate::linalg::DofMap;
use crate::low_rank::Column;
use crate::material::{deviator, Tangent, Voigt, SHEARS};
use crate::model::Options;
use nalgebra::{Matrix6, SVector, SymmetricEigen};
use rayon::prelude::*;
use std::collections::HashMap;

/// Share of the plastic elements that may have yielded without their tangent in K yet.
const WAITING_YIELDS: f64 = 0.05;
/// Eigenvalues of an element's tangent change below this × its largest are round-off.
const RANK_NOISE: f64 = 1e-10;

/// Which tangents an update renews.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Renewal {
    /// Yields, unloads, and plastic tangents whose flow direction turned by more than `turn`;
    /// `yields_may_wait`: fresh yields may wait while they are few (`Tangents::changes`).
    Changed { turn: f64, yields_may_wait: bool },
    /// Every plastic tangent (a stage's final correction: `plasticity::settle_on_surfaces`).
    All,
}

impl Renewal {
    /// The renewal of an increment: `tangent_turn` with drift control (0, every increment,
    /// in the paper's setting); fresh yields wait in a plastic window with held tangents.
    pub fn of_increment(options: &Options, window: bool) -> Self {
        let turn = if options.drift_control { options.tangent_turn } else { 0.0 };
        Renewal::Changed { turn, yields_may_wait: window && options.tangent_turn != 0.0 }
    }
}

/// The tangent of every element as K holds it, and as the last factor K_f holds it.
pub(super) struct Tangents {
    /// (Changed only by `renew`, which keeps `flowing` with it.)
    pub held: Vec<Tangent>,
    /// Whether each element's held tangent is plastic (D_ep): the stress increments and the
    /// renewals of the elastic elements then never read their 350-byte tangents (at 24.5k DOFs
    /// a stress increment of every element took 2.0 ms with the tangents read, 1.5 without, in
    /// the run).
    flowing: Vec<bool>,
    /// The tangent K_f holds of each element renewed since the last factorization (the others
    /// hold the same one as K): a factorization clears these instead of copying every
    /// element's tangent (at 24.5k DOFs 8.5 MB a time, 50 ms over the 36 factorizations of
    /// the elastoplastic Hertz).
    replaced: HashMap<usize, Tangent>,
    /// Each material's elastic tangent: an elastic element's stress increment reads this one
    /// (a few cache lines for the whole mesh) instead of its own copy in `held`.
    elastic: Vec<Tangent>,
}

impl Tangents {
    /// Every element elastic.
    pub fn elastic<D: Dim>(problem: &Problem<D>) -> Self {
        let held: Vec<Tangent> =
            problem.sections.iter().map(|s| s.tangent(&Voigt::zeros(), false)).collect();
        let elastic =
            problem.model.materials.iter().map(|m| m.tangent(&Voigt::zeros(), false)).collect();
        Tangents { flowing: vec![false; held.len()], held, replaced: HashMap::new(), elastic }
    }

    /// After a factorization: K_f holds every element's current tangent.
    pub fn factored(&mut self) {
        self.replaced.clear();
    }

    /// Element e's tangent as the last factor holds it.
    fn factored_tangent(&self, e: usize) -> &Tangent {
        self.replaced.get(&e).unwrap_or(&self.held[e])
    }

    /// The elements whose tangent changed with the state (now renewed in `held`), or None when
    /// the update waits (`yields_can_wait`).
    pub fn renew<D: Dim>(
        &mut self,
        problem: &Problem<D>,
        state: &State<D>,
        renewal: Renewal,
    ) -> Option<Vec<usize>> {
        let turn = match renewal {
            Renewal::Changed { yields_may_wait: true, .. } if self.yields_can_wait(state) => {
                return None
            }
            Renewal::Changed { turn, .. } => turn,
            Renewal::All => 0.0,
        };
        Some(
            (0..problem.elements.len())
                .filter(|&e| self.refresh(problem, e, state, turn))
                .collect(),
        )
    }

    /// Grouped increments with drift control and held tangents (tangent_turn > 0): K is left as
    /// it is while the elements that yielded since it was last brought up to date are fewer
    /// than `WAITING_YIELDS` of the plastic elements and none unloaded. Their stresses are
    /// integrated regardless, each increment is re-integrated until balanced, and a correction
    /// that leaves the state too far off the yield surfaces renews every tangent
    /// (`plasticity::restore_equilibrium`). Measured on the elastoplastic Hertz at 24.5k DOFs,
    /// δ = 0.05: 76 → 23 factorizations, p0 and a unchanged to 1e-5. (Event by event, without
    /// the re-integration, it would move plastic strains by up to 2.7 % on the dolfinx
    /// replays: not there.)
    fn yields_can_wait<D: Dim>(&self, state: &State<D>) -> bool {
        let (mut plastic, mut waiting) = (0usize, 0usize);
        for (&f, &p) in self.flowing.iter().zip(&state.plastic) {
            plastic += p as usize;
            waiting += (p && !f) as usize;
        }
        let unloads = self.flowing.iter().zip(&state.plastic).any(|(&f, &p)| f && !p);
        !unloads && (waiting as f64) < WAITING_YIELDS * plastic as f64
    }

    /// Set element e's tangent from the state if it must change (yield, unload, or a flow
    /// direction turned by more than `turn`); true if it changed.
    fn refresh<D: Dim>(
        &mut self,
        problem: &Problem<D>,
        e: usize,
        state: &State<D>,
        turn: f64,
    ) -> bool {
        let change = match (self.flowing[e], state.plastic[e]) {
            (false, false) => false,
            (true, false) | (false, true) => true,
            (true, true) => {
                self.held[e].flow.is_some_and(|f| turned(&f.da, &state.stress[e]) > turn)
            }
        };
        if change {
            let renewed = problem.sections[e].tangent(&state.stress[e], state.plastic[e]);
            self.flowing[e] = renewed.flow.is_some();
            self.replaced.entry(e).or_insert(std::mem::replace(&mut self.held[e], renewed));
        }
        change
    }

    /// K_e(held) − K_e(factored) of element e as signed rank-one terms over the equations:
    /// w Bᵀ ΔD B with ΔD = Σ λ v vᵀ (its eigenvalues), so each term is s c cᵀ with
    /// c = √(w |λ|) Bᵀ v (w the element's volume).
    pub fn columns<D: Dim>(&self, problem: &Problem<D>, e: usize, map: &DofMap) -> Vec<Column> {
        let section = &problem.sections[e];
        let delta: Matrix6<f64> = section.element_matrix(&self.held[e])
            - section.element_matrix(self.factored_tangent(e));
        // (the eigen decomposition at the element's own size: nalgebra's needs a concrete one)
        match &problem.elements {
            Elements::Plane(els) => {
                let eig = SymmetricEigen::new(Cst::rows_of(&delta));
                rank_one_terms(
                    &els[e],
                    e,
                    eig.eigenvalues.as_slice(),
                    |i| eig.eigenvectors.column(i).into_owned(),
                    map,
                )
            }
            Elements::Space(els) => {
                let eig = SymmetricEigen::new(Tet4::rows_of(&delta));
                rank_one_terms(
                    &els[e],
                    e,
                    eig.eigenvalues.as_slice(),
                    |i| eig.eigenvectors.column(i).into_owned(),
                    map,
                )
            }
        }
    }

    /// Δσ and Δεp of every element for a displacement increment (eqs. 10, 11, 18), with the
    /// tangents K holds. (The strain increments themselves are not kept: the stress
    /// integration takes the few it needs from Δu.)
    pub fn stress_increment<D: Dim>(
        &self,
        problem: &Problem<D>,
        du: &[f64],
    ) -> (Vec<Voigt>, Vec<f64>) {
        let material = &problem.model.element_material;
        (0..self.held.len())
            .into_par_iter()
            .with_min_len(PARALLEL_CHUNK)
            .zip(&self.flowing)
            .zip(&problem.sections)
            .map(|((el, &flowing), section)| {
                let e = problem.elements.strain(el, du);
                match flowing {
                    false => (section.stress_increment(&self.elastic[material[el]], &e), 0.0),
                    true => (
                        section.stress_increment(&self.held[el], &e),
                        section.plastic_multiplier(&self.held[el], &e),
                    ),
                }
            })
            .unzip()
    }
}

/// w Bᵀ ΔD B of one element as signed rank-one terms over the equations (`columns`), from the
/// eigenvalues λ_i and eigenvectors v_i of ΔD restricted to the element's rows.
fn rank_one_terms<const S: usize, const N: usize>(
    el: &impl Element<S, N>,
    e: usize,
    eigenvalues: &[f64],
    eigenvector: impl Fn(usize) -> SVector<f64, S>,
    map: &DofMap,
) -> Vec<Column> {
    let largest = eigenvalues.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let weight = el.measure();
    (0..S)
        .filter(|&i| eigenvalues[i].abs() > RANK_NOISE * largest)
        .map(|i| {
            let lambda = eigenvalues[i];
            let w = el.b().transpose() * eigenvector(i) * (weight * lambda.abs()).sqrt();
            let entries = el
                .dofs()
                .iter()
                .zip(w.iter())
                .filter_map(|(&g, &v)| map.equation(g).map(|q| (q, v)))
                .collect();
            Column { entries, sign: lambda.signum(), owner: e }
        })
        .collect()
}

/// The angle between a held flow direction D a and the current one. For von Mises D a is
/// 3G/σe s, s the stress deviator (its shears the τ's), so they are compared as deviators,
/// with the tensor inner product s:s' = Σ s_i s'_i + 2 Σ τ τ' (invariant under rotation), and
/// without building a tangent.
fn turned(held_da: &Voigt, stress: &Voigt) -> f64 {
    let now = deviator(stress);
    let inner = |a: &Voigt, b: &Voigt| {
        SHEARS.fold(a[0] * b[0] + a[1] * b[1] + a[2] * b[2], |s, k| s + 2.0 * a[k] * b[k])
    };
    let cos = inner(held_da, &now) / (inner(held_da, held_da) * inner(&now, &now)).sqrt();
    cos.clamp(-1.0, 1.0).acos()
}

#[cfg(test)]
mod tests {
    use super::super::clock::Clock;
    use super::super::engine::Engine;
    use super::super::scenes::*;
    use super::*;
    use crate::dim::Planar;
    use crate::material::from_planar;
    use nalgebra::SMatrix;

    /// Round-off of the few dozen operations behind each entry (~1e-16 relative each), with room.
    const ROUND_OFF: f64 = 1e-10;

    /// Σ s c cᵀ of element e's low-rank terms, over its own DOFs (rows of fixed DOFs stay 0).
    fn low_rank_matrix<D: Dim>(eng: &Engine<D>, e: usize) -> SMatrix<f64, 6, 6> {
        let map = &eng.problem.dofs.map;
        let dofs = eng.problem.elements.dofs(e);
        let local = |q: usize| {
            dofs.iter().position(|&d| d == map.dof_of_equation[q]).expect("a DOF of the element")
        };
        let mut k = SMatrix::<f64, 6, 6>::zeros();
        for c in eng.stiffness.tangents.columns(&eng.problem, e, map) {
            for &(qi, vi) in &c.entries {
                for &(qj, vj) in &c.entries {
                    k[(local(qi), local(qj))] += c.sign * vi * vj;
                }
            }
        }
        k
    }

    /// Element 0 of the pressed square yields at σ1 (uniaxial) and its flow then turns to σ2
    /// (pure shear), both renewals before any factorization: its low-rank terms are K − K_f,
    /// w Bᵀ (D_ep(σ2) − D) B with D the elastic tangent the factor still holds (recomputed
    /// here from the element's B), not D_ep(σ2) − D_ep(σ1); its stress increment follows
    /// D_ep(σ2) and its plastic multiplier the flow at σ2. Unloaded, it is elastic again and
    /// equal to what the factor holds (no terms); element 1 stays elastic throughout.
    #[test]
    fn renewals_between_factorizations_keep_the_factored_tangent() {
        let sy = 200.0;
        let m = square_on_rollers(0.0, -sy, plastic(sy, 500.0));
        let clock = Clock::new();
        let (mut eng, mut state) = start(&m, &clock);
        let (s1, s2) =
            (from_planar([sy, 0.0, 0.0, 0.0]), from_planar([0.0, 0.0, 0.0, sy / 3f64.sqrt()]));
        let renew = |eng: &mut Engine<Planar>, state: &State<Planar>| {
            eng.stiffness
                .tangents
                .renew(&eng.problem, state, Renewal::All)
                .expect("a renewal of all never waits")
        };
        (state.plastic[0], state.stress[0]) = (true, s1);
        assert_eq!(renew(&mut eng, &state), vec![0]);
        state.stress[0] = s2;
        assert_eq!(renew(&mut eng, &state), vec![0], "a flow turned by 90 degrees is renewed");

        let section = eng.problem.sections[0];
        let (elastic, at_s2) =
            (section.tangent(&Voigt::zeros(), false), section.tangent(&s2, true));
        let Elements::Plane(els) = &eng.problem.elements else { panic!("a plane scene") };
        let expected =
            els[0].stiffness(&(section.element_matrix(&at_s2) - section.element_matrix(&elastic)));
        let got = low_rank_matrix(&eng, 0);
        let dofs = eng.problem.elements.dofs(0);
        let scale = expected.amax();
        for i in 0..6 {
            for j in 0..6 {
                let free = eng.problem.dofs.map.equation(dofs[i]).is_some()
                    && eng.problem.dofs.map.equation(dofs[j]).is_some();
                let want = if free { expected[(i, j)] } else { 0.0 };
                assert!(
                    (got[(i, j)] - want).abs() < ROUND_OFF * scale,
                    "K - K_f [{i},{j}] = {} vs {want}",
                    got[(i, j)]
                );
            }
        }

        let du: Vec<f64> = (0..8).map(|k| 1e-3 * (k as f64 - 3.5)).collect();
        let (dstress, dplastic) = eng.stiffness.tangents.stress_increment(&eng.problem, &du);
        let (e0, e1) = (eng.problem.elements.strain(0, &du), eng.problem.elements.strain(1, &du));
        assert_eq!(
            (dstress[0], dplastic[0]),
            (section.stress_increment(&at_s2, &e0), section.plastic_multiplier(&at_s2, &e0))
        );
        assert_eq!(
            (dstress[1], dplastic[1]),
            (eng.problem.sections[1].stress_increment(&elastic, &e1), 0.0)
        );

        state.plastic[0] = false;
        assert_eq!(renew(&mut eng, &state), vec![0], "an unload is renewed");
        assert!(
            eng.stiffness.tangents.columns(&eng.problem, 0, &eng.problem.dofs.map).is_empty(),
            "elastic again: K_f's own tangent"
        );
        let (dstress, dplastic) = eng.stiffness.tangents.stress_increment(&eng.problem, &du);
        assert_eq!((dstress[0], dplastic[0]), (section.stress_increment(&elastic, &e0), 0.0));
    }
}
