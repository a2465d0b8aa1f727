//! Issue 61: `/cmd_vel` as ROS 2 stacks send it, every packet on loopback (DDS domains 161-164,
//! loopback only), each test bounded in time (< 40 s):
//! - `geometry_msgs/TwistStamped` (Nav2 from Jazzy with `enable_stamped_cmd_vel`,
//!   `diff_drive_controller`), best effort at 20 Hz, drives the robot as `Twist` does;
//! - a best-effort `geometry_msgs/Twist` publisher (teleop, Nav2's default QoS) drives it too
//!   (the reliable reader never matched it: the robot moved 0.002 m in 2 s);
//! - a stamped command older than the 0.5 s `cmd_vel` timeout is dropped, with a warning that
//!   names the topic and says how to stamp.
//!
//! Each publishes 0.3 m/s for 2 s of wall time into a paced session; the robot must cover at
//! least 0.3 m (the discovery latency and the belts' spin-up take some of the 0.6 m).

use ros2_client::qos::{History, Reliability};
use ros2_client::{MessageTypeName, Name, QosProfile};
use std::path::Path;
use std::time::{Duration, Instant};
use tracksim::rosmsg::{Header, Time, Twist, TwistStamped, Vector3};

#[path = "support/proc.rs"]
mod proc;
use proc::{Proc, spawn};

#[path = "support/dds.rs"]
mod dds;

/// `tracksim ros` of packbot_flat for 6 s, paced, in DDS domain `domain`.
fn ros(domain: u16, out: &Path) -> Proc {
    spawn(&[
        "ros",
        "scenarios/packbot_flat.toml",
        "--duration",
        "6",
        "--domain-id",
        &domain.to_string(),
        "--out",
        out.to_str().unwrap(),
        "--no-plot",
    ])
}

/// Best effort, keep last 10: what Nav2's and teleop's `cmd_vel` publishers use.
fn best_effort() -> QosProfile {
    QosProfile {
        reliability: Reliability::BestEffort,
        history: History::KeepLast { depth: 10 },
        ..QosProfile::publisher_default()
    }
}

fn twist(v: f64) -> Twist {
    Twist {
        linear: Vector3 {
            x: v,
            ..Vector3::default()
        },
        angular: Vector3::default(),
    }
}

/// The distance the robot's base covered in the run written to `out`, m (start to end).
fn moved(out: &Path) -> f64 {
    let summary: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("summary.json")).unwrap()).unwrap();
    summary["net_displacement_m"].as_f64().unwrap()
}

/// Publishes `msg(t_wall)` on `/cmd_vel` as type `ty` every 50 ms for 2 s once the node is up;
/// returns the finished run's (exit code, stdout, stderr).
fn publish_for_2_s<T: tracksim::rosmsg::RosMessage + 'static>(
    domain: u16,
    out: &Path,
    ty: &str,
    msg: impl Fn() -> T,
) -> (i32, Vec<String>, Vec<String>) {
    let mut p = ros(domain, out);
    let (_ctx, mut node) = dds::peer(domain, "cmd_vel_test");
    let q = best_effort();
    let topic = node
        .create_topic(
            &Name::parse("/cmd_vel").unwrap(),
            MessageTypeName::new("geometry_msgs", ty),
            &q,
        )
        .unwrap();
    let publisher = node.create_publisher::<T>(&topic, Some(q)).unwrap();
    p.line_with("ros        node");
    let t0 = Instant::now();
    while t0.elapsed() < Duration::from_secs(2) {
        let _ = publisher.publish(msg());
        std::thread::sleep(Duration::from_millis(50));
    }
    p.finish(Duration::from_secs(40))
}

#[test]
fn a_stamped_cmd_vel_best_effort_drives_the_robot() {
    let out = tempfile::tempdir().unwrap();
    let (code, stdout, stderr) =
        publish_for_2_s(161, out.path(), "TwistStamped", || TwistStamped {
            header: Header {
                stamp: Time::default(),
                frame_id: "base_link".into(),
            },
            twist: twist(0.3),
        });
    assert_eq!(code, 0, "{stdout:?} {stderr:?}");
    let d = moved(out.path());
    eprintln!("stamped: moved {d:.3} m; {stderr:?}");
    assert!(d > 0.3, "moved {d} m: {stdout:?} {stderr:?}");
    assert!(
        !stderr.iter().any(|l| l.contains("do not decode")),
        "neither form is reported as the other: {stderr:?}"
    );
}

#[test]
fn a_best_effort_twist_drives_the_robot() {
    let out = tempfile::tempdir().unwrap();
    let (code, stdout, stderr) = publish_for_2_s(162, out.path(), "Twist", || twist(0.3));
    assert_eq!(code, 0, "{stdout:?} {stderr:?}");
    let d = moved(out.path());
    eprintln!("best-effort Twist: moved {d:.3} m");
    assert!(d > 0.3, "moved {d} m: {stdout:?} {stderr:?}");
    assert!(
        !stderr.iter().any(|l| l.contains("do not decode")),
        "{stderr:?}"
    );
}

#[test]
fn a_stale_stamped_cmd_vel_is_dropped_and_said() {
    let out = tempfile::tempdir().unwrap();
    // Stamped at simulated time 1 ns (0 means now), so it is stale from 0.5 s on.
    let (code, stdout, stderr) =
        publish_for_2_s(163, out.path(), "TwistStamped", || TwistStamped {
            header: Header {
                stamp: Time { sec: 0, nanosec: 1 },
                frame_id: String::new(),
            },
            twist: twist(0.3),
        });
    assert_eq!(code, 0, "{stdout:?} {stderr:?}");
    assert!(
        stderr
            .iter()
            .any(|l| l.contains("/cmd_vel") && l.contains("use_sim_time")),
        "{stderr:?}"
    );
    // It drives at most while the stamp is fresh (simulated time < 0.5 s) and then until the
    // watchdog stops it 0.5 s after the last command taken: 1 s at 0.3 m/s, plus the belts'
    // spin-down (10 % allowed); a fresh command drives it about 0.69 m in the same test.
    let d = moved(out.path());
    eprintln!("stale: moved {d:.3} m");
    assert!(d < 0.33, "moved {d} m: {stderr:?}");
}

/// A publisher of another type on `/cmd_vel` (here `geometry_msgs/Vector3`) never matches the
/// node's readers, so no sample arrives: the node says so once, naming the topic, the type
/// found and the types it reads.
#[test]
fn a_publisher_of_another_type_is_named_once() {
    let out = tempfile::tempdir().unwrap();
    let (code, stdout, stderr) = publish_for_2_s(164, out.path(), "Vector3", || Vector3 {
        x: 0.3,
        ..Vector3::default()
    });
    assert_eq!(code, 0, "{stdout:?} {stderr:?}");
    let said: Vec<&String> = stderr
        .iter()
        .filter(|l| l.contains("geometry_msgs/msg/Vector3"))
        .collect();
    assert_eq!(said.len(), 1, "{stderr:?}");
    assert!(
        said[0].contains("/cmd_vel") && said[0].contains("geometry_msgs/msg/TwistStamped"),
        "{said:?}"
    );
    let d = moved(out.path());
    assert!(d < 0.01, "moved {d} m");
}
