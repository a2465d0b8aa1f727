//! Issue 12, the operator's seat, without a browser: the WebSocket protocol (connect, drive
//! forward, see the pose advance in the streamed state, stop, see it stop; a second connection
//! only watches), the session recorded as a run that `tracksim run --commands` reproduces byte
//! for byte, the loopback default and the refusal of anything outside the page's own files.
//!
//! No assertion is on wall-clock time: loops wait for a state and give up after a number of
//! messages.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::sync::Arc;
use tracksim::live::{DriveOptions, Hub, Mode, Server};
use tungstenite::Message;

pub(crate) type Ws = tungstenite::WebSocket<tungstenite::stream::MaybeTlsStream<TcpStream>>;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

pub(crate) fn next_json(ws: &mut Ws) -> serde_json::Value {
    loop {
        match ws.read().expect("the server keeps the socket open") {
            Message::Text(t) => return serde_json::from_str(t.as_str()).expect("JSON"),
            Message::Close(_) => panic!("closed by the server"),
            _ => {}
        }
    }
}

/// Reads states until `pred` holds; panics after `max` messages.
pub(crate) fn until(
    ws: &mut Ws,
    max: usize,
    what: &str,
    pred: impl Fn(&serde_json::Value) -> bool,
) -> serde_json::Value {
    for _ in 0..max {
        let m = next_json(ws);
        if m["type"] == "state" && pred(&m) {
            return m;
        }
    }
    panic!("no state with {what} in {max} messages");
}

/// A live `drive` session of the team scenario `sc` at `speed` times real time: its loopback
/// server (any free port), the thread running the session, and the WebSocket URL
/// with the session's token (append `&robot=NAME` for a seat).
pub(crate) struct TeamDrive {
    pub server: Server,
    pub session: std::thread::JoinHandle<tracksim::Result<tracksim::live::TeamSession>>,
    pub url: String,
}

pub(crate) fn team_drive(sc: &tracksim::Scenario, speed: f64) -> TeamDrive {
    let hub = Hub::team(sc.robot_names(), 0.0);
    let scene_json = (0..sc.robot_count())
        .map(|k| tracksim::output::Scene::new(&sc.robot_view(k)).to_json())
        .collect();
    let mode = Mode::Drive {
        hub: hub.clone(),
        scene_json,
    };
    let server = Server::start(tracksim::live::DEFAULT_BIND, 0, mode).unwrap();
    let (sc2, hub2) = (sc.clone(), hub.clone());
    let session = std::thread::spawn(move || {
        let opts = DriveOptions {
            speed,
            ..DriveOptions::default()
        };
        tracksim::live::run_team_session(&sc2, &hub2, opts)
    });
    let url = format!(
        "ws://{}/ws?session={}",
        server.addr(),
        hub.session_token().unwrap()
    );
    TeamDrive {
        server,
        session,
        url,
    }
}

/// A drive server on loopback (any free port) for `hub`, serving `scene_json`.
fn drive_server(hub: Arc<Hub>, scene_json: impl Into<String>) -> Server {
    let mode = Mode::Drive {
        hub,
        scene_json: vec![scene_json.into()],
    };
    Server::start(tracksim::live::DEFAULT_BIND, 0, mode).unwrap()
}

fn control(ws: &mut Ws, forward: f64, flippers: serde_json::Value) {
    let msg = serde_json::json!({
        "type": "control", "forward_mps": forward, "yaw_rate_rad_s": 0.0,
        "flipper_angle_deg": flippers,
    });
    ws.send(Message::text(msg.to_string())).unwrap();
}

