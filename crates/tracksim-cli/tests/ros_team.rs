//! `tracksim ros` with several robots (issue 40), without DDS: each robot's topics and frames
//! in its namespace and unique in the world, each robot's own watchdog, and the session's
//! commands replaying it. (The node on DDS is exercised end to end by
//! `python/tests/test_ros_dds.py`, in a network namespace.)

use std::path::{Path, PathBuf};
use tracksim::output::ros_messages::{encoder_model, encoder_odometry, tf_of_sample, tf_static};
use tracksim::output::ros_names::Namespace;
use tracksim::ros::{Command, RobotControl, WATCHDOG_TIMEOUT_S, topics};
use tracksim::run::{
    CommandLog, End, LogHeader, SessionLimits, TeamRunner, WorldSource, run_world_session,
};
use tracksim::spec::CommandSpec;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[test]
fn each_robots_topics_and_frames_are_under_its_name_and_unique_in_the_world() {
    let sc = tracksim::load_scenario(&root().join("scenarios/team/rescue_site.toml")).unwrap();
    let names = sc.robot_names();
    assert!(names.len() >= 3);
    let mut all_topics = Vec::new();
    let mut all_frames = Vec::new();
    let mut sim = tracksim::Simulation::new(&sc).unwrap();
    for (k, name) in names.iter().enumerate() {
        let view = sc.robot_view(k);
        let ns = Namespace::robot(name);
        let t = topics::robot_topics(&view.vehicle, view.course.is_some(), &ns);
        assert!(t.contains(&format!("/{name}/cmd_vel")), "{t:?}");
        assert!(t.contains(&format!("/{name}/odom")));
        for x in &t {
            assert!(x.starts_with(&format!("/{name}/")), "{x} is robot {name}'s");
        }
        all_topics.extend(t);
        // The frames of its transforms, as the node publishes them on /tf and /tf_static.
        sim.select(k);
        let sample = sim.sample();
        let odom = encoder_odometry(&sample, &mut encoder_model(&view));
        let tf = ns.tf(tf_of_sample(&view, &sample, &odom, true));
        let pairs: Vec<(String, String)> = tf
            .transforms
            .iter()
            .chain(&ns.tf(tf_static(&view)).transforms)
            .map(|t| (t.header.frame_id.clone(), t.child_frame_id.clone()))
            .collect();
        assert!(pairs.contains(&(format!("{name}/odom"), format!("{name}/base_link"))));
        assert!(pairs.contains(&("map".to_string(), format!("{name}/odom"))));
        for (parent, child) in &pairs {
            assert!(child.starts_with(&format!("{name}/")), "{child}");
            assert!(parent == "map" || parent.starts_with(&format!("{name}/")));
        }
        all_frames.extend(pairs.into_iter().map(|p| p.1));
    }
    for list in [&all_topics, &all_frames] {
        let mut u = list.clone();
        u.sort();
        u.dedup();
        assert_eq!(u.len(), list.len(), "unique in the world: {list:?}");
    }
    for shared in ["/clock", "/tf", "/tf_static", "/rosout"] {
        assert!(!all_topics.iter().any(|t| t == shared));
        assert_eq!(Namespace::robot("a").topic(shared), shared, "one {shared}");
    }
    // A course's topics are each robot's, when the scenario has a course.
    assert!(!all_topics.iter().any(|t| t.contains("/course")));
    let race = tracksim::load_scenario(&root().join("scenarios/team/race_step.toml")).unwrap();
    for (k, name) in race.robot_names().iter().enumerate() {
        let view = race.robot_view(k);
        assert!(view.course.is_some());
        let t = topics::robot_topics(&view.vehicle, true, &Namespace::robot(name));
        assert!(t.contains(&format!("/{name}/course")), "{t:?}");
        assert!(t.contains(&format!("/{name}/course/events")), "{t:?}");
    }
    // No sensor may take a topic of the node's own (a sensor publishes on /<name>).
    let mut own: Vec<String> = topics::robot_topics(
        &tracksim::load_scenario(&root().join("scenarios/packbot_flat.toml"))
            .unwrap()
            .vehicle,
        true,
        &Namespace::none(),
    );
    own.extend([topics::CLOCK, topics::TF, topics::TF_STATIC].map(String::from));
    for t in own.iter().filter(|t| t.matches('/').count() == 1) {
        let name = t.trim_start_matches('/');
        assert!(
            tracksim::model::RESERVED_SENSOR_NAMES.contains(&name),
            "{t} is not reserved"
        );
    }
    // One robot keeps today's names unless namespaced.
    let one = tracksim::load_scenario(&root().join("scenarios/packbot_flat.toml")).unwrap();
    let t = topics::robot_topics(&one.vehicle, false, &Namespace::none());
    assert!(t.contains(&"/cmd_vel".to_string()) && t.contains(&"/odom".to_string()));
}

/// Two robots' peers: `a`'s sends /a/cmd_vel every 0.1 s, `b`'s once at t = 0 and then falls
/// silent. Each robot's commands go through its own [`RobotControl`], as on the node.
struct Peers {
    robots: Vec<RobotControl>,
    stops: Vec<Vec<f64>>,
}

