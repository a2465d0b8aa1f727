//! `std_msgs/Float64`: one number (what per-track speed and per-flipper position commands
//! carry, as ROS 2 joint and velocity controllers take them).

use super::schema::{MsgDef, RosMessage};
use serde::{Deserialize, Serialize};

/// `std_msgs/Float64`: one number (its unit is the topic's: m/s, rad).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Float64 {
    /// The value.
    pub data: f64,
}

/// `std_msgs/Float64`.
pub const FLOAT64: MsgDef = MsgDef {
    name: "std_msgs/Float64",
    text: "float64 data\n",
    deps: &[],
};

impl RosMessage for Float64 {
    const DEF: &'static MsgDef = &FLOAT64;
}

/// `std_msgs/String` (`/robot_description`: the robot's URDF).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RosString {
    /// The text.
    pub data: String,
}

/// `std_msgs/String`.
pub const STRING: MsgDef = MsgDef {
    name: "std_msgs/String",
    text: "string data\n",
    deps: &[],
};

impl RosMessage for RosString {
    const DEF: &'static MsgDef = &STRING;
}
