//! `tracksim ros --play-commands` (issue 42), without DDS: the file's `[[commands]]` drive the
//! robot until its first ROS command, which then wins (a line says so); the session's
//! `commands.toml` (file entries and ROS commands alike) replays it sample for sample. Without
//! the flag the file's commands are not played.

use std::path::{Path, PathBuf};
use tracksim::ros::{Command, FileCommands, RobotControl};
use tracksim::run::{
    CommandLog, ControlSource, End, LogHeader, Runner, SessionLimits, run_session,
};
use tracksim::spec::CommandSpec;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A ROS peer that is silent until `from` s, then stops the robot by `/cmd_vel` at 10 Hz.
struct LatePeer {
    robot: RobotControl,
    from: f64,
    said: Vec<(f64, String)>,
}

impl ControlSource for LatePeer {
    fn controls(&mut self, runner: &Runner) -> Option<CommandSpec> {
        let t = runner.time();
        let k = (t * 100.0).round() as i64;
        let received = if t >= self.from - 1e-9 && k % 10 == 0 {
            vec![Command::Twist {
                forward_mps: 0.0,
                yaw_rate_rad_s: 0.0,
            }]
        } else {
            Vec::new()
        };
        let v = &runner.scenario().vehicle;
        let said = &mut self.said;
        self.robot
            .controls(v, t, received, &mut |m| said.push((t, m.to_string())))
    }
}

fn session(
    play: bool,
) -> (
    tracksim::Scenario,
    tracksim::RunResult,
    CommandLog,
    LatePeer,
) {
    let file = root().join("scenarios/packbot_flat.toml");
    let sc = tracksim::load_scenario(&file).unwrap();
    let runner = Runner::new(&sc).unwrap().without_commands().unbounded();
    let files = FileCommands::new(&sc.vehicle, &sc.commands, play);
    assert_eq!(files.len(), 1);
    let mut peer = LatePeer {
        robot: RobotControl::new(None, &sc.vehicle).with_file_commands(files),
        from: 1.0,
        said: Vec::new(),
    };
    let limits = SessionLimits {
        max_time: Some(2.0),
        interrupt: None,
    };
    let run = run_session(runner, &mut peer, limits).unwrap();
    let log = run.log.clone();
    let r = run.runner.finish(End::Reached);
    (sc, r, log, peer)
}

#[test]
fn the_files_commands_drive_until_the_first_ros_command_and_replay() {
    let (sc, r, log, peer) = session(true);
    // The file's 0.3 m/s until 1 s, then the ROS stop.
    let at = |t: f64| {
        r.samples
            .iter()
            .find(|s| (s.t - t).abs() < 1e-6)
            .expect("sample")
    };
    assert!(at(0.5).belt_cmd.iter().all(|&v| (v - 0.3).abs() < 1e-12));
    assert!(at(0.99).belt_cmd.iter().all(|&v| (v - 0.3).abs() < 1e-12));
    assert!(at(1.5).belt_cmd.iter().all(|&v| v == 0.0));
    let x = |t: f64| at(t).pose.x - r.samples.first().unwrap().pose.x;
    assert!(x(1.0) > 0.2, "the file's command drove: {} m", x(1.0));
    assert_eq!(peer.said.len(), 1, "{:?}", peer.said);
    assert!((peer.said[0].0 - 1.0).abs() < 1e-9);
    assert!(peer.said[0].1.contains("ROS command"), "{:?}", peer.said);
    assert_eq!(log.commands()[0].t_s, 0.0);
    assert_eq!(log.len(), 2, "{:?}", log.commands());

    // commands.toml replays the session.
    let file = root().join("scenarios/packbot_flat.toml");
    let dir = std::env::temp_dir().join(format!("tracksim-ros-play-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let header = LogHeader {
        what: "test",
        notes: &[],
        seed: None,
    };
    let path = log.write(header, &file, &dir, 2.0).unwrap();
    let o = tracksim::Overrides {
        commands: Some(path),
        duration_s: Some(2.0),
        ..Default::default()
    };
    let replay_sc = tracksim::load_scenario_with(&file, &o).unwrap();
    let again = tracksim::run_scenario(&replay_sc, |_, _| {}).unwrap();
    assert_eq!(r.samples.len(), again.samples.len());
    for (a, b) in r.samples.iter().zip(&again.samples) {
        assert_eq!(format!("{a:?}"), format!("{b:?}"), "at {} s", a.t);
    }
    let _ = std::fs::remove_dir_all(&dir);
    drop(sc);
}

#[test]
fn without_the_flag_the_files_commands_are_not_played() {
    let (_, r, log, peer) = session(false);
    let at1 = r.samples.iter().find(|s| (s.t - 0.9).abs() < 1e-6).unwrap();
    assert!(at1.belt_cmd.iter().all(|&v| v == 0.0), "{:?}", at1.belt_cmd);
    assert!(peer.said.is_empty());
    // What was logged before the ROS command is the idle state, no file entry.
    assert!(log.commands().iter().all(|c| c.t_s == 0.0 || c.t_s >= 1.0));
}
