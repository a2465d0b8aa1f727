//! Issue 43, the robot school's debrief side, as a user runs it (every packet on 127.0.0.1):
//! - a session that completes its course and drives on is reproduced byte for byte by the
//!   command `drive` prints (and `commands.toml`'s header holds), which runs past the outcome;
//!   without `--keep-running` the run stops at the outcome and is shorter;
//! - two trainees drive the two seats of a `[[vehicles]]` file over WebSocket, each named in
//!   their robot's `summary.json` and in `team.json` with their score, and the session replays
//!   byte for byte for both robots;
//! - an instructor's command latency delays a trainee's control by that much in the recorded
//!   controls, and the session still replays byte for byte;
//! - `debrief.html` is written with a course run, self-contained, holding the run's numbers,
//!   and `tracksim debrief DIR` writes the same page again.

#![warn(clippy::too_many_lines)]

use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;
use tungstenite::Message;

#[path = "support/proc.rs"]
mod proc;
use proc::{root, spawn};

type Ws = tungstenite::WebSocket<tungstenite::stream::MaybeTlsStream<std::net::TcpStream>>;

fn next_json(ws: &mut Ws) -> Option<serde_json::Value> {
    loop {
        match ws.read() {
            Ok(Message::Text(t)) => return serde_json::from_str(t.as_str()).ok(),
            Ok(Message::Close(_)) | Err(_) => return None,
            _ => {}
        }
    }
}

/// Reads states until `pred` holds (None: the socket closed or 20 000 messages passed).
fn until(ws: &mut Ws, pred: impl Fn(&serde_json::Value) -> bool) -> Option<serde_json::Value> {
    for _ in 0..20_000 {
        let m = next_json(ws)?;
        if m["type"] == "state" && pred(&m) {
            return Some(m);
        }
    }
    None
}

fn control(ws: &mut Ws, forward: f64, yaw_rate: f64) {
    let msg = serde_json::json!({
        "type": "control", "forward_mps": forward, "yaw_rate_rad_s": yaw_rate,
    });
    ws.send(Message::text(msg.to_string())).unwrap();
}

/// The command after "reproduce: " on `drive`'s last line, as arguments (`tracksim` left out).
fn reproduce_args(out: &[String]) -> Vec<String> {
    let line = out
        .iter()
        .find(|l| l.contains("reproduce: "))
        .unwrap_or_else(|| panic!("no reproduce line in {out:?}"));
    let cmd = line
        .split("reproduce: ")
        .nth(1)
        .unwrap()
        .trim_end_matches(')');
    let words: Vec<String> = cmd.split_whitespace().map(str::to_string).collect();
    assert_eq!(words[0], "tracksim", "{line}");
    words[1..].to_vec()
}

/// Runs `tracksim ARGS --out DIR --quiet --no-plot`; panics unless it exits 0.
fn run_into(args: &[String], dir: &Path) {
    let o = Command::new(env!("CARGO_BIN_EXE_tracksim"))
        .current_dir(root())
        .args(args)
        .args(["--out", dir.to_str().unwrap(), "--quiet", "--no-plot"])
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "{args:?}: {}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn json(p: &Path) -> serde_json::Value {
    serde_json::from_str(&read(p)).unwrap()
}

