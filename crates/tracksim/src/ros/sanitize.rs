//! What a ROS message may ask of the physics: every command is checked here before it becomes
//! a control. A value that is not a finite number (NaN, infinite) drops the whole message; a
//! finite value beyond its limit is clamped to it; a flipper name the vehicle does not have is
//! dropped. Each such case is a [`Problem`], which the node reports through [`Warnings`]
//! (rate-limited by kind and topic, never by anything the peer chose: issue 45) on `/rosout`
//! and standard error. A joint command names at most [`MAX_JOINT_NAMES`] joints, and its unknown
//! names are one problem per message (the first named, the others counted).

use crate::model::VehicleModel;
use crate::rosmsg::{JointState, Twist};

/// Largest forward speed accepted from `/cmd_vel`, m/s (as the drive page's).
pub const MAX_FORWARD_MPS: f64 = crate::live::hub::MAX_FORWARD_MPS;
/// Largest yaw rate accepted from `/cmd_vel`, rad/s (as the drive page's).
pub const MAX_YAW_RATE_RAD_S: f64 = crate::live::hub::MAX_YAW_RATE_RAD_S;
/// Largest belt speed accepted from a per-track command, m/s (either way).
pub const MAX_BELT_MPS: f64 = 5.0;
/// Largest flipper target accepted, rad (either way: half a turn, as the drive page's 180 deg).
pub const MAX_FLIPPER_RAD: f64 = std::f64::consts::PI;
/// Most joints a joint command may name (the subscription refuses longer ones as it reads).
pub const MAX_JOINT_NAMES: usize = super::decode::MAX_JOINT_NAMES;
/// Most characters of a peer's name quoted in a warning.
const QUOTED_CHARS: usize = 64;

/// Why (part of) a message did not reach the physics as it was sent.
#[derive(Clone, Debug, PartialEq)]
pub enum Problem {
    /// A field was NaN or infinite: the message was dropped.
    NotFinite {
        /// The ROS topic.
        topic: String,
        /// The field (`linear.x`, `data`, `position[1]`).
        field: String,
    },
    /// A field was beyond its limit: it was clamped.
    Clamped {
        /// The ROS topic.
        topic: String,
        /// The field.
        field: String,
        /// What was sent (m/s, rad/s or rad).
        value: f64,
        /// What was used instead.
        used: f64,
    },
    /// A joint command named flippers the vehicle does not have: those entries were dropped.
    UnknownFlipper {
        /// The ROS topic.
        topic: String,
        /// The first unknown name sent (at most 64 characters of it).
        name: String,
        /// How many more unknown names the message had.
        more: usize,
    },
    /// Samples on the topic did not decode as its message type (another type under its name,
    /// cut short, bytes left over, beyond the bounds): dropped ([`super::decode`]).
    Undecodable {
        /// The ROS topic.
        topic: String,
        /// How many since the last check.
        count: u64,
    },
    /// A stamped command older than the `cmd_vel` timeout at the simulated time (issue 61;
    /// `diff_drive_controller` drops these too): the message was dropped.
    Stale {
        /// The ROS topic.
        topic: String,
        /// How long before the simulated time it was stamped, s.
        age_s: f64,
    },
    /// A joint command's arrays disagree in length: the message was dropped.
    Malformed {
        /// The ROS topic.
        topic: String,
        /// What is wrong.
        what: String,
    },
}

impl Problem {
    /// The problem's kind: one of a fixed set.
    pub fn kind(&self) -> &'static str {
        match self {
            Problem::NotFinite { .. } => "not a finite number",
            Problem::Clamped { .. } => "beyond its limit",
            Problem::UnknownFlipper { .. } => "unknown flipper name",
            Problem::Malformed { .. } => "malformed joint command",
            Problem::Undecodable { .. } => "sample not of the topic's type",
            Problem::Stale { .. } => "stale stamp",
        }
    }

    /// The topic (one of the node's own).
    pub fn topic(&self) -> &str {
        match self {
            Problem::NotFinite { topic, .. }
            | Problem::Clamped { topic, .. }
            | Problem::UnknownFlipper { topic, .. }
            | Problem::Malformed { topic, .. }
            | Problem::Stale { topic, .. }
            | Problem::Undecodable { topic, .. } => topic,
        }
    }

    /// The key warnings are rate-limited by: the kind on the node's topic (never a field or
    /// name the peer chose, so the keys are as few as the node's topics times the kinds).
    pub fn key(&self) -> String {
        format!("{}: {}", self.topic(), self.kind())
    }
}

