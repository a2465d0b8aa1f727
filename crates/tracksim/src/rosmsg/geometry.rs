//! `geometry_msgs`: vectors, points, quaternions, poses, twists and transforms, and
//! `tf2_msgs/TFMessage` (what `/tf` and `/tf_static` carry).

use super::builtin::{HEADER, Header};
use super::cdr::fixed_array;
use super::schema::{MsgDef, RosMessage};
use serde::{Deserialize, Serialize};

/// `geometry_msgs/Vector3`: a free vector (m, m/s, rad/s or m/s^2 by context).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Vector3 {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
}

/// `geometry_msgs/Point`: a position, m.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Point {
    /// x, m.
    pub x: f64,
    /// y, m.
    pub y: f64,
    /// z, m.
    pub z: f64,
}

/// `geometry_msgs/Quaternion`: an orientation (unit quaternion, x y z w).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Quaternion {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
    /// w.
    pub w: f64,
}

impl Default for Quaternion {
    /// The identity (the message's default, w = 1).
    fn default() -> Self {
        Quaternion {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            w: 1.0,
        }
    }
}

/// `geometry_msgs/Pose`: position and orientation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// Position, m.
    pub position: Point,
    /// Orientation.
    pub orientation: Quaternion,
}

/// `geometry_msgs/PoseWithCovariance`: a pose and its 6 x 6 covariance (row-major, about x, y,
/// z, rotation about x, y, z; m^2, rad^2).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PoseWithCovariance {
    /// Pose.
    pub pose: Pose,
    /// Covariance, row-major 6 x 6 (all 0: unknown).
    #[serde(with = "fixed_array")]
    pub covariance: [f64; 36],
}

impl Default for PoseWithCovariance {
    fn default() -> Self {
        PoseWithCovariance {
            pose: Pose::default(),
            covariance: [0.0; 36],
        }
    }
}

/// `geometry_msgs/Twist`: linear (m/s) and angular (rad/s) velocity.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Twist {
    /// Linear velocity, m/s.
    pub linear: Vector3,
    /// Angular velocity, rad/s.
    pub angular: Vector3,
}

/// `geometry_msgs/TwistStamped`: a twist with a time and frame: what Nav2 (with
/// `enable_stamped_cmd_vel`, the default from Jazzy), `diff_drive_controller` and the
/// Clearpath and TurtleBot 4 simulations send on `cmd_vel` (issue 61).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TwistStamped {
    /// Time (zero: now) and frame (the robot's base frame, or empty).
    pub header: Header,
    /// The twist.
    pub twist: Twist,
}

/// `geometry_msgs/TwistWithCovariance`: a twist and its 6 x 6 covariance (row-major).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TwistWithCovariance {
    /// Twist.
    pub twist: Twist,
    /// Covariance, row-major 6 x 6 ((m/s)^2, (rad/s)^2; all 0: unknown).
    #[serde(with = "fixed_array")]
    pub covariance: [f64; 36],
}

impl Default for TwistWithCovariance {
    fn default() -> Self {
        TwistWithCovariance {
            twist: Twist::default(),
            covariance: [0.0; 36],
        }
    }
}

/// `geometry_msgs/Transform`: a child frame's pose in its parent frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Transform {
    /// Origin of the child frame in the parent frame, m.
    pub translation: Vector3,
    /// Orientation of the child frame in the parent frame.
    pub rotation: Quaternion,
}

/// `geometry_msgs/TransformStamped`: a transform from `header.frame_id` (parent) to
/// `child_frame_id` at `header.stamp`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TransformStamped {
    /// Time and parent frame.
    pub header: Header,
    /// Child frame.
    pub child_frame_id: String,
    /// The child's pose in the parent.
    pub transform: Transform,
}

/// `tf2_msgs/TFMessage`: transforms (`/tf`, `/tf_static`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TFMessage {
    /// The transforms.
    pub transforms: Vec<TransformStamped>,
}

