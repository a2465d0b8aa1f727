//! A simulation driven by its scenario's `[[commands]]`: what `tracksim run` does, and what
//! tests use to drive a scenario step by step.

use super::timeline::Timeline;
use crate::error::Result;
use crate::model::Scenario;
use crate::world::Simulation;

/// A [`Simulation`] whose controls come from its scenario's command timeline; it dereferences
/// to the simulation for every query.
pub struct Scripted {
    /// The simulation.
    pub sim: Simulation,
    timeline: Timeline,
}

impl Scripted {
    /// Builds the simulation of `sc` with its command timeline.
    pub fn new(sc: &Scenario) -> Result<Self> {
        Ok(Scripted {
            sim: Simulation::new(sc)?,
            timeline: Timeline::new(&sc.commands),
        })
    }

    /// [`Scripted::new`] of a shared scenario (not copied).
    pub fn from_shared(sc: std::sync::Arc<Scenario>) -> Result<Self> {
        let timeline = Timeline::new(&sc.commands);
        Ok(Scripted {
            sim: Simulation::from_shared(sc)?,
            timeline,
        })
    }

    /// Drops the command timeline: from now on the controls come only from the caller.
    pub fn clear_commands(&mut self) {
        self.timeline = Timeline::new(&[]);
    }

    /// Rebuilds the simulation from its compiled scenario ([`Simulation::reset`]) and starts
    /// the command timeline again from its first command.
    pub fn reset(&mut self, seed: Option<u64>) -> Result<()> {
        self.sim.reset(seed)?;
        self.timeline.rewind();
        Ok(())
    }

    /// Applies the commands that have fallen due, then advances one step.
    pub fn step(&mut self) -> Result<()> {
        for c in self.timeline.due(self.sim.time()) {
            if c.reset {
                self.sim.reset_robot()?;
            }
            self.sim.apply(&c);
        }
        self.sim.step()
    }
}

impl std::ops::Deref for Scripted {
    type Target = Simulation;
    fn deref(&self) -> &Simulation {
        &self.sim
    }
}

impl std::ops::DerefMut for Scripted {
    fn deref_mut(&mut self) -> &mut Simulation {
        &mut self.sim
    }
}
