//! What the simulation loop and the connections share, and the WebSocket protocol.
//!
//! The simulation publishes its state into a latest-value slot ([`Hub::publish`]) and reads
//! the latest control ([`Hub::take_control`]); both only take a mutex for a copy, so the
//! physics never waits for the network. Each connection's thread sends the newest state it has
//! not sent yet (older ones are dropped for a slow client) and, for the driver, hands the
//! messages it receives to the hub.
//!
//! Protocol (JSON text frames). Server to client:
//! `{"type":"hello","role":"driver"|"watcher","token":T|null,"grace_s":G}` on connecting and
//! again whenever the role changes (a watcher promoted to driver), then
//! `{"type":"state", ...}` (see `drive::state_json`), and on soil
//! `{"type":"ruts","epoch":E,"first":S,"cells":[[x,y,surface_z,depth,cell],...]}` (m): the
//! rut cells made since the connection's last such message, numbered from `S` (a cell that
//! deepens comes again), from a log every connection reads in full (unlike the states, none is
//! dropped; the newest [`MAX_RUT_LOG`] are kept); a new `E` (the session was reset, a new
//! episode began) means the ruts before are gone. A driver keeps its token `T` and
//! presents it when it reconnects (`/ws?token=T`) to take the seat back within the grace
//! period `G`, s ([`super::seat`]). Client to server (driver only; a watcher's messages are
//! answered with an error and ignored):
//! - `{"type":"control","forward_mps":F,"yaw_rate_rad_s":W,"flipper_angle_deg":[A|null,...]}`
//!   (m/s, rad/s, degrees by flipper index; `null` keeps a flipper's target);
//! - `{"type":"reset"}`: the session starts again from the scenario's start;
//! - `{"type":"stop"}`: the session ends and its outputs are written.
//!
//! When the driver's connection closes, the robot stops and the seat is held for the driver
//! for the grace period ([`super::seat::Seat`]); the session ends on `stop`, Ctrl-C/SIGTERM,
//! its `--duration`, or when the grace has passed with no page connected.

use super::seat::{DEFAULT_RECONNECT_GRACE_S, DriverStatus, Seat};
use serde::Deserialize;
use std::net::TcpStream;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use tungstenite::Message;

/// Rut cells the hub keeps for connections that have not read them yet (the newest).
pub const MAX_RUT_LOG: usize = 1 << 20;
/// Rut cells one message carries at most.
const RUT_MESSAGE_CELLS: usize = 4096;

/// The session's rut cells, `[x, y, surface_z, depth, cell]` m, numbered from `first`.
#[derive(Default)]
struct RutLog {
    epoch: u64,
    first: u64,
    cells: std::collections::VecDeque<[f64; 5]>,
}

/// How long a connection waits for a client message before it sends the newest state.
const POLL: std::time::Duration = std::time::Duration::from_millis(4);

/// Largest forward speed accepted from a client, m/s.
pub const MAX_FORWARD_MPS: f64 = 3.0;
/// Largest yaw rate accepted from a client, rad/s.
pub const MAX_YAW_RATE_RAD_S: f64 = 6.0;
/// Largest flipper target accepted from a client, degrees (either way).
pub const MAX_FLIPPER_DEG: f64 = 180.0;

/// The operator's controls: body twist and flipper targets (degrees, as a scenario file's
/// `flipper_angle_deg`; `None`: not commanded, held where it is).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DriveControl {
    /// Forward speed, m/s.
    pub forward_mps: f64,
    /// Yaw rate, rad/s (positive turns left).
    pub yaw_rate_rad_s: f64,
    /// Flipper targets by index, degrees.
    pub flipper_angle_deg: Vec<Option<f64>>,
}

#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
enum ClientMessage {
    Control {
        forward_mps: f64,
        yaw_rate_rad_s: f64,
        #[serde(default)]
        flipper_angle_deg: Vec<Option<f64>>,
    },
    Reset,
    Stop,
}

