//! The engine in three parts, and the stage's loads: the immutable problem (`problem`), the
//! stiffness with its factor and held tangents (`stiffness`), the loads of the current stage
//! (`loads`); the evolving state is the loop's (`state`). The phases take the engine and the
//! state as arguments.

use super::clock::{Clock, Phase};
use super::loads::StageLoads;
use super::problem::Problem;
use super::state::State;
use super::stiffness::Stiffness;
use crate::dim::Dim;
use crate::element::Discretization;
use crate::error::Result;
use crate::model::Model;

pub(super) struct Engine<'m, 'c, D: Dim> {
    pub problem: Problem<'m, D>,
    pub stiffness: Stiffness,
    pub loads: StageLoads,
    /// Where the time goes (owned by `run`, so that a timer needs no borrow of the engine).
    pub clock: &'c Clock,
}

impl<'m, 'c, D: Dim> Engine<'m, 'c, D> {
    /// The problem, K factored, and the first stage's loads; `model` must have passed
    /// `Model::validate`.
    pub fn new(model: &'m Model<D>, clock: &'c Clock) -> Result<Self>
    where
        D: Discretization,
    {
        let problem = {
            let _t = clock.time(Phase::Assembly);
            Problem::new(model)?
        };
        let mut stiffness = Stiffness::new(&problem, clock)?;
        let loads = StageLoads::begin(&problem, &mut stiffness, 0, Default::default(), clock);
        Ok(Engine { problem, stiffness, loads, clock })
    }

    /// The state at the start of the path.
    pub fn initial_state(&self) -> State<D> {
        let p = &self.problem;
        State::initial(
            &p.pairs,
            p.loop_dofs(),
            p.loop_elements(),
            p.bodies.modes.len(),
            p.scales.touching(),
        )
    }

    /// Start stage k (0-based) at s = 0, from the state the previous stage left.
    pub fn begin_stage(&mut self, k: usize, state: &mut State<D>) {
        state.begin_stage(k);
        if k > 0 {
            let done = std::mem::take(&mut self.loads.reduced);
            self.loads = StageLoads::begin(&self.problem, &mut self.stiffness, k, done, self.clock);
        }
    }
}
