//! A sensor reading as its ROS 2 message, for `run.mcap` (from the recorded streams) and for
//! the ROS node (from the live sensors) alike, on topic `/<sensor name>`:
//! - IMU: `sensor_msgs/Imu` in `<sensor>_link` (orientation in `map`, covariances of its
//!   white noise on the diagonal);
//! - lidar: `sensor_msgs/LaserScan` for one scan line, else an organised
//!   `sensor_msgs/PointCloud2` (elevation rows of azimuth columns, x y z float32 in
//!   `<sensor>_link`, NaN for no return);
//! - depth camera: `sensor_msgs/Image` `32FC1` (m along the optical axis, REP 117
//!   infinities) in `<sensor>_optical_frame`;
//! - elevation map: `sensor_msgs/PointCloud2` of its cells' surface points in `map`
//!   (organised: `x` rows of `y` columns, NaN where a cell is unknown);
//! - encoders: `sensor_msgs/JointState` with the names of `/joint_states` (quantised; the
//!   flippers' velocity NaN: not measured).

use crate::model::{SensorKind, SensorModel};
use crate::rosmsg::{
    Header, Image, Imu, JointState, LaserScan, PointCloud2, PointField, Quaternion, Vector3,
};
use glam::{DQuat, DVec3};

/// The world frame (REP 105 `map`).
pub const MAP_FRAME: &str = "map";

/// The frame of sensor `name`.
pub fn sensor_frame(name: &str) -> String {
    format!("{name}_link")
}

/// The optical frame of depth camera `name` (z forward, x right, y down).
pub fn optical_frame(name: &str) -> String {
    format!("{name}_optical_frame")
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
    /// An encoder reading.
    Joints(JointState),
}

/// Where a reading's values come from: `channel(name)` one reading of a channel (empty if
/// there is none), `axis(name)` a fixed axis of the sensor (`azimuth`, `x`, `y`).
pub struct Reading<'a> {
    /// A channel's values at this reading.
    pub channel: &'a dyn Fn(&str) -> Vec<f64>,
    /// A fixed axis.
    pub axis: &'a dyn Fn(&str) -> Vec<f64>,
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
    let header = Header::new(t, &sensor_frame(&m.name));
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
            header: Header::new(t, &optical_frame(&m.name)),
            height: p.height as u32,
            width: p.width as u32,
            encoding: "32FC1".into(),
            is_bigendian: 0,
            step: 4 * p.width as u32,
            data: f32_bytes((r.channel)("depth")),
        }),
        SensorKind::RgbCamera(p) => rgb_image(&m.name, t, &p, (r.channel)("rgb")),
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

/// A colour camera's reading as `sensor_msgs/Image` (`rgb8`, rows from the top) in its
/// optical frame.
fn rgb_image(name: &str, t: f64, p: &crate::model::RgbCameraModel, rgb: Vec<f64>) -> SensorMessage {
    let w = p.intrinsics.width as u32;
    SensorMessage::Image(Image {
        header: Header::new(t, &optical_frame(name)),
        height: p.intrinsics.height as u32,
        width: w,
        encoding: "rgb8".into(),
        is_bigendian: 0,
        step: 3 * w,
        data: rgb
            .iter()
            .map(|v| v.round().clamp(0.0, 255.0) as u8)
            .collect(),
    })
}
