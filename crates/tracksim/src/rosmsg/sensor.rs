//! `sensor_msgs`: `JointState`, `Imu`, `LaserScan`, `PointField`, `PointCloud2`, `Image`.

use super::builtin::{HEADER, Header};
use super::cdr::{byte_seq, fixed_array};
use super::geometry::{QUATERNION, Quaternion, VECTOR3, Vector3};
use super::schema::{MsgDef, RosMessage};
use serde::{Deserialize, Serialize};

/// `sensor_msgs/JointState`: joints by name; each array is empty or as long as `name`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct JointState {
    /// Time (the frame is not used).
    pub header: Header,
    /// Joint names.
    pub name: Vec<String>,
    /// Positions, rad (revolute) or m (linear).
    pub position: Vec<f64>,
    /// Velocities, rad/s or m/s.
    pub velocity: Vec<f64>,
    /// Efforts, N m or N.
    pub effort: Vec<f64>,
}

/// `sensor_msgs/Imu`: orientation, angular velocity and linear acceleration (specific force) in
/// the header's frame; a covariance of all 0 is unknown, element 0 at -1 means not measured.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Imu {
    /// Time and the sensor's frame.
    pub header: Header,
    /// Orientation of the sensor frame in the world (odom) frame.
    pub orientation: Quaternion,
    /// Covariance of the orientation (row-major 3 x 3), rad^2.
    #[serde(with = "fixed_array")]
    pub orientation_covariance: [f64; 9],
    /// Angular velocity, rad/s.
    pub angular_velocity: Vector3,
    /// Its covariance, (rad/s)^2.
    #[serde(with = "fixed_array")]
    pub angular_velocity_covariance: [f64; 9],
    /// Linear acceleration (specific force: +9.81 along z at rest), m/s^2.
    pub linear_acceleration: Vector3,
    /// Its covariance, (m/s^2)^2.
    #[serde(with = "fixed_array")]
    pub linear_acceleration_covariance: [f64; 9],
}

/// `sensor_msgs/LaserScan`: one scan line, counter-clockwise from `angle_min` (REP 117: `+inf`
/// no return within range, `-inf` too near).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct LaserScan {
    /// Time and the scanner's frame.
    pub header: Header,
    /// First ray's angle about z, rad.
    pub angle_min: f32,
    /// Last ray's angle, rad.
    pub angle_max: f32,
    /// Angle between rays, rad.
    pub angle_increment: f32,
    /// Time between rays, s.
    pub time_increment: f32,
    /// Time between scans, s.
    pub scan_time: f32,
    /// Shortest range, m.
    pub range_min: f32,
    /// Longest range, m.
    pub range_max: f32,
    /// Ranges, m.
    pub ranges: Vec<f32>,
    /// Intensities (empty: none).
    pub intensities: Vec<f32>,
}

/// `sensor_msgs/PointField`: one field of a [`PointCloud2`]'s points.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PointField {
    /// Field name (`x`, `y`, `z`).
    pub name: String,
    /// Byte offset in a point.
    pub offset: u32,
    /// Type ([`PointField::FLOAT32`], ...).
    pub datatype: u8,
    /// Number of elements.
    pub count: u32,
}

impl PointField {
    /// `datatype` of a 32-bit float.
    pub const FLOAT32: u8 = 7;
    /// `datatype` of a 64-bit float.
    pub const FLOAT64: u8 = 8;

    /// The fields `x`, `y`, `z` as float32 (a 12-byte point).
    pub fn xyz32() -> Vec<PointField> {
        ["x", "y", "z"]
            .iter()
            .enumerate()
            .map(|(i, n)| PointField {
                name: n.to_string(),
                offset: 4 * i as u32,
                datatype: PointField::FLOAT32,
                count: 1,
            })
            .collect()
    }
}