impl std::fmt::Display for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Problem::NotFinite { topic, field } => {
                write!(
                    f,
                    "{topic}: {field} is not a finite number; message dropped"
                )
            }
            Problem::Clamped {
                topic,
                field,
                value,
                used,
            } => write!(
                f,
                "{topic}: {field} = {value} is beyond its limit; {used} used"
            ),
            Problem::UnknownFlipper {
                topic,
                name,
                more: 0,
            } => write!(
                f,
                "{topic}: the vehicle has no flipper named {name:?}; that entry dropped"
            ),
            Problem::UnknownFlipper { topic, name, more } => write!(
                f,
                "{topic}: the vehicle has no flipper named {name:?} nor {more} other name(s) \
                 of the message; those entries dropped"
            ),
            Problem::Malformed { topic, what } => write!(f, "{topic}: {what}; message dropped"),
            Problem::Stale { topic, age_s } => write!(
                f,
                "{topic}: a TwistStamped stamped {age_s:.3} s before the simulated time (older \
                 than the {} s cmd_vel timeout); message dropped: stamp it with the simulation's \
                 /clock (use_sim_time) or leave the stamp 0 (now)",
                super::commands::WATCHDOG_TIMEOUT_S
            ),
            Problem::Undecodable { topic, count } => write!(
                f,
                "{topic}: {count} sample(s) that do not decode as the topic's type (another \
                 type under its name, or beyond the bounds); dropped"
            ),
        }
    }
}

/// `value` within `[-limit, limit]`, or the problem of it: `Err` for NaN or infinity, `Ok`
/// with the clamped value and the clamping noted in `problems`.
pub fn clamp_field(
    topic: &str,
    field: &str,
    value: f64,
    limit: f64,
    problems: &mut Vec<Problem>,
) -> Result<f64, Problem> {
    if !value.is_finite() {
        return Err(Problem::NotFinite {
            topic: topic.into(),
            field: field.into(),
        });
    }
    let used = value.clamp(-limit, limit);
    if used != value {
        problems.push(Problem::Clamped {
            topic: topic.into(),
            field: field.into(),
            value,
            used,
        });
    }
    Ok(used)
}

/// The twist of a stamped `/cmd_vel` received at simulated time `t` s, if it is not stale: a
/// zero stamp means now; a stamp more than [`super::commands::WATCHDOG_TIMEOUT_S`] before `t`
/// is a [`Problem::Stale`] (issue 61). A stamp after `t` (a peer on the wall clock) is taken.
pub fn fresh_twist<'a>(
    topic: &str,
    m: &'a crate::rosmsg::TwistStamped,
    t: f64,
    problems: &mut Vec<Problem>,
) -> Option<&'a Twist> {
    let stamp = &m.header.stamp;
    if stamp.sec == 0 && stamp.nanosec == 0 {
        return Some(&m.twist);
    }
    let age_s = t - f64::from(stamp.sec) - 1e-9 * f64::from(stamp.nanosec);
    if age_s > super::commands::WATCHDOG_TIMEOUT_S {
        problems.push(Problem::Stale {
            topic: topic.into(),
            age_s,
        });
        return None;
    }
    Some(&m.twist)
}

