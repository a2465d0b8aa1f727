//! The node on DDS (`ros2-client` over RustDDS, pure Rust): one participant restricted to its
//! [`NetworkRange`], the node `/tracksim`, its publishers and subscriptions (QoS below), and
//! `/rosout`. It never blocks the simulation: subscriptions are read without waiting, and a
//! publisher whose history is full drops the message rather than wait.
//!
//! QoS: every publisher is reliable, volatile, keep last 10 (ROS's default; a best-effort
//! subscriber such as a `SensorDataQoS` one matches it too), `/tf` keep last 100, `/clock`
//! keep last 1, `/tf_static` and `/robot_description` transient local keep last 1 (latched, as
//! tf2 and `robot_state_publisher` have them). The
//! subscriptions are reliable, keep last 10 (the default of `ros2 topic pub`, Nav2 and
//! `teleop_twist_keyboard`).

use super::decode::{Bounded, Whole};
use super::network::NetworkRange;
use super::topics;
use crate::output::ros_names::Namespace;
use crate::rosmsg::{
    Clock, CourseEvent, CourseStatus, Float64, JointState, Odometry, RosString, TFMessage,
    TrackStates, Twist, TwistStamped,
};
use ros2_client::dds::rustdds::DomainParticipantBuilder;
use ros2_client::log::LogLevel;
use ros2_client::qos::{Durability, History, Reliability, WhenFull};
use ros2_client::{
    Context, MessageTypeName, Name, Node, NodeName, NodeOptions, Publisher, QosProfile, RosoutRaw,
    Subscription,
};
use serde::Serialize;

/// Why the node could not start.
pub type DdsError = String;

fn qos(depth: usize, latched: bool) -> QosProfile {
    QosProfile {
        reliability: Reliability::Reliable {
            when_full: WhenFull::Fail,
        },
        durability: if latched {
            Durability::TransientLocal
        } else {
            Durability::Volatile
        },
        history: History::KeepLast { depth },
        ..QosProfile::publisher_default()
    }
}

/// The QoS of the services' requests and replies: reliable, volatile, keep last 10 (ROS's
/// services default).
pub fn service_qos() -> QosProfile {
    qos(10, false)
}

/// A publisher of a ROS message type on one topic.
pub struct Pub<T: Serialize> {
    inner: Publisher<T>,
}

impl<T: Serialize> Pub<T> {
    /// Sends `msg` (a full history drops it: the simulation never waits).
    pub fn publish(&self, msg: T) {
        let _ = self.inner.publish(msg);
    }
}

/// A subscription of a ROS message type on one topic.
pub struct Sub<T> {
    inner: Subscription<T>,
    /// The ROS topic.
    pub topic: String,
    /// Samples that did not decode as `T` since the last [`Sub::take_dropped`].
    dropped: std::cell::Cell<u64>,
}

impl<T: Bounded> Sub<T> {
    /// Every message received since the last call, oldest first: each sample read whole and
    /// within bounds ([`super::decode`]); one that does not decode as `T` is dropped and
    /// counted ([`Sub::take_dropped`]).
    pub fn drain(&self) -> Vec<T> {
        let mut out = Vec::new();
        // Bounded: a flood cannot hold the simulation here.
        for _ in 0..1000 {
            match self.inner.take_seed(Whole::<T>::default()) {
                Ok(Some((m, _))) => out.push(m),
                Ok(None) => break,
                Err(_) => self.dropped.set(self.dropped.get() + 1),
            }
        }
        out
    }

    /// How many samples did not decode since the last call.
    pub fn take_dropped(&self) -> u64 {
        self.dropped.replace(0)
    }
}

/// The ROS 2 node: participant, node and `/rosout`.
pub struct DdsNode {
    node: Node,
    // Kept alive with the node.
    _context: Context,
}

/// The `pkg/Type` of a message as DDS names it.
fn type_name(full: &str) -> MessageTypeName {
    let (pkg, ty) = full.split_once('/').unwrap_or(("", full));
    MessageTypeName::new(pkg, ty)
}

impl DdsNode {
    /// Starts the participant in DDS domain `domain` (`ROS_DOMAIN_ID`) on `range`, and the node.
    pub fn start(domain: u16, range: &NetworkRange) -> Result<Self, DdsError> {
        let mut b = DomainParticipantBuilder::new(domain);
        if let Some(nets) = range.only_networks() {
            b = b.with_only_networks(nets);
        }
        let dp = b.build().map_err(|e| format!("DDS participant: {e:?}"))?;
        let context =
            Context::from_domain_participant(dp).map_err(|e| format!("ROS context: {e:?}"))?;
        let name = NodeName::new("/", topics::NODE_NAME).map_err(|e| format!("{e:?}"))?;
        let node = context
            .new_node(
                name,
                NodeOptions::new()
                    .enable_rosout(true)
                    .start_parameter_services(false),
            )
            .map_err(|e| format!("ROS node: {e:?}"))?;
        Ok(DdsNode {
            node,
            _context: context,
        })
    }

