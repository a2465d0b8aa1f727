//! The operator's seat: `tracksim drive` (a scenario driven live from a 3-D page) and
//! `tracksim view` (a finished run replayed in the same page).
//!
//! - [`access`]: who may use the server: its own `Host` and `Origin` only, and the session's
//!   token for driving (issue 45);
//! - [`assets`]: the page and the pinned three.js build, embedded in the binary;
//! - [`server`]: HTTP for the assets and the run's data, a WebSocket for the live state, on
//!   loopback unless told otherwise;
//! - [`hub`]: the latest-value state and control shared by the simulation and the
//!   connections, and the WebSocket protocol;
//! - [`instructor`]: the instructor's seat: pause, reset, end, faults (issue 43); `latency`:
//!   a trainee's controls delayed by an injected latency;
//! - [`seat`]: who drives, and the grace a dropped driver has to come back;
//! - [`drive`]: the paced session loop, recorded as a run;
//! - [`team_drive`]: a session of several robots, a seat each;
//! - [`hud_feed`]: slip, stall, tilt limit and the terrain ahead, for the page's warnings;
//! - [`sensor_feed`]: the lidar and depth camera readings a live state carries;
//! - [`watch`]: a learning environment's live page (watch-only, `render_mode="human"`).

pub mod access;
pub mod assets;
pub mod drive;
pub mod hub;
pub mod hud_feed;
pub mod instructor;
mod latency;
pub mod seat;
pub mod sensor_feed;
pub mod server;
pub mod team_drive;
pub mod watch;

pub use access::{Access, SessionToken};
pub use drive::{DriveOptions, Session, run_session};
pub use hub::{DriveControl, Hub};
pub use instructor::InstructorAction;
pub use seat::{DEFAULT_RECONNECT_GRACE_S, DriverStatus};
pub use server::{Mode, Server, ViewVideo, view_files};
pub use team_drive::{TeamSession, run_team_session};
pub use watch::Watch;

/// The default address: loopback only.
pub const DEFAULT_BIND: std::net::IpAddr = std::net::IpAddr::V4(std::net::Ipv4Addr::LOCALHOST);
/// The default port.
pub const DEFAULT_PORT: u16 = 8642;