impl WorldSource<TeamRunner> for Peers {
    fn controls(&mut self, runner: &TeamRunner, k: usize) -> Option<CommandSpec> {
        let t = runner.sim().time();
        let tick = ((t * 1000.0).round() as i64) % 100 == 0;
        let send = if k == 0 { tick } else { t == 0.0 };
        let received = if send {
            vec![Command::Twist {
                forward_mps: 0.3,
                yaw_rate_rad_s: 0.0,
            }]
        } else {
            Vec::new()
        };
        let v = &runner.robot_scenario(k).vehicle;
        let stops = &mut self.stops[k];
        self.robots[k].controls(v, t, received, &mut |_| stops.push(t))
    }
}

#[test]
fn a_silent_peer_stops_its_robot_only_and_the_commands_replay_the_session() {
    let file = root().join("scenarios/team/corridor_head_on.toml");
    let sc = tracksim::load_scenario(&file).unwrap();
    let runner = TeamRunner::new(&sc).unwrap().without_commands().unbounded();
    let mut peers = Peers {
        robots: (0..2)
            .map(|k| RobotControl::new(Some(&sc.robot_names()[k]), &sc.robot_view(k).vehicle))
            .collect(),
        stops: vec![Vec::new(); 2],
    };
    let limits = SessionLimits {
        max_time: Some(2.0),
        interrupt: None,
    };
    let order = runner.sim().build_order().to_vec();
    let run = run_world_session(runner, &mut peers, limits, &order).unwrap();
    let logs: Vec<CommandLog> = run.logs.clone();
    let r = run.world.finish(End::Reached);
    assert!(
        peers.stops[0].is_empty(),
        "a's peer kept talking: {:?}",
        peers.stops[0]
    );
    assert_eq!(peers.stops[1].len(), 1, "b's watchdog stopped it once");
    let when = peers.stops[1][0];
    assert!(
        when > WATCHDOG_TIMEOUT_S && when < WATCHDOG_TIMEOUT_S + 0.02,
        "b stopped {when} s after its last command"
    );
    assert_eq!(peers.robots[0].counts.watchdog_stops, 0);
    assert_eq!(peers.robots[1].counts.watchdog_stops, 1);
    let moved = |k: usize| {
        let s = &r.robots[k].1.samples;
        (s.last().unwrap().pose.x - s.first().unwrap().pose.x).abs()
    };
    let speed = |k: usize| r.robots[k].1.samples.last().unwrap().belt_cmd.clone();
    eprintln!(
        "west moved {:.4} m, east {:.4} m; east stopped at {when} s",
        moved(0),
        moved(1)
    );
    assert!(moved(0) > 0.45, "a drove on: {} m", moved(0));
    assert!(moved(1) < 0.2, "b stopped early: {} m", moved(1));
    assert!(
        speed(0).iter().all(|&v| (v - 0.3).abs() < 1e-9),
        "{:?}",
        speed(0)
    );
    assert!(speed(1).iter().all(|&v| v == 0.0), "{:?}", speed(1));

    // The session's commands file replays it: the same trajectories, sample for sample.
    let dir = std::env::temp_dir().join(format!("tracksim-ros-team-{}", std::process::id()));
    let names = sc.robot_names();
    let pairs: Vec<(&str, &CommandLog)> =
        names.iter().map(String::as_str).zip(logs.iter()).collect();
    std::fs::create_dir_all(&dir).unwrap();
    let header = LogHeader {
        what: "test",
        notes: &[],
        seed: None,
    };
    tracksim::run::write_team_log(&pairs, header, &file, &dir, 2.0).unwrap();
    let o = tracksim::Overrides {
        commands: Some(dir.join("commands.toml")),
        duration_s: Some(2.0),
        ..Default::default()
    };
    let replay_sc = tracksim::load_scenario_with(&file, &o).unwrap();
    let replay = tracksim::run::run_team(&replay_sc, Default::default()).unwrap();
    for ((name, live), (_, again)) in r.robots.iter().zip(&replay.robots) {
        assert_eq!(live.samples.len(), again.samples.len(), "{name}");
        for (x, y) in live.samples.iter().zip(&again.samples) {
            assert_eq!(format!("{x:?}"), format!("{y:?}"), "{name} at {} s", x.t);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn namespace_is_refused_for_a_team_file_and_a_bad_name_before_any_node_starts() {
    let run = |args: &[&str]| {
        let o = assert_cmd::Command::cargo_bin("tracksim")
            .unwrap()
            .current_dir(root())
            .args(args)
            .timeout(std::time::Duration::from_secs(60))
            .output()
            .unwrap();
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stderr).to_string(),
        )
    };
    let (code, err) = run(&[
        "ros",
        "scenarios/team/corridor_head_on.toml",
        "--namespace",
        "x",
        "--duration",
        "0.1",
    ]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("--namespace") && err.contains("several robots"),
        "{err}"
    );
    let (code, err) = run(&["ros", "packbot_flat", "--namespace", "Bad-Name"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("--namespace"), "{err}");
}
