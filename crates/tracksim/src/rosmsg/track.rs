//! `tracksim_msgs/TrackStates`: tracksim's per-track figures, one entry per track in the
//! vehicle file's order (every array as long as `name`; the motor arrays empty when no track
//! has a `[tracks.motor]`, NaN for a track without one when another has one). Its `.msg` text
//! ([`TRACK_STATES`], fields with their units) is also the file
//! `ros/tracksim_msgs/msg/TrackStates.msg` of a ROS 2 package to build where a recording is
//! read with generated types (`tests/suite/issue_27_mcap.rs` keeps the two equal).

use super::builtin::{HEADER, Header};
use super::schema::{MsgDef, RosMessage};
use serde::{Deserialize, Serialize};

/// `tracksim_msgs/TrackStates`: slip, traction, load, belt and motor figures of every track.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TrackStates {
    /// Time and frame (`base_link`: traction is along its x axis).
    pub header: Header,
    /// Track names.
    pub name: Vec<String>,
    /// Slip ratio, 1 (positive: the belt runs faster than the track moves over the ground).
    pub slip: Vec<f64>,
    /// Measured belt speed, m/s.
    pub belt_speed: Vec<f64>,
    /// Commanded belt speed, m/s.
    pub belt_command: Vec<f64>,
    /// Unwrapped belt travel, m.
    pub belt_position: Vec<f64>,
    /// The terrain's force on the track along the chassis's forward axis, N.
    pub traction: Vec<f64>,
    /// Its friction part, N.
    pub friction_traction: Vec<f64>,
    /// Normal load (sum of the contact normal forces), N.
    pub normal_load: Vec<f64>,
    /// Contact points with the terrain.
    pub contacts: Vec<u32>,
    /// Drive motor's belt force, N (empty without motors).
    pub belt_force: Vec<f64>,
    /// Torque at the motor shaft, N m (empty without motors).
    pub motor_torque: Vec<f64>,
}

/// `tracksim_msgs/TrackStates`.
pub const TRACK_STATES: MsgDef = MsgDef {
    name: "tracksim_msgs/TrackStates",
    text:
        "# Per-track figures of a tracksim run (topic /tracks), one entry per track in the vehicle
# file's order. Every array is as long as name; belt_force and motor_torque are empty when no
# track has a drive motor, NaN for a track without one when another has one. SI units.
std_msgs/Header header       # sample time; frame base_link (traction is along its x axis)
string[] name                # track names
float64[] slip               # (belt - ground) / max(|belt|, |ground|), 1; > 0 driving
float64[] belt_speed         # measured belt speed, m/s
float64[] belt_command       # commanded belt speed, m/s
float64[] belt_position      # unwrapped belt travel, m
float64[] traction           # terrain's force on the track along base_link x, N
float64[] friction_traction  # its friction part (the belt's grip), N
float64[] normal_load        # sum of the contact normal forces, N
uint32[] contacts            # contact points with the terrain
float64[] belt_force         # drive motor's belt force, N
float64[] motor_torque       # torque at the motor shaft, N m
",
    deps: &[&HEADER],
};

impl RosMessage for TrackStates {
    const DEF: &'static MsgDef = &TRACK_STATES;
}
