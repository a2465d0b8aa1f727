//! One robot of a run as a live front end reads it ([`RunView`]): the world with that robot
//! selected, its scenario, samples, sensors, outcome and course score. A [`super::Runner`]
//! gives its one robot's ([`super::Runner::view`]), a [`super::TeamRunner`] any robot's
//! ([`super::TeamRunner::view`]).

use super::course::CourseScore;
use super::outcome::Outcome;
use crate::model::Scenario;
use crate::sensors::SensorSet;
use crate::world::Simulation;

/// One robot of a running world.
pub struct RunView<'a> {
    /// The world, with this robot selected ([`Simulation::select`]).
    pub sim: &'a Simulation,
    /// The robot's scenario (the world with it as its one robot).
    pub scenario: &'a Scenario,
    /// Its samples so far (at the output interval; the first at t = 0).
    pub samples: &'a super::SampleLog,
    /// Its sensors.
    pub sensors: &'a SensorSet,
    /// Its outcome and the time it was decided, s.
    pub decided: Option<&'a (Outcome, f64)>,
    /// Its course score so far (`[course]`).
    pub course: Option<CourseScore>,
}
