//! Issue 59: no stop loses a session. Two robots in one world, one driven away from the other
//! until they are further apart than one world holds (`model::MAX_ROBOT_SPREAD_M`): the world
//! stops there, and the session (live, two WebSocket drivers on loopback) and the run (`run_team_kept`)
//! keep every robot's samples, controls and outcome up to that moment, say why, and the pages
//! are told. No assertion is on wall-clock time: loops give up after a number of messages.

use crate::common::root;
use crate::live::{TeamDrive, Ws, next_json, team_drive};
use std::path::PathBuf;
use tungstenite::Message;

/// Two PackBots 9.2 m apart along x on flat ground (within the 10 m one world holds), `a`
/// behind `b`, both facing +x; with `commands`, `a` reverses at 0.3 m/s from t = 0.5 s.
fn spread_file(dir: &std::path::Path, commands: bool) -> PathBuf {
    let vehicle = root().join("vehicles/packbot510.toml");
    let robot = |name: &str, x: f64, cmd: &str| {
        format!(
            "[[vehicles]]\nname = \"{name}\"\n[vehicles.vehicle]\nfile = \"{}\"\nx_m = {x}\n{cmd}",
            vehicle.display()
        )
    };
    let back = if commands {
        "[[vehicles.commands]]\nt_s = 0.5\nbelt_speed_mps = -0.3\n"
    } else {
        ""
    };
    let text = format!(
        "[terrain.ground]\nfriction = 0.8\n[simulation]\nduration_s = 30.0\n{}{}",
        robot("a", -4.6, back),
        robot("b", 4.6, "")
    );
    let file = dir.join("spread.toml");
    std::fs::write(&file, text).unwrap();
    file
}

fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tracksim-59-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The time, s, at which robots 9.2 m apart of which one reverses at `v` m/s from `t0` s pass
/// the 10 m a world holds: `t0 + 0.8 / v` (a belt-speed command gives about its speed on
/// friction 0.8 ground, Table II).
fn expected_stop_s(t0: f64, v: f64) -> f64 {
    t0 + (tracksim::model::MAX_ROBOT_SPREAD_M - 9.2) / v
}

#[test]
fn a_run_whose_robots_part_keeps_every_robots_run_up_to_the_stop() {
    let dir = temp_dir("run");
    let file = spread_file(&dir, true);
    let sc = tracksim::load_scenario(&file).unwrap();
    // As before: the plain run is an error ...
    let e = tracksim::run::run_team(&sc, Default::default()).unwrap_err();
    assert!(e.stops_world(), "{e}");
    // ... and the kept run holds what was simulated.
    let (r, e) = tracksim::run::run_team_kept(&sc, Default::default()).unwrap();
    let e = e.expect("the world stops");
    let why = r.stopped.clone().expect("the result says why");
    assert_eq!(why, e.to_string());
    assert!(why.contains("m apart"), "{why}");
    let t_stop = r.robots[0].1.samples.last().unwrap().t;
    let want = expected_stop_s(0.5, 0.3);
    assert!(
        (t_stop - want).abs() < 0.3,
        "stopped at {t_stop:.3} s, the spread says {want:.3} s (+-0.3 s: belt slip and spin-up)"
    );
    for (name, run) in &r.robots {
        let last = run.samples.last().unwrap();
        assert!(
            (last.t - t_stop).abs() < 1e-9,
            "{name}: every robot's samples end at the stop"
        );
        assert_eq!(run.summary.stopped.as_deref(), Some(why.as_str()), "{name}");
        assert_eq!(run.outcome.name(), "failure", "{name}: {:?}", run.outcome);
    }
    // The robots' distance at the last sample is past the limit by at most one step's travel
    // plus the sample interval's (the check runs every step; the last sample is that step's).
    let xa = r.robots[0].1.samples.last().unwrap().pose.x;
    let xb = r.robots[1].1.samples.last().unwrap().pose.x;
    let d = xb - xa;
    assert!(
        d > tracksim::model::MAX_ROBOT_SPREAD_M && d < tracksim::model::MAX_ROBOT_SPREAD_M + 0.01,
        "{d:.4} m apart at the stop"
    );
    // Written: each robot's folder and the world's team.json with the reason.
    let out = dir.join("out");
    let which = tracksim::output::Outputs {
        replay: true,
        plots: false,
        mcap: false,
        raw_images: false,
    };
    tracksim::output::write_team(&sc, &r, &out, which).unwrap();
    let team: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("team.json")).unwrap()).unwrap();
    assert_eq!(team["stopped"], serde_json::json!(why));
    assert_eq!(team["outcome"], "failure");
    for name in ["a", "b"] {
        let csv = std::fs::read_to_string(out.join(name).join("trajectory.csv")).unwrap();
        assert!(csv.lines().count() > 10, "{name}'s trajectory written");
        let s: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(out.join(name).join("summary.json")).unwrap(),
        )
        .unwrap();
        assert_eq!(s["stopped"], serde_json::json!(why), "{name}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn back(ws: &mut Ws, v: f64) {
    let msg = serde_json::json!({ "type": "control", "forward_mps": v, "yaw_rate_rad_s": 0.0 });
    ws.send(Message::text(msg.to_string())).unwrap();
}

