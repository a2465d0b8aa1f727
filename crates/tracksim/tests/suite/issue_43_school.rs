//! Issue 43, the school's live side: an instructor's faults do what they say in the physics
//! (a stopped track's belt stays at 0 and the robot turns about it, an unpowered belt
//! free-wheels at the ground's speed with no motor torque, a jammed flipper stays where it
//! was), bad fault keys are refused naming the key, and a live session with the instructor's
//! pause, fault and reset keeps every attempt, each replayed byte for byte by its
//! `commands.toml`.

use crate::common::{self, root};
use crate::live::{Ws, next_json, until as state_where};
use std::collections::BTreeMap;
use std::path::Path;
use tracksim::Scripted;
use tracksim::live::{DriveOptions, Hub, Mode, Server};
use tracksim::spec::{CommandSpec, FaultSpec, PerTrack, ScenarioSpec};
use tungstenite::Message;

/// A fault entry at `t` s: tracks by name to `track` faults, flippers to `flipper` ones.
fn fault_at(t: f64, track: &[(&str, &str)], flipper: &[(&str, &str)]) -> CommandSpec {
    let map = |v: &[(&str, &str)]| -> BTreeMap<String, String> {
        v.iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect()
    };
    CommandSpec {
        t_s: t,
        fault: Some(FaultSpec {
            track: map(track),
            flipper: map(flipper),
            ..FaultSpec::default()
        }),
        ..CommandSpec::default()
    }
}

/// PackBot on flat ground (`vehicle_file`) with every belt at 0.3 m/s from t = 0 and the
/// commands `more` after, for `duration` s.
fn flat(vehicle_file: &str, duration: f64, more: Vec<CommandSpec>) -> tracksim::Scenario {
    common::with_vehicle(
        vehicle_file,
        |s: &mut ScenarioSpec| {
            s.simulation.duration_s = duration;
            s.expect = Default::default();
            s.commands.extend(more);
        },
        |_| {},
    )
}

/// The samples of a run of `sc` from its start to its end.
fn samples(sc: &tracksim::Scenario) -> Vec<tracksim::world::Sample> {
    tracksim::run_scenario(sc, |_, _| {})
        .unwrap()
        .samples
        .to_vec()
}

/// The ground's speed along the track under track `i` (the body's forward speed less the yaw
/// rate times the track's lateral offset), m/s: what a free-rolling belt runs at.
fn ground_speed(sc: &tracksim::Scenario, s: &tracksim::world::Sample, i: usize) -> f64 {
    let (y, p) = (s.pose.yaw, s.pose.pitch);
    let heading = [y.cos() * p.cos(), y.sin() * p.cos(), -p.sin()];
    let forward: f64 = (0..3).map(|k| s.linvel[k] * heading[k]).sum();
    sc.vehicle.twist_belt_speed(i, forward, s.angvel[2])
}

/// A track stopped at 1 s holds its belt at ~0 while the other drives at 0.3 m/s, so the robot
/// turns towards the stopped side (left stopped: yaw grows); without the fault it goes
/// straight.
#[test]
fn a_stopped_track_holds_its_belt_and_the_robot_turns_about_it() {
    let sc = flat(
        "vehicles/packbot510.toml",
        3.0,
        vec![fault_at(1.0, &[("left", "stopped")], &[])],
    );
    let left = sc.vehicle.track_index("left").unwrap();
    let right = sc.vehicle.track_index("right").unwrap();
    let run = samples(&sc);
    let late: Vec<_> = run.iter().filter(|s| s.t > 1.5).collect();
    assert!(!late.is_empty());
    for s in &late {
        // The belt is commanded to 0 and measured at 0 (the links' motors hold it).
        assert_eq!(s.belt_cmd[left], 0.0, "t = {}", s.t);
        assert!(
            s.belt_speed[left].abs() < 0.01,
            "left belt {} m/s at t = {}",
            s.belt_speed[left],
            s.t
        );
        assert!(
            (s.belt_speed[right] - 0.3).abs() < 0.01,
            "right belt {} m/s",
            s.belt_speed[right]
        );
    }
    let end = run.last().unwrap();
    let at_fault = run.iter().find(|s| s.t >= 1.0).unwrap();
    // 2 s at 0.3 m/s on the right track about the left (track separation ~0.5 m): a pure
    // pivot would turn 0.3 / 0.5 * 2 = 1.2 rad; skid turning loses some. Without the fault the
    // robot holds its heading within 0.01 rad.
    let turned = end.pose.yaw - at_fault.pose.yaw;
    assert!(
        turned > 0.3,
        "turned {turned} rad towards the stopped left track"
    );
    let straight = samples(&flat("vehicles/packbot510.toml", 3.0, vec![]));
    assert!(straight.last().unwrap().pose.yaw.abs() < 0.01);
}