/// `geometry_msgs/Vector3`.
pub const VECTOR3: MsgDef = MsgDef {
    name: "geometry_msgs/Vector3",
    text: "float64 x\nfloat64 y\nfloat64 z\n",
    deps: &[],
};
/// `geometry_msgs/Point`.
pub const POINT: MsgDef = MsgDef {
    name: "geometry_msgs/Point",
    text: "float64 x\nfloat64 y\nfloat64 z\n",
    deps: &[],
};
/// `geometry_msgs/Quaternion`.
pub const QUATERNION: MsgDef = MsgDef {
    name: "geometry_msgs/Quaternion",
    text: "float64 x\nfloat64 y\nfloat64 z\nfloat64 w\n",
    deps: &[],
};
/// `geometry_msgs/Pose`.
pub const POSE: MsgDef = MsgDef {
    name: "geometry_msgs/Pose",
    text: "geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n",
    deps: &[&POINT, &QUATERNION],
};
/// `geometry_msgs/PoseWithCovariance`.
pub const POSE_WITH_COVARIANCE: MsgDef = MsgDef {
    name: "geometry_msgs/PoseWithCovariance",
    text: "geometry_msgs/Pose pose\nfloat64[36] covariance\n",
    deps: &[&POSE],
};
/// `geometry_msgs/Twist`.
pub const TWIST: MsgDef = MsgDef {
    name: "geometry_msgs/Twist",
    text: "geometry_msgs/Vector3 linear\ngeometry_msgs/Vector3 angular\n",
    deps: &[&VECTOR3],
};
/// `geometry_msgs/TwistStamped`.
pub const TWIST_STAMPED: MsgDef = MsgDef {
    name: "geometry_msgs/TwistStamped",
    text: "std_msgs/Header header\ngeometry_msgs/Twist twist\n",
    deps: &[&HEADER, &TWIST],
};
/// `geometry_msgs/TwistWithCovariance`.
pub const TWIST_WITH_COVARIANCE: MsgDef = MsgDef {
    name: "geometry_msgs/TwistWithCovariance",
    text: "geometry_msgs/Twist twist\nfloat64[36] covariance\n",
    deps: &[&TWIST],
};
/// `geometry_msgs/Transform`.
pub const TRANSFORM: MsgDef = MsgDef {
    name: "geometry_msgs/Transform",
    text: "geometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation\n",
    deps: &[&VECTOR3, &QUATERNION],
};
/// `geometry_msgs/TransformStamped`.
pub const TRANSFORM_STAMPED: MsgDef = MsgDef {
    name: "geometry_msgs/TransformStamped",
    text: "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/Transform transform\n",
    deps: &[&HEADER, &TRANSFORM],
};
/// `tf2_msgs/TFMessage`.
pub const TF_MESSAGE: MsgDef = MsgDef {
    name: "tf2_msgs/TFMessage",
    text: "geometry_msgs/TransformStamped[] transforms\n",
    deps: &[&TRANSFORM_STAMPED],
};

impl RosMessage for Vector3 {
    const DEF: &'static MsgDef = &VECTOR3;
}
impl RosMessage for Point {
    const DEF: &'static MsgDef = &POINT;
}
impl RosMessage for Quaternion {
    const DEF: &'static MsgDef = &QUATERNION;
}
impl RosMessage for Pose {
    const DEF: &'static MsgDef = &POSE;
}
impl RosMessage for PoseWithCovariance {
    const DEF: &'static MsgDef = &POSE_WITH_COVARIANCE;
}
impl RosMessage for Twist {
    const DEF: &'static MsgDef = &TWIST;
}
impl RosMessage for TwistStamped {
    const DEF: &'static MsgDef = &TWIST_STAMPED;
}
impl RosMessage for TwistWithCovariance {
    const DEF: &'static MsgDef = &TWIST_WITH_COVARIANCE;
}
impl RosMessage for Transform {
    const DEF: &'static MsgDef = &TRANSFORM;
}
impl RosMessage for TransformStamped {
    const DEF: &'static MsgDef = &TRANSFORM_STAMPED;
}
impl RosMessage for TFMessage {
    const DEF: &'static MsgDef = &TF_MESSAGE;
}