/// A flat-ground course for PackBot: one gate line 0.3 m ahead, one repetition.
fn gate_course(dir: &Path) -> PathBuf {
    let vehicle = root().join("vehicles/packbot510.toml");
    let text = format!(
        "description = \"one gate 0.3 m ahead\"\n\
         [vehicle]\nfile = \"{}\"\n\
         [terrain.ground]\nfriction = 0.6\n\
         [simulation]\ndt_s = 0.001\nduration_s = 30.0\n\
         [course]\nname = \"one gate\"\nrepetitions = 1\n\
         [[course.gates]]\nx_m = 0.3\ny_m = 0.0\nwidth_m = 1.0\n",
        vehicle.display()
    );
    let p = dir.join("one_gate.toml");
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn a_session_that_completes_its_course_and_drives_on_replays_with_the_printed_command() {
    let tmp = tempfile::tempdir().unwrap();
    let file = gate_course(tmp.path());
    let out = tmp.path().join("session");
    let mut p = spawn(&[
        "drive",
        file.to_str().unwrap(),
        "--port",
        "0",
        "--duration",
        "2.5",
        "--speed",
        "2",
        "--wait-for-page",
        "--no-plot",
        "--trainee",
        "A. Trainee",
        "--out",
        out.to_str().unwrap(),
    ]);
    let (addr, token) = p.address_and_token();
    let (mut ws, _) = tungstenite::connect(format!("ws://{addr}/ws?session={token}")).unwrap();
    control(&mut ws, 0.4, 0.0);
    let done = until(&mut ws, |s| s["course"]["status"] == "completed");
    let done = done.expect("the course completed live");
    assert!(done["t"].as_f64().unwrap() < 2.0, "{}", done["t"]);
    // Driving on after the outcome: a turn.
    control(&mut ws, 0.2, 0.8);
    while next_json(&mut ws).is_some() {}
    let (code, stdout, stderr) = p.finish(Duration::from_secs(120));
    assert_eq!(code, 0, "{stdout:?} {stderr:?}");
    let summary = json(&out.join("summary.json"));
    assert_eq!(summary["course"]["status"], "completed", "{summary}");
    assert_eq!(summary["trainee"], "A. Trainee");
    let decided = summary["outcome_time_s"].as_f64().unwrap();
    let end = summary["sim_time_s"].as_f64().unwrap();
    assert!(decided < end - 0.4, "decided at {decided} s of {end} s");
    // The printed command, the one commands.toml's header holds, reproduces every sample.
    let args = reproduce_args(&stdout);
    assert!(args.iter().any(|a| a == "--keep-running"), "{args:?}");
    let header = read(&out.join("commands.toml"));
    assert!(
        header.contains(&format!("#   tracksim {}\n", args.join(" "))),
        "{header}"
    );
    let replay = tmp.path().join("replay");
    run_into(&args, &replay);
    let session_csv = read(&out.join("trajectory.csv"));
    assert_eq!(
        read(&replay.join("trajectory.csv")),
        session_csv,
        "the replay is the session"
    );
    // The turn after the outcome is in it (the yaw moved), and without the flag the run stops
    // at the outcome: shorter than the session.
    let last_yaw = summary["final_pose"]["yaw"].as_f64().unwrap();
    assert!(last_yaw > 0.1, "turned {last_yaw} rad after the course");
    let stopped = tmp.path().join("stopped");
    let without: Vec<String> = args
        .iter()
        .filter(|a| *a != "--keep-running")
        .cloned()
        .collect();
    run_into(&without, &stopped);
    let short = read(&stopped.join("trajectory.csv"));
    assert!(
        short.lines().count() < session_csv.lines().count() - 40,
        "{} rows against {}",
        short.lines().count(),
        session_csv.lines().count()
    );
    assert!(
        session_csv.starts_with(&short),
        "the same samples up to the outcome"
    );
}

/// Drives `robot`'s seat at `forward` m/s until the session closes the socket.
fn seat(addr: SocketAddr, token: &str, robot: &str, forward: f64) -> std::thread::JoinHandle<()> {
    let url = format!("ws://{addr}/ws?session={token}&robot={robot}");
    std::thread::spawn(move || {
        let (mut ws, _) = tungstenite::connect(url).unwrap();
        let hello = next_json(&mut ws).unwrap();
        assert_eq!(hello["role"], "driver", "{hello}");
        control(&mut ws, forward, 0.0);
        while next_json(&mut ws).is_some() {}
    })
}

#[test]
fn two_trainees_drive_their_seats_and_the_session_replays_for_both() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("race");
    let mut p = spawn(&[
        "drive",
        "scenarios/team/race_step.toml",
        "--port",
        "0",
        "--duration",
        "3",
        "--speed",
        "2",
        "--wait-for-page",
        "--no-plot",
        "--trainee",
        "red=Ann Red",
        "--trainee",
        "blue=Bo Blue",
        "--out",
        out.to_str().unwrap(),
    ]);
    let (addr, token) = p.address_and_token();
    let red = seat(addr, &token, "red", 0.4);
    let blue = seat(addr, &token, "blue", 0.25);
    red.join().unwrap();
    blue.join().unwrap();
    let (code, stdout, stderr) = p.finish(Duration::from_secs(120));
    assert_eq!(code, 0, "{stdout:?} {stderr:?}");
    let team = json(&out.join("team.json"));
    let robots = team["robots"].as_array().unwrap();
    for (name, trainee) in [("red", "Ann Red"), ("blue", "Bo Blue")] {
        let line = robots.iter().find(|r| r["name"] == name).unwrap();
        assert_eq!(line["trainee"], trainee, "{line}");
        let summary = json(&out.join(name).join("summary.json"));
        assert_eq!(summary["trainee"], trainee);
        // The score in team.json is the robot's own course score.
        assert_eq!(line["score"], summary["course"]["score"], "{line}");
        assert!(line["score"]["time_s"].as_f64().unwrap() > 2.9, "{line}");
        assert!(
            stdout
                .iter()
                .any(|l| l.starts_with(name) && l.contains(trainee)),
            "{stdout:?}"
        );
    }
    // Each drove at its own speed: red further than blue.
    let x = |n: &str| {
        json(&out.join(n).join("summary.json"))["final_pose"]["x"]
            .as_f64()
            .unwrap()
    };
    assert!(
        x("red") > x("blue") + 0.2,
        "red {} blue {}",
        x("red"),
        x("blue")
    );
    let args = reproduce_args(&stdout);
    let replay = tmp.path().join("replay");
    run_into(&args, &replay);
    for name in ["red", "blue"] {
        assert_eq!(
            read(&replay.join(name).join("trajectory.csv")),
            read(&out.join(name).join("trajectory.csv")),
            "{name}'s replay is its session"
        );
    }
}