/// State shared by the simulation loop and the connections.
pub struct Hub {
    /// Generation and text of the newest state.
    state: Mutex<(u64, Arc<String>)>,
    control: Mutex<Option<DriveControl>>,
    reset: AtomicBool,
    stop: AtomicBool,
    seat: Mutex<Seat>,
    next_id: AtomicU64,
    watchers: AtomicU64,
    /// Every connection watches (a learning environment's page: nobody drives).
    watch_only: bool,
    /// The scene the page loads (`/scene.json`), when it changes during the session (a new
    /// episode of a randomised scenario); `None`: the server's.
    scene: Mutex<Option<Arc<String>>>,
    /// Soil ruts made during the session ([`Hub::append_ruts`]).
    ruts: Mutex<RutLog>,
}

impl Hub {
    /// A hub with no state yet, and the default reconnect grace
    /// ([`DEFAULT_RECONNECT_GRACE_S`]).
    pub fn new() -> Arc<Hub> {
        Hub::with_grace(DEFAULT_RECONNECT_GRACE_S)
    }

    /// A hub whose dropped driver has `grace_s` seconds to reconnect (0: none).
    pub fn with_grace(grace_s: f64) -> Arc<Hub> {
        Arc::new(Hub {
            state: Mutex::default(),
            control: Mutex::default(),
            reset: AtomicBool::default(),
            stop: AtomicBool::default(),
            seat: Mutex::new(Seat::new(grace_s)),
            next_id: AtomicU64::default(),
            watchers: AtomicU64::default(),
            watch_only: false,
            scene: Mutex::default(),
            ruts: Mutex::default(),
        })
    }

    /// A hub whose every connection watches: the page shows the state, nobody drives (a
    /// learning environment's `render_mode="human"`).
    pub fn watch_only() -> Arc<Hub> {
        Arc::new(Hub {
            watch_only: true,
            ..Arc::into_inner(Hub::with_grace(0.0)).expect("a new hub")
        })
    }

    /// Replaces the scene pages load at `/scene.json` (a page loaded before keeps its own
    /// until reloaded).
    pub fn set_scene(&self, json: String) {
        *self.scene.lock().expect("hub lock") = Some(Arc::new(json));
    }

    /// The scene set by [`Hub::set_scene`], if any.
    pub fn scene(&self) -> Option<Arc<String>> {
        self.scene.lock().expect("hub lock").clone()
    }

    /// The driver's status: connected, or the grace left to a dropped one.
    pub fn driver_status(&self) -> DriverStatus {
        self.seat.lock().expect("hub lock").status()
    }

    /// The reconnect grace, s.
    pub fn grace_s(&self) -> f64 {
        self.seat.lock().expect("hub lock").grace_s()
    }

    /// Whether the session has been left: the driver dropped, its grace passed, and no page
    /// is connected to take the seat.
    pub fn abandoned(&self) -> bool {
        self.connections() == 0 && self.seat.lock().expect("hub lock").abandoned()
    }

    /// Appends rut cells (`[x, y, surface_z, depth, cell]`, m) for every connection to send.
    pub fn append_ruts(&self, cells: &[[f64; 5]]) {
        if cells.is_empty() {
            return;
        }
        let mut log = self.ruts.lock().expect("hub lock");
        log.cells.extend(cells.iter().copied());
        let over = log.cells.len().saturating_sub(MAX_RUT_LOG);
        log.cells.drain(..over);
        log.first += over as u64;
    }

    /// Forgets the ruts (a reset session, a new episode): pages clear theirs.
    pub fn clear_ruts(&self) {
        let mut log = self.ruts.lock().expect("hub lock");
        let epoch = log.epoch + 1;
        *log = RutLog {
            epoch,
            ..RutLog::default()
        };
    }

    /// The `ruts` message for a connection that has sent the cells before `next` of epoch
    /// `epoch`, and what it will have sent then (None: nothing new).
    fn ruts_message(&self, epoch: u64, next: u64) -> Option<(String, u64, u64)> {
        let log = self.ruts.lock().expect("hub lock");
        let from = if log.epoch == epoch {
            next.max(log.first)
        } else {
            log.first
        };
        let end = log.first + log.cells.len() as u64;
        if from >= end {
            return None;
        }
        let skip = (from - log.first) as usize;
        let cells: Vec<[f64; 5]> = log
            .cells
            .iter()
            .skip(skip)
            .take(RUT_MESSAGE_CELLS)
            .copied()
            .collect();
        let n = cells.len() as u64;
        let msg = serde_json::json!({ "type": "ruts", "epoch": log.epoch, "first": from, "cells": cells });
        Some((msg.to_string(), log.epoch, from + n))
    }

