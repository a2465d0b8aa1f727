//! What the simulation loop and the connections share, and the WebSocket protocol.
//!
//! The simulation publishes its state into a latest-value slot ([`Hub::publish`]) and reads
//! the latest control ([`Hub::take_control`]); both only take a mutex for a copy, so the
//! physics never waits for the network. Each connection's thread sends the newest state it has
//! not sent yet (older ones are dropped for a slow client) and, for the driver, hands the
//! messages it receives to the hub.
//!
//! Seats: a session has a seat per robot (one for a one-robot file). A page asks for robot `N`
//! with `/ws?robot=N` (else it takes the first free seat in file order), or only watches with
//! `/ws?watch=1` (with `robot=N`: following robot `N`); each seat has its own token and grace.
//! Only a connection presenting the session's token (`/ws?session=TOKEN`,
//! [`super::access::SessionToken`]: the served page reads it from `/session.json`, the terminal
//! prints it) takes a seat; any other watches.
//!
//! Bounds (issue 45): a message from a page is at most [`MAX_MESSAGE_BYTES`] (a larger frame or
//! message closes the connection before it is held in memory), a control's flipper table at
//! most as long as the robot's flippers (a longer one is refused; a shorter one holds the rest),
//! and the states sent to the pages carry only the controls in force, never a page's table.
//!
//! Protocol (JSON text frames). Server to client:
//! `{"type":"hello","role":"driver"|"watcher","token":T|null,"grace_s":G,"robot":N,"robots":[...]}`
//! on connecting and again whenever the role changes (a watcher promoted to driver), `robot`
//! the robot the connection drives or follows, `robots` every robot's name, then
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
//! - `{"type":"reset"}`: the session starts again from the scenario's start; in a session of
//!   several robots only the driver's own robot starts again (a new attempt of it) while the
//!   others go on;
//! - `{"type":"stop"}`: the session ends and its outputs are written; in a session of several
//!   robots the driver's seat closes (the robot stops) and the session ends once every seat
//!   that was taken has closed.
//!
//! A connection presenting the instructor's token (`/ws?instructor=TOKEN`, issue 43) never
//! drives: it watches with the role `instructor` and its messages are the instructor's (pause,
//! resume, reset, end, fault: [`super::instructor`]), checked and queued for the session
//! ([`Hub::take_actions`]).
//!
//! When the driver's connection closes, the robot stops and the seat is held for the driver
//! for the grace period ([`super::seat::Seat`]); the session ends on `stop`, Ctrl-C/SIGTERM,
//! its `--duration`, or when the grace has passed with no page connected.

use super::access::SessionToken;
pub use super::instructor::InstructorAction;
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
/// Largest WebSocket message (and frame) accepted from a page, bytes: a control is ~100.
pub const MAX_MESSAGE_BYTES: usize = 64 << 10;
/// Longest flipper table a control may carry before the session has said how many flippers
/// its robot has ([`Hub::set_flipper_count`]).
pub const MAX_FLIPPER_TABLE: usize = 64;
/// Longest error text sent back to a page, characters.
const MAX_ERROR_CHARS: usize = 200;

/// The operator's controls: body twist and flipper targets (degrees, as a scenario file's
/// `flipper_angle_deg`; `None`: not commanded, held where it is).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
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

/// What an instructor's page sends (`{"type": ...}`; see [`super::instructor`]).
#[derive(Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
enum InstructorMessage {
    Pause,
    Resume,
    End,
    Reset {
        #[serde(default)]
        robot: Option<String>,
    },
    Fault {
        #[serde(default)]
        robot: Option<String>,
        fault: crate::spec::FaultSpec,
    },
}

/// Checks an instructor's fault for robot `k` against the session's scenario (the track and
/// flipper names, the method): `Err` with the reason, sent back to the instructor's page.
pub type FaultCheck =
    Box<dyn Fn(usize, &crate::spec::FaultSpec) -> std::result::Result<(), String> + Send + Sync>;