/// The forward speed (m/s) and yaw rate (rad/s) of a `/cmd_vel` twist: `linear.x` and
/// `angular.z`, clamped; `None` if either is not finite. The other components are ignored (a
/// tracked robot cannot move sideways), unless they are not finite (dropped too).
pub fn twist(topic: &str, t: &Twist, problems: &mut Vec<Problem>) -> Option<(f64, f64)> {
    let others = [
        ("linear.y", t.linear.y),
        ("linear.z", t.linear.z),
        ("angular.x", t.angular.x),
        ("angular.y", t.angular.y),
    ];
    if let Some((field, _)) = others.iter().find(|(_, v)| !v.is_finite()) {
        problems.push(Problem::NotFinite {
            topic: topic.into(),
            field: (*field).into(),
        });
        return None;
    }
    let v = clamp_field(topic, "linear.x", t.linear.x, MAX_FORWARD_MPS, problems);
    let w = clamp_field(
        topic,
        "angular.z",
        t.angular.z,
        MAX_YAW_RATE_RAD_S,
        problems,
    );
    match (v, w) {
        (Ok(v), Ok(w)) => Some((v, w)),
        (Err(p), _) | (_, Err(p)) => {
            problems.push(p);
            None
        }
    }
}

/// A per-track belt speed command (`std_msgs/Float64` `data`, m/s), clamped to
/// [`MAX_BELT_MPS`]; `None` if not finite.
pub fn belt_speed(topic: &str, data: f64, problems: &mut Vec<Problem>) -> Option<f64> {
    clamp_field(topic, "data", data, MAX_BELT_MPS, problems)
        .map_err(|p| problems.push(p))
        .ok()
}

/// A flipper position command (`std_msgs/Float64` `data`, rad), clamped to
/// [`MAX_FLIPPER_RAD`]; `None` if not finite.
pub fn flipper_angle(topic: &str, data: f64, problems: &mut Vec<Problem>) -> Option<f64> {
    clamp_field(topic, "data", data, MAX_FLIPPER_RAD, problems)
        .map_err(|p| problems.push(p))
        .ok()
}

/// The flipper targets of a `sensor_msgs/JointState` command (names and positions, rad): by
/// flipper index, clamped; unknown names dropped (each a problem); the whole message dropped
/// if a position is not finite or `position` is not as long as `name`.
pub fn joint_command(
    topic: &str,
    v: &VehicleModel,
    js: &JointState,
    problems: &mut Vec<Problem>,
) -> Vec<(usize, f64)> {
    if js.name.len() > MAX_JOINT_NAMES {
        problems.push(Problem::Malformed {
            topic: topic.into(),
            what: format!("{} names (at most {MAX_JOINT_NAMES})", js.name.len()),
        });
        return Vec::new();
    }
    if js.position.len() != js.name.len() {
        problems.push(Problem::Malformed {
            topic: topic.into(),
            what: format!(
                "{} names but {} positions",
                js.name.len(),
                js.position.len()
            ),
        });
        return Vec::new();
    }
    let mut out = Vec::new();
    let mut unknown: Option<(&String, usize)> = None;
    for (k, (name, &p)) in js.name.iter().zip(&js.position).enumerate() {
        let field = format!("position[{k}]");
        let a = match clamp_field(topic, &field, p, MAX_FLIPPER_RAD, problems) {
            Ok(a) => a,
            Err(e) => {
                problems.push(e);
                return Vec::new();
            }
        };
        match (
            v.flippers.iter().position(|f| &f.name == name),
            &mut unknown,
        ) {
            (Some(i), _) => out.push((i, a)),
            (None, Some((_, more))) => *more += 1,
            (None, None) => unknown = Some((name, 0)),
        }
    }
    if let Some((name, more)) = unknown {
        problems.push(Problem::UnknownFlipper {
            topic: topic.into(),
            name: name.chars().take(QUOTED_CHARS).collect(),
            more,
        });
    }
    out
}

/// Rate-limited warnings: each [`Problem::key`] is reported at most once per `interval` s of
/// wall time; the ones held back in between are counted and said in the next report, or, when
/// the problem has stopped, by [`Warnings::held_back`].
pub struct Warnings {
    interval: f64,
    /// Per key: when it was last reported, how many were held back since, when it was last
    /// seen.
    last: std::collections::HashMap<String, (std::time::Instant, u64, std::time::Instant)>,
}

