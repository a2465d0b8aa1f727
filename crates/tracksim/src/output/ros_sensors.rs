//! A sensor reading as its ROS 2 message, for `run.mcap` (from the recorded streams) and for
//! the ROS node (from the live sensors) alike, on topic `/<sensor name>`:
//! - IMU: `sensor_msgs/Imu` in `<sensor>_link` (orientation in `map`, covariances of its
//!   white noise on the diagonal);
//! - lidar: `sensor_msgs/LaserScan` for one scan line, else an organised
//!   `sensor_msgs/PointCloud2` (elevation rows of azimuth columns, x y z float32 in
//!   `<sensor>_link`, NaN for no return);
//! - depth camera: `sensor_msgs/Image` `32FC1` (m along the optical axis, REP 117
//!   infinities) in `<sensor>_optical_frame`;
//! - colour camera ([`CameraMessages`]): `sensor_msgs/CompressedImage` (PNG,
//!   `"rgb8; png compressed bgr8"` as `compressed_image_transport` names it) on
//!   `/<sensor>/compressed` and `sensor_msgs/CameraInfo` (K from the field of view, no
//!   distortion) on `/<sensor>/camera_info`, both in `<sensor>_optical_frame` with the same
//!   stamp, and on request (`raw_images`) the raw `sensor_msgs/Image` `rgb8` on `/<sensor>`;
//! - elevation map: `sensor_msgs/PointCloud2` of its cells' surface points in `map`
//!   (organised: `x` rows of `y` columns, NaN where a cell is unknown);
//! - encoders: `sensor_msgs/JointState` with the names of `/joint_states` (quantised; the
//!   flippers' velocity NaN: not measured).

use crate::model::{SensorKind, SensorModel};
use crate::rosmsg::{
    CameraInfo, CompressedImage, Header, Image, Imu, JointState, LaserScan, PointCloud2,
    PointField, Quaternion, Vector3,
};
use glam::{DQuat, DVec3};

/// The world frame (REP 105 `map`).
pub const MAP_FRAME: &str = "map";

/// The frame of sensor `name`.
pub fn sensor_frame(name: &str) -> String {
    format!("{name}_link")
}

/// The optical frame of camera `name` (z forward, x right, y down).
pub fn optical_frame(name: &str) -> String {
    format!("{name}_optical_frame")
}

fn is_camera(m: &SensorModel) -> bool {
    matches!(
        m.kind,
        SensorKind::DepthCamera(_) | SensorKind::RgbCamera(_)
    )
}

/// The frame sensor `m` is mounted as on `/tf_static`: its `frame_id` if the file sets one
/// (a camera's `frame_id` names its optical frame instead), else `<name>_link`.
pub fn link_frame(m: &SensorModel) -> String {
    match &m.frame_id {
        Some(f) if !is_camera(m) => f.clone(),
        _ => sensor_frame(&m.name),
    }
}

/// The frame of sensor `m`'s messages (`header.frame_id`): its `frame_id` if the file sets
/// one, else a camera's `<name>_optical_frame` and another sensor's `<name>_link` (an
/// elevation map's messages are in `map` whatever it is).
pub fn message_frame(m: &SensorModel) -> String {
    match &m.frame_id {
        Some(f) => f.clone(),
        None if is_camera(m) => optical_frame(&m.name),
        None => sensor_frame(&m.name),
    }
}

/// The `format` of a colour camera's `sensor_msgs/CompressedImage`: a PNG of an rgb8 image,
/// named as ROS's `compressed_image_transport` names it (the `bgr8` is OpenCV's order before
/// encoding; the PNG holds ordinary RGB).
pub const PNG_FORMAT: &str = "rgb8; png compressed bgr8";

/// The topic of a colour camera's compressed images, from its image topic (`/<sensor>`).
pub fn compressed_topic(image_topic: &str) -> String {
    format!("{image_topic}/compressed")
}

/// The topic of a colour camera's calibration, from its image topic (`/<sensor>`).
pub fn camera_info_topic(image_topic: &str) -> String {
    format!("{image_topic}/camera_info")
}

