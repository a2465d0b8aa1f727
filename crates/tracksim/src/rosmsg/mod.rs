//! ROS 2 messages as plain Rust structs (serde `Serialize`/`Deserialize`), their CDR encoding
//! and their `ros2msg` schema text: what `run.mcap` records (`crate::output::mcap`) and what a
//! ROS 2 node would publish. No ROS installation is needed.
//!
//! - `cdr.rs`: CDR, as ROS 2 puts it on the wire and in bags: little-endian plain CDR (XCDR1)
//!   behind the 4-byte encapsulation header `00 01 00 00`, every primitive aligned to its size
//!   (8 at most) relative to the first byte after the header ([`encode`], [`decode`]);
//! - `schema.rs`: a message's definition ([`MsgDef`]) and its `ros2msg` text with every
//!   dependency appended ([`RosMessage::schema_text`]), as the MCAP ROS 2 profile and rosbag2
//!   store it;
//! - `builtin.rs`: `builtin_interfaces/Time`, `std_msgs/Header`, `rosgraph_msgs/Clock`;
//! - `geometry.rs`: `geometry_msgs` (vectors, poses, twists, transforms) and `tf2_msgs/TFMessage`;
//! - `nav.rs`: `nav_msgs/Odometry`;
//! - `std_msgs.rs`: `std_msgs/Float64` (the ROS node's per-track and per-flipper commands),
//!   `std_msgs/String` (`/robot_description`);
//! - `sensor.rs`: `sensor_msgs` (`JointState`, `Imu`, `LaserScan`, `PointField`,
//!   `PointCloud2`, `Image`, `CompressedImage`, `RegionOfInterest`, `CameraInfo`);
//! - `track.rs`: `tracksim_msgs/TrackStates`, tracksim's own message of per-track figures
//!   (slip, traction, normal load, belt speed and position, motor figures);
//! - `course.rs`: `tracksim_msgs/CourseStatus` and `tracksim_msgs/CourseEvent`, a scored
//!   course's live score and its events.
//!
//! Field names, types and order are those of the ROS 2 (Humble and later) `.msg` files, so the
//! bytes are what a ROS 2 node sends; units are the messages' (SI, REP 103).

mod builtin;
mod cdr;
mod course;
mod geometry;
mod nav;
mod schema;
mod sensor;
mod std_msgs;
mod track;

pub use builtin::{Clock, Header, Time};
pub use cdr::{CdrError, decode, encode};
pub use course::{CourseEvent, CourseStatus};
pub use geometry::{
    Point, Pose, PoseWithCovariance, Quaternion, TFMessage, Transform, TransformStamped, Twist,
    TwistStamped, TwistWithCovariance, Vector3,
};
pub use nav::Odometry;
pub use schema::{MsgDef, RosMessage};
pub use sensor::{
    CameraInfo, CompressedImage, Image, Imu, JointState, LaserScan, PointCloud2, PointField,
    RegionOfInterest,
};
pub use std_msgs::{Float64, RosString};
pub use track::TrackStates;

/// serde helpers for the CDR shapes serde has no derive for.
pub mod serde_helpers {
    pub use super::cdr::{byte_seq, fixed_array};
}
