//! Issue 45, the drive server used only by its own pages and peers, every packet on loopback:
//! a page of another site (its `Origin`) or a rebound DNS name (its `Host`) is refused with
//! 403 before anything is served; the server's own page gets the session's token from
//! `/session.json` and only a connection presenting it drives; a page's message is bounded
//! (its size before it is read, a flipper table by the robot's flippers) and the states sent
//! to the pages never carry a page's table.
//!
//! Loops wait for a message and give up after a number of them; each test ends in seconds.

use super::live::{Ws, next_json};
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::Path;
use std::sync::Arc;
use std::time::Duration;
use tracksim::live::{Access, DriveOptions, Hub, Mode, Server};
use tungstenite::Message;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn server(hub: Arc<Hub>, access: Access) -> Server {
    let mode = Mode::Drive {
        hub,
        scene_json: vec!["{\"scene\":1}".into()],
    };
    Server::start_with(tracksim::live::DEFAULT_BIND, 0, mode, access).unwrap()
}

/// Sends a raw request head (`lines`, each without its CRLF) and returns the status line and
/// the whole answer (the server closes after an HTTP answer; a 101 is read up to its head).
fn raw(addr: SocketAddr, lines: &[String]) -> (String, String) {
    let mut s = TcpStream::connect(addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    let head = lines.join("\r\n") + "\r\n\r\n";
    s.write_all(head.as_bytes()).unwrap();
    let mut got = Vec::new();
    let mut buf = [0u8; 4096];
    loop {
        match s.read(&mut buf) {
            Ok(0) | Err(_) => break,
            Ok(n) => got.extend_from_slice(&buf[..n]),
        }
        if got.starts_with(b"HTTP/1.1 101") && got.windows(4).any(|w| w == b"\r\n\r\n") {
            break;
        }
    }
    let text = String::from_utf8_lossy(&got).into_owned();
    (text.lines().next().unwrap_or("").to_string(), text)
}

fn get(addr: SocketAddr, path: &str, host: &str, origin: Option<&str>) -> (String, String) {
    let mut lines = vec![format!("GET {path} HTTP/1.1"), format!("Host: {host}")];
    lines.extend(origin.map(|o| format!("Origin: {o}")));
    raw(addr, &lines)
}

fn upgrade(addr: SocketAddr, query: &str, host: &str, origin: Option<&str>) -> (String, String) {
    let mut lines = vec![
        format!("GET /ws{query} HTTP/1.1"),
        format!("Host: {host}"),
        "Upgrade: websocket".into(),
        "Connection: Upgrade".into(),
        "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==".into(),
        "Sec-WebSocket-Version: 13".into(),
    ];
    lines.extend(origin.map(|o| format!("Origin: {o}")));
    raw(addr, &lines)
}

#[test]
fn another_sites_page_and_a_rebound_name_are_refused() {
    let hub = Hub::new();
    let srv = server(hub.clone(), Access::loopback());
    let addr = srv.addr();
    let own = format!("127.0.0.1:{}", addr.port());
    let own_origin = format!("http://{own}");
    // A cross-site WebSocket (another site's page in the trainer's browser).
    let (status, text) = upgrade(addr, "", &own, Some("http://evil.example"));
    assert!(status.starts_with("HTTP/1.1 403"), "{text}");
    assert!(text.contains("Origin"), "the reason: {text}");
    assert_eq!(hub.connections(), 0, "no connection was made");
    // DNS rebinding: the other site's name in Host, the data read as same-origin.
    let evil_host = format!("evil.example:{}", addr.port());
    let (status, text) = get(addr, "/scene.json", &evil_host, None);
    assert!(status.starts_with("HTTP/1.1 403"), "{text}");
    assert!(text.contains("Host") && !text.contains("scene"), "{text}");
    let (status, _) = upgrade(addr, "", &evil_host, Some(&own_origin));
    assert!(status.starts_with("HTTP/1.1 403"), "{status}");
    let (status, _) = get(addr, "/scene.json", &own, Some("http://evil.example"));
    assert!(
        status.starts_with("HTTP/1.1 403"),
        "a cross-site fetch: {status}"
    );
    // The server's own names: served.
    for host in [
        own.clone(),
        format!("localhost:{}", addr.port()),
        format!("[::1]:{}", addr.port()),
    ] {
        let (status, text) = get(addr, "/scene.json", &host, None);
        assert!(status.starts_with("HTTP/1.1 200"), "{host}: {text}");
        assert!(text.ends_with("{\"scene\":1}"), "{text}");
    }
    let (status, _) = upgrade(addr, "?watch=1", &own, Some(&own_origin));
    assert!(status.starts_with("HTTP/1.1 101"), "own origin: {status}");
    let (status, _) = upgrade(addr, "?watch=1", &own, None);
    assert!(status.starts_with("HTTP/1.1 101"), "a program: {status}");
    // Names given on the command line.
    let access = Access::loopback()
        .allow_host("robots.lab")
        .unwrap()
        .allow_origin("https://dash.lab")
        .unwrap();
    let srv = server(Hub::new(), access);
    let lab = format!("robots.lab:{}", srv.addr().port());
    let (status, _) = get(srv.addr(), "/scene.json", &lab, None);
    assert!(status.starts_with("HTTP/1.1 200"), "{status}");
    let (status, _) = upgrade(srv.addr(), "?watch=1", &lab, Some("https://dash.lab"));
    assert!(status.starts_with("HTTP/1.1 101"), "{status}");
    let (status, _) = upgrade(srv.addr(), "", &lab, Some("https://evil.lab"));
    assert!(status.starts_with("HTTP/1.1 403"), "{status}");
}

#[test]
fn the_token_is_given_to_the_own_page_and_needed_to_drive() {
    let sc = tracksim::load_scenario(&root().join("scenarios/packbot_flat.toml")).unwrap();
    let hub = Hub::with_grace(0.0);
    let srv = server(hub.clone(), Access::loopback());
    let addr = srv.addr();
    let own = format!("127.0.0.1:{}", addr.port());
    // The page's /session.json (same origin) carries the token.
    let (status, text) = get(addr, "/session.json", &own, Some(&format!("http://{own}")));
    assert!(status.starts_with("HTTP/1.1 200"), "{text}");
    let body = text.split("\r\n\r\n").nth(1).unwrap();
    let session: serde_json::Value = serde_json::from_str(body).unwrap();
    let token = session["token"].as_str().expect("a token").to_string();
    assert_eq!(Some(token.as_str()), hub.session_token());
    assert_eq!(token.len(), 32);
    let (sc2, hub2) = (sc.clone(), hub.clone());
    let session = std::thread::spawn(move || {
        let opts = DriveOptions {
            speed: 1.0,
            max_time: Some(5.0),
            ..DriveOptions::default()
        };
        tracksim::live::run_session(&sc2, &hub2, opts)
    });
    let url = format!("ws://{}/ws", addr);
    // Without the token: the first page watches, its control refused, the robot stays.
    let (mut anon, _) = tungstenite::connect(&url).unwrap();
    let hello = next_json(&mut anon);
    assert_eq!(hello["role"], "watcher", "{hello}");
    assert!(hello["token"].is_null());
    let forward = r#"{"type":"control","forward_mps":1.0,"yaw_rate_rad_s":0.0}"#;
    anon.send(Message::text(forward)).unwrap();
    let refused = (0..500)
        .map(|_| next_json(&mut anon))
        .find(|m| m["type"] == "error")
        .expect("refused");
    assert!(
        refused["message"]
            .as_str()
            .unwrap()
            .contains("only watches")
    );
    anon.send(Message::text(r#"{"type":"stop"}"#)).unwrap();
    // A wrong token: watching, and told so.
    let (mut wrong, _) = tungstenite::connect(format!("{url}?session={}", "0".repeat(32))).unwrap();
    let first: Vec<_> = (0..2).map(|_| next_json(&mut wrong)).collect();
    assert!(
        first
            .iter()
            .any(|m| m["type"] == "error" && m["message"].as_str().unwrap().contains("token")),
        "{first:?}"
    );
    assert!(first.iter().any(|m| m["role"] == "watcher"), "{first:?}");
    // With it: drives.
    let (mut driver, _) = tungstenite::connect(format!("{url}?session={token}")).unwrap();
    let hello = next_json(&mut driver);
    assert_eq!(hello["role"], "driver", "{hello}");
    driver.send(Message::text(forward)).unwrap();
    let moving = (0..5000)
        .map(|_| next_json(&mut driver))
        .find(|m| m["type"] == "state" && m["forward_mps"].as_f64().unwrap() > 0.5);
    assert!(moving.is_some(), "the driver drives");
    assert!(!hub.stop_requested(), "the watcher's stop was refused");
    let s = session.join().unwrap().unwrap();
    assert!(s.duration() > 4.9);
}

/// Sends `text` and returns the first error the server answers, reading at most `max`
/// messages.
fn error_for(ws: &mut Ws, text: &str, max: usize) -> Option<String> {
    ws.send(Message::text(text)).unwrap();
    (0..max)
        .map(|_| next_json(ws))
        .find(|m| m["type"] == "error")
        .map(|m| m["message"].as_str().unwrap().to_string())
}

#[test]
fn a_pages_tables_and_messages_are_bounded() {
    let sc = tracksim::load_scenario(&root().join("scenarios/packbot_stairs.toml")).unwrap();
    let flippers = sc.vehicle.flippers.len();
    assert!(flippers >= 1);
    let hub = Hub::with_grace(0.0);
    let srv = server(hub.clone(), Access::loopback());
    let (sc2, hub2) = (sc.clone(), hub.clone());
    let session = std::thread::spawn(move || {
        let opts = DriveOptions {
            speed: 1.0,
            max_time: Some(6.0),
            ..DriveOptions::default()
        };
        tracksim::live::run_session(&sc2, &hub2, opts)
    });
    let url = format!(
        "ws://{}/ws?session={}",
        srv.addr(),
        hub.session_token().unwrap()
    );
    let (mut ws, _) = tungstenite::connect(&url).unwrap();
    assert_eq!(next_json(&mut ws)["role"], "driver");
    let control = |table: &str| {
        format!(
            r#"{{"type":"control","forward_mps":0.2,"yaw_rate_rad_s":0.0,"flipper_angle_deg":[{table}]}}"#
        )
    };
    // 10^4 entries (50 kB: under the message bound) for a robot with `flippers`: refused.
    let big = vec!["null"; 10_000].join(",");
    let e = error_for(&mut ws, &control(&big), 2000).expect("refused");
    assert!(
        e.contains("10000 entries") && e.contains(&format!("{flippers} flippers")),
        "{e}"
    );
    // One more than the robot has: refused too; as many: taken, the rest padded.
    let over = vec!["10"; flippers + 1].join(",");
    assert!(error_for(&mut ws, &control(&over), 2000).is_some());
    ws.send(Message::text(control("5"))).unwrap();
    let state = (0..5000)
        .map(|_| next_json(&mut ws))
        .find(|m| m["type"] == "state" && m["control"]["forward_mps"] == 0.2)
        .expect("the control taken");
    let table = state["control"]["flipper_angle_deg"].as_array().unwrap();
    assert_eq!(table.len(), flippers, "the robot's table: {state}");
    assert_eq!(table[0], 5.0);
    // A long name in an error is cut.
    let e = error_for(
        &mut ws,
        &format!(r#"{{"type":"{}"}}"#, "x".repeat(20_000)),
        2000,
    );
    assert!(e.unwrap().chars().count() < 400);
    // 10^5 entries (500 kB): beyond the message bound, the connection closes unread.
    let huge = vec!["null"; 100_000].join(",");
    let _ = ws.send(Message::text(control(&huge)));
    let closed = (0..10_000).any(|_| ws.read().is_err());
    assert!(closed, "a 500 kB message closes the connection");
    // The session goes on (its driver dropped: the robot stops); a new page may drive.
    let (mut again, _) = tungstenite::connect(&url).unwrap();
    assert_eq!(next_json(&mut again)["role"], "driver");
    drop(again);
    let s = session.join().unwrap().unwrap();
    assert!(
        s.controls
            .iter()
            .all(|c| c.flipper_angle_deg.len() == flippers)
    );
}
