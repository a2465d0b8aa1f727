//! Issue 40, live: a `drive` session of two robots, a seat each, driven at once by two
//! WebSocket clients on loopback (no browser), watched by a third; the session replays byte for
//! byte with `run --commands`. No assertion is on wall-clock time: loops wait for a state and
//! give up after a number of messages.

use crate::common::root;
use crate::live::{TeamDrive, Ws, next_json, team_drive};
use std::path::PathBuf;
use tungstenite::Message;

/// Reads messages until one of `kind` satisfies `pred`; panics after `max` messages.
fn until(
    ws: &mut Ws,
    max: usize,
    kind: &str,
    pred: impl Fn(&serde_json::Value) -> bool,
) -> serde_json::Value {
    for _ in 0..max {
        let m = next_json(ws);
        if m["type"] == kind && pred(&m) {
            return m;
        }
    }
    panic!("no {kind} message as wanted in {max} messages");
}

fn twist(ws: &mut Ws, v: f64, w: f64) {
    let msg = serde_json::json!({ "type": "control", "forward_mps": v, "yaw_rate_rad_s": w });
    ws.send(Message::text(msg.to_string())).unwrap();
}

/// Two PackBots side by side, 1.5 m apart, on flat ground (no commands of their own).
fn two_robot_file(dir: &std::path::Path) -> PathBuf {
    let vehicle = root().join("vehicles/packbot510.toml");
    let robot = |name: &str, y: f64| {
        format!(
            "[[vehicles]]\nname = \"{name}\"\n[vehicles.vehicle]\nfile = \"{}\"\ny_m = {y}\n",
            vehicle.display()
        )
    };
    let text = format!(
        "[terrain.ground]\nfriction = 0.8\n[simulation]\nduration_s = 60.0\n{}{}",
        robot("a", 0.75),
        robot("b", -0.75)
    );
    let file = dir.join("two.toml");
    std::fs::write(&file, text).unwrap();
    file
}

/// Session `s` of `file` written into `out` and replayed as `tracksim run FILE --commands
/// OUT/commands.toml --duration T` does: every robot's trajectory.csv byte for byte.
fn replays_byte_for_byte(
    s: &tracksim::live::TeamSession,
    sc: &tracksim::Scenario,
    file: &std::path::Path,
    out: &std::path::Path,
) {
    let written = s.write(sc, file, out, false).unwrap();
    for f in [
        "a/trajectory.csv",
        "b/controls.csv",
        "team.json",
        "commands.toml",
    ] {
        assert!(written.contains(&out.join(f)), "{f} not written");
    }
    // Replayed as `tracksim run FILE --commands OUT/commands.toml --duration T` does.
    let replay = tracksim::load_scenario_with(
        file,
        &tracksim::Overrides {
            commands: Some(out.join("commands.toml")),
            duration_s: Some(s.duration()),
            ..Default::default()
        },
    )
    .unwrap();
    let r = tracksim::run::run_team(&replay, tracksim::RunOptions::default()).unwrap();
    for (name, run) in &r.robots {
        let recorded = std::fs::read_to_string(out.join(name).join("trajectory.csv")).unwrap();
        assert_eq!(
            tracksim::output::trajectory_csv(run),
            recorded,
            "robot {name}'s replay differs"
        );
    }
}