/// Shortest wall time between two reports of the same problem, s.
pub const WARNING_INTERVAL_S: f64 = 1.0;

impl Default for Warnings {
    fn default() -> Self {
        Warnings::new(WARNING_INTERVAL_S)
    }
}

impl Warnings {
    /// Reports each problem at most once per `interval_s` seconds.
    pub fn new(interval_s: f64) -> Self {
        Warnings {
            interval: interval_s,
            last: Default::default(),
        }
    }

    /// The text to report for `p` now, or `None` if it is held back (counted).
    pub fn admit(&mut self, p: &Problem) -> Option<String> {
        let now = std::time::Instant::now();
        match self.last.get_mut(&p.key()) {
            Some((t, held, seen)) if now.duration_since(*t).as_secs_f64() < self.interval => {
                *held += 1;
                *seen = now;
                None
            }
            Some((t, held, seen)) => {
                *seen = now;
                let text = if *held > 0 {
                    format!("{p} (and {held} more like it since the last warning)")
                } else {
                    p.to_string()
                };
                *t = now;
                *held = 0;
                Some(text)
            }
            None => {
                self.last.insert(p.key(), (now, 0, now));
                Some(p.to_string())
            }
        }
    }

    /// For each kind with warnings held back and none seen for an interval (the problem
    /// stopped; one that goes on is counted by its next report): a line counting them. Call it
    /// periodically, so that the end of a burst is still counted.
    pub fn held_back(&mut self) -> Vec<String> {
        let now = std::time::Instant::now();
        let mut out = Vec::new();
        for (key, (t, held, seen)) in &mut self.last {
            if *held > 0 && now.duration_since(*seen).as_secs_f64() >= self.interval {
                out.push(format!("{key}: {held} more like it since the last warning"));
                *t = now;
                *held = 0;
            }
        }
        out.sort();
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rosmsg::Vector3;

    fn vehicle() -> VehicleModel {
        let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenarios/packbot_stairs.toml");
        crate::load_scenario(&p).unwrap().vehicle.clone()
    }

    fn tw(vx: f64, wz: f64) -> Twist {
        Twist {
            linear: Vector3 {
                x: vx,
                ..Vector3::default()
            },
            angular: Vector3 {
                z: wz,
                ..Vector3::default()
            },
        }
    }

    #[test]
    fn non_finite_values_drop_the_message() {
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let mut p = Vec::new();
            assert_eq!(twist("/cmd_vel", &tw(bad, 0.0), &mut p), None);
            assert_eq!(twist("/cmd_vel", &tw(0.1, bad), &mut p), None);
            let mut t = tw(0.1, 0.0);
            t.linear.y = bad;
            assert_eq!(twist("/cmd_vel", &t, &mut p), None);
            assert_eq!(belt_speed("/tracks/left/cmd_speed", bad, &mut p), None);
            assert_eq!(flipper_angle("/flippers/f/cmd_position", bad, &mut p), None);
            assert_eq!(p.len(), 5);
            assert!(p.iter().all(|x| matches!(x, Problem::NotFinite { .. })));
        }
    }

    #[test]
    fn out_of_range_values_are_clamped_and_reported() {
        let mut p = Vec::new();
        assert_eq!(
            twist("/cmd_vel", &tw(100.0, -1e9), &mut p),
            Some((MAX_FORWARD_MPS, -MAX_YAW_RATE_RAD_S))
        );
        assert_eq!(p.len(), 2);
        assert_eq!(belt_speed("t", -1e300, &mut p), Some(-MAX_BELT_MPS));
        assert_eq!(flipper_angle("f", 10.0, &mut p), Some(MAX_FLIPPER_RAD));
        assert_eq!(p.len(), 4);
        assert!(matches!(&p[3], Problem::Clamped { value, used, .. }
            if *value == 10.0 && *used == MAX_FLIPPER_RAD));
        // In range: untouched, nothing reported; sideways components ignored.
        let mut q = Vec::new();
        let mut t = tw(0.3, 0.5);
        t.linear.y = 2.0;
        assert_eq!(twist("/cmd_vel", &t, &mut q), Some((0.3, 0.5)));
        assert_eq!(belt_speed("t", 0.2, &mut q), Some(0.2));
        assert!(q.is_empty());
    }

