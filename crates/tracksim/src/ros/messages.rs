//! The messages the node publishes, built from the run's latest [`Sample`]: the same frames,
//! joint names and conversions as `run.mcap` ([`crate::output::mcap`]): `/tf`'s `odom ->
//! base_link` is the encoders' estimate (what `/odom` says, planar), as a robot's base
//! controller broadcasts it (REP 105); the true pose is on `/ground_truth/odom`, and on `/tf`
//! as `map -> odom` only when asked (`--map-tf`), since a localisation node (AMCL, SLAM)
//! publishes that transform itself.

use crate::model::Scenario;
use crate::output::mcap::{belt_joint, tf_of_sample};
pub use crate::output::mcap::{joint_state, tf_static};
use crate::rosmsg::{Clock, Odometry, TFMessage, Time};
use crate::world::Sample;

/// `/clock` at `t` s of simulated time.
pub fn clock(t: f64) -> Clock {
    Clock {
        clock: Time::from_secs(t),
    }
}

/// `/tf` of sample `s`: [`tf_of_sample`] (`odom -> base_link` from the encoder odometry
/// `odom`, the flippers, and with `map` also `map -> odom` from the true pose).
pub fn tf(sc: &Scenario, s: &Sample, odom: &Odometry, map: bool) -> TFMessage {
    tf_of_sample(sc, s, odom, map)
}

/// The joint names of `/joint_states`: the flippers (revolute, rad), then each track's belt
/// as the continuous joint `<track>_belt` (its travel, m).
pub fn joint_names(sc: &Scenario) -> Vec<String> {
    let mut names: Vec<String> = sc.vehicle.flippers.iter().map(|f| f.name.clone()).collect();
    names.extend(sc.vehicle.tracks.iter().map(|t| belt_joint(&t.name)));
    names
}
