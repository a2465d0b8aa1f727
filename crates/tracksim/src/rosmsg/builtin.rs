//! `builtin_interfaces/Time`, `std_msgs/Header` and `rosgraph_msgs/Clock`.

use super::schema::{MsgDef, RosMessage};
use serde::{Deserialize, Serialize};

/// `builtin_interfaces/Time`: seconds and nanoseconds (simulated time in tracksim's outputs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Time {
    /// Whole seconds, s.
    pub sec: i32,
    /// Nanoseconds within the second, ns (0 to 999 999 999).
    pub nanosec: u32,
}

impl Time {
    /// The time `ns` nanoseconds after zero (seconds saturate at `i32::MAX`).
    pub fn from_nanos(ns: u64) -> Self {
        Time {
            sec: (ns / 1_000_000_000).min(i32::MAX as u64) as i32,
            nanosec: (ns % 1_000_000_000) as u32,
        }
    }

    /// The time `t` seconds after zero, rounded to the nanosecond (negative or NaN: zero).
    pub fn from_secs(t: f64) -> Self {
        Time::from_nanos(secs_to_nanos(t))
    }

    /// Nanoseconds after zero (a negative time: 0).
    pub fn nanos(&self) -> u64 {
        (self.sec.max(0) as u64) * 1_000_000_000 + self.nanosec as u64
    }
}

/// Seconds as nanoseconds, rounded (negative or NaN: 0).
pub fn secs_to_nanos(t: f64) -> u64 {
    if t.is_finite() && t > 0.0 {
        (t * 1e9).round() as u64
    } else {
        0
    }
}

/// `std_msgs/Header`: when and in which frame.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Header {
    /// Time of the data.
    pub stamp: Time,
    /// Frame the data is expressed in.
    pub frame_id: String,
}

impl Header {
    /// A header at `t` s in frame `frame`.
    pub fn new(t: f64, frame: &str) -> Self {
        Header {
            stamp: Time::from_secs(t),
            frame_id: frame.to_string(),
        }
    }
}

/// `rosgraph_msgs/Clock`: the simulated clock (`/clock`, what `use_sim_time` follows).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Clock {
    /// The simulated time.
    pub clock: Time,
}

/// `builtin_interfaces/Time`.
pub const TIME: MsgDef = MsgDef {
    name: "builtin_interfaces/Time",
    text: "int32 sec\nuint32 nanosec\n",
    deps: &[],
};
/// `std_msgs/Header`.
pub const HEADER: MsgDef = MsgDef {
    name: "std_msgs/Header",
    text: "builtin_interfaces/Time stamp\nstring frame_id\n",
    deps: &[&TIME],
};
/// `rosgraph_msgs/Clock`.
pub const CLOCK: MsgDef = MsgDef {
    name: "rosgraph_msgs/Clock",
    text: "builtin_interfaces/Time clock\n",
    deps: &[&TIME],
};

impl RosMessage for Time {
    const DEF: &'static MsgDef = &TIME;
}
impl RosMessage for Header {
    const DEF: &'static MsgDef = &HEADER;
}
impl RosMessage for Clock {
    const DEF: &'static MsgDef = &CLOCK;
}
