//! `nav_msgs/Odometry`.

use super::builtin::{HEADER, Header};
use super::geometry::{
    POSE_WITH_COVARIANCE, PoseWithCovariance, TWIST_WITH_COVARIANCE, TwistWithCovariance,
};
use super::schema::{MsgDef, RosMessage};
use serde::{Deserialize, Serialize};

/// `nav_msgs/Odometry`: the pose in `header.frame_id` (e.g. `odom`) and the twist in
/// `child_frame_id` (e.g. `base_link`), as REP 105 wants.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Odometry {
    /// Time and the pose's frame.
    pub header: Header,
    /// The frame the twist is expressed in (the robot's).
    pub child_frame_id: String,
    /// Pose of the child frame in the header's frame, m.
    pub pose: PoseWithCovariance,
    /// Velocity of the child frame in its own axes, m/s and rad/s.
    pub twist: TwistWithCovariance,
}

/// `nav_msgs/Odometry`.
pub const ODOMETRY: MsgDef = MsgDef {
    name: "nav_msgs/Odometry",
    text: "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\ngeometry_msgs/TwistWithCovariance twist\n",
    deps: &[&HEADER, &POSE_WITH_COVARIANCE, &TWIST_WITH_COVARIANCE],
};

impl RosMessage for Odometry {
    const DEF: &'static MsgDef = &ODOMETRY;
}