#[test]
fn two_trainees_drive_at_once_and_the_session_replays_byte_for_byte() {
    let dir = std::env::temp_dir().join(format!("tracksim-team-drive-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let file = two_robot_file(&dir);
    let sc = tracksim::load_scenario(&file).unwrap();
    let TeamDrive {
        server: _server,
        session,
        url,
        ..
    } = team_drive(&sc, 4.0);
    // Seat b asked by name, seat a taken as the first free one; a third page watches.
    let (mut b, _) = tungstenite::connect(format!("{url}&robot=b")).unwrap();
    let hb = next_json(&mut b);
    assert_eq!(
        (&hb["role"], &hb["robot"]),
        (&"driver".into(), &"b".into()),
        "{hb}"
    );
    assert_eq!(hb["robots"], serde_json::json!(["a", "b"]));
    let (mut a, _) = tungstenite::connect(&url).unwrap();
    let ha = next_json(&mut a);
    assert_eq!(
        (&ha["role"], &ha["robot"]),
        (&"driver".into(), &"a".into()),
        "{ha}"
    );
    assert_ne!(ha["token"], hb["token"], "a token per seat");
    let (mut w, _) = tungstenite::connect(format!("{url}&watch=1&robot=b")).unwrap();
    let hw = next_json(&mut w);
    assert_eq!(
        (&hw["role"], &hw["robot"]),
        (&"watcher".into(), &"b".into()),
        "{hw}"
    );
    twist(&mut w, 1.0, 0.0);
    let refused = until(&mut w, 500, "error", |_| true);
    assert!(
        refused["message"]
            .as_str()
            .unwrap()
            .contains("only watches")
    );
    // (A driver's reset of their own robot in such a session: issue_43_team_reset.rs.)

    // a drives straight, b turns left on the spot; each page sees its own robot and the other.
    twist(&mut a, 0.3, 0.0);
    twist(&mut b, 0.0, 0.4);
    let sa = until(&mut a, 5000, "state", |m| {
        m["pose"][0].as_f64().unwrap() > 0.15
    });
    assert_eq!(sa["robot"], "a");
    assert_eq!(sa["others"][0]["name"], "b");
    assert!(
        sa["pose"][1].as_f64().unwrap() > 0.7,
        "a keeps its lane: {}",
        sa["pose"]
    );
    let sb = until(&mut b, 5000, "state", |m| {
        m["pose"][5].as_f64().unwrap() > 0.2
    });
    assert_eq!(sb["robot"], "b");
    assert!(
        sb["pose"][0].as_f64().unwrap().abs() < 0.05,
        "b turns on the spot"
    );
    let seen = until(&mut w, 5000, "state", |m| {
        m["pose"][5].as_f64().unwrap() > 0.2
    });
    assert_eq!(seen["robot"], "b", "the watcher follows b");
    assert!(
        seen["others"][0]["pose"][0].as_f64().unwrap() > 0.1,
        "and sees a"
    );

    // a stops: its seat closes, b drives on; b stops: the session ends.
    a.send(Message::text(r#"{"type":"stop"}"#)).unwrap();
    let ha2 = until(&mut a, 5000, "hello", |_| true);
    assert_eq!(ha2["role"], "watcher", "a stopped driver watches: {ha2}");
    let t_stop = until(&mut b, 5000, "state", |_| true)["t"]
        .as_f64()
        .unwrap();
    until(&mut b, 5000, "state", |m| {
        m["t"].as_f64().unwrap() > t_stop + 0.5
    });
    b.send(Message::text(r#"{"type":"stop"}"#)).unwrap();
    let s = session.join().unwrap().unwrap();
    assert_eq!(s.result.outcome.name(), "ended_by_operator");
    let names: Vec<&str> = s.result.robots.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["a", "b"]);
    // a: forward, then the dead-man stop of its closed seat; b: the turn (its stop ended it).
    assert_eq!(s.logs[0].len(), 2, "{:?}", s.logs[0]);
    assert_eq!(s.logs[0].commands()[1].forward_mps, Some(0.0));
    assert_eq!(s.logs[1].len(), 1, "{:?}", s.logs[1]);
    assert_eq!(s.logs[1].commands()[0].yaw_rate_rad_s, Some(0.4));

    replays_byte_for_byte(&s, &sc, &file, &dir.join("out"));
    let a_end = &s.result.robots[0].1.summary.final_pose;
    assert!(a_end.x > 0.15 && a_end.y > 0.6, "{a_end:?}");
}

#[test]
fn a_team_commands_file_must_name_every_robot_and_only_them() {
    let dir = std::env::temp_dir().join(format!("tracksim-team-cmds-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let file = two_robot_file(&dir);
    let cmds = dir.join("commands.toml");
    let load = |text: &str| {
        std::fs::write(&cmds, text).unwrap();
        let o = tracksim::Overrides {
            commands: Some(cmds.clone()),
            ..Default::default()
        };
        tracksim::load_scenario_with(&file, &o).map_err(|e| e.to_string())
    };
    let e = load("[[vehicles]]\nname = \"a\"\n[[vehicles]]\nname = \"c\"\n").unwrap_err();
    assert!(e.contains("commands.toml"), "names the commands file: {e}");
    assert!(
        e.contains("no robot `c`") && e.contains("robot `b` is not listed"),
        "{e}"
    );
    let e = load("[[commands]]\nt_s = 0.0\nbelt_speed_mps = 0.3\n").unwrap_err();
    assert!(e.contains("drives one robot"), "{e}");
    let ok = load(
        "[[vehicles]]\nname = \"b\"\n[[vehicles.commands]]\nt_s = 0.0\nbelt_speed_mps = 0.2\n\
         [[vehicles]]\nname = \"a\"\ncommands = []\n",
    )
    .unwrap();
    let team = ok.team.as_ref().unwrap();
    assert!(team.robots[0].commands.is_empty());
    assert_eq!(team.robots[1].commands.len(), 1);
    // A one-robot file refuses a commands file of several robots.
    let one = root().join("scenarios/packbot_flat.toml");
    let o = tracksim::Overrides {
        commands: Some(cmds.clone()),
        ..Default::default()
    };
    let e = tracksim::load_scenario_with(&one, &o)
        .unwrap_err()
        .to_string();
    assert!(e.contains("drives several robots"), "{e}");
}