/// A colour camera's reading: the image (raw and PNG) and the camera's calibration, all in
/// its optical frame with the same stamp.
#[derive(Clone, Debug)]
pub struct CameraMessages {
    /// The raw image (`rgb8`; published on `/<sensor>` only with `raw_images`).
    pub image: Image,
    /// The image as PNG ([`PNG_FORMAT`]), on `/<sensor>/compressed`.
    pub compressed: CompressedImage,
    /// The calibration (K from the field of view), on `/<sensor>/camera_info`.
    pub info: CameraInfo,
}

/// One reading as its message.
#[derive(Clone, Debug)]
pub enum SensorMessage {
    /// An IMU reading.
    Imu(Imu),
    /// A one-line lidar scan.
    Scan(LaserScan),
    /// A multi-line lidar scan or an elevation map.
    Cloud(PointCloud2),
    /// A depth image.
    Image(Image),
    /// A colour camera's image and calibration.
    Camera(Box<CameraMessages>),
    /// An encoder reading.
    Joints(JointState),
}

/// Where a reading's values come from: `channel(name)` one reading of a channel (empty if
/// there is none), `axis(name)` a fixed axis of the sensor (`azimuth`, `x`, `y`), `png(name)`
/// an image channel's reading as the PNG bytes already made of it (`None`: encoded from
/// `channel`).
pub struct Reading<'a> {
    /// A channel's values at this reading.
    pub channel: &'a dyn Fn(&str) -> Vec<f64>,
    /// A fixed axis.
    pub axis: &'a dyn Fn(&str) -> Vec<f64>,
    /// An image channel's PNG bytes, when stored as such (a run's stream).
    pub png: &'a dyn Fn(&str) -> Option<Vec<u8>>,
}

/// Little-endian float32 bytes of `values`.
fn f32_bytes(values: impl IntoIterator<Item = f64>) -> Vec<u8> {
    values
        .into_iter()
        .flat_map(|v| (v as f32).to_le_bytes())
        .collect()
}

/// An organised cloud of `rows` x `cols` x y z float32 points.
fn cloud(header: Header, rows: usize, cols: usize, xyz: Vec<f64>) -> PointCloud2 {
    let is_dense = xyz.iter().all(|v| v.is_finite());
    PointCloud2 {
        header,
        height: rows as u32,
        width: cols as u32,
        fields: PointField::xyz32(),
        is_bigendian: false,
        point_step: 12,
        row_step: 12 * cols as u32,
        data: f32_bytes(xyz),
        is_dense,
    }
}