    /// Publishes a new state (replacing any the connections have not sent yet).
    pub fn publish(&self, json: String) {
        let mut s = self.state.lock().expect("hub lock");
        s.0 += 1;
        s.1 = Arc::new(json);
    }

    fn latest(&self) -> (u64, Arc<String>) {
        self.state.lock().expect("hub lock").clone()
    }

    /// The newest control the driver sent since the last call, if any.
    pub fn take_control(&self) -> Option<DriveControl> {
        self.control.lock().expect("hub lock").take()
    }

    /// Whether the driver asked for a reset since the last call.
    pub fn take_reset(&self) -> bool {
        self.reset.swap(false, Ordering::Relaxed)
    }

    /// Asks the session to end (stop button, closed page, Ctrl-C).
    pub fn request_stop(&self) {
        self.stop.store(true, Ordering::Relaxed);
    }

    /// Whether the session should end.
    pub fn stop_requested(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }

    /// Open WebSocket connections (driver and watchers).
    pub fn connections(&self) -> u64 {
        self.watchers.load(Ordering::Relaxed)
    }

    /// Handles one message of connection `id`; returns an error text for the client.
    fn receive(&self, id: u64, text: &str) -> Option<String> {
        if !self.seat.lock().expect("hub lock").drives(id) {
            return Some("this connection only watches: another one drives".into());
        }
        match serde_json::from_str::<ClientMessage>(text) {
            Ok(ClientMessage::Control {
                forward_mps,
                yaw_rate_rad_s,
                flipper_angle_deg,
            }) => {
                let finite = forward_mps.is_finite()
                    && yaw_rate_rad_s.is_finite()
                    && flipper_angle_deg.iter().flatten().all(|a| a.is_finite());
                if !finite {
                    return Some("control values must be finite numbers".into());
                }
                *self.control.lock().expect("hub lock") = Some(DriveControl {
                    forward_mps: forward_mps.clamp(-MAX_FORWARD_MPS, MAX_FORWARD_MPS),
                    yaw_rate_rad_s: yaw_rate_rad_s.clamp(-MAX_YAW_RATE_RAD_S, MAX_YAW_RATE_RAD_S),
                    flipper_angle_deg: flipper_angle_deg
                        .iter()
                        .map(|a| a.map(|a| a.clamp(-MAX_FLIPPER_DEG, MAX_FLIPPER_DEG)))
                        .collect(),
                });
                None
            }
            Ok(ClientMessage::Reset) => {
                self.reset.store(true, Ordering::Relaxed);
                None
            }
            Ok(ClientMessage::Stop) => {
                self.request_stop();
                None
            }
            Err(e) => Some(format!(
                "bad message ({e}); see the protocol in live/hub.rs"
            )),
        }
    }
}

/// The token a page presents in its WebSocket URL's query (`token=HEX`), if any.
fn query_token(query: &str) -> Option<&str> {
    query
        .split('&')
        .find_map(|kv| kv.strip_prefix("token="))
        .filter(|t| !t.is_empty() && t.len() <= 64 && t.bytes().all(|b| b.is_ascii_hexdigit()))
}

/// The hello of a connection that drives (with its token) or watches.
fn hello(token: Option<&str>, grace_s: f64) -> String {
    let role = if token.is_some() { "driver" } else { "watcher" };
    serde_json::json!({ "type": "hello", "role": role, "token": token, "grace_s": grace_s })
        .to_string()
}

/// Serves one WebSocket connection (its request's query in `query`) until it closes or the
/// session stops. It drives if it takes the seat ([`Seat::claim`]: the first page, a dropped
/// driver presenting its token within the grace, anybody once the seat is free), else it
/// watches and takes the seat when it falls free. When the driver leaves, its control is
/// dropped (the session stops the robot) and the seat is held for the grace period.
pub(super) fn serve_socket(stream: TcpStream, hub: &Hub, query: &str) -> std::io::Result<()> {
    let mut ws = tungstenite::accept(stream).map_err(std::io::Error::other)?;
    let id = hub.next_id.fetch_add(1, Ordering::Relaxed);
    let presented = query_token(query);
    let token = if hub.watch_only {
        None
    } else {
        hub.seat.lock().expect("hub lock").claim(id, presented)
    };
    hub.watchers.fetch_add(1, Ordering::Relaxed);
    ws.get_mut().set_read_timeout(Some(POLL))?;
    let result = socket_loop(&mut ws, hub, (id, presented), token);
    let mut seat = hub.seat.lock().expect("hub lock");
    if seat.drives(id) {
        *hub.control.lock().expect("hub lock") = None;
    }
    seat.leave(id);
    hub.watchers.fetch_sub(1, Ordering::Relaxed);
    result
}