/// Sets a 30 s read timeout on `ws`: a server that stops answering fails the test (`next_json`
/// gives `None`) instead of hanging it.
fn bounded(ws: &mut Ws) {
    if let tungstenite::stream::MaybeTlsStream::Plain(s) = ws.get_mut() {
        s.set_read_timeout(Some(Duration::from_secs(30))).unwrap();
    }
}

fn send(ws: &mut Ws, v: serde_json::Value) {
    ws.send(Message::text(v.to_string())).unwrap();
}

/// The instructor pauses the session; the trainee sends `forward` m/s while it stands still;
/// the instructor resumes. Returns the simulated time of the pause, s: the session takes the
/// control at that time exactly (no sample passes while paused).
fn control_while_paused(ins: &mut Ws, trainee: &mut Ws, forward: f64) -> f64 {
    send(ins, serde_json::json!({"type": "pause"}));
    let held = until(trainee, |s| s["paused"] == true).expect("paused");
    control(trainee, forward, 0.0);
    std::thread::sleep(Duration::from_millis(300));
    send(ins, serde_json::json!({"type": "resume"}));
    held["t"].as_f64().unwrap()
}

/// `(t_s, forward_mps)` of every `[[commands]]` entry of a `commands.toml` that has both.
fn forward_entries(text: &str) -> Vec<(f64, f64)> {
    text.split("[[commands]]")
        .skip(1)
        .filter_map(|entry| {
            let value = |key: &str| {
                entry
                    .lines()
                    .find_map(|l| l.strip_prefix(key))
                    .and_then(|v| v.trim().parse::<f64>().ok())
            };
            Some((value("t_s = ")?, value("forward_mps = ")?))
        })
        .collect()
}