#[test]
fn a_class_session_whose_trainees_part_is_kept_and_its_pages_told_why() {
    let dir = temp_dir("drive");
    let file = spread_file(&dir, false);
    let sc = tracksim::load_scenario(&file).unwrap();
    let TeamDrive {
        mut server,
        session,
        url,
        ..
    } = team_drive(&sc, 8.0);
    let (mut a, _) = tungstenite::connect(format!("{url}&robot=a")).unwrap();
    assert_eq!(next_json(&mut a)["robot"], "a");
    let (mut b, _) = tungstenite::connect(format!("{url}&robot=b")).unwrap();
    assert_eq!(next_json(&mut b)["robot"], "b");
    // a reverses away from b, b drives on away from a.
    back(&mut a, -0.3);
    back(&mut b, 0.3);
    // b's page gets the session's last state, which says why it stopped.
    let mut last = None;
    for _ in 0..200_000 {
        let m = next_json(&mut b);
        if m["type"] == "state" && m["session_ended"] == true {
            last = Some(m);
            break;
        }
    }
    let last = last.expect("the page is told the session ended");
    let told = last["stopped"].as_str().expect("and why").to_string();
    assert!(told.contains("m apart"), "{told}");
    let s = session.join().unwrap().unwrap();
    server.shutdown();
    assert_eq!(s.result.stopped.as_deref(), Some(told.as_str()));
    // Both robots moved apart at about 0.3 m/s each: 0.8 m more in about 1.3 s of driving.
    for (name, run) in &s.result.robots {
        assert_eq!(
            run.summary.stopped.as_deref(),
            Some(told.as_str()),
            "{name}"
        );
        assert!(run.samples.len() > 10, "{name}: its samples are kept");
    }
    // Written: every robot's run, the controls, and commands.toml that replays up to the stop.
    let out = dir.join("out");
    let written = s.write(&sc, &file, &out, false).unwrap();
    for f in [
        "a/trajectory.csv",
        "b/trajectory.csv",
        "team.json",
        "commands.toml",
    ] {
        assert!(written.contains(&out.join(f)), "{f} not written");
    }
    let replay = tracksim::load_scenario_with(
        &file,
        &tracksim::Overrides {
            commands: Some(out.join("commands.toml")),
            duration_s: Some(s.duration()),
            ..Default::default()
        },
    )
    .unwrap();
    let (r, e) = tracksim::run::run_team_kept(&replay, Default::default()).unwrap();
    assert_eq!(
        e.map(|e| e.to_string()).as_deref(),
        Some(told.as_str()),
        "the replay stops where the session did, for the same reason"
    );
    for (name, run) in &r.robots {
        let recorded = std::fs::read_to_string(out.join(name).join("trajectory.csv")).unwrap();
        assert_eq!(
            tracksim::output::trajectory_csv(run),
            recorded,
            "robot {name}'s replay differs"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