fn socket_loop(
    ws: &mut tungstenite::WebSocket<TcpStream>,
    hub: &Hub,
    (id, presented): (u64, Option<&str>),
    mut token: Option<String>,
) -> std::io::Result<()> {
    let other = std::io::Error::other;
    let grace = hub.grace_s();
    ws.send(Message::text(hello(token.as_deref(), grace)))
        .map_err(other)?;
    let mut sent = 0u64;
    // (epoch, next cell) of the ruts sent on this connection.
    let mut ruts_sent = (u64::MAX, 0u64);
    loop {
        if token.is_none() && !hub.watch_only {
            // A watcher takes a free seat; a reconnected driver whose old connection was
            // still open takes it back once that one has closed.
            token = hub.seat.lock().expect("hub lock").claim(id, presented);
            if token.is_some() {
                ws.send(Message::text(hello(token.as_deref(), grace)))
                    .map_err(other)?;
            }
        }
        if hub.stop_requested() {
            // The last state, then a close frame; errors do not matter any more.
            let (_, s) = hub.latest();
            let _ = ws.send(Message::text(s.as_str()));
            let _ = ws.close(None);
            let _ = ws.flush();
            return Ok(());
        }
        match ws.read() {
            Ok(Message::Text(t)) => {
                if let Some(err) = hub.receive(id, t.as_str()) {
                    let msg = serde_json::json!({ "type": "error", "message": err }).to_string();
                    ws.send(Message::text(msg)).map_err(other)?;
                }
            }
            Ok(Message::Close(_)) => return Ok(()),
            Ok(_) => {}
            Err(tungstenite::Error::Io(e))
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                ) => {}
            Err(e) => return Err(other(e)),
        }
        let (g, s) = hub.latest();
        if g != sent && g > 0 {
            sent = g;
            ws.send(Message::text(s.as_str())).map_err(other)?;
        }
        if let Some((msg, epoch, next)) = hub.ruts_message(ruts_sent.0, ruts_sent.1) {
            ruts_sent = (epoch, next);
            ws.send(Message::text(msg)).map_err(other)?;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A page that connects late gets every rut made before; one that has them gets only the
    /// new ones; after a reset (a new epoch) it gets the new log from its start.
    #[test]
    fn the_rut_log_reaches_every_connection_whole() {
        let hub = Hub::new();
        let cell = |i: usize| [i as f64, 0.0, 0.0, 0.002, 0.01];
        let cells: Vec<_> = (0..5000).map(cell).collect();
        hub.append_ruts(&cells);
        // A new connection (no epoch yet): the log in messages of RUT_MESSAGE_CELLS.
        let (m1, e, next) = hub.ruts_message(u64::MAX, 0).unwrap();
        assert_eq!(next, RUT_MESSAGE_CELLS as u64);
        let v: serde_json::Value = serde_json::from_str(&m1).unwrap();
        assert_eq!(v["first"], 0);
        assert_eq!(v["cells"].as_array().unwrap().len(), RUT_MESSAGE_CELLS);
        let (_, _, next) = hub.ruts_message(e, next).unwrap();
        assert_eq!(next, 5000);
        assert!(hub.ruts_message(e, next).is_none(), "nothing new");
        hub.append_ruts(&[cell(5000)]);
        let (m, _, next) = hub.ruts_message(e, next).unwrap();
        assert_eq!((next, m.contains("\"first\":5000")), (5001, true));
        hub.clear_ruts();
        assert!(
            hub.ruts_message(e, next).is_none(),
            "a cleared log sends nothing"
        );
        hub.append_ruts(&[cell(7)]);
        let (m, e2, next) = hub.ruts_message(e, next).unwrap();
        assert!(e2 != e && next == 1 && m.contains("\"first\":0"), "{m}");
    }
}