/// An instructor's command latency end to end (`tracksim drive`, every packet on 127.0.0.1):
/// with `latency_s = 0.5` a trainee's control taken at the resume of a pause (a known
/// simulated time) is applied and recorded in `commands.toml` 0.5 s later (within one output
/// interval); with the latency cleared the next is recorded at its resume's time exactly. The
/// printed command replays the session byte for byte.
#[test]
fn a_trainees_control_under_latency_is_applied_that_much_later() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("latency");
    let mut p = spawn(&[
        "drive",
        "scenarios/packbot_flat.toml",
        "--port",
        "0",
        "--duration",
        "20",
        "--speed",
        "2",
        "--wait-for-page",
        "--no-plot",
        "--out",
        out.to_str().unwrap(),
    ]);
    let (addr, token) = p.address_and_token();
    let itoken = p.instructor_token();
    let (mut ws, _) = tungstenite::connect(format!("ws://{addr}/ws?session={token}")).unwrap();
    let (mut ins, _) = tungstenite::connect(format!("ws://{addr}/ws?instructor={itoken}")).unwrap();
    bounded(&mut ws);
    bounded(&mut ins);
    let fault = |ins: &mut Ws, l: f64| {
        send(
            ins,
            serde_json::json!({"type": "fault", "fault": {"latency_s": l}}),
        );
    };
    fault(&mut ins, 0.5);
    until(&mut ws, |s| s["faults"]["latency_s"] == 0.5).expect("latency in force");
    let late = control_while_paused(&mut ins, &mut ws, 0.3);
    let on = until(&mut ws, |s| s["control"]["forward_mps"] == 0.3).expect("applied");
    // Live too: the control in force shows no earlier than 0.5 s after it was taken.
    assert!(on["t"].as_f64().unwrap() >= late + 0.5 - 1e-9, "{on}");
    fault(&mut ins, 0.0);
    until(&mut ws, |s| s["faults"]["latency_s"] == 0.0).expect("latency cleared");
    let prompt = control_while_paused(&mut ins, &mut ws, 0.1);
    until(&mut ws, |s| s["control"]["forward_mps"] == 0.1).expect("applied");
    send(&mut ins, serde_json::json!({"type": "end"}));
    while next_json(&mut ws).is_some() {}
    let (code, stdout, stderr) = p.finish(Duration::from_secs(120));
    assert_eq!(code, 0, "{stdout:?} {stderr:?}");
    let commands = read(&out.join("commands.toml"));
    assert!(commands.contains("latency_s = 0.5"), "{commands}");
    let entries = forward_entries(&commands);
    let first = |v: f64| {
        entries
            .iter()
            .find(|e| e.1 == v)
            .unwrap_or_else(|| panic!("no {v} m/s in {entries:?}"))
            .0
    };
    let interval = 0.01; // scenarios/packbot_flat.toml's output interval, s
    let (t_late, t_prompt) = (first(0.3), first(0.1));
    println!(
        "taken at {late} s, recorded at {t_late} s; without latency {prompt} s -> {t_prompt} s"
    );
    assert!(
        t_late >= late + 0.5 - 1e-9 && t_late < late + 0.5 + interval,
        "taken at {late} s under 0.5 s of latency, recorded at {t_late} s"
    );
    assert!(
        (t_prompt - prompt).abs() < 1e-9,
        "taken at {prompt} s without latency, recorded at {t_prompt} s"
    );
    let replay = tmp.path().join("replay");
    run_into(&reproduce_args(&stdout), &replay);
    assert_eq!(
        read(&replay.join("trajectory.csv")),
        read(&out.join("trajectory.csv")),
        "the replay is the session"
    );
}

/// Every `src="..."` and `href="..."` value of `html`.
fn links(html: &str) -> Vec<String> {
    let mut found = Vec::new();
    for attr in ["src=", "href="] {
        for part in html.split(attr).skip(1) {
            let q = part.chars().next().unwrap_or('"');
            found.push(part[1..].split(q).next().unwrap_or("").to_string());
        }
    }
    found
}