/// State shared by the simulation loop and the connections.
pub struct Hub {
    /// Each robot's generation and text of its newest state.
    states: Mutex<Vec<(u64, Arc<String>)>>,
    /// Each robot's newest control from its driver.
    controls: Mutex<Vec<Option<DriveControl>>>,
    /// Each robot's driver asked for a reset since the session last took it.
    resets: Mutex<Vec<bool>>,
    stop: AtomicBool,
    /// Each robot's seat.
    seats: Mutex<Vec<Seat>>,
    /// The robots' names (a seat each); `team`: a session of several robots.
    robots: Vec<String>,
    team: bool,
    next_id: AtomicU64,
    watchers: AtomicU64,
    /// Every connection watches (a learning environment's page: nobody drives).
    watch_only: bool,
    /// The scene the page loads (`/scene.json`), when it changes during the session (a new
    /// episode of a randomised scenario); `None`: the server's.
    scene: Mutex<Option<Arc<String>>>,
    /// Soil ruts made during the session ([`Hub::append_ruts`]).
    ruts: Mutex<RutLog>,
    /// What a connection presents to drive.
    token: SessionToken,
    /// Each robot's flipper count: the longest table a control may carry.
    flippers: Mutex<Vec<usize>>,
    /// What a connection presents to take the instructor's seat (issue 43): printed on the
    /// terminal, never served.
    instructor: SessionToken,
    /// The instructor's actions not yet taken by the session, in order.
    actions: Mutex<Vec<InstructorAction>>,
    /// The session's check of an instructor's fault ([`Hub::set_fault_check`]).
    fault_check: Mutex<Option<FaultCheck>>,
}

impl Hub {
    /// A hub with no state yet, and the default reconnect grace
    /// ([`DEFAULT_RECONNECT_GRACE_S`]).
    pub fn new() -> Arc<Hub> {
        Hub::with_grace(DEFAULT_RECONNECT_GRACE_S)
    }

    /// A hub whose dropped driver has `grace_s` seconds to reconnect (0: none).
    pub fn with_grace(grace_s: f64) -> Arc<Hub> {
        Arc::new(Hub::seats(
            vec![crate::model::DEFAULT_ROBOT_NAME.into()],
            grace_s,
            false,
        ))
    }

    /// A hub for a session of several robots (`names`, in file order): a seat each, each
    /// dropped driver with `grace_s` seconds to reconnect.
    pub fn team(names: Vec<String>, grace_s: f64) -> Arc<Hub> {
        Arc::new(Hub::seats(names, grace_s, true))
    }

    fn seats(robots: Vec<String>, grace_s: f64, team: bool) -> Hub {
        let n = robots.len();
        Hub {
            states: Mutex::new(vec![(0, Arc::default()); n]),
            controls: Mutex::new(vec![None; n]),
            resets: Mutex::new(vec![false; n]),
            stop: AtomicBool::default(),
            seats: Mutex::new((0..n).map(|_| Seat::new(grace_s)).collect()),
            robots,
            team,
            next_id: AtomicU64::default(),
            watchers: AtomicU64::default(),
            watch_only: false,
            scene: Mutex::default(),
            ruts: Mutex::default(),
            token: SessionToken::new(),
            flippers: Mutex::new(vec![MAX_FLIPPER_TABLE; n]),
            instructor: SessionToken::new(),
            actions: Mutex::default(),
            fault_check: Mutex::default(),
        }
    }

    /// The instructor's token, which a connection presents (`/ws?instructor=TOKEN`, the page
    /// opened as `/?instructor=TOKEN`) to pause, reset, end and inject faults; `None` for a
    /// watch-only hub. Never served: the terminal prints the instructor's URL.
    pub fn instructor_token(&self) -> Option<&str> {
        (!self.watch_only).then(|| self.instructor.as_str())
    }

    /// Sets the check an instructor's fault must pass before it is queued (the session's
    /// scenario knows the names and the method).
    pub fn set_fault_check(&self, check: FaultCheck) {
        *self.fault_check.lock().expect("hub lock") = Some(check);
    }