    fn topic<T: crate::rosmsg::RosMessage>(
        &mut self,
        name: &str,
        q: &QosProfile,
    ) -> Result<ros2_client::dds::rustdds::Topic, DdsError> {
        let n = Name::parse(name).map_err(|e| format!("topic {name}: {e:?}"))?;
        self.node
            .create_topic(&n, type_name(T::DEF.name), q)
            .map_err(|e| format!("topic {name}: {e:?}"))
    }

    /// A publisher on `name` with `depth` messages of history (`latched`: transient local).
    pub fn publisher<T: crate::rosmsg::RosMessage>(
        &mut self,
        name: &str,
        depth: usize,
        latched: bool,
    ) -> Result<Pub<T>, DdsError> {
        let q = qos(depth, latched);
        let topic = self.topic::<T>(name, &q)?;
        let inner = self
            .node
            .create_publisher::<T>(&topic, Some(q))
            .map_err(|e| format!("publisher {name}: {e:?}"))?;
        Ok(Pub { inner })
    }

    /// A subscription of `name`.
    pub fn subscription<T: crate::rosmsg::RosMessage + 'static>(
        &mut self,
        name: &str,
    ) -> Result<Sub<T>, DdsError> {
        self.subscription_with::<T>(name, qos(10, false))
    }

    fn subscription_with<T: crate::rosmsg::RosMessage + 'static>(
        &mut self,
        name: &str,
        q: QosProfile,
    ) -> Result<Sub<T>, DdsError> {
        let topic = self.topic::<T>(name, &q)?;
        let inner = self
            .node
            .create_subscription::<T>(&topic, Some(q))
            .map_err(|e| format!("subscription {name}: {e:?}"))?;
        Ok(Sub {
            inner,
            topic: name.to_string(),
            dropped: std::cell::Cell::new(0),
        })
    }

    /// A subscription of `name` that matches reliable and best-effort publishers alike (a
    /// best-effort reader; issue 61: a best-effort `/cmd_vel` publisher, as many teleop and
    /// Nav2 setups have, never matched the reliable reader).
    pub fn command_subscription<T: crate::rosmsg::RosMessage + 'static>(
        &mut self,
        name: &str,
    ) -> Result<Sub<T>, DdsError> {
        let q = QosProfile {
            reliability: Reliability::BestEffort,
            ..qos(10, false)
        };
        self.subscription_with::<T>(name, q)
    }

    /// Every remote publisher DDS discovery knows of: its ROS topic (`rt/cmd_vel` ->
    /// `/cmd_vel`) and ROS type (`geometry_msgs::msg::dds_::Twist_` -> `geometry_msgs/Twist`);
    /// endpoints that are not ROS topics are left out.
    pub fn discovered_publishers(&self) -> Vec<(String, String)> {
        self._context
            .domain_participant()
            .discovered_writers()
            .iter()
            .filter_map(|w| {
                let d = &w.publication_topic_data;
                let topic = d.topic_name.strip_prefix("rt")?.to_string();
                let parts: Vec<&str> = d.type_name.split("::").collect();
                let ty = match parts.as_slice() {
                    [pkg, "msg", "dds_", name] => {
                        format!("{pkg}/{}", name.strip_suffix('_').unwrap_or(name))
                    }
                    _ => d.type_name.clone(),
                };
                Some((topic, ty))
            })
            .collect()
    }

    /// The ros2-client node (for its services).
    pub fn node_mut(&mut self) -> &mut Node {
        &mut self.node
    }

    /// Logs `msg` on `/rosout` at `level`, stamped `t` s of simulated time.
    pub fn rosout(&self, level: LogLevel, t: f64, msg: &str) {
        let ns = crate::rosmsg::Time::from_secs(t).nanos();
        self.node.logging_handle().rosout_raw(
            ros2_client::builtin_interfaces::Time::from_nanos(ns as i64),
            level,
            topics::NODE_NAME,
            msg,
            file!(),
            "tracksim::ros",
            line!(),
        );
    }
}

/// The world's publishers, one of each whatever the robots: `/clock`, `/tf` (every robot's
/// transforms), `/tf_static` (every robot's sensor mounts).
pub struct WorldPublishers {
    /// `/clock`.
    pub clock: Pub<Clock>,
    /// `/tf`.
    pub tf: Pub<TFMessage>,
    /// `/tf_static`.
    pub tf_static: Pub<TFMessage>,
}

impl WorldPublishers {
    /// Creates them on `node`.
    pub fn new(node: &mut DdsNode) -> Result<Self, DdsError> {
        Ok(WorldPublishers {
            clock: node.publisher(topics::CLOCK, 1, false)?,
            tf: node.publisher(topics::TF, 100, false)?,
            tf_static: node.publisher(topics::TF_STATIC, 1, true)?,
        })
    }
}