/// `sensor_msgs/PointCloud2`: points as packed bytes (`height` rows of `width`; organised
/// clouds keep a NaN point where a ray saw nothing).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PointCloud2 {
    /// Time and the points' frame.
    pub header: Header,
    /// Rows.
    pub height: u32,
    /// Points per row.
    pub width: u32,
    /// What a point holds.
    pub fields: Vec<PointField>,
    /// Byte order of `data` (false: little-endian).
    pub is_bigendian: bool,
    /// Bytes per point.
    pub point_step: u32,
    /// Bytes per row.
    pub row_step: u32,
    /// The points.
    #[serde(with = "byte_seq")]
    pub data: Vec<u8>,
    /// True when no point is invalid (NaN).
    pub is_dense: bool,
}

/// `sensor_msgs/Image`: pixels row by row from the top-left (a depth image: `32FC1` in m).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Image {
    /// Time and the camera's optical frame (z forward, x right, y down).
    pub header: Header,
    /// Rows.
    pub height: u32,
    /// Columns.
    pub width: u32,
    /// Pixel encoding (`32FC1`).
    pub encoding: String,
    /// Byte order of `data` (0: little-endian).
    pub is_bigendian: u8,
    /// Bytes per row.
    pub step: u32,
    /// The pixels.
    #[serde(with = "byte_seq")]
    pub data: Vec<u8>,
}

/// `sensor_msgs/JointState`.
pub const JOINT_STATE: MsgDef = MsgDef {
    name: "sensor_msgs/JointState",
    text: "std_msgs/Header header\nstring[] name\nfloat64[] position\nfloat64[] velocity\nfloat64[] effort\n",
    deps: &[&HEADER],
};
/// `sensor_msgs/Imu`.
pub const IMU: MsgDef = MsgDef {
    name: "sensor_msgs/Imu",
    text: "std_msgs/Header header\ngeometry_msgs/Quaternion orientation\nfloat64[9] orientation_covariance\ngeometry_msgs/Vector3 angular_velocity\nfloat64[9] angular_velocity_covariance\ngeometry_msgs/Vector3 linear_acceleration\nfloat64[9] linear_acceleration_covariance\n",
    deps: &[&HEADER, &QUATERNION, &VECTOR3],
};
/// `sensor_msgs/LaserScan`.
pub const LASER_SCAN: MsgDef = MsgDef {
    name: "sensor_msgs/LaserScan",
    text: "std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\nfloat32 angle_increment\nfloat32 time_increment\nfloat32 scan_time\nfloat32 range_min\nfloat32 range_max\nfloat32[] ranges\nfloat32[] intensities\n",
    deps: &[&HEADER],
};
/// `sensor_msgs/PointField`.
pub const POINT_FIELD: MsgDef = MsgDef {
    name: "sensor_msgs/PointField",
    text: "uint8 INT8=1\nuint8 UINT8=2\nuint8 INT16=3\nuint8 UINT16=4\nuint8 INT32=5\nuint8 UINT32=6\nuint8 FLOAT32=7\nuint8 FLOAT64=8\nstring name\nuint32 offset\nuint8 datatype\nuint32 count\n",
    deps: &[],
};
/// `sensor_msgs/PointCloud2`.
pub const POINT_CLOUD2: MsgDef = MsgDef {
    name: "sensor_msgs/PointCloud2",
    text: "std_msgs/Header header\nuint32 height\nuint32 width\nsensor_msgs/PointField[] fields\nbool is_bigendian\nuint32 point_step\nuint32 row_step\nuint8[] data\nbool is_dense\n",
    deps: &[&HEADER, &POINT_FIELD],
};
/// `sensor_msgs/Image`.
pub const IMAGE: MsgDef = MsgDef {
    name: "sensor_msgs/Image",
    text: "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\nuint32 step\nuint8[] data\n",
    deps: &[&HEADER],
};

impl RosMessage for JointState {
    const DEF: &'static MsgDef = &JOINT_STATE;
}
impl RosMessage for Imu {
    const DEF: &'static MsgDef = &IMU;
}
impl RosMessage for LaserScan {
    const DEF: &'static MsgDef = &LASER_SCAN;
}
impl RosMessage for PointField {
    const DEF: &'static MsgDef = &POINT_FIELD;
}
impl RosMessage for PointCloud2 {
    const DEF: &'static MsgDef = &POINT_CLOUD2;
}
impl RosMessage for Image {
    const DEF: &'static MsgDef = &IMAGE;
}