    /// The instructor's actions since the last call, in order.
    pub fn take_actions(&self) -> Vec<InstructorAction> {
        std::mem::take(&mut *self.actions.lock().expect("hub lock"))
    }

    /// Queues an instructor's action as its page would (what `receive_instructor` does with a
    /// checked message).
    pub fn push_action(&self, a: InstructorAction) {
        self.actions.lock().expect("hub lock").push(a);
    }

    /// Handles one message of the instructor's connection; returns an error text for it.
    fn receive_instructor(&self, text: &str) -> Option<String> {
        let msg = match serde_json::from_str::<InstructorMessage>(text) {
            Ok(m) => m,
            Err(e) => {
                return Some(format!(
                    "bad instructor message ({}); see the protocol in live/instructor.rs",
                    e.to_string()
                        .chars()
                        .take(MAX_ERROR_CHARS)
                        .collect::<String>()
                ));
            }
        };
        let robot = |name: &Option<String>| match name {
            None => Ok(0),
            Some(n) => self.robots.iter().position(|r| r == n).ok_or_else(|| {
                format!(
                    "no robot `{}` in this session (its robots: {})",
                    n.chars().take(64).collect::<String>(),
                    self.robots.join(", ")
                )
            }),
        };
        let action = match msg {
            InstructorMessage::Pause => InstructorAction::Pause,
            InstructorMessage::Resume => InstructorAction::Resume,
            InstructorMessage::End => InstructorAction::End,
            InstructorMessage::Reset { robot: r } => {
                // In a session of several robots the reset puts one robot back at its start
                // while the others go on: which one must be said.
                if self.team && r.is_none() {
                    return Some(format!(
                        "name the robot to reset: {{\"type\":\"reset\",\"robot\":NAME}} (this \
                         session's robots: {})",
                        self.robots.join(", ")
                    ));
                }
                match robot(&r) {
                    Ok(k) => InstructorAction::Reset(k),
                    Err(e) => return Some(e),
                }
            }
            InstructorMessage::Fault { robot: r, fault } => {
                let k = match robot(&r) {
                    Ok(k) => k,
                    Err(e) => return Some(e),
                };
                if let Some(check) = self.fault_check.lock().expect("hub lock").as_ref()
                    && let Err(e) = check(k, &fault)
                {
                    return Some(e.chars().take(MAX_ERROR_CHARS).collect());
                }
                InstructorAction::Fault(k, fault)
            }
        };
        self.push_action(action);
        None
    }

    /// The session's token, which a connection presents (`/ws?session=TOKEN`) to drive;
    /// `None` for a watch-only hub (nobody drives).
    pub fn session_token(&self) -> Option<&str> {
        (!self.watch_only).then(|| self.token.as_str())
    }

    /// Robot `k` has `n` flippers: a control's table may be no longer (the session sets it
    /// when it starts).
    pub fn set_flipper_count(&self, k: usize, n: usize) {
        if let Some(c) = self.flippers.lock().expect("hub lock").get_mut(k) {
            *c = n.min(MAX_FLIPPER_TABLE);
        }
    }

    /// The robots' names, a seat each (one for a one-robot session).
    pub fn robots(&self) -> &[String] {
        &self.robots
    }

    /// A hub whose every connection watches: the page shows the state, nobody drives (a
    /// learning environment's `render_mode="human"`).
    pub fn watch_only() -> Arc<Hub> {
        Arc::new(Hub {
            watch_only: true,
            ..Arc::into_inner(Hub::with_grace(0.0)).expect("a new hub")
        })
    }