/// A robot's publishers (in its namespace, [`Namespace::topic`]).
pub struct Publishers {
    /// `/odom`.
    pub odom: Pub<Odometry>,
    /// `/ground_truth/odom`.
    pub truth: Pub<Odometry>,
    /// `/joint_states`.
    pub joints: Pub<JointState>,
    /// `/tracks`.
    pub tracks: Pub<TrackStates>,
    /// `/robot_description` (transient local, keep last 1, reliable: as
    /// `robot_state_publisher` offers it).
    pub description: Pub<RosString>,
    /// `/course` and `/course/events` when the scenario has a `[course]`. The events are
    /// transient local, keep last 100: each is sent once, and a scoreboard that joins late
    /// still gets the last 100.
    pub course: Option<(Pub<CourseStatus>, Pub<CourseEvent>)>,
}

impl Publishers {
    /// Creates them on `node` in namespace `ns`, the course's when `course`.
    pub fn new(node: &mut DdsNode, ns: &Namespace, course: bool) -> Result<Self, DdsError> {
        let course = if course {
            Some((
                node.publisher(&ns.topic(topics::COURSE), 10, false)?,
                node.publisher(&ns.topic(topics::COURSE_EVENTS), 100, true)?,
            ))
        } else {
            None
        };
        Ok(Publishers {
            course,
            odom: node.publisher(&ns.topic(topics::ODOM), 10, false)?,
            truth: node.publisher(&ns.topic(topics::GROUND_TRUTH), 10, false)?,
            joints: node.publisher(&ns.topic(topics::JOINT_STATES), 10, false)?,
            tracks: node.publisher(&ns.topic(topics::TRACKS), 10, false)?,
            description: node.publisher(&ns.topic(topics::ROBOT_DESCRIPTION), 1, true)?,
        })
    }
}

/// A robot's subscriptions (in its namespace).
pub struct Subscriptions {
    /// `/cmd_vel` as `geometry_msgs/Twist`.
    pub cmd_vel: Sub<Twist>,
    /// `/cmd_vel` as `geometry_msgs/TwistStamped` (Nav2 from Jazzy, `diff_drive_controller`:
    /// issue 61), on the same topic.
    pub cmd_vel_stamped: Sub<TwistStamped>,
    /// The plain reader's undecodable samples less the stamped reader's decoded ones, not yet
    /// reported (`session.rs`, `cmd_vel_undecodable`).
    pub cmd_vel_balance: std::cell::Cell<i64>,
    /// Per track (by index): its belt speed command, if its name makes a ROS name.
    pub track_speed: Vec<Option<Sub<Float64>>>,
    /// Per flipper (by index): its target command, if its name makes a ROS name.
    pub flipper_position: Vec<Option<Sub<Float64>>>,
    /// `/flippers/cmd_positions`.
    pub flipper_positions: Sub<JointState>,
}

impl Subscriptions {
    /// Each command topic read and the message types it is read as (`pkg/Type`), for the
    /// report of a publisher of another type (issue 61: such a publisher never matches, and
    /// nothing arrives to say so).
    pub fn read_types(&self) -> Vec<(String, Vec<&'static str>)> {
        use crate::rosmsg::RosMessage;
        let mut out = vec![(
            self.cmd_vel.topic.clone(),
            vec![Twist::DEF.name, TwistStamped::DEF.name],
        )];
        for s in self
            .track_speed
            .iter()
            .chain(&self.flipper_position)
            .flatten()
        {
            out.push((s.topic.clone(), vec![Float64::DEF.name]));
        }
        out.push((
            self.flipper_positions.topic.clone(),
            vec![JointState::DEF.name],
        ));
        out
    }

    /// Creates them on `node` in namespace `ns` for tracks `tracks` and flippers `flippers`
    /// (names); a name that makes no valid ROS topic is skipped and reported in the second
    /// value.
    pub fn new(
        node: &mut DdsNode,
        ns: &Namespace,
        tracks: &[String],
        flippers: &[String],
    ) -> Result<(Self, Vec<String>), DdsError> {
        let mut skipped = Vec::new();
        let mut each =
            |node: &mut DdsNode, topic: String| match node.subscription::<Float64>(&topic) {
                Ok(s) => Some(s),
                Err(e) => {
                    skipped.push(e);
                    None
                }
            };
        let track_speed = tracks
            .iter()
            .map(|n| each(node, ns.topic(&topics::track_speed(n))))
            .collect();
        let flipper_position = flippers
            .iter()
            .map(|n| each(node, ns.topic(&topics::flipper_position(n))))
            .collect();
        Ok((
            Subscriptions {
                cmd_vel: node.command_subscription(&ns.topic(topics::CMD_VEL))?,
                cmd_vel_stamped: node.command_subscription(&ns.topic(topics::CMD_VEL))?,
                cmd_vel_balance: std::cell::Cell::new(0),
                track_speed,
                flipper_position,
                flipper_positions: node.subscription(&ns.topic(topics::FLIPPER_POSITIONS))?,
            },
            skipped,
        ))
    }
}
