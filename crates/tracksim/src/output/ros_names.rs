//! A robot's ROS names in a world of several robots ([`Namespace`]), the way ROS 2 multi-robot
//! stacks expect them: its topics under `/<name>/` (`/a/cmd_vel`, `/a/odom`), its frames
//! prefixed `<name>/` (tf `a/odom -> a/base_link`, `a/imu_link`), the world's own names
//! shared (`/clock`, `/tf`, `/tf_static`, `/rosout`, the frame `map`). The ROS 2 node
//! (`crate::ros`) and the world's `run.mcap` ([`super::mcap`]) name robots with it, so the two
//! cannot disagree. A robot without a namespace keeps the one-robot names.

use super::ros_sensors::{MAP_FRAME, SensorMessage};
use crate::rosmsg::{Header, Odometry, TFMessage, TrackStates};

/// The topics every robot shares: one clock and one transform tree for the world.
pub const SHARED_TOPICS: [&str; 4] = ["/clock", "/tf", "/tf_static", "/rosout"];

/// A robot's namespace (`None`: the one-robot names, unprefixed).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Namespace(Option<String>);

impl Namespace {
    /// No namespace: topics and frames as a one-robot node names them.
    pub fn none() -> Self {
        Namespace(None)
    }

    /// The namespace of robot `name` (a ROS-safe name, as `[[vehicles]]` names are checked);
    /// an empty name is no namespace.
    pub fn robot(name: &str) -> Self {
        let n = name.trim_matches('/');
        Namespace((!n.is_empty()).then(|| n.to_string()))
    }

    /// The name, if any.
    pub fn name(&self) -> Option<&str> {
        self.0.as_deref()
    }

    /// Topic `topic` (absolute, e.g. `/odom`) of this robot: `/<name>/odom`; a shared topic
    /// ([`SHARED_TOPICS`]) stays as it is.
    pub fn topic(&self, topic: &str) -> String {
        match &self.0 {
            Some(n) if !SHARED_TOPICS.contains(&topic) => {
                format!("/{n}/{}", topic.trim_start_matches('/'))
            }
            _ => topic.to_string(),
        }
    }

    /// Frame `frame` of this robot: `<name>/<frame>`; the world's frame `map` and the empty
    /// frame (no frame) stay as they are.
    pub fn frame(&self, frame: &str) -> String {
        match &self.0 {
            Some(n) if !frame.is_empty() && frame != MAP_FRAME => format!("{n}/{frame}"),
            _ => frame.to_string(),
        }
    }

    fn header(&self, h: &mut Header) {
        h.frame_id = self.frame(&h.frame_id);
    }

    /// A transform message with every parent and child frame in this namespace.
    pub fn tf(&self, mut m: TFMessage) -> TFMessage {
        for t in &mut m.transforms {
            self.header(&mut t.header);
            t.child_frame_id = self.frame(&t.child_frame_id);
        }
        m
    }

    /// An odometry message with its frame and child frame in this namespace.
    pub fn odometry(&self, mut m: Odometry) -> Odometry {
        self.header(&mut m.header);
        m.child_frame_id = self.frame(&m.child_frame_id);
        m
    }

    /// A per-track message with its frame in this namespace.
    pub fn track_states(&self, mut m: TrackStates) -> TrackStates {
        self.header(&mut m.header);
        m
    }

    /// A sensor's message with its frame in this namespace (an elevation map stays in `map`).
    pub fn sensor(&self, m: SensorMessage) -> SensorMessage {
        match m {
            SensorMessage::Imu(mut x) => {
                self.header(&mut x.header);
                SensorMessage::Imu(x)
            }
            SensorMessage::Scan(mut x) => {
                self.header(&mut x.header);
                SensorMessage::Scan(x)
            }
            SensorMessage::Cloud(mut x) => {
                self.header(&mut x.header);
                SensorMessage::Cloud(x)
            }
            SensorMessage::Image(mut x) => {
                self.header(&mut x.header);
                SensorMessage::Image(x)
            }
            SensorMessage::Camera(mut x) => {
                self.header(&mut x.image.header);
                self.header(&mut x.compressed.header);
                self.header(&mut x.info.header);
                SensorMessage::Camera(x)
            }
            SensorMessage::Joints(mut x) => {
                self.header(&mut x.header);
                SensorMessage::Joints(x)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_robot_namespace_prefixes_its_names_and_keeps_the_shared_ones() {
        let a = Namespace::robot("a");
        assert_eq!(a.topic("/cmd_vel"), "/a/cmd_vel");
        assert_eq!(a.topic("/ground_truth/odom"), "/a/ground_truth/odom");
        assert_eq!(a.topic("/clock"), "/clock");
        assert_eq!(a.topic("/tf"), "/tf");
        assert_eq!(a.frame("base_link"), "a/base_link");
        assert_eq!(a.frame("map"), "map");
        assert_eq!(a.frame(""), "");
        let none = Namespace::none();
        assert_eq!(none.topic("/odom"), "/odom");
        assert_eq!(none.frame("odom"), "odom");
        assert_eq!(Namespace::robot(""), none);
    }
}