    /// Whether every connection only watches ([`Hub::watch_only`]): the page is told so in
    /// `/session.json` (`watch_only`) and shows no drive controls and no driver's status.
    pub fn is_watch_only(&self) -> bool {
        self.watch_only
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

    /// The (first) robot's driver status: connected, or the grace left to a dropped one.
    pub fn driver_status(&self) -> DriverStatus {
        self.driver_status_of(0)
    }

    /// Robot `k`'s driver status.
    pub fn driver_status_of(&self, k: usize) -> DriverStatus {
        self.seats.lock().expect("hub lock")[k].status()
    }

    /// The reconnect grace, s.
    pub fn grace_s(&self) -> f64 {
        self.seats.lock().expect("hub lock")[0].grace_s()
    }

    /// Whether the session has been left: a driver dropped and its grace passed, no seat is
    /// driven or held for its driver, and no page is connected to take a seat.
    pub fn abandoned(&self) -> bool {
        let seats = self.seats.lock().expect("hub lock");
        self.connections() == 0
            && seats.iter().any(Seat::abandoned)
            && seats.iter().all(|s| {
                let st = s.status();
                !st.connected && st.grace_left_s.is_none()
            })
    }

    /// Whether every driver of a session of several robots has stopped: each seat that was
    /// taken is closed ([`Seat::finish`]) and at least one was.
    pub fn all_stopped(&self) -> bool {
        let seats = self.seats.lock().expect("hub lock");
        self.team
            && seats.iter().any(|s| s.status().finished)
            && seats
                .iter()
                .all(|s| s.status().finished || !s.ever_driven() || s.abandoned())
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

    /// Publishes a new state of the (first) robot (replacing any the connections have not
    /// sent yet).
    pub fn publish(&self, json: String) {
        self.publish_robot(0, json);
    }

    /// Publishes a new state of robot `k`: what the pages driving or following it are sent.
    pub fn publish_robot(&self, k: usize, json: String) {
        let mut s = self.states.lock().expect("hub lock");
        s[k].0 += 1;
        s[k].1 = Arc::new(json);
    }

    fn latest(&self, k: usize) -> (u64, Arc<String>) {
        self.states.lock().expect("hub lock")[k].clone()
    }

    /// The newest control the (first) robot's driver sent since the last call, if any.
    pub fn take_control(&self) -> Option<DriveControl> {
        self.take_control_of(0)
    }

    /// The newest control robot `k`'s driver sent since the last call, if any.
    pub fn take_control_of(&self, k: usize) -> Option<DriveControl> {
        self.controls.lock().expect("hub lock")[k].take()
    }

    /// Whether the (first) robot's driver asked for a reset since the last call.
    pub fn take_reset(&self) -> bool {
        self.take_reset_of(0)
    }

    /// Whether robot `k`'s driver asked for a reset since the last call.
    pub fn take_reset_of(&self, k: usize) -> bool {
        self.resets
            .lock()
            .expect("hub lock")
            .get_mut(k)
            .is_some_and(std::mem::take)
    }

    /// Asks the session to end (stop button, closed page, Ctrl-C).
    pub fn request_stop(&self) {
        self.stop.store(true, Ordering::Relaxed);
    }

    /// Waits until a page has connected (or a stop is asked): a session started with
    /// `--wait-for-page` starts its clock then.
    pub fn wait_for_page(&self) {
        while self.connections() == 0 && !self.stop_requested() {
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
    }

    /// Whether the session should end.
    pub fn stop_requested(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }

    /// Open WebSocket connections (driver and watchers).
    pub fn connections(&self) -> u64 {
        self.watchers.load(Ordering::Relaxed)
    }

    /// The seat connection `id` drives, if any.
    fn seat_of(&self, id: u64) -> Option<usize> {
        self.seats
            .lock()
            .expect("hub lock")
            .iter()
            .position(|s| s.drives(id))
    }

    /// Connection `id` (presenting `token`) asks for a seat among `wanted` (in order); returns
    /// the seat and its token if it now drives.
    fn claim(&self, id: u64, token: Option<&str>, wanted: &[usize]) -> Option<(usize, String)> {
        let mut seats = self.seats.lock().expect("hub lock");
        // A token names its seat: the seats held for their drivers first.
        let held: Vec<usize> = wanted
            .iter()
            .copied()
            .filter(|&k| token.is_some() && seats[k].status().grace_left_s.is_some())
            .collect();
        held.into_iter()
            .chain(wanted.iter().copied())
            .find_map(|k| seats[k].claim(id, token).map(|t| (k, t)))
    }

    /// Handles one message of connection `id`; returns an error text for the client.
    fn receive(&self, id: u64, text: &str) -> Option<String> {
        let Some(k) = self.seat_of(id) else {
            return Some("this connection only watches: another one drives".into());
        };
        match serde_json::from_str::<ClientMessage>(text) {
            Ok(ClientMessage::Control {
                forward_mps,
                yaw_rate_rad_s,
                mut flipper_angle_deg,
            }) => {
                let n = self.flippers.lock().expect("hub lock")[k];
                if flipper_angle_deg.len() > n {
                    return Some(format!(
                        "flipper_angle_deg has {} entries but this robot has {n} flippers; \
                         control refused",
                        flipper_angle_deg.len()
                    ));
                }
                flipper_angle_deg.resize(n, None);
                let finite = forward_mps.is_finite()
                    && yaw_rate_rad_s.is_finite()
                    && flipper_angle_deg.iter().flatten().all(|a| a.is_finite());
                if !finite {
                    return Some("control values must be finite numbers".into());
                }
                self.controls.lock().expect("hub lock")[k] = Some(DriveControl {
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
                self.resets.lock().expect("hub lock")[k] = true;
                None
            }
            Ok(ClientMessage::Stop) if self.team => {
                self.controls.lock().expect("hub lock")[k] = None;
                self.seats.lock().expect("hub lock")[k].finish();
                None
            }
            Ok(ClientMessage::Stop) => {
                self.request_stop();
                None
            }
            Err(e) => Some(format!(
                "bad message ({}); see the protocol in live/hub.rs",
                e.to_string()
                    .chars()
                    .take(MAX_ERROR_CHARS)
                    .collect::<String>()
            )),
        }
    }
}

/// The value of `key` in a WebSocket URL's query (`key=VALUE`), if any.
fn query_value<'a>(query: &'a str, key: &str) -> Option<&'a str> {
    query
        .split('&')
        .find_map(|kv| kv.strip_prefix(key)?.strip_prefix('='))
}

/// The token a page presents in its WebSocket URL's query (`token=HEX`), if any.
fn query_token(query: &str) -> Option<&str> {
    query_value(query, "token")
        .filter(|t| !t.is_empty() && t.len() <= 64 && t.bytes().all(|b| b.is_ascii_hexdigit()))
}

/// The robot a request's query names (`robot=NAME`) among `robots`, by index.
pub(super) fn query_robot(query: &str, robots: &[String]) -> Option<usize> {
    let n = query_value(query, "robot")?;
    robots.iter().position(|r| r == n)
}

/// What a connection asks for in its query: the robot (`robot=NAME`, by index; an unknown
/// name is an error text), and whether it only watches (`watch=1`).
fn query_seat(
    query: &str,
    robots: &[String],
) -> (std::result::Result<Option<usize>, String>, bool) {
    let watch = query_value(query, "watch").is_some_and(|v| v == "1" || v == "true");
    let robot = match query_value(query, "robot") {
        None => Ok(None),
        Some(n) => robots.iter().position(|r| r == n).map(Some).ok_or_else(|| {
            format!(
                "no robot `{}` in this session (its robots: {}); watching",
                n.chars().take(64).collect::<String>(),
                robots.join(", ")
            )
        }),
    };
    (robot, watch)
}

/// The hello of a connection that drives (with its token), is the instructor's or watches
/// robot `robot`.
fn hello(
    (token, instructor): (Option<&str>, bool),
    grace_s: f64,
    robot: &str,
    robots: &[String],
) -> String {
    let role = if token.is_some() {
        "driver"
    } else if instructor {
        "instructor"
    } else {
        "watcher"
    };
    serde_json::json!({
        "type": "hello", "role": role, "token": token, "grace_s": grace_s,
        "robot": robot, "robots": robots,
    })
    .to_string()
}

/// What a connection wants and has: the seats it would take (in order; none when it only
/// watches), the robot it follows, its seat and token once it drives.
struct Wants {
    seats: Vec<usize>,
    follow: usize,
    token: Option<String>,
    /// The connection is the instructor's (it presented the instructor's token).
    instructor: bool,
}

/// Serves one WebSocket connection (its request's query in `query`) until it closes or the
/// session stops. It drives if it takes the seat ([`Seat::claim`]: the first page, a dropped
/// driver presenting its token within the grace, anybody once the seat is free), else it
/// watches and takes the seat when it falls free. When the driver leaves, its control is
/// dropped (the session stops the robot) and the seat is held for the grace period.
pub(super) fn serve_socket(stream: TcpStream, hub: &Hub, query: &str) -> std::io::Result<()> {
    let config = tungstenite::protocol::WebSocketConfig::default()
        .max_message_size(Some(MAX_MESSAGE_BYTES))
        .max_frame_size(Some(MAX_MESSAGE_BYTES));
    let mut ws =
        tungstenite::accept_with_config(stream, Some(config)).map_err(std::io::Error::other)?;
    let id = hub.next_id.fetch_add(1, Ordering::Relaxed);
    let presented = query_token(query);
    let session = query_value(query, "session");
    let authorised = hub.token.matches(session);
    let instructor = !hub.watch_only && hub.instructor.matches(query_value(query, "instructor"));
    let (robot, watch) = query_seat(query, &hub.robots);
    let asked = robot.clone().unwrap_or(None);
    let seats = match asked {
        _ if hub.watch_only || watch || instructor || robot.is_err() || !authorised => Vec::new(),
        Some(k) => vec![k],
        None => (0..hub.robots.len()).collect(),
    };
    let mut wants = Wants {
        seats,
        follow: asked.unwrap_or(0),
        token: None,
        instructor,
    };
    if let Some((k, t)) = hub.claim(id, presented, &wants.seats) {
        wants.follow = k;
        wants.token = Some(t);
    }
    hub.watchers.fetch_add(1, Ordering::Relaxed);
    ws.get_mut().set_read_timeout(Some(POLL))?;
    if let Err(why) = robot {
        let msg = serde_json::json!({ "type": "error", "message": why }).to_string();
        let _ = ws.send(Message::text(msg));
    }
    if query_value(query, "instructor").is_some() && !instructor && !hub.watch_only {
        let why = "not the instructor's token: watching (`tracksim drive` printed the \
                   instructor's URL)";
        let msg = serde_json::json!({ "type": "error", "message": why }).to_string();
        let _ = ws.send(Message::text(msg));
    }
    if session.is_some() && !authorised && !hub.watch_only {
        let why = "not the session's token: watching (the page served by this server has it; \
                   `tracksim drive` printed it)";
        let msg = serde_json::json!({ "type": "error", "message": why }).to_string();
        let _ = ws.send(Message::text(msg));
    }
    let result = socket_loop(&mut ws, hub, (id, presented), wants);
    if let Some(k) = hub.seat_of(id) {
        hub.controls.lock().expect("hub lock")[k] = None;
        hub.seats.lock().expect("hub lock")[k].leave(id);
    }
    hub.watchers.fetch_sub(1, Ordering::Relaxed);
    result
}

fn socket_loop(
    ws: &mut tungstenite::WebSocket<TcpStream>,
    hub: &Hub,
    (id, presented): (u64, Option<&str>),
    mut wants: Wants,
) -> std::io::Result<()> {
    let other = std::io::Error::other;
    let grace = hub.grace_s();
    let hi = |w: &Wants| {
        hello(
            (w.token.as_deref(), w.instructor),
            grace,
            &hub.robots[w.follow],
            &hub.robots,
        )
    };
    ws.send(Message::text(hi(&wants))).map_err(other)?;
    let mut sent = 0u64;
    // (epoch, next cell) of the ruts sent on this connection.
    let mut ruts_sent = (u64::MAX, 0u64);
    loop {
        if wants.token.is_none() && !wants.seats.is_empty() {
            // A watcher takes a free seat; a reconnected driver whose old connection was
            // still open takes it back once that one has closed.
            if let Some((k, t)) = hub.claim(id, presented, &wants.seats) {
                wants.follow = k;
                wants.token = Some(t);
                ws.send(Message::text(hi(&wants))).map_err(other)?;
            }
        } else if wants.token.is_some() && hub.seat_of(id).is_none() {
            // The driver stopped: its seat closed; it watches its robot from now on.
            wants.token = None;
            wants.seats.clear();
            ws.send(Message::text(hi(&wants))).map_err(other)?;
        }
        if hub.stop_requested() {
            // The last state, then a close frame; errors do not matter any more.
            let (_, s) = hub.latest(wants.follow);
            let _ = ws.send(Message::text(s.as_str()));
            let _ = ws.close(None);
            let _ = ws.flush();
            return Ok(());
        }
        match ws.read() {
            Ok(Message::Text(t)) => {
                let err = if wants.instructor {
                    hub.receive_instructor(t.as_str())
                } else {
                    hub.receive(id, t.as_str())
                };
                if let Some(err) = err {
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
        let (g, s) = hub.latest(wants.follow);
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

    /// A session of several robots: a page asking for a robot gets its seat, another page the
    /// first free one; each seat its own token; a stop closes one seat and the session ends
    /// only once every taken seat has stopped; with every driver gone past the grace (0 here)
    /// and no page connected, the session is left.
    #[test]
    fn a_seat_per_robot_each_with_its_token_and_its_own_end() {
        let names = vec!["a".to_string(), "b".to_string(), "c".to_string()];
        let hub = Hub::team(names.clone(), 0.0);
        let (robot, watch) = query_seat("robot=b", &names);
        assert_eq!((robot, watch), (Ok(Some(1)), false));
        assert!(query_seat("robot=zz&watch=1", &names).0.is_err());
        let (kb, tb) = hub.claim(1, None, &[1]).expect("b's seat");
        let (ka, ta) = hub.claim(2, None, &[0, 1, 2]).expect("the first free seat");
        assert_eq!((kb, ka), (1, 0));
        assert_ne!(ta, tb, "a token per seat");
        assert!(
            hub.claim(3, Some(&tb), &[1]).is_none(),
            "b's seat is driven"
        );
        // A control goes to the sender's robot only.
        let ctl = r#"{"type":"control","forward_mps":0.2,"yaw_rate_rad_s":0.0}"#;
        assert_eq!(hub.receive(1, ctl), None);
        assert!(hub.take_control_of(0).is_none());
        assert_eq!(hub.take_control_of(1).map(|c| c.forward_mps), Some(0.2));
        assert!(hub.receive(3, ctl).unwrap().contains("only watches"));
        // b's reset is b's robot's only.
        assert_eq!(hub.receive(1, r#"{"type":"reset"}"#), None);
        assert!(!hub.take_reset_of(0) && hub.take_reset_of(1) && !hub.take_reset_of(1));
        assert!(
            hub.receive(3, r#"{"type":"reset"}"#)
                .unwrap()
                .contains("only watches")
        );
        // b stops: its seat closes (nobody takes it again), a drives on.
        assert_eq!(hub.receive(1, r#"{"type":"stop"}"#), None);
        assert!(hub.driver_status_of(1).finished && !hub.all_stopped());
        assert!(
            hub.claim(4, None, &[1]).is_none(),
            "a closed seat stays closed"
        );
        assert!(
            !hub.stop_requested(),
            "one driver's stop is not the session's"
        );
        // a's page drops: with no grace and no page connected, the session is left.
        hub.seats.lock().unwrap()[0].leave(2);
        assert!(hub.abandoned());
        // a stops instead: every taken seat has stopped (c was never taken).
        let hub = Hub::team(names, 0.0);
        hub.claim(1, None, &[0]).unwrap();
        assert_eq!(hub.receive(1, r#"{"type":"stop"}"#), None);
        assert!(hub.all_stopped());
    }

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
