//! The vehicle's sensors on ROS topics (`/<sensor name>`, `/<robot>/<sensor name>` in a
//! robot's namespace), each reading once, when it is new
//! (at the sensor's own rate): the same messages and frames as `run.mcap`
//! ([`crate::output::ros_sensors`] builds them for both), the elevation map included. A colour
//! camera publishes `sensor_msgs/CompressedImage` (PNG) on `/<sensor>/compressed` and
//! `sensor_msgs/CameraInfo` on `/<sensor>/camera_info`, and with `raw_images` the raw
//! `sensor_msgs/Image` (`rgb8`) on `/<sensor>`.

use super::dds::{DdsError, DdsNode, Pub};
use super::topics;
use crate::model::{Scenario, SensorKind};
use crate::output::ros_names::Namespace;
use crate::output::ros_sensors::{
    Reading, SensorMessage, camera_info_topic, compressed_topic, sensor_message,
};
use crate::rosmsg::{CameraInfo, CompressedImage, Image, Imu, JointState, LaserScan, PointCloud2};
use crate::sensors::{Channel, SensorSet};

/// A sensor's publisher, by the message its readings become.
enum Publisher {
    Imu(Pub<Imu>),
    Scan(Pub<LaserScan>),
    Cloud(Pub<PointCloud2>),
    Image(Pub<Image>),
    Joints(Pub<JointState>),
    /// A colour camera: raw images (with `raw_images`), compressed images, calibration.
    Camera(Box<CameraPubs>),
}

/// A colour camera's publishers.
struct CameraPubs {
    raw: Option<Pub<Image>>,
    compressed: Pub<CompressedImage>,
    info: Pub<CameraInfo>,
}

/// The sensors' publishers and the time of the reading each sent last.
pub struct SensorPublishers {
    pubs: Vec<Publisher>,
    sent: Vec<f64>,
    joint_names: Vec<String>,
    ns: Namespace,
}

fn data(chs: &[Channel], name: &str) -> Vec<f64> {
    chs.iter()
        .find(|c| c.name == name)
        .map_or_else(Vec::new, |c| c.data.clone())
}

impl SensorPublishers {
    /// A publisher per sensor of `sc`'s vehicle, in namespace `ns` (topics and frames);
    /// colour cameras' raw images too with `raw_images`.
    pub fn new(
        node: &mut DdsNode,
        sc: &Scenario,
        ns: &Namespace,
        raw_images: bool,
    ) -> Result<Self, DdsError> {
        let mut pubs = Vec::new();
        for m in &sc.vehicle.sensors {
            let t = ns.topic(&topics::sensor(&m.name));
            pubs.push(match m.kind {
                SensorKind::Imu(_) => Publisher::Imu(node.publisher(&t, 10, false)?),
                SensorKind::Lidar(p) if p.elevation_rays == 1 => {
                    Publisher::Scan(node.publisher(&t, 10, false)?)
                }
                SensorKind::Lidar(_) | SensorKind::ElevationMap(_) => {
                    Publisher::Cloud(node.publisher(&t, 10, false)?)
                }
                SensorKind::DepthCamera(_) => Publisher::Image(node.publisher(&t, 10, false)?),
                SensorKind::RgbCamera(_) => Publisher::Camera(Box::new(CameraPubs {
                    raw: match raw_images {
                        true => Some(node.publisher(&t, 10, false)?),
                        false => None,
                    },
                    compressed: node.publisher(&compressed_topic(&t), 10, false)?,
                    info: node.publisher(&camera_info_topic(&t), 10, false)?,
                })),
                SensorKind::Encoders(_) => Publisher::Joints(node.publisher(&t, 10, false)?),
            });
        }
        Ok(SensorPublishers {
            sent: vec![f64::NEG_INFINITY; pubs.len()],
            pubs,
            joint_names: crate::output::ros_messages::joint_names(sc),
            ns: ns.clone(),
        })
    }

    /// Publishes every reading of `set` newer than the last one sent; a reading that cannot
    /// become a message is reported to `warn`.
    pub fn publish(&mut self, set: &SensorSet, warn: &mut dyn FnMut(&str)) {
        for i in 0..set.len().min(self.pubs.len()) {
            let t = set.reading_time(i);
            if t <= self.sent[i] {
                continue;
            }
            self.sent[i] = t;
            let s = set.sensor(i);
            let chs = s.channels();
            let axes = s.axes();
            let r = Reading {
                channel: &|name| data(chs, name),
                axis: &|name| data(&axes, name),
                png: &|_| None,
            };
            match (
                &self.pubs[i],
                sensor_message(s.model(), t, &r, &self.joint_names).map(|m| self.ns.sensor(m)),
            ) {
                (Publisher::Imu(p), Ok(SensorMessage::Imu(m))) => p.publish(m),
                (Publisher::Scan(p), Ok(SensorMessage::Scan(m))) => p.publish(m),
                (Publisher::Cloud(p), Ok(SensorMessage::Cloud(m))) => p.publish(m),
                (Publisher::Image(p), Ok(SensorMessage::Image(m))) => p.publish(m),
                (Publisher::Joints(p), Ok(SensorMessage::Joints(m))) => p.publish(m),
                (Publisher::Camera(p), Ok(SensorMessage::Camera(m))) => {
                    let m = *m;
                    if let Some(raw) = &p.raw {
                        raw.publish(m.image);
                    }
                    p.compressed.publish(m.compressed);
                    p.info.publish(m.info);
                }
                (_, Err(e)) => warn(&e),
                _ => warn(&format!(
                    "sensor {}: its message does not match its topic",
                    s.model().name
                )),
            }
        }
    }
}
