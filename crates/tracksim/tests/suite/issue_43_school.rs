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
use tracksim::spec::{CommandSpec, FaultSpec, PatchArea, PatchSpec, PerTrack, ScenarioSpec};
use tungstenite::Message;

/// A spin on the spot (left belt -0.3 m/s, right +0.3 m/s from t = 0), then `more`.
fn spin_commands(more: Vec<CommandSpec>) -> Vec<CommandSpec> {
    let mut c = vec![CommandSpec {
        t_s: 0.0,
        belt_speed_mps: Some(PerTrack::ByName(
            [("left".to_string(), -0.3), ("right".to_string(), 0.3)].into(),
        )),
        ..CommandSpec::default()
    }];
    c.extend(more);
    c
}

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
        let c = spin_commands(more);
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

/// The plate chain (`plates`) unpowered: the sprocket's motor lets go, so the chain of the
/// left track, driven backwards at -0.3 m/s in a spin, runs with the ground under it
/// (forwards) within 0.06 m/s on average; given back (`"ok"`), it is driven backwards again.
#[test]
fn an_unpowered_plate_chain_free_wheels() {
    let spin = |more: Vec<CommandSpec>| {
        let c = spin_commands(more);
        common::packbot(
            |s: &mut ScenarioSpec| {
                s.simulation.method = "plates".into();
                s.simulation.duration_s = 3.0;
                s.expect = Default::default();
                s.commands = c;
            },
            |_| {},
        )
    };
    let sc = spin(vec![fault_at(1.0, &[("left", "unpowered")], &[])]);
    let left = sc.vehicle.track_index("left").unwrap();
    let run = samples(&sc);
    let before = run.iter().find(|s| s.t > 0.9).unwrap();
    assert!(
        before.belt_speed[left] < -0.2,
        "driven backwards: {}",
        before.belt_speed[left]
    );
    let late: Vec<_> = run.iter().filter(|s| s.t > 1.8).collect();
    let n = late.len() as f64;
    let mean = late.iter().map(|s| s.belt_speed[left]).sum::<f64>() / n;
    let ground = late.iter().map(|s| ground_speed(&sc, s, left)).sum::<f64>() / n;
    let off = late
        .iter()
        .map(|s| (s.belt_speed[left] - ground_speed(&sc, s, left)).abs())
        .sum::<f64>()
        / n;
    println!(
        "plates unpowered: belt {mean:.4} m/s, ground under it {ground:.4} m/s, mean off {off:.4} m/s"
    );
    // The belt speed reported is the sprocket's (a free wheel now, turned by the chain through
    // friction and the chain's polygon): it lags the ground's by a few cm/s (0.040 m/s
    // measured), where a driven chain would run at -0.3 m/s, 0.55 m/s off.
    assert!(
        off < 0.06,
        "the free chain strays {off} m/s from the ground's speed on average"
    );
    assert!(mean > 0.1, "the free chain rolls forwards: {mean} m/s");
    let back = spin(vec![
        fault_at(1.0, &[("left", "unpowered")], &[]),
        fault_at(2.2, &[("left", "ok")], &[]),
    ]);
    let end = samples(&back).last().unwrap().clone();
    assert!(
        end.belt_speed[left] < -0.2,
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

/// The problems of the packbot_flat scenario under `method` with a fault entry `f` at 1 s, one
/// per line (its compile must fail).
fn refused(f: FaultSpec, method: &str) -> String {
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
}

/// The packbot_flat scenario file with `entry` appended (a `[[commands]]` entry's text),
/// loaded from a temporary folder (`name` tells the tests' files apart).
fn load_with_entry(name: &str, entry: &str) -> tracksim::Result<tracksim::Scenario> {
    let text = std::fs::read_to_string(root().join("scenarios/packbot_flat.toml")).unwrap()
        + "\n[[commands]]\nt_s = 1.0\n"
        + entry
        + "\n";
    let dir = std::env::temp_dir().join(format!("tracksim-43-{name}-{}", std::process::id()));
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
    tracksim::load_scenario(&f)
}

/// Bad fault keys are refused with their key path and what to write instead.
#[test]
fn bad_faults_are_refused_naming_the_key() {
    let track = |n: &str, k: &str| FaultSpec {
        track: [(n.to_string(), k.to_string())].into(),
        ..FaultSpec::default()
    };
    let e = refused(track("lft", "stopped"), "okada2020");
    assert!(
        e.contains("commands[1].fault.track.lft") && e.contains("no track called"),
        "{e}"
    );
    let e = refused(track("left", "broken"), "okada2020");
    assert!(
        e.contains("commands[1].fault.track.left") && e.contains("\"unpowered\""),
        "{e}"
    );
    let e = refused(track("left", "unpowered"), "constraint_to_ground");
    assert!(
        e.contains("commands[1].fault.track") && e.contains("\"stopped\""),
        "{e}"
    );
    let e = refused(
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
    let e = load_with_entry(
        "bad",
        "fault = { track = { left = \"stopped\" }, lag_s = 1 }",
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("lag_s"), "{e}");
}

/// A bad low-friction patch is refused naming its key (a non-finite centre, a side of 0, a
/// friction above 2, a word other than "ok", an unknown key of its table, a centre of three
/// numbers); a good one and "ok" are read back from a file as written.
#[test]
fn bad_patches_are_refused_naming_the_key() {
    let e = refused(
        FaultSpec {
            patch: Some(PatchSpec::Area(PatchArea {
                centre_m: [f64::NAN, 0.0],
                size_m: [0.0, 1.0],
                friction: 3.0,
            })),
            ..FaultSpec::default()
        },
        "okada2020",
    );
    for key in ["centre_m", "size_m[0]", "friction"] {
        assert!(
            e.contains(&format!("commands[1].fault.patch.{key}")),
            "{key} in {e}"
        );
    }
    let e = refused(
        FaultSpec {
            patch: Some(PatchSpec::Word("wet".into())),
            ..FaultSpec::default()
        },
        "okada2020",
    );
    assert!(
        e.contains("commands[1].fault.patch") && e.contains("use \"ok\" to remove"),
        "{e}"
    );
    let patched = |entry: &str| load_with_entry("patch", &format!("fault.patch = {entry}"));
    let e = patched("{ centre_m = [0, 0], size_m = [1, 1], mu = 0.1 }")
        .unwrap_err()
        .to_string();
    assert!(e.contains("mu") && e.contains("friction"), "{e}");
    let e = patched("{ centre_m = [0, 0, 0], size_m = [1, 1], friction = 0.1 }")
        .unwrap_err()
        .to_string();
    assert!(e.contains("centre_m"), "{e}");
    let sc = patched("{ centre_m = [1, 2], size_m = [3, 4], friction = 0.1 }").unwrap();
    assert_eq!(
        sc.commands.last().unwrap().controls.faults.patch,
        Some(Some(tracksim::model::FrictionPatch {
            centre: [1.0, 2.0],
            size: [3.0, 4.0],
            friction: 0.1
        }))
    );
    let sc = patched("\"ok\"").unwrap();
    assert_eq!(
        sc.commands.last().unwrap().controls.faults.patch,
        Some(None)
    );
}

pub(crate) fn send(ws: &mut Ws, v: serde_json::Value) {
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
    let replay = common::session_replay(file, dir, duration);
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
pub(crate) fn hello_of(ws: &mut Ws) -> serde_json::Value {
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

/// A `fault.patch` entry at `t` s: a low-friction patch centred at `centre` m (world x, y) of
/// sides `size` m and friction `mu`.
fn patch_at(t: f64, centre: [f64; 2], size: [f64; 2], mu: f64) -> CommandSpec {
    CommandSpec {
        t_s: t,
        fault: Some(FaultSpec {
            patch: Some(PatchSpec::Area(PatchArea {
                centre_m: centre,
                size_m: size,
                friction: mu,
            })),
            ..FaultSpec::default()
        }),
        ..CommandSpec::default()
    }
}

/// The patch removed at `t` s (`fault.patch = "ok"`).
fn patch_gone(t: f64) -> CommandSpec {
    CommandSpec {
        t_s: t,
        fault: Some(FaultSpec {
            patch: Some(PatchSpec::Word("ok".into())),
            ..FaultSpec::default()
        }),
        ..CommandSpec::default()
    }
}

/// The plate's angle in `scenarios/packbot_parked_slope.toml`, deg (friction 0.6).
const PLATE_DEG: f64 = 20.0;

/// PackBot parked (belts held at 0) on the 20 deg plate of friction 0.6 of
/// `scenarios/packbot_parked_slope.toml`, with the commands `more`, for `duration` s.
fn parked(duration: f64, more: Vec<CommandSpec>) -> tracksim::Scenario {
    common::file_with(
        "scenarios/packbot_parked_slope.toml",
        |s: &mut ScenarioSpec| {
            s.simulation.duration_s = duration;
            s.expect = Default::default();
            s.commands.extend(more);
        },
        |_| {},
    )
}

/// The body's speed down the plate, m/s (the plate rises along +x).
fn downhill_speed(s: &tracksim::world::Sample) -> f64 {
    let a = PLATE_DEG.to_radians();
    -s.linvel[0] * a.cos() - s.linvel[2] * a.sin()
}

/// A low-friction patch: a PackBot parked on 20 deg with friction 0.6 holds (tan 20 = 0.36 <
/// 0.6); a patch of friction 0.1 put under it makes it slide down at g (sin 20 - 0.1 cos 20) =
/// 2.43 m/s^2 as a block would, since the held belts make the robot one rigid body; removed,
/// friction 0.6 stops it again. A patch beside it does not move it.
#[test]
fn a_low_friction_patch_under_a_parked_robot_makes_it_slide() {
    let sc = parked(
        3.2,
        vec![patch_at(1.0, [0.0, 0.0], [8.0, 3.0], 0.1), patch_gone(1.8)],
    );
    let th = PLATE_DEG.to_radians();
    let run = samples(&sc);
    let at = |t: f64| run.iter().find(|s| s.t >= t - 1e-9).unwrap();
    let start = &run[0];
    let before = at(1.0);
    assert!(
        (before.pose.x - start.pose.x).abs() < 0.002,
        "holds before the patch: moved {} m",
        before.pose.x - start.pose.x
    );
    // The acceleration from the speed down the plate between 1.2 s and 1.7 s (after the
    // first moments of breaking loose, before the patch is removed).
    let (a0, a1) = (at(1.2), at(1.7));
    let accel = (downhill_speed(a1) - downhill_speed(a0)) / (a1.t - a0.t);
    let expected = 9.81 * (th.sin() - 0.1 * th.cos());
    println!("patch: {accel:.4} m/s^2 down the plate, expected {expected:.4}");
    // The held belts make the robot one rigid body sliding on its contacts: Rapier's Coulomb
    // friction at the sliding limit is exact up to the solver's convergence (0.01 % measured);
    // 1 % leaves room for its iterations, and is far from no patch (0) or friction 0 (3.36).
    assert!(
        (accel - expected).abs() < 0.01 * expected,
        "slides at {accel} m/s^2 on the patch, expected g (sin - mu cos) = {expected}"
    );
    // Removed at 1.8 s (1.9 m/s down the plate): friction 0.6 brakes it at
    // g (0.6 cos 20 - sin 20) = 2.18 m/s^2 to a stop in 0.9 s.
    let (d0, d1) = (at(1.9), at(2.4));
    let decel = (downhill_speed(d0) - downhill_speed(d1)) / (d1.t - d0.t);
    let braking = 9.81 * (0.6 * th.cos() - th.sin());
    let end = run.last().unwrap();
    println!(
        "patch removed at 1.8 s: braking {decel:.4} m/s^2, expected {braking:.4}; speed {:.4} m/s at {} s",
        downhill_speed(end),
        end.t
    );
    assert!(
        (decel - braking).abs() < 0.01 * braking,
        "brakes at {decel} m/s^2 off the patch, expected g (mu cos - sin) = {braking}"
    );
    assert!(
        downhill_speed(end).abs() < 0.02,
        "friction 0.6 again stops it: {} m/s at {} s",
        downhill_speed(end),
        end.t
    );
    // A patch of friction 0 beside the robot (y from 1.5 to 3.5 m; the robot stands within
    // 0.3 m of y = 0) leaves it parked as without one (on it, it would slide at
    // g sin 20 = 3.4 m/s^2: 1.7 m in the second after).
    let still = |run: &[tracksim::world::Sample]| {
        let (a, b) = (&run[0], run.last().unwrap());
        ((b.pose.x - a.pose.x).powi(2) + (b.pose.y - a.pose.y).powi(2)).sqrt()
    };
    let plain = still(&samples(&parked(1.5, vec![])));
    let beside = still(&samples(&parked(
        1.5,
        vec![patch_at(0.5, [0.0, 2.5], [8.0, 2.0], 0.0)],
    )));
    println!("parked 1.5 s: moved {plain:.2e} m, with a patch beside {beside:.2e} m");
    assert!(
        beside < 0.002 && plain < 0.002,
        "a patch beside it moved it {beside} m (without one: {plain} m)"
    );
}

/// The time of the first entry of `log` that commands `forward` m/s, s.
fn forward_at(log: &tracksim::run::CommandLog, forward: f64) -> f64 {
    log.commands()
        .iter()
        .find(|c| c.forward_mps == Some(forward))
        .unwrap_or_else(|| panic!("no {forward} m/s entry in {:?}", log.commands()))
        .t_s
}

/// A live session of `scenarios/team/race_step.toml` at twice real time on loopback, with its
/// two trainees (`red`, `blue`) and the instructor connected and greeted.
pub(crate) struct TeamSeats {
    pub file: std::path::PathBuf,
    pub sc: tracksim::Scenario,
    pub red: Ws,
    pub blue: Ws,
    pub ins: Ws,
    pub session: std::thread::JoinHandle<tracksim::Result<tracksim::live::TeamSession>>,
    /// Kept for the session's life.
    pub _server: Server,
}

/// Starts [`TeamSeats`]' session.
pub(crate) fn race_step_session() -> TeamSeats {
    let file = root().join("scenarios/team/race_step.toml");
    let sc = tracksim::load_scenario(&file).unwrap();
    let hub = Hub::team(sc.robot_names(), 5.0);
    let mode = Mode::Drive {
        hub: hub.clone(),
        scene_json: vec!["{}".into(), "{}".into()],
    };
    let server = Server::start(tracksim::live::DEFAULT_BIND, 0, mode).unwrap();
    let (sc2, hub2) = (sc.clone(), hub.clone());
    let opts = DriveOptions {
        speed: 2.0,
        ..DriveOptions::default()
    };
    let session = std::thread::spawn(move || tracksim::live::run_team_session(&sc2, &hub2, opts));
    let addr = server.addr();
    let url = format!("ws://{addr}/ws?session={}", hub.session_token().unwrap());
    let (mut red, _) = tungstenite::connect(format!("{url}&robot=red")).unwrap();
    assert_eq!(hello_of(&mut red)["robot"], "red");
    let (mut blue, _) = tungstenite::connect(format!("{url}&robot=blue")).unwrap();
    assert_eq!(hello_of(&mut blue)["robot"], "blue");
    let itoken = hub.instructor_token().unwrap().to_string();
    let (mut ins, _) = tungstenite::connect(format!("ws://{addr}/ws?instructor={itoken}")).unwrap();
    assert_eq!(hello_of(&mut ins)["role"], "instructor");
    TeamSeats {
        file,
        sc,
        red,
        blue,
        ins,
        session,
        _server: server,
    }
}

/// Added latency in a session of several robots: the instructor gives robot `red` 0.4 s of
/// latency; both trainees send a control while the session is paused, so the session takes
/// both at the resume's time exactly; red's is applied and recorded 0.4 s later (within one
/// output interval), blue's at once. The session replays byte for byte for both robots. The
/// instructor's reset there must name its robot (`issue_43_team_reset.rs` resets one).
#[test]
fn latency_in_a_team_session_delays_only_that_robot() {
    let TeamSeats {
        file,
        sc,
        mut red,
        mut blue,
        mut ins,
        session,
        ..
    } = race_step_session();
    // A reset in a session of several robots names its robot: refused without, saying so.
    send(&mut ins, serde_json::json!({"type":"reset"}));
    let e = error_of(&mut ins, 500);
    assert!(
        e.contains("name the robot to reset") && e.contains("red, blue"),
        "{e}"
    );
    send(
        &mut ins,
        serde_json::json!({"type":"fault","robot":"red","fault":{"latency_s":0.4}}),
    );
    state_where(&mut red, 5000, "red's latency 0.4 s", |m| {
        m["faults"]["latency_s"] == 0.4
    });
    send(&mut ins, serde_json::json!({"type": "pause"}));
    let held = state_where(&mut red, 5000, "paused", |m| m["paused"] == true);
    let t_pause = held["t"].as_f64().unwrap();
    for ws in [&mut red, &mut blue] {
        send(
            ws,
            serde_json::json!({"type":"control","forward_mps":0.3,"yaw_rate_rad_s":0.0}),
        );
    }
    std::thread::sleep(std::time::Duration::from_millis(300));
    send(&mut ins, serde_json::json!({"type": "resume"}));
    state_where(&mut red, 5000, "red driving", |m| {
        m["control"]["forward_mps"] == 0.3
    });
    state_where(&mut blue, 5000, "t 0.3 s past the latency", |m| {
        m["t"].as_f64().unwrap() > t_pause + 0.7
    });
    send(&mut ins, serde_json::json!({"type": "end"}));
    let s = session.join().unwrap().unwrap();
    let interval = sc.output_interval;
    let (r, b) = (forward_at(&s.logs[0], 0.3), forward_at(&s.logs[1], 0.3));
    println!("paused at {t_pause} s: red applied at {r} s, blue at {b} s");
    assert!(
        (b - t_pause).abs() < 1e-9,
        "blue (no latency) at the resume: {b} s, paused at {t_pause} s"
    );
    assert!(
        r >= t_pause + 0.4 - 1e-9 && r < t_pause + 0.4 + interval,
        "red 0.4 s late: {r} s, paused at {t_pause} s"
    );
    let dir = std::env::temp_dir().join(format!("tracksim-43-team-lat-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    s.write(&sc, &file, &dir, false).unwrap();
    let replay = common::session_replay(&file, &dir, s.duration());
    let r = tracksim::run::run_team(&replay, tracksim::RunOptions::default()).unwrap();
    for (name, run) in &r.robots {
        assert_eq!(
            tracksim::output::trajectory_csv(run),
            std::fs::read_to_string(dir.join(name).join("trajectory.csv")).unwrap(),
            "{name}'s replay is its session"
        );
    }
}