#[test]
fn a_course_run_writes_a_self_contained_debrief_with_its_numbers() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("stairs");
    let args: Vec<String> = [
        "run",
        "scenarios/course_stairs.toml",
        "--trainee",
        "C. Climber",
    ]
    .map(String::from)
    .to_vec();
    run_into(&args, &dir);
    let page = read(&dir.join("debrief.html"));
    let summary = json(&dir.join("summary.json"));
    let course = &summary["course"];
    assert_eq!(course["status"], "completed", "{course}");
    // Self-contained: no script, nothing fetched, no link out of the file.
    assert!(!page.contains("<script"), "no script");
    for l in links(&page) {
        assert!(
            !(l.starts_with("http:") || l.starts_with("https:") || l.starts_with("//")),
            "{l}"
        );
    }
    assert!(!page.contains("<img") && !page.contains("@import") && !page.contains("url("));
    // The run's numbers, as summary.json has them.
    let cell = |id: &str| {
        let at = page
            .find(&format!("id=\"{id}\">"))
            .unwrap_or_else(|| panic!("no {id}"));
        let rest = &page[at + id.len() + 6..];
        rest[..rest.find("</td>").unwrap()].to_string()
    };
    let score = course["score"]["score_s"].as_f64().unwrap();
    assert!(
        cell("score").contains(&format!("{score:.2} s")),
        "{}",
        cell("score")
    );
    let gates = course["events"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["kind"] == "gate")
        .count();
    assert_eq!(gates, 2, "both gates of the stairs");
    assert_eq!(cell("gates"), gates.to_string());
    assert_eq!(course["gates_passed"], gates);
    assert!(cell("outcome").contains(summary["outcome"].as_str().unwrap()));
    assert!(cell("status").contains("completed"));
    assert!(cell("trainee").contains("C. Climber"));
    // The events with their times, the path on the map with both gates, the plots.
    for e in course["events"].as_array().unwrap() {
        let t = format!("{:.2}</td>", e["t_s"].as_f64().unwrap());
        assert!(page.contains(&t), "event at {t}");
    }
    assert_eq!(page.matches("class=\"gate\"").count(), 2);
    assert_eq!(
        page.matches("class=\"obstacle\"").count(),
        2,
        "the side rails"
    );
    assert!(page.contains("class=\"path\""));
    assert!(page.matches("<svg").count() >= 4, "the map and three plots");
    assert!(page.contains("@media print"));
    // `tracksim debrief` writes the same page again, from the folder alone.
    std::fs::remove_file(dir.join("debrief.html")).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_tracksim"))
        .args(["debrief", dir.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(read(&dir.join("debrief.html")), page);
    // A folder without a run is named with what it lacks.
    let empty = tempfile::tempdir().unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_tracksim"))
        .args(["debrief", empty.path().to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("summary.json") && err.contains("folder of a run"),
        "{err}"
    );
}

#[test]
fn a_trainee_per_seat_is_checked_before_the_session_starts() {
    let run = |trainees: &[&str]| {
        let mut args = vec!["drive", "scenarios/team/race_step.toml", "--port", "0"];
        for t in trainees {
            args.extend(["--trainee", t]);
        }
        let o = Command::new(env!("CARGO_BIN_EXE_tracksim"))
            .current_dir(root())
            .args(&args)
            .output()
            .unwrap();
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    for (given, says) in [
        (vec!["Ann"], "ROBOT=NAME"),
        (vec!["green=Ann"], "no robot \"green\""),
        (vec!["red=Ann", "red=Bo"], "twice"),
        (vec!["red=\t"], "characters"),
    ] {
        let (code, err) = run(&given);
        assert_eq!(code, Some(2), "{given:?}: {err}");
        assert!(
            err.contains("--trainee") && err.contains(says),
            "{given:?}: {err}"
        );
        if says != "twice" && says != "characters" {
            assert!(err.contains("red") && err.contains("blue"), "{err}");
        }
    }
    // One robot has one trainee.
    let o = Command::new(env!("CARGO_BIN_EXE_tracksim"))
        .current_dir(root())
        .args(["drive", "scenarios/packbot_flat.toml", "--port", "0"])
        .args(["--trainee", "A", "--trainee", "B"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("give --trainee once"));
}
