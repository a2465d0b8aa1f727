//! `sensor_msgs`: `JointState`, `Imu`, `LaserScan`, `PointField`, `PointCloud2`, `Image`,
//! `CompressedImage`, `RegionOfInterest`, `CameraInfo`.

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

/// `sensor_msgs/CompressedImage`: an image as the bytes of an image file (`format`, as
/// ROS's `compressed_image_transport` writes it: `"rgb8; png compressed bgr8"` for a PNG of an
/// rgb8 image).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CompressedImage {
    /// Time and the camera's optical frame.
    pub header: Header,
    /// The encoding and the compression (`"rgb8; png compressed bgr8"`, `"jpeg"`, ...).
    pub format: String,
    /// The file's bytes.
    #[serde(with = "byte_seq")]
    pub data: Vec<u8>,
}

/// `sensor_msgs/RegionOfInterest`: a window of an image (all 0: the whole image).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RegionOfInterest {
    /// Leftmost column, pixels.
    pub x_offset: u32,
    /// Top row, pixels.
    pub y_offset: u32,
    /// Rows, pixels.
    pub height: u32,
    /// Columns, pixels.
    pub width: u32,
    /// Whether the window is to be rectified.
    pub do_rectify: bool,
}

/// `sensor_msgs/CameraInfo`: a camera's calibration for the images of the same stamp and
/// frame (its optical frame: z forward, x right, y down).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CameraInfo {
    /// Time and the camera's optical frame.
    pub header: Header,
    /// Rows, pixels.
    pub height: u32,
    /// Columns, pixels.
    pub width: u32,
    /// Distortion model (`"plumb_bob"`).
    pub distortion_model: String,
    /// Distortion coefficients (plumb bob: k1, k2, t1, t2, k3; zeros for a pinhole).
    pub d: Vec<f64>,
    /// Intrinsic matrix K (row-major 3 x 3): `[fx 0 cx; 0 fy cy; 0 0 1]`, pixels.
    #[serde(with = "fixed_array")]
    pub k: [f64; 9],
    /// Rectification rotation (row-major 3 x 3; identity for a monocular camera).
    #[serde(with = "fixed_array")]
    pub r: [f64; 9],
    /// Projection matrix P (row-major 3 x 4): `[fx 0 cx Tx; 0 fy cy Ty; 0 0 1 0]`, pixels.
    #[serde(with = "fixed_array")]
    pub p: [f64; 12],
    /// Horizontal binning (0 or 1: none).
    pub binning_x: u32,
    /// Vertical binning (0 or 1: none).
    pub binning_y: u32,
    /// Region of interest (all 0: the whole image).
    pub roi: RegionOfInterest,
}

impl CameraInfo {
    /// A distortion-free pinhole camera of `width` x `height` pixels with intrinsic matrix `k`
    /// (row-major), stamped `header`: plumb bob with zero coefficients, R the identity, P
    /// `[K | 0]`.
    pub fn pinhole(header: Header, width: u32, height: u32, k: [f64; 9]) -> Self {
        CameraInfo {
            header,
            height,
            width,
            distortion_model: "plumb_bob".into(),
            d: vec![0.0; 5],
            k,
            r: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
            p: [
                k[0], k[1], k[2], 0.0, k[3], k[4], k[5], 0.0, k[6], k[7], k[8], 0.0,
            ],
            binning_x: 0,
            binning_y: 0,
            roi: RegionOfInterest::default(),
        }
    }
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

/// `sensor_msgs/CompressedImage`.
pub const COMPRESSED_IMAGE: MsgDef = MsgDef {
    name: "sensor_msgs/CompressedImage",
    text: "std_msgs/Header header\nstring format\nuint8[] data\n",
    deps: &[&HEADER],
};
/// `sensor_msgs/RegionOfInterest`.
pub const REGION_OF_INTEREST: MsgDef = MsgDef {
    name: "sensor_msgs/RegionOfInterest",
    text: "uint32 x_offset\nuint32 y_offset\nuint32 height\nuint32 width\nbool do_rectify\n",
    deps: &[],
};
/// `sensor_msgs/CameraInfo`.
pub const CAMERA_INFO: MsgDef = MsgDef {
    name: "sensor_msgs/CameraInfo",
    text: "std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\nfloat64[] d\nfloat64[9] k\nfloat64[9] r\nfloat64[12] p\nuint32 binning_x\nuint32 binning_y\nsensor_msgs/RegionOfInterest roi\n",
    deps: &[&HEADER, &REGION_OF_INTEREST],
};

impl RosMessage for CompressedImage {
    const DEF: &'static MsgDef = &COMPRESSED_IMAGE;
}
impl RosMessage for RegionOfInterest {
    const DEF: &'static MsgDef = &REGION_OF_INTEREST;
}
impl RosMessage for CameraInfo {
    const DEF: &'static MsgDef = &CAMERA_INFO;
}
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
