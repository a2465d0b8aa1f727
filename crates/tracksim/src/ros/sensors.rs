//! The vehicle's sensors on ROS topics, each reading once, when it is new (at the sensor's own
//! rate): the same messages, frames and topics (`/<sensor name>`) as `run.mcap`
//! ([`crate::output::mcap`]) for the kinds a node publishes live:
//! - IMU: `sensor_msgs/Imu` in `<sensor>_link` (orientation in `odom`, covariances of its
//!   white noise on the diagonal);
//! - lidar: `sensor_msgs/LaserScan` for one scan line, else an organised
//!   `sensor_msgs/PointCloud2` (x y z float32 in `<sensor>_link`, NaN for no return);
//! - depth camera: `sensor_msgs/Image` `32FC1` (m along the optical axis) in
//!   `<sensor>_optical_frame`;
//! - encoders: `sensor_msgs/JointState` with the names of `/joint_states` (quantised; the
//!   flippers' velocity NaN: not measured).
//!
//! An elevation map is not published live (it is in `run.mcap`).

use super::dds::{DdsError, DdsNode, Pub};
use super::topics;
use crate::model::{Scenario, SensorKind, SensorModel};
use crate::output::mcap::{optical_frame, sensor_frame};
use crate::rosmsg::{
    Header, Image, Imu, JointState, LaserScan, PointCloud2, PointField, Quaternion, Vector3,
};
use crate::sensors::{Channel, Sensor, SensorSet};

/// A sensor's publisher, by the message its readings become.
enum Publisher {
    Imu(Pub<Imu>),
    Scan(Pub<LaserScan>),
    Cloud(Pub<PointCloud2>),
    Image(Pub<Image>),
    Joints(Pub<JointState>),
    None,
}

/// The sensors' publishers and the time of the reading each sent last.
pub struct SensorPublishers {
    pubs: Vec<Publisher>,
    sent: Vec<f64>,
    joint_names: Vec<String>,
}

fn data<'a>(chs: &'a [Channel], name: &str) -> &'a [f64] {
    chs.iter()
        .find(|c| c.name == name)
        .map_or(&[], |c| c.data.as_slice())
}

fn v3(a: &[f64]) -> Vector3 {
    match a {
        [x, y, z, ..] => Vector3 {
            x: *x,
            y: *y,
            z: *z,
        },
        _ => Vector3::default(),
    }
}

fn f32_bytes(values: &[f64]) -> Vec<u8> {
    values
        .iter()
        .flat_map(|v| (*v as f32).to_le_bytes())
        .collect()
}

impl SensorPublishers {
    /// A publisher per sensor of `sc`'s vehicle (an elevation map has none).
    pub fn new(node: &mut DdsNode, sc: &Scenario) -> Result<Self, DdsError> {
        let mut pubs = Vec::new();
        for m in &sc.vehicle.sensors {
            let t = topics::sensor(&m.name);
            pubs.push(match m.kind {
                SensorKind::Imu(_) => Publisher::Imu(node.publisher(&t, 10, false)?),
                SensorKind::Lidar(p) if p.elevation_rays == 1 => {
                    Publisher::Scan(node.publisher(&t, 10, false)?)
                }
                SensorKind::Lidar(_) => Publisher::Cloud(node.publisher(&t, 10, false)?),
                SensorKind::DepthCamera(_) => Publisher::Image(node.publisher(&t, 10, false)?),
                SensorKind::Encoders(_) => Publisher::Joints(node.publisher(&t, 10, false)?),
                SensorKind::ElevationMap(_) => Publisher::None,
            });
        }
        Ok(SensorPublishers {
            sent: vec![f64::NEG_INFINITY; pubs.len()],
            pubs,
            joint_names: super::messages::joint_names(sc),
        })
    }

    /// Publishes every reading of `set` newer than the last one sent.
    pub fn publish(&mut self, set: &SensorSet) {
        for i in 0..set.len().min(self.pubs.len()) {
            let t = set.reading_time(i);
            if t <= self.sent[i] {
                continue;
            }
            self.sent[i] = t;
            self.publish_one(set.sensor(i), t, i);
        }
    }

    fn publish_one(&self, s: &dyn Sensor, t: f64, i: usize) {
        let m: &SensorModel = s.model();
        let chs = s.channels();
        let header = Header::new(t, &sensor_frame(&m.name));
        match (&self.pubs[i], m.kind) {
            (Publisher::Imu(p), SensorKind::Imu(k)) => {
                let diag = |sigma: f64| {
                    let v = sigma * sigma;
                    [v, 0.0, 0.0, 0.0, v, 0.0, 0.0, 0.0, v]
                };
                let rate = m.rate_hz.sqrt();
                let q = data(chs, "orientation");
                let orientation = match q {
                    [x, y, z, w, ..] => Quaternion {
                        x: *x,
                        y: *y,
                        z: *z,
                        w: *w,
                    },
                    _ => Quaternion::default(),
                };
                p.publish(Imu {
                    header,
                    orientation,
                    orientation_covariance: [0.0; 9],
                    angular_velocity: v3(data(chs, "gyro")),
                    angular_velocity_covariance: diag(k.gyro_noise_density * rate),
                    linear_acceleration: v3(data(chs, "accel")),
                    linear_acceleration_covariance: diag(k.accel_noise_density * rate),
                });
            }
            (Publisher::Scan(p), SensorKind::Lidar(k)) => {
                let axes = s.axes();
                let az = axes
                    .iter()
                    .find(|a| a.name == "azimuth")
                    .map_or(&[][..], |a| a.data.as_slice());
                let first = az.first().copied().unwrap_or(0.0);
                let step = if az.len() > 1 { az[1] - az[0] } else { 0.0 };
                p.publish(LaserScan {
                    header,
                    angle_min: first as f32,
                    angle_max: az.last().copied().unwrap_or(0.0) as f32,
                    angle_increment: step as f32,
                    time_increment: 0.0,
                    scan_time: (1.0 / m.rate_hz) as f32,
                    range_min: k.min_range as f32,
                    range_max: k.max_range as f32,
                    ranges: data(chs, "range").iter().map(|r| *r as f32).collect(),
                    intensities: Vec::new(),
                });
            }
            (Publisher::Cloud(p), SensorKind::Lidar(k)) => {
                let xyz = data(chs, "points");
                p.publish(PointCloud2 {
                    header,
                    height: k.elevation_rays as u32,
                    width: k.azimuth_rays as u32,
                    fields: PointField::xyz32(),
                    is_bigendian: false,
                    point_step: 12,
                    row_step: 12 * k.azimuth_rays as u32,
                    data: f32_bytes(xyz),
                    is_dense: xyz.iter().all(|v| v.is_finite()),
                });
            }
            (Publisher::Image(p), SensorKind::DepthCamera(k)) => p.publish(Image {
                header: Header::new(t, &optical_frame(&m.name)),
                height: k.height as u32,
                width: k.width as u32,
                encoding: "32FC1".into(),
                is_bigendian: 0,
                step: 4 * k.width as u32,
                data: f32_bytes(data(chs, "depth")),
            }),
            (Publisher::Joints(p), SensorKind::Encoders(_)) => {
                let mut position = data(chs, "flipper_angle").to_vec();
                let mut velocity = vec![f64::NAN; position.len()];
                position.extend(data(chs, "belt_position"));
                velocity.extend(data(chs, "belt_speed"));
                p.publish(JointState {
                    header: Header::new(t, ""),
                    name: self.joint_names.clone(),
                    position,
                    velocity,
                    effort: Vec::new(),
                });
            }
            _ => {}
        }
    }
}
