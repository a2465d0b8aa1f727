//! Several robots in one world (`[[vehicles]]`, issue 40): each robot compiled as the one robot
//! of a scenario ([`RobotModel`]), the rule that decides the world's outcome ([`TeamRule`]) and
//! the world's own `[expect]` ([`Team`]). A one-robot file has no [`Team`]: its scenario is its
//! robot's.
//!
//! Every layer that knows one robot (sensors, samples, summaries, outputs) reads a robot
//! through `Scenario::robot_view` (`robot_view.rs`): the world with that robot as its one
//! robot.

use super::outcome::OutcomeModel;
use super::{Command, Drawbar, Expectation, VehicleModel};

/// Most robots one world holds: each takes a collision-group bit of Rapier's 32 (16 are the
/// world's and the vehicle parts'), so robots touch each other and never themselves.
pub const MAX_ROBOTS: usize = 16;

/// Largest distance, m, between two robots' chassis (in x or y) that one world holds. Rapier
/// works in f32 with one floating origin kept at the centre of the robots: within 10 m of it
/// the spacing of f32 is at most 0.95 um (0.24 um within 2 m, where one robot is kept), and the
/// flat-ground tile (`terrain::GROUND_TILE_HALF_M`, 10 m) still lies under every robot. Checked
/// at the start (a file's error) and at every step (the run stops with a message).
pub const MAX_ROBOT_SPREAD_M: f64 = 10.0;

/// Name of the robot of a one-robot file.
pub const DEFAULT_ROBOT_NAME: &str = "robot";

/// How a world with several robots is decided (`outcome.team`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TeamRule {
    /// A success once every robot has succeeded; a failure as soon as one fails.
    #[default]
    All,
    /// A race: a success when the first robot succeeds; a failure once every robot has failed.
    First,
}

impl TeamRule {
    /// The rule named by `outcome.team` (`"all"` or `"first"`).
    pub fn from_name(s: &str) -> Option<Self> {
        match s {
            "all" => Some(TeamRule::All),
            "first" => Some(TeamRule::First),
            _ => None,
        }
    }

    /// The rule `outcome.team` names (absent: [`TeamRule::All`]), or the problem with it.
    pub(crate) fn parse(team: Option<&str>) -> Result<Self, crate::error::SpecIssue> {
        match team {
            None => Ok(TeamRule::All),
            Some(s) => Self::from_name(s).ok_or_else(|| {
                crate::error::SpecIssue::new(
                    "outcome.team",
                    format!(
                        "unknown team rule `{}`: give \"all\" (every robot succeeds, none fails) \
                         or \"first\" (a race)",
                        crate::check::echoed(s)
                    ),
                )
            }),
        }
    }

    /// The rule's name in files.
    pub fn name(self) -> &'static str {
        match self {
            TeamRule::All => "all",
            TeamRule::First => "first",
        }
    }
}

/// One robot of a world with several, compiled: what a one-robot [`Scenario`] holds for its
/// robot.
#[derive(Clone, Debug)]
pub struct RobotModel {
    /// Its name (unique, ROS-safe).
    pub name: String,
    /// Its vehicle.
    pub vehicle: VehicleModel,
    /// Start position, m.
    pub start_xy: (f64, f64),
    /// Start height, m (None: rest on the ground).
    pub start_z: Option<f64>,
    /// Start yaw, rad.
    pub start_yaw: f64,
    /// Start pitch, rad.
    pub start_pitch: f64,
    /// Its commands, sorted by time.
    pub commands: Vec<Command>,
    /// Its outcome conditions.
    pub outcome: OutcomeModel,
    /// A drawbar load on its chassis, if any.
    pub drawbar: Option<Drawbar>,
    /// What its run must show.
    pub expect: Expectation,
}

/// The robots of a world with several, in file order, and how the world is decided.
#[derive(Clone, Debug)]
pub struct Team {
    /// Every robot, the first included (the scenario's own robot fields are the first's).
    pub robots: Vec<RobotModel>,
    /// How the world's outcome is decided.
    pub rule: TeamRule,
    /// Stop the run once the world's outcome is decided (the file's `outcome.stop`).
    pub stop: bool,
    /// What the world's run must show (`[expect]`: its outcome and outcome time).
    pub expect: Expectation,
}