/// A spin in place (left belt -0.3, right +0.3 m/s) whose left track loses power at 1.5 s:
/// the left belt no longer runs at its command but free-wheels at the ground's speed under it
/// (within 0.03 m/s of it, and forwards: the right track now pushes the robot ahead), its
/// drive motor giving no torque (exactly 0); powered again ("ok"), it runs backwards again.
#[test]
fn an_unpowered_belt_free_wheels_with_no_motor_torque() {
    let spin = |more: Vec<CommandSpec>| {
        let mut c = vec![CommandSpec {
            t_s: 0.0,
            belt_speed_mps: Some(PerTrack::ByName(
                [("left".to_string(), -0.3), ("right".to_string(), 0.3)].into(),
            )),
            ..CommandSpec::default()
        }];
        c.extend(more);
        common::with_vehicle(
            "vehicles/packbot510_motors.toml",
            |s: &mut ScenarioSpec| {
                s.simulation.duration_s = 4.0;
                s.expect = Default::default();
                s.commands = c;
            },
            |_| {},
        )
    };
    let sc = spin(vec![fault_at(1.5, &[("left", "unpowered")], &[])]);
    let left = sc.vehicle.track_index("left").unwrap();
    let run = samples(&sc);
    let before = run.iter().find(|s| s.t > 1.0).unwrap();
    // The motor cannot hold -0.3 m/s in a spin on flat ground (its torque limit): the belt
    // runs backwards all the same, driven.
    assert!(
        before.belt_speed[left] < -0.05,
        "{}",
        before.belt_speed[left]
    );
    assert!(before.drive[left].as_ref().unwrap().motor_torque_nm.abs() > 0.0);
    let late: Vec<_> = run.iter().filter(|s| s.t > 2.5).collect();
    let mut worst: f64 = 0.0;
    for s in &late {
        let d = s.drive[left].as_ref().expect("the motor's figures");
        assert_eq!(d.motor_torque_nm, 0.0, "t = {}", s.t);
        assert_eq!(d.belt_force_n, 0.0, "t = {}", s.t);
        assert_eq!(
            s.belt_cmd[left], -0.3,
            "the trainee's command stays in the record"
        );
        worst = worst.max((s.belt_speed[left] - ground_speed(&sc, s, left)).abs());
    }
    assert!(
        worst < 0.03,
        "the free belt strays {worst} m/s from the ground's speed"
    );
    let mean = late.iter().map(|s| s.belt_speed[left]).sum::<f64>() / late.len() as f64;
    assert!(
        mean > 0.0,
        "the free belt rolls forwards with the ground: {mean} m/s"
    );
    let back = spin(vec![
        fault_at(1.5, &[("left", "unpowered")], &[]),
        fault_at(3.0, &[("left", "ok")], &[]),
    ]);
    let end = samples(&back).last().unwrap().clone();
    assert!(
        end.belt_speed[left] < -0.05,
        "driven backwards again: {}",
        end.belt_speed[left]
    );
}

