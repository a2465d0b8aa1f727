//! The messages the node publishes, built from the run's latest [`Sample`]: the same frames,
//! joint names and conversions as `run.mcap` ([`crate::output::mcap`]): `/tf`'s `odom ->
//! base_link` is the encoders' estimate (what `/odom` says, planar), as a robot's base
//! controller broadcasts it (REP 105); the true pose is on `/ground_truth/odom`, and on `/tf`
//! as `map -> odom` only when asked (`--map-tf`), since a localisation node (AMCL, SLAM)
//! publishes that transform itself.

use crate::model::{Mount, Scenario, SensorKind};
use crate::output::mcap::{
    BASE_FRAME, belt_joint, flipper_frame, optical_frame, optical_rotation, sensor_frame,
    tf_of_sample, transform,
};
use crate::rosmsg::{Clock, Header, JointState, Odometry, TFMessage, Time};
use crate::world::Sample;
use glam::DVec3;

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

/// `/tf_static`: each sensor's frame on its mount (`base_link` or the flipper's link) and the
/// depth cameras' optical frames (encoders have no frame).
pub fn tf_static(sc: &Scenario) -> TFMessage {
    let mut transforms = Vec::new();
    for m in &sc.vehicle.sensors {
        if matches!(m.kind, SensorKind::Encoders(_)) {
            continue;
        }
        let (parent, at) = match m.mount {
            Mount::Body => (BASE_FRAME.to_string(), m.position),
            Mount::Flipper(i) => {
                let f = &sc.vehicle.flippers[i];
                (flipper_frame(&f.name), m.position - f.pivot)
            }
        };
        let frame = sensor_frame(&m.name);
        transforms.push(transform(0.0, &parent, &frame, at, m.rotation));
        if matches!(m.kind, SensorKind::DepthCamera(_)) {
            transforms.push(transform(
                0.0,
                &frame,
                &optical_frame(&m.name),
                DVec3::ZERO,
                optical_rotation(),
            ));
        }
    }
    TFMessage { transforms }
}

/// The joint names of `/joint_states`: the flippers (revolute, rad), then each track's belt
/// as the continuous joint `<track>_belt` (its travel, m).
pub fn joint_names(sc: &Scenario) -> Vec<String> {
    let mut names: Vec<String> = sc.vehicle.flippers.iter().map(|f| f.name.clone()).collect();
    names.extend(sc.vehicle.tracks.iter().map(|t| belt_joint(&t.name)));
    names
}

/// `/joint_states` of sample `s`: flipper angles (rad; velocity by backward difference from
/// `prev`, 0 without it), belt travel (m) and measured belt speed (m/s).
pub fn joint_state(names: &[String], s: &Sample, prev: Option<&Sample>) -> JointState {
    let mut position = s.flipper_angle.clone();
    position.extend(&s.belt_position);
    let mut velocity: Vec<f64> = match prev {
        Some(p) if s.t > p.t => s
            .flipper_angle
            .iter()
            .zip(&p.flipper_angle)
            .map(|(a, b)| (a - b) / (s.t - p.t))
            .collect(),
        _ => vec![0.0; s.flipper_angle.len()],
    };
    velocity.extend(&s.belt_speed);
    JointState {
        header: Header::new(s.t, ""),
        name: names.to_vec(),
        position,
        velocity,
        effort: Vec::new(),
    }
}