/// The reading of `m` taken at `t` s as its message; `joint_names` are `/joint_states`'
/// names (for encoders). An incomplete reading is an error naming the sensor.
pub fn sensor_message(
    m: &SensorModel,
    t: f64,
    r: &Reading,
    joint_names: &[String],
) -> Result<SensorMessage, String> {
    let incomplete = || format!("sensor {}: the reading at {t} s is incomplete", m.name);
    let (header, frame) = (Header::new(t, &link_frame(m)), message_frame(m));
    Ok(match m.kind {
        SensorKind::Imu(p) => {
            let (a, g, q) = (
                (r.channel)("accel"),
                (r.channel)("gyro"),
                (r.channel)("orientation"),
            );
            if a.len() < 3 || g.len() < 3 || q.len() < 4 {
                return Err(incomplete());
            }
            let diag = |sigma: f64| {
                let v = sigma * sigma;
                [v, 0.0, 0.0, 0.0, v, 0.0, 0.0, 0.0, v]
            };
            let rate = m.rate_hz.sqrt();
            let v3 = |v: &[f64]| Vector3 {
                x: v[0],
                y: v[1],
                z: v[2],
            };
            SensorMessage::Imu(Imu {
                header,
                orientation: Quaternion {
                    x: q[0],
                    y: q[1],
                    z: q[2],
                    w: q[3],
                },
                orientation_covariance: [0.0; 9],
                angular_velocity: v3(&g),
                angular_velocity_covariance: diag(p.gyro_noise_density * rate),
                linear_acceleration: v3(&a),
                linear_acceleration_covariance: diag(p.accel_noise_density * rate),
            })
        }
        SensorKind::Lidar(p) if p.elevation_rays == 1 => {
            let az = (r.axis)("azimuth");
            let first = az.first().copied().unwrap_or(0.0);
            let last = az.last().copied().unwrap_or(0.0);
            let step = if az.len() > 1 { az[1] - az[0] } else { 0.0 };
            SensorMessage::Scan(LaserScan {
                header,
                angle_min: first as f32,
                angle_max: last as f32,
                angle_increment: step as f32,
                time_increment: 0.0,
                scan_time: (1.0 / m.rate_hz) as f32,
                range_min: p.min_range as f32,
                range_max: p.max_range as f32,
                ranges: (r.channel)("range").iter().map(|v| *v as f32).collect(),
                intensities: Vec::new(),
            })
        }
        SensorKind::Lidar(p) => SensorMessage::Cloud(cloud(
            header,
            p.elevation_rays,
            p.azimuth_rays,
            (r.channel)("points"),
        )),
        SensorKind::DepthCamera(p) => SensorMessage::Image(Image {
            header: Header::new(t, &frame),
            height: p.height as u32,
            width: p.width as u32,
            encoding: "32FC1".into(),
            is_bigendian: 0,
            step: 4 * p.width as u32,
            data: f32_bytes((r.channel)("depth")),
        }),
        SensorKind::RgbCamera(p) => {
            let msgs = camera_messages(&frame, t, &p, (r.channel)("rgb"), (r.png)("rgb"));
            if msgs.image.data.len() != 3 * p.intrinsics.width * p.intrinsics.height {
                return Err(incomplete());
            }
            SensorMessage::Camera(Box::new(msgs))
        }
        SensorKind::Encoders(_) => {
            let mut position = (r.channel)("flipper_angle");
            let mut velocity = vec![f64::NAN; position.len()];
            position.extend((r.channel)("belt_position"));
            velocity.extend((r.channel)("belt_speed"));
            SensorMessage::Joints(JointState {
                header: Header::new(t, ""),
                name: joint_names.to_vec(),
                position,
                velocity,
                effort: Vec::new(),
            })
        }
        SensorKind::ElevationMap(_) => {
            let (xs, ys) = ((r.axis)("x"), (r.axis)("y"));
            let (h, pos, q) = (
                (r.channel)("height"),
                (r.channel)("position"),
                (r.channel)("orientation"),
            );
            if pos.len() < 3 || q.len() < 4 || h.len() != xs.len() * ys.len() {
                return Err(incomplete());
            }
            // The map's axes follow the robot's heading (yaw only).
            let heading = DQuat::from_xyzw(q[0], q[1], q[2], q[3]) * DVec3::X;
            let (s, c) = heading.y.atan2(heading.x).sin_cos();
            let mut xyz = Vec::with_capacity(3 * h.len());
            for (i, xi) in xs.iter().enumerate() {
                for (j, yj) in ys.iter().enumerate() {
                    let z = h[i * ys.len() + j];
                    if z.is_finite() {
                        xyz.extend([
                            pos[0] + c * xi - s * yj,
                            pos[1] + s * xi + c * yj,
                            pos[2] + z,
                        ]);
                    } else {
                        xyz.extend([f64::NAN; 3]);
                    }
                }
            }
            SensorMessage::Cloud(cloud(Header::new(t, MAP_FRAME), xs.len(), ys.len(), xyz))
        }
    })
}

/// A colour camera's reading (`rgb`: 8-bit levels, rows from the top; `png`: the same image
/// as PNG bytes if already encoded) as its messages in its optical frame `frame`.
fn camera_messages(
    frame: &str,
    t: f64,
    p: &crate::model::RgbCameraModel,
    rgb: Vec<f64>,
    png: Option<Vec<u8>>,
) -> CameraMessages {
    let i = p.intrinsics;
    let (w, h) = (i.width as u32, i.height as u32);
    let header = Header::new(t, frame);
    let data: Vec<u8> = rgb
        .iter()
        .map(|v| v.round().clamp(0.0, 255.0) as u8)
        .collect();
    let png = png.unwrap_or_else(|| crate::render::encode::rgb8_png(i.width, i.height, &data));
    CameraMessages {
        compressed: CompressedImage {
            header: header.clone(),
            format: PNG_FORMAT.into(),
            data: png,
        },
        info: CameraInfo::pinhole(header.clone(), w, h, i.k_matrix()),
        image: Image {
            header,
            height: h,
            width: w,
            encoding: "rgb8".into(),
            is_bigendian: 0,
            step: 3 * w,
            data,
        },
    }
}