/// When the flipper jams on its way, s.
const JAM_S: f64 = 0.02;

/// The PackBot with front flippers.
const FLIPPERS: &str = "vehicles/packbot510_flippers.toml";

/// A flipper jammed on its way to 60 deg stays where it was (within 1 deg) while its target
/// is 60 deg; freed, it reaches the target.
#[test]
fn a_jammed_flipper_stays_where_it_was() {
    let mut go = CommandSpec {
        t_s: 0.0,
        belt_speed_mps: Some(PerTrack::All(0.0)),
        ..CommandSpec::default()
    };
    let sc0 = flat(FLIPPERS, 1.0, vec![]);
    let name = sc0.vehicle.flippers[0].name.clone();
    go.flipper_angle_deg.insert(name.clone(), 60.0);
    let jam = fault_at(JAM_S, &[], &[(name.as_str(), "jammed")]);
    let sc = common::with_vehicle(
        FLIPPERS,
        |s| {
            s.simulation.duration_s = 1.5;
            s.expect = Default::default();
            s.commands = vec![go.clone(), jam.clone()];
        },
        |_| {},
    );
    let mut sim = Scripted::new(&sc).unwrap();
    common::run_until(&mut sim, JAM_S);
    let before = sim.flipper_angle(0);
    sim.step().unwrap();
    let held = sim.flipper_angle(0);
    // The arm's speed when it jammed, deg/s: its position motor stops it from there.
    let rate = (held - before).to_degrees() / sim.dt();
    assert!(sim.flipper_jammed(0));
    common::run_until(&mut sim, 0.5);
    let settled = sim.flipper_angle(0);
    common::run_until(&mut sim, 1.5);
    let start = sc.vehicle.flippers[0].initial_angle;
    assert!(
        (held - start).abs() > 2f64.to_radians()
            && (held - 60f64.to_radians()).abs() > 10f64.to_radians(),
        "jammed on its way: {} deg",
        held.to_degrees()
    );
    // Jammed at the sample boundary at `before` while turning at `rate` (~1100 deg/s), the
    // arm goes on ~1 deg in the step and its position motor brings it back to the jam angle:
    // within 0.5 deg of it 0.5 s later (measured: 13.33 deg jammed, 13.26 deg at 0.5 s), then
    // it stays (less than 0.1 deg in the next second), some 47 deg short of its 60 deg target.
    let off = (settled - before).abs().to_degrees();
    assert!(
        off < 0.5,
        "jammed at {rate:.0} deg/s, it settled {off} deg from the jam angle"
    );
    let moved = (sim.flipper_angle(0) - settled).abs().to_degrees();
    assert!(moved < 0.1, "a jammed flipper moved {moved} deg in 1 s");
    // Freed at 1.5 s: it goes on to 60 deg.
    let free = fault_at(1.5, &[], &[(name.as_str(), "ok")]);
    let sc = common::with_vehicle(
        FLIPPERS,
        |s| {
            s.simulation.duration_s = 3.0;
            s.expect = Default::default();
            s.commands = vec![go, jam, free];
        },
        |_| {},
    );
    let mut sim = Scripted::new(&sc).unwrap();
    common::run_until(&mut sim, 3.0);
    let end = sim.flipper_angle(0).to_degrees();
    assert!((end - 60.0).abs() < 2.0, "freed, it reached {end} deg");
}