    #[test]
    fn joint_commands_drop_unknown_flippers_and_bad_messages() {
        let v = vehicle();
        let name = v.flippers[0].name.clone();
        let js = |names: &[&str], pos: &[f64]| JointState {
            name: names.iter().map(|s| s.to_string()).collect(),
            position: pos.to_vec(),
            ..JointState::default()
        };
        let mut p = Vec::new();
        let got = joint_command("/j", &v, &js(&[&name, "no_such"], &[0.5, 0.1]), &mut p);
        assert_eq!(got, vec![(0, 0.5)]);
        assert!(matches!(&p[..], [Problem::UnknownFlipper { name, .. }] if name == "no_such"));
        let mut p = Vec::new();
        assert!(joint_command("/j", &v, &js(&[&name], &[f64::NAN]), &mut p).is_empty());
        assert!(joint_command("/j", &v, &js(&[&name], &[]), &mut p).is_empty());
        assert!(matches!(&p[1], Problem::Malformed { .. }));
        let mut p = Vec::new();
        assert_eq!(
            joint_command("/j", &v, &js(&[&name], &[-7.0]), &mut p),
            vec![(0, -MAX_FLIPPER_RAD)]
        );
    }

    #[test]
    fn warnings_are_rate_limited_per_kind() {
        let mut w = Warnings::new(3600.0);
        let a = Problem::NotFinite {
            topic: "/cmd_vel".into(),
            field: "linear.x".into(),
        };
        let b = Problem::UnknownFlipper {
            topic: "/j".into(),
            name: "x".into(),
            more: 0,
        };
        assert!(w.admit(&a).is_some());
        assert!(w.admit(&a).is_none());
        assert!(w.admit(&b).is_some());
        // The peer's name or field is not the key: another name is the same kind.
        let c = Problem::UnknownFlipper {
            topic: "/j".into(),
            name: "y".into(),
            more: 3,
        };
        assert!(w.admit(&c).is_none());
        let d = Problem::NotFinite {
            topic: "/cmd_vel".into(),
            field: "angular.z".into(),
        };
        assert!(w.admit(&d).is_none());
        assert_eq!(w.last.len(), 2);
        assert!(w.held_back().is_empty(), "within the interval");
        let mut w = Warnings::new(0.0);
        assert!(w.admit(&a).is_some());
        assert!(w.admit(&a).is_some());
        let mut w = Warnings::new(0.05);
        assert!(w.admit(&b).is_some());
        assert!(w.admit(&c).is_none() && w.admit(&c).is_none());
        std::thread::sleep(std::time::Duration::from_millis(60));
        let held = w.held_back();
        assert!(
            held.len() == 1 && held[0].contains("/j: unknown flipper name: 2 more"),
            "{held:?}"
        );
        assert!(w.held_back().is_empty(), "counted once");
    }

    #[test]
    fn a_joint_command_is_bounded_and_its_unknown_names_one_problem() {
        let v = vehicle();
        let many = JointState {
            name: (0..50_000).map(|i| format!("nope{i}")).collect(),
            position: vec![0.0; 50_000],
            ..JointState::default()
        };
        let mut p = Vec::new();
        assert!(joint_command("/j", &v, &many, &mut p).is_empty());
        assert!(matches!(&p[..], [Problem::Malformed { what, .. }] if what.contains("at most 64")));
        let some = JointState {
            name: (0..MAX_JOINT_NAMES)
                .map(|i| format!("{}{i}", "n".repeat(500)))
                .collect(),
            position: vec![0.0; MAX_JOINT_NAMES],
            ..JointState::default()
        };
        let mut p = Vec::new();
        joint_command("/j", &v, &some, &mut p);
        assert!(
            matches!(&p[..], [Problem::UnknownFlipper { name, more: 63, .. }] if name.len() == 64),
            "{p:?}"
        );
    }
}