#[test]
fn drive_protocol_and_the_session_replays_as_a_run() {
    let file = root().join("scenarios/packbot_stairs.toml");
    let sc = tracksim::load_scenario(&file).unwrap();
    let hub = Hub::new();
    let server = drive_server(hub.clone(), tracksim::output::Scene::new(&sc).to_json());
    assert!(server.addr().ip().is_loopback());
    let (sc2, hub2) = (sc.clone(), hub.clone());
    let session = std::thread::spawn(move || {
        tracksim::live::run_session(
            &sc2,
            &hub2,
            DriveOptions {
                speed: 2.0,
                max_time: None,
                wait_for_page: false,
                interrupt: None,
            },
        )
    });
    let url = format!(
        "ws://{}/ws?session={}",
        server.addr(),
        hub.session_token().unwrap()
    );
    let (mut ws, _) = tungstenite::connect(&url).unwrap();
    let hello = next_json(&mut ws);
    assert_eq!(hello["role"], "driver", "{hello}");
    // A second page only watches: its controls are refused.
    let (mut watcher, _) = tungstenite::connect(&url).unwrap();
    assert_eq!(next_json(&mut watcher)["role"], "watcher");
    control(&mut watcher, 1.0, serde_json::json!([]));
    let refused = (0..200)
        .map(|_| next_json(&mut watcher))
        .find(|m| m["type"] == "error")
        .expect("the watcher's control is answered with an error");
    assert!(
        refused["message"]
            .as_str()
            .unwrap()
            .contains("only watches")
    );

    let first = until(&mut ws, 1000, "a pose", |_| true);
    let x0 = first["pose"][0].as_f64().unwrap();
    // Forward, front flippers to 30 deg.
    control(&mut ws, 0.3, serde_json::json!([30.0, 30.0]));
    let moving = until(&mut ws, 3000, "x advanced 5 cm", |m| {
        m["pose"][0].as_f64().unwrap() > x0 + 0.05
    });
    assert!(moving["forward_mps"].as_f64().unwrap() > 0.1, "{moving}");
    assert_eq!(moving["control"]["forward_mps"], 0.3);
    // Stop: the speed falls to rest and the pose stays.
    control(&mut ws, 0.0, serde_json::json!([30.0, 30.0]));
    let rest = until(&mut ws, 3000, "speed below 5 mm/s", |m| {
        m["control"]["forward_mps"] == 0.0 && m["forward_mps"].as_f64().unwrap().abs() < 0.005
    });
    let later = until(&mut ws, 3000, "0.5 s later", |m| {
        m["t"].as_f64().unwrap() > rest["t"].as_f64().unwrap() + 0.5
    });
    let drift = later["pose"][0].as_f64().unwrap() - rest["pose"][0].as_f64().unwrap();
    // Still driving it would have gone 0.15 m; the body only settles (flippers, contacts).
    assert!(drift.abs() < 0.02, "moved {drift} m in 0.5 s after stop");
    ws.send(Message::text(r#"{"type":"stop"}"#)).unwrap();
    let s = session.join().unwrap().unwrap();
    assert_eq!(s.log.len(), 2, "forward then stop: {:?}", s.log);
    assert_eq!(s.controls.len(), s.result.samples.len());

    // The session is a run: written like one, and replayed by its commands.toml.
    let dir = tempfile_dir("live_session");
    let written = s.write(&sc, &file, &dir, false).unwrap();
    for f in [
        "summary.json",
        "trajectory.csv",
        "scene.json",
        "belts.csv",
        "commands.toml",
        "controls.csv",
    ] {
        assert!(written.contains(&dir.join(f)), "{f} not written");
    }
    // Ended from the page: recorded as the operator's end, not as the scenario's timeout.
    assert_eq!(s.result.outcome.name(), "ended_by_operator");
    assert!(
        s.result
            .outcome
            .reason()
            .contains("the scenario's outcome: undecided"),
        "{:?}",
        s.result.outcome
    );
    let summary = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    assert!(summary.contains("\"outcome\": \"ended_by_operator\""));
    // Replayed as `tracksim run FILE --commands DIR/commands.toml --duration T` does.
    let replay = crate::common::session_replay(&file, &dir, s.duration());
    assert_eq!(replay.overridden, ["simulation.duration_s", "commands"]);
    let r = tracksim::run_scenario(&replay, |_, _| {}).unwrap();
    let session_csv = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
    assert_eq!(tracksim::output::trajectory_csv(&r), session_csv);
    assert!(s.result.summary.final_pose.x > x0 + 0.05);
    let controls = std::fs::read_to_string(dir.join("controls.csv")).unwrap();
    assert!(controls.starts_with("t_s,forward_mps,yaw_rate_rad_s,flipper_front_left_target_deg"));
    assert!(
        controls
            .lines()
            .any(|l| l.contains(",0.300000,0.000000,30.000000"))
    );
}

#[test]
fn reset_restarts_the_session() {
    let sc = tracksim::load_scenario(&root().join("scenarios/packbot_flat.toml")).unwrap();
    let hub = Hub::with_grace(0.0);
    let server = drive_server(hub.clone(), "{}");
    let (sc2, hub2) = (sc.clone(), hub.clone());
    let session = std::thread::spawn(move || {
        tracksim::live::run_session(
            &sc2,
            &hub2,
            DriveOptions {
                speed: 4.0,
                max_time: None,
                wait_for_page: false,
                interrupt: None,
            },
        )
    });
    let (mut ws, _) = tungstenite::connect(format!(
        "ws://{}/ws?session={}",
        server.addr(),
        hub.session_token().unwrap()
    ))
    .unwrap();
    control(&mut ws, 0.3, serde_json::json!([]));
    until(&mut ws, 5000, "t > 0.5 s", |m| {
        m["t"].as_f64().unwrap() > 0.5
    });
    ws.send(Message::text(r#"{"type":"reset"}"#)).unwrap();
    until(&mut ws, 5000, "t back below 0.2 s", |m| {
        m["t"].as_f64().unwrap() < 0.2
    });
    // With no reconnect grace, closing the only page ends the session.
    ws.close(None).unwrap();
    let _ = ws.flush();
    while ws.read().is_ok() {}
    let s = session.join().unwrap().unwrap();
    assert!(s.result.samples.first().unwrap().t == 0.0);
    assert!(
        s.log.is_empty(),
        "the reset cleared the commands: {:?}",
        s.log
    );
}

fn tempfile_dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("tracksim-test-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn get(addr: std::net::SocketAddr, target: &str) -> (String, String) {
    let mut s = TcpStream::connect(addr).unwrap();
    write!(
        s,
        "GET {target} HTTP/1.1\r\nHost: localhost:{}\r\n\r\n",
        addr.port()
    )
    .unwrap();
    let mut text = String::new();
    s.read_to_string(&mut text).unwrap();
    let status = text.lines().next().unwrap_or("").to_string();
    (status, text)
}

#[test]
fn view_serves_only_its_own_files() {
    // A finished run in dir/run; a secret next to it and one inside it.
    let base = tempfile_dir("traversal");
    let run = base.join("run");
    std::fs::create_dir_all(&run).unwrap();
    for f in ["scene.json", "trajectory.csv", "belts.csv"] {
        std::fs::write(run.join(f), format!("content of {f}")).unwrap();
    }
    std::fs::write(base.join("secret.txt"), "SECRET-OUTSIDE").unwrap();
    std::fs::write(run.join("secret.txt"), "SECRET-INSIDE").unwrap();
    let files = tracksim::live::view_files(&run).unwrap();
    let server = Server::start(
        tracksim::live::DEFAULT_BIND,
        0,
        Mode::View { files, video: None },
    )
    .unwrap();
    let addr = server.addr();
    let (ok, body) = get(addr, "/run/trajectory.csv");
    assert!(ok.contains("200"), "{ok}");
    assert!(body.ends_with("content of trajectory.csv"));
    assert!(get(addr, "/").0.contains("200"));
    assert!(get(addr, "/vendor/three.module.js").0.contains("200"));
    for bad in [
        "/../secret.txt",
        "/run/../secret.txt",
        "/run/../../secret.txt",
        "/%2e%2e/secret.txt",
        "/run/%2e%2e/%2e%2e/secret.txt",
        "/run/secret.txt",
        "/vendor/../../../../etc/passwd",
        "//etc/passwd",
        "/run/..%2fsecret.txt",
        "/run\\..\\secret.txt",
        "http://localhost/../secret.txt",
    ] {
        let (status, body) = get(addr, bad);
        assert!(
            status.contains("404") || status.contains("400"),
            "{bad}: {status}"
        );
        assert!(
            !body.contains("SECRET") && !body.contains("root:"),
            "{bad} leaked"
        );
    }
}

#[test]
fn view_serves_a_compare_folder_by_index() {
    // A compare folder: a run per method (in compare.csv's order), no run of its own.
    let base = tempfile_dir("compare_view");
    for m in ["plates", "okada2020"] {
        let run = base.join(m);
        std::fs::create_dir_all(&run).unwrap();
        for f in ["scene.json", "trajectory.csv", "belts.csv", "summary.json"] {
            std::fs::write(run.join(f), format!("{m} {f}")).unwrap();
        }
    }
    std::fs::create_dir_all(base.join("not_a_run")).unwrap();
    std::fs::write(
        base.join("compare.csv"),
        "method,outcome\nplates,x\nokada2020,y\n",
    )
    .unwrap();
    std::fs::write(base.join("secret.txt"), "SECRET").unwrap();
    let files = tracksim::live::view_files(&base).unwrap();
    let server = Server::start(
        tracksim::live::DEFAULT_BIND,
        0,
        Mode::View { files, video: None },
    )
    .unwrap();
    let addr = server.addr();
    let (ok, body) = get(addr, "/runs.json");
    assert!(ok.contains("200"), "{ok}");
    let list: serde_json::Value =
        serde_json::from_str(body.split("\r\n\r\n").nth(1).unwrap()).unwrap();
    assert_eq!(list["compare"], true);
    let names: Vec<_> = list["runs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| (r["name"].as_str().unwrap(), r["base"].as_str().unwrap()))
        .collect();
    assert_eq!(names, [("plates", "/run/0"), ("okada2020", "/run/1")]);
    assert!(
        get(addr, "/run/1/trajectory.csv")
            .1
            .ends_with("okada2020 trajectory.csv")
    );
    assert!(get(addr, "/scene.json").1.ends_with("plates scene.json"));
    for bad in [
        "/run/trajectory.csv",
        "/run/2/trajectory.csv",
        "/run/0/../secret.txt",
        "/run/plates/trajectory.csv",
        "/secret.txt",
    ] {
        let (status, body) = get(addr, bad);
        assert!(status.contains("404"), "{bad}: {status}");
        assert!(!body.contains("SECRET"), "{bad} leaked");
    }
}

#[test]
fn view_names_what_a_folder_lacks() {
    let d = tempfile_dir("empty_view");
    let e = tracksim::live::view_files(&d)
        .expect_err("an empty folder is refused")
        .to_string();
    assert!(e.contains("scene.json") && e.contains("re-run"), "{e}");
}

#[test]
fn loopback_is_the_default() {
    assert!(tracksim::live::DEFAULT_BIND.is_loopback());
    let hub: Arc<Hub> = Hub::new();
    let s = drive_server(hub, String::new());
    assert!(s.url().starts_with("http://127.0.0.1:"));
}

/// The world position of a point at `xyz` in the body frame of a state's `pose`.
fn body_point(state: &serde_json::Value, xyz: [f64; 3]) -> glam::DVec3 {
    let p: Vec<f64> = (0..6).map(|i| state["pose"][i].as_f64().unwrap()).collect();
    let r = glam::DQuat::from_euler(glam::EulerRot::ZYX, p[5], p[4], p[3]);
    glam::DVec3::new(p[0], p[1], p[2]) + r * glam::DVec3::from_array(xyz)
}

fn sensor_entry<'a>(state: &'a serde_json::Value, kind: &str) -> Option<&'a serde_json::Value> {
    state["sensors"]
        .as_array()?
        .iter()
        .find(|e| e["kind"] == kind)
}

#[test]
fn drive_streams_lidar_points_and_depth_images() {
    let sc = tracksim::load_scenario(&root().join("scenarios/packbot_sensors.toml")).unwrap();
    let scene = tracksim::output::Scene::new(&sc).to_json();
    let scene_v: serde_json::Value = serde_json::from_str(&scene).unwrap();
    let names: Vec<&str> = scene_v["sensors"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["name"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        [
            "imu",
            "encoders",
            "scan",
            "elevation",
            "front_camera",
            "flipper_imu"
        ]
    );
    let cam = &scene_v["sensors"][4];
    assert_eq!(cam["mount"], "body");
    assert_eq!(cam["depth_camera"]["width_px"], 64);
    let q = cam["quat_xyzw"].as_array().unwrap();
    assert!((q[1].as_f64().unwrap() - 7.5f64.to_radians().sin()).abs() < 1e-9);
    assert_eq!(scene_v["sensors"][5]["mount"], "front_left");
    assert_eq!(scene_v["sensors"][5]["mount_index"], 0);
    assert_eq!(scene_v["sensors"][2]["lidar"]["max_range_m"], 10.0);
    let hub = Hub::new();
    let server = drive_server(hub.clone(), scene);
    let (sc2, hub2) = (sc.clone(), hub.clone());
    let session = std::thread::spawn(move || {
        let opts = DriveOptions {
            speed: 2.0,
            ..DriveOptions::default()
        };
        tracksim::live::run_session(&sc2, &hub2, opts)
    });
    let (mut ws, _) = tungstenite::connect(format!(
        "ws://{}/ws?session={}",
        server.addr(),
        hub.session_token().unwrap()
    ))
    .unwrap();
    // Two lidar readings: each is sent once, so their times differ by the scan period.
    let a = until(&mut ws, 3000, "a lidar reading", |m| {
        sensor_entry(m, "lidar").is_some()
    });
    let b = until(&mut ws, 3000, "another lidar reading", |m| {
        sensor_entry(m, "lidar").is_some()
    });
    let (la, lb) = (
        sensor_entry(&a, "lidar").unwrap(),
        sensor_entry(&b, "lidar").unwrap(),
    );
    let dt = lb["t"].as_f64().unwrap() - la["t"].as_f64().unwrap();
    assert!((dt - 0.1).abs() < 0.01, "scans {dt} s apart");
    let hits = la["hits"].as_u64().unwrap() as usize;
    let pts = la["points"].as_array().unwrap();
    assert!(
        hits > 10 && pts.len() == 3 * hits && pts.len() <= 6000,
        "{hits} hits, {} values",
        pts.len()
    );
    // The points are in the world: within range of the lidar, on the staircase ahead (x >= 0.9).
    let origin = body_point(&a, [0.15, 0.0, 0.10]);
    for p in pts.chunks(3) {
        let p = glam::DVec3::new(
            p[0].as_f64().unwrap(),
            p[1].as_f64().unwrap(),
            p[2].as_f64().unwrap(),
        );
        assert!(
            p.distance(origin) <= 10.01,
            "{p} is {} m away",
            p.distance(origin)
        );
        assert!(
            p.x > 0.85 && p.y.abs() < 0.65,
            "{p} is not on the staircase"
        );
        assert!(
            (p.z - origin.z).abs() < 0.05,
            "{p}: the scan is about horizontal"
        );
    }
    let d = until(&mut ws, 3000, "a depth image", |m| {
        sensor_entry(m, "depth_camera").is_some()
    });
    let img = sensor_entry(&d, "depth_camera").unwrap();
    assert_eq!(
        (img["width"].as_u64(), img["height"].as_u64()),
        (Some(64), Some(48))
    );
    let depth: Vec<u64> = img["depth_mm"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_u64().unwrap())
        .collect();
    assert_eq!(depth.len(), 64 * 48);
    assert!(depth.iter().all(|&x| x <= 5000) && depth.iter().filter(|&&x| x > 0).count() > 1000);
    let cam_pos: Vec<f64> = (0..3)
        .map(|i| img["position"][i].as_f64().unwrap())
        .collect();
    let expect = body_point(&d, [0.26, 0.0, 0.03]);
    assert!(
        expect.distance(glam::DVec3::from_slice(&cam_pos)) < 1e-3,
        "{cam_pos:?} vs {expect}"
    );
    ws.send(Message::text(r#"{"type":"stop"}"#)).unwrap();
    session.join().unwrap().unwrap();
}

#[test]
fn view_serves_the_listed_sensor_streams_only() {
    let base = tempfile_dir("view_sensors");
    let run = base.join("run");
    std::fs::create_dir_all(run.join("sensors")).unwrap();
    for f in ["scene.json", "trajectory.csv", "belts.csv"] {
        std::fs::write(run.join(f), format!("content of {f}")).unwrap();
    }
    std::fs::write(run.join("sensors/scan.npz"), "NPZ-SCAN").unwrap();
    std::fs::write(run.join("sensors/imu.csv"), "CSV-IMU").unwrap();
    std::fs::write(run.join("sensors/unlisted.npz"), "NPZ-UNLISTED").unwrap();
    std::fs::write(base.join("secret.npz"), "SECRET").unwrap();
    // Too large to be held: left out (a sparse file, nothing written).
    let big = std::fs::File::create(run.join("sensors/big.npz")).unwrap();
    big.set_len(tracksim::live::server::MAX_SENSOR_FILE_BYTES + 1)
        .unwrap();
    let listed = [
        "sensors/scan.npz",
        "sensors/imu.csv",
        "sensors/../../secret.npz",
        "sensors/big.npz",
    ];
    let sensors: Vec<_> = listed
        .iter()
        .map(|f| serde_json::json!({ "file": f }))
        .collect();
    let summary = serde_json::json!({ "sensors": sensors }).to_string();
    std::fs::write(run.join("summary.json"), summary).unwrap();
    let files = tracksim::live::view_files(&run).unwrap();
    let server = Server::start(
        tracksim::live::DEFAULT_BIND,
        0,
        Mode::View { files, video: None },
    )
    .unwrap();
    let addr = server.addr();
    let (ok, body) = get(addr, "/run/sensors/scan.npz");
    assert!(ok.contains("200") && body.ends_with("NPZ-SCAN"), "{ok}");
    for bad in [
        "/run/sensors/imu.csv",
        "/run/sensors/unlisted.npz",
        "/run/sensors/big.npz",
        "/run/sensors/../../secret.npz",
        "/secret.npz",
    ] {
        let (status, body) = get(addr, bad);
        assert!(status.contains("404"), "{bad}: {status}");
        assert!(
            !body.contains("SECRET") && !body.contains("CSV-IMU"),
            "{bad} leaked"
        );
    }
}

/// The first message of type `kind`; panics after `max` messages.
fn next_of(ws: &mut Ws, max: usize, kind: &str) -> serde_json::Value {
    for _ in 0..max {
        let m = next_json(ws);
        if m["type"] == kind {
            return m;
        }
    }
    panic!("no {kind} message in {max} messages");
}

/// Issue 28.6: a dropped driver's page may come back within the grace period. Meanwhile the
/// robot stops (a dead-man stop, recorded in commands.toml so the session still replays), a
/// page without the driver's token only watches, the page with it drives again; once the
/// grace has passed with no page connected, the session ends and says why.
#[test]
fn a_dropped_driver_reconnects_within_the_grace() {
    let file = root().join("scenarios/packbot_flat.toml");
    let sc = tracksim::load_scenario(&file).unwrap();
    let hub = Hub::with_grace(3.0);
    let server = drive_server(hub.clone(), "{}");
    let (sc2, hub2) = (sc.clone(), hub.clone());
    let session = std::thread::spawn(move || {
        tracksim::live::run_session(&sc2, &hub2, DriveOptions::default())
    });
    let url = format!(
        "ws://{}/ws?session={}",
        server.addr(),
        hub.session_token().unwrap()
    );
    let (mut ws, _) = tungstenite::connect(&url).unwrap();
    let hello = next_of(&mut ws, 50, "hello");
    assert_eq!(hello["role"], "driver", "{hello}");
    assert_eq!(hello["grace_s"], 3.0, "{hello}");
    let token = hello["token"].as_str().unwrap().to_string();
    control(&mut ws, 0.3, serde_json::json!([]));
    let moving = until(&mut ws, 5000, "moving at 0.25 m/s", |m| {
        m["forward_mps"].as_f64().unwrap() > 0.25
    });
    assert_eq!(moving["driver"]["connected"], true, "{moving}");
    // The driver's page drops (no close frame: the TCP connection just goes).
    drop(ws);
    // Another page without the token: it only watches, sees the seat held and the robot stop.
    let (mut other, _) = tungstenite::connect(&url).unwrap();
    let hello = next_of(&mut other, 50, "hello");
    assert_eq!(hello["role"], "watcher", "{hello}");
    assert!(hello["token"].is_null(), "{hello}");
    let held = until(&mut other, 5000, "the seat held", |m| {
        m["driver"]["connected"] == false
    });
    let left = held["driver"]["grace_left_s"].as_f64().unwrap();
    assert!(left > 0.0 && left <= 3.0, "{held}");
    let stopped = until(&mut other, 5000, "stopped", |m| {
        m["control"]["forward_mps"] == 0.0 && m["forward_mps"].as_f64().unwrap().abs() < 0.02
    });
    let t_stop = stopped["t"].as_f64().unwrap();
    // The driver's page comes back with its token and drives on.
    let (mut back, _) = tungstenite::connect(format!("{url}&token={token}")).unwrap();
    let hello = next_of(&mut back, 50, "hello");
    assert_eq!(hello["role"], "driver", "{hello}");
    assert_eq!(hello["token"], token.as_str());
    control(&mut back, 0.3, serde_json::json!([]));
    let again = until(&mut back, 5000, "moving again", |m| {
        m["forward_mps"].as_f64().unwrap() > 0.25
    });
    assert_eq!(again["driver"]["reconnects"], 1, "{again}");
    assert!(again["t"].as_f64().unwrap() > t_stop);
    // Both pages go; after the grace the session ends on its own.
    drop(back);
    drop(other);
    let s = session.join().unwrap().unwrap();
    assert_eq!(s.result.outcome.name(), "ended_by_operator");
    assert!(
        s.result.outcome.reason().contains("within the 3 s grace"),
        "{}",
        s.result.outcome.reason()
    );
    // Commands: forward, the dead-man stop, forward again, the final dead-man stop.
    let forward: Vec<f64> = s
        .log
        .commands()
        .iter()
        .filter_map(|c| c.forward_mps)
        .collect();
    assert_eq!(forward, vec![0.3, 0.0, 0.3, 0.0], "{:?}", s.log);
    // The session replays as a run.
    let dir = tempfile_dir("reconnect");
    s.write(&sc, &file, &dir, false).unwrap();
    let text = std::fs::read_to_string(dir.join("commands.toml")).unwrap();
    let cmd_file = dir.join("commands.toml");
    let over = tracksim::Overrides {
        commands: Some(cmd_file.clone()),
        duration_s: Some(s.duration()),
        ..Default::default()
    };
    let rerun = tracksim::load_scenario_with(&file, &over).unwrap();
    let r = tracksim::run_scenario(&rerun, |_, _| {}).unwrap();
    assert_eq!(
        tracksim::output::trajectory_csv(&r),
        std::fs::read_to_string(dir.join("trajectory.csv")).unwrap(),
        "{text}"
    );
}
