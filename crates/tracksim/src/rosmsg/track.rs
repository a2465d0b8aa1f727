//! `tracksim_msgs/TrackStates`: tracksim's per-track figures, one entry per track in the
//! vehicle file's order (every array as long as `name`; the motor arrays empty when no track
//! has a `[tracks.motor]`, NaN for a track without one when another has one).
//!
//! ```text
//! std_msgs/Header header
//! string[] name                # track names
//! float64[] slip               # (belt - ground) / max(|belt|, |ground|), 1
//! float64[] belt_speed         # measured belt speed, m/s
//! float64[] belt_command       # commanded belt speed, m/s
//! float64[] belt_position      # unwrapped belt travel, m
//! float64[] traction           # terrain force along the chassis x axis, N
//! float64[] friction_traction  # its friction part, N
//! float64[] normal_load        # sum of the contact normal forces, N
//! uint32[] contacts            # contact points with the terrain
//! float64[] belt_force         # drive motor's belt force, N
//! float64[] motor_torque       # torque at the motor shaft, N m
//! ```

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
    text: "# Per-track figures of a tracksim run, one entry per track (motor arrays empty without motors).\nstd_msgs/Header header\nstring[] name\nfloat64[] slip\nfloat64[] belt_speed\nfloat64[] belt_command\nfloat64[] belt_position\nfloat64[] traction\nfloat64[] friction_traction\nfloat64[] normal_load\nuint32[] contacts\nfloat64[] belt_force\nfloat64[] motor_torque\n",
    deps: &[&HEADER],
};

impl RosMessage for TrackStates {
    const DEF: &'static MsgDef = &TRACK_STATES;
}