/// Bad fault keys are refused with their key path and what to write instead.
#[test]
fn bad_faults_are_refused_naming_the_key() {
    let bad = |f: FaultSpec, method: &str| {
        let mut spec: ScenarioSpec =
            tracksim::model::read_toml(&root().join("scenarios/packbot_flat.toml")).unwrap();
        spec.simulation.method = method.into();
        spec.commands.push(CommandSpec {
            t_s: 1.0,
            fault: Some(f),
            ..CommandSpec::default()
        });
        let v = tracksim::model::load_vehicle(&root().join("vehicles/packbot510.toml")).unwrap();
        let issues = tracksim::compile_scenario(&spec, v, &root().join("scenarios")).unwrap_err();
        issues
            .iter()
            .map(|i| i.to_string())
            .collect::<Vec<_>>()
            .join("\n")
    };
    let track = |n: &str, k: &str| FaultSpec {
        track: [(n.to_string(), k.to_string())].into(),
        ..FaultSpec::default()
    };
    let e = bad(track("lft", "stopped"), "okada2020");
    assert!(
        e.contains("commands[1].fault.track.lft") && e.contains("no track called"),
        "{e}"
    );
    let e = bad(track("left", "broken"), "okada2020");
    assert!(
        e.contains("commands[1].fault.track.left") && e.contains("\"unpowered\""),
        "{e}"
    );
    let e = bad(track("left", "unpowered"), "constraint_to_ground");
    assert!(
        e.contains("commands[1].fault.track") && e.contains("\"stopped\""),
        "{e}"
    );
    let e = bad(
        FaultSpec {
            latency_s: Some(-1.0),
            video: Some("snow".into()),
            flipper: [("tail".to_string(), "jammed".to_string())].into(),
            ..FaultSpec::default()
        },
        "okada2020",
    );
    for key in ["fault.latency_s", "fault.video", "fault.flipper.tail"] {
        assert!(e.contains(&format!("commands[1].{key}")), "{key} in {e}");
    }
    // An unknown key of the table is refused by the parser, naming it.
    let text = std::fs::read_to_string(root().join("scenarios/packbot_flat.toml")).unwrap()
        + "\n[[commands]]\nt_s = 1.0\nfault = { track = { left = \"stopped\" }, lag_s = 1 }\n";
    let dir = std::env::temp_dir().join(format!("tracksim-43-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("s.toml");
    std::fs::write(
        &f,
        text.replace(
            "../vehicles",
            &root().join("vehicles").display().to_string(),
        ),
    )
    .unwrap();
    let e = tracksim::load_scenario(&f).unwrap_err().to_string();
    assert!(e.contains("lag_s"), "{e}");
}

fn send(ws: &mut Ws, v: serde_json::Value) {
    ws.send(Message::text(v.to_string())).unwrap();
}

/// Reads messages until an error comes; panics after `max`.
fn error_of(ws: &mut Ws, max: usize) -> String {
    for _ in 0..max {
        let m = next_json(ws);
        if m["type"] == "error" {
            return m["message"].as_str().unwrap().to_string();
        }
    }
    panic!("no error in {max} messages");
}

/// `run FILE --commands DIR/commands.toml --duration T` of `dir` gives its trajectory.csv.
fn replays(file: &Path, dir: &Path) {
    let duration: f64 = {
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap())
                .unwrap();
        s["sim_time_s"].as_f64().unwrap()
    };
    let replay = tracksim::load_scenario_with(
        file,
        &tracksim::Overrides {
            commands: Some(dir.join("commands.toml")),
            duration_s: Some(duration),
            ..Default::default()
        },
    )
    .unwrap();
    let r = tracksim::run_scenario(&replay, |_, _| {}).unwrap();
    let csv = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
    assert!(
        tracksim::output::trajectory_csv(&r) == csv,
        "{} does not replay byte for byte",
        dir.display()
    );
}

/// The instructor's seat over the WebSocket: its token is not the page's (`/session.json` does
/// not serve it; a wrong one watches), a pause stops simulated time and the resume goes on
/// without a catch-up burst, a fault stops the left track (in the states and `commands.toml`),
/// a reset starts a second attempt, the instructor ends the session; both attempts are written
/// as run folders, each replayed byte for byte, and every action is an event.
#[test]
fn the_instructor_pauses_injects_resets_and_ends_and_every_attempt_replays() {
    let file = root().join("scenarios/packbot_flat.toml");
    let sc = tracksim::load_scenario(&file).unwrap();
    let hub = Hub::with_grace(5.0);
    let mode = Mode::Drive {
        hub: hub.clone(),
        scene_json: vec!["{}".into()],
    };
    let server = Server::start(tracksim::live::DEFAULT_BIND, 0, mode).unwrap();
    let (sc2, hub2) = (sc.clone(), hub.clone());
    let opts = DriveOptions {
        speed: 2.0,
        ..DriveOptions::default()
    };
    let session = std::thread::spawn(move || tracksim::live::run_session(&sc2, &hub2, opts));
    let itoken = hub.instructor_token().unwrap().to_string();
    assert_ne!(itoken, hub.session_token().unwrap());
    let addr = server.addr();
    let url = format!("ws://{addr}/ws?session={}", hub.session_token().unwrap());
    let (mut driver, _) = tungstenite::connect(&url).unwrap();
    assert_eq!(hello_of(&mut driver)["role"], "driver");
    let (mut wrong, _) = tungstenite::connect(format!("ws://{addr}/ws?instructor=00ff")).unwrap();
    assert!(error_of(&mut wrong, 50).contains("not the instructor's token"));
    assert_eq!(hello_of(&mut wrong)["role"], "watcher");
    send(&mut wrong, serde_json::json!({"type": "pause"}));
    assert!(error_of(&mut wrong, 500).contains("only watches"));
    drop(wrong);
    let (mut ins, _) = tungstenite::connect(format!("ws://{addr}/ws?instructor={itoken}")).unwrap();
    assert_eq!(hello_of(&mut ins)["role"], "instructor");
    // The driver's page cannot pause.
    send(&mut driver, serde_json::json!({"type": "pause"}));
    assert!(error_of(&mut driver, 500).contains("bad message"));
    send(
        &mut driver,
        serde_json::json!({"type":"control","forward_mps":0.3,"yaw_rate_rad_s":0.0}),
    );
    state_where(&mut ins, 5000, "t > 0.5 s", |m| {
        m["t"].as_f64().unwrap() > 0.5
    });
    pause_and_resume(&mut ins);
    // A fault: the left track stops; a bad one is refused with the reason.
    send(
        &mut ins,
        serde_json::json!({"type":"fault","fault":{"track":{"lft":"stopped"}}}),
    );
    assert!(error_of(&mut ins, 500).contains("no track called \"lft\""));
    send(
        &mut ins,
        serde_json::json!({"type":"fault","fault":{"track":{"left":"stopped"}}}),
    );
    state_where(&mut ins, 5000, "the left track stopped", |m| {
        m["faults"]["track"][0] == "stopped" || m["faults"]["track"][1] == "stopped"
    });
    state_where(&mut driver, 5000, "t > 1.5 s", |m| {
        m["t"].as_f64().unwrap() > 1.5
    });
    // Reset: a second attempt.
    send(&mut ins, serde_json::json!({"type": "reset"}));
    state_where(&mut ins, 5000, "attempt 2", |m| m["attempt"] == 2);
    send(
        &mut driver,
        serde_json::json!({"type":"control","forward_mps":0.2,"yaw_rate_rad_s":0.1}),
    );
    state_where(&mut ins, 5000, "attempt 2 at t > 0.5 s", |m| {
        m["attempt"] == 2 && m["t"].as_f64().unwrap() > 0.5
    });
    send(&mut ins, serde_json::json!({"type": "end"}));
    let s = session.join().unwrap().unwrap();
    assert_eq!(s.attempts.len(), 1);
    let dir = std::env::temp_dir().join(format!("tracksim-43-school-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    s.write(&sc, &file, &dir, false).unwrap();
    let first = dir.join("attempts/1");
    for f in [
        "summary.json",
        "trajectory.csv",
        "commands.toml",
        "controls.csv",
    ] {
        assert!(first.join(f).is_file(), "attempts/1/{f}");
    }
    let commands = std::fs::read_to_string(first.join("commands.toml")).unwrap();
    assert!(
        commands.contains("[commands.fault.track]") || commands.contains("fault"),
        "{commands}"
    );
    assert!(commands.contains("left = \"stopped\""), "{commands}");
    replays(&file, &first);
    replays(&file, &dir);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let attempts = summary["attempts"].as_array().unwrap();
    assert_eq!(attempts.len(), 2, "{summary}");
    assert_eq!(attempts[0]["folder"], "attempts/1");
    assert_eq!(attempts[0]["ended_by"], "the instructor");
    assert_eq!(attempts[1]["folder"], ".");
    let kinds = |v: &serde_json::Value| -> Vec<String> {
        v["events"]
            .as_array()
            .unwrap()
            .iter()
            .map(|e| e["kind"].as_str().unwrap().to_string())
            .collect()
    };
    let one: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(first.join("summary.json")).unwrap())
            .unwrap();
    for k in ["pause", "resume", "fault", "reset"] {
        assert!(
            kinds(&one).iter().any(|e| e == k),
            "{k} in {:?}",
            kinds(&one)
        );
    }
    assert!(
        kinds(&summary).iter().any(|e| e == "end"),
        "{:?}",
        kinds(&summary)
    );
    // The instructor's token is never served to a page.
    let body = get(addr, "/session.json");
    assert!(body.contains("\"token\""), "{body}");
    assert!(!body.contains(&itoken), "{body}");
}

/// The response to a GET of `target` from the server at `addr`, head and body.
fn get(addr: std::net::SocketAddr, target: &str) -> String {
    use std::io::{Read, Write};
    let mut s = std::net::TcpStream::connect(addr).unwrap();
    write!(
        s,
        "GET {target} HTTP/1.1\r\nHost: localhost:{}\r\n\r\n",
        addr.port()
    )
    .unwrap();
    let mut text = String::new();
    s.read_to_string(&mut text).unwrap();
    text
}

/// The first hello a connection is sent (an error may come before it).
fn hello_of(ws: &mut Ws) -> serde_json::Value {
    for _ in 0..50 {
        let m = next_json(ws);
        if m["type"] == "hello" {
            return m;
        }
    }
    panic!("no hello");
}

/// The instructor pauses: simulated time stands still for 0.6 s of wall time; resumes: no
/// catch-up burst.
fn pause_and_resume(ins: &mut Ws) {
    // Pause: simulated time stands still for 0.6 s of wall time.
    send(ins, serde_json::json!({"type": "pause"}));
    let p = state_where(ins, 5000, "paused", |m| m["paused"] == true);
    let t_pause = p["t"].as_f64().unwrap();
    let wall = std::time::Instant::now();
    while wall.elapsed().as_secs_f64() < 0.6 {
        let m = state_where(ins, 5000, "a state", |_| true);
        assert_eq!(m["t"].as_f64().unwrap(), t_pause, "time moved while paused");
    }
    send(ins, serde_json::json!({"type": "resume"}));
    let r = state_where(ins, 5000, "resumed", |m| m["paused"] == false);
    let resumed = std::time::Instant::now();
    // No burst: at speed 2 the 0.6 s pause would be 1.2 s of catch-up; 0.15 s of wall after
    // the resume the session is at most 0.3 s (+ one state interval and stepping) further.
    let m = state_where(ins, 5000, "0.15 s later", |_| {
        resumed.elapsed().as_secs_f64() > 0.15
    });
    let ahead = m["t"].as_f64().unwrap() - r["t"].as_f64().unwrap();
    let allowed = 2.0 * resumed.elapsed().as_secs_f64() + 0.1;
    assert!(
        ahead < allowed,
        "{ahead} s simulated in {allowed} s allowed: a catch-up burst"
    );
}
