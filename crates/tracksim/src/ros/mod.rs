//! `tracksim ros`: a scenario as a ROS 2 node over pure-Rust DDS (`ros2-client` on RustDDS;
//! no ROS installation), on the same run loop as `tracksim run` and `drive` (`run::Runner`),
//! recorded as a run. `docs/ROS2.md` lists the topics, types, frames, rates and QoS.
//!
//! - [`topics`]: the node's ROS names;
//! - [`network`]: which interfaces DDS uses (loopback only by default);
//! - [`sanitize`]: what a message may ask of the physics (non-finite values dropped, limits
//!   clamped, unknown flipper names dropped) and the rate-limited warnings;
//! - [`decode`]: a DDS sample read as its type only when it is one (whole, within bounds);
//! - [`commands`]: the commands in force, turned into controls, and the `cmd_vel` watchdog;
//! - the published messages are built from a sample by [`crate::output::ros_messages`], the
//!   module `run.mcap` records them with;
//! - [`sensors`]: the vehicle's sensors on their topics, at their rates;
//! - [`dds`]: the participant, node, publishers, subscriptions and `/rosout`;
//! - [`services`]: `/tracksim/reset` and `/tracksim/set_paused` (one-robot sessions);
//! - [`session`]: the session of one robot or of several (each robot's topics and frames in
//!   its namespace, [`crate::output::ros_names`]) and its run folder.

pub mod commands;
pub mod dds;
pub mod decode;
pub mod network;
pub mod sanitize;
pub mod sensors;
pub mod services;
pub mod session;
pub mod topics;

pub use commands::{Command, CommandState, WATCHDOG_TIMEOUT_S};
pub use network::NetworkRange;
pub use session::{
    Counts, FileCommands, RobotControl, RosOptions, RosSession, RosTeamSession, run_ros,
    run_ros_team,
};
