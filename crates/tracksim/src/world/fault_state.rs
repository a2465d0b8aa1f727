//! A robot's faults in force ([`FaultState`], issue 43): which tracks are stopped or
//! unpowered and which flippers jammed, with the commands given meanwhile, restored when a
//! fault clears. A field type of [`super::Simulation`]'s robots: imports nothing of it.

use crate::model::{MotorCommand, TrackFault};

/// A track's latest drive command, kept while a fault overrides it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum BeltCommand {
    /// A belt speed set-point, m/s.
    Speed(f64),
    /// A duty or torque command.
    Motor(MotorCommand),
}

/// The faults in force on one robot, and what its operator commanded meanwhile.
#[derive(Clone, Debug, Default)]
pub(crate) struct FaultState {
    /// Each track's fault.
    pub(crate) track: Vec<TrackFault>,
    /// Each track's latest command (what applies again once its fault clears).
    pub(crate) wanted: Vec<BeltCommand>,
    /// Whether each flipper is jammed.
    pub(crate) jammed: Vec<bool>,
    /// Each flipper's latest target, rad (what applies again once it is freed).
    pub(crate) wanted_flipper: Vec<f64>,
}

impl FaultState {
    /// No fault on `tracks` tracks and the flippers of targets `flipper_targets` rad.
    pub(crate) fn new(tracks: usize, flipper_targets: Vec<f64>) -> Self {
        FaultState {
            track: vec![TrackFault::Ok; tracks],
            wanted: vec![BeltCommand::Speed(0.0); tracks],
            jammed: vec![false; flipper_targets.len()],
            wanted_flipper: flipper_targets,
        }
    }
}
