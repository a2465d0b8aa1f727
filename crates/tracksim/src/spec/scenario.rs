//! Scenario files (`scenarios/*.toml`): which vehicle and where it starts, the time stepping
//! and solver settings, timed drive commands and the outcome conditions, with their serde
//! defaults. The `[terrain]` table is [`super::TerrainSpec`]. Unknown keys are rejected; units
//! are SI unless the key name says otherwise (`yaw_deg`).

use super::terrain::TerrainSpec;
use super::vehicle::{ComplianceSpec, VehicleSpec};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A scenario file (`scenarios/*.toml`).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ScenarioSpec {
    /// One-line description.
    #[serde(default)]
    pub description: String,
    /// Which vehicle, and where it starts (a one-robot file; absent when `[[vehicles]]` lists
    /// several robots).
    #[serde(default)]
    pub vehicle: VehicleRefSpec,
    /// Several robots in one world (`[[vehicles]]`, issue 40): each with a name, its vehicle
    /// and start pose, its own commands, outcome and `[expect]`. Empty: the file's one robot is
    /// `[vehicle]`.
    #[serde(default)]
    pub vehicles: Vec<RobotSpec>,
    /// The world.
    #[serde(default)]
    pub terrain: TerrainSpec,
    /// Time stepping and solver.
    #[serde(default)]
    pub simulation: SimulationSpec,
    /// Timed drive commands; each holds until the next.
    #[serde(default)]
    pub commands: Vec<CommandSpec>,
    /// Success and failure conditions.
    #[serde(default)]
    pub outcome: OutcomeSpec,
    /// Randomised parameters by name, sampled from the run's seed (empty: a fixed scenario).
    #[serde(default)]
    pub randomize: BTreeMap<String, super::randomize::RandomParamSpec>,
    /// A drawbar load on the chassis (`[drawbar]`): the classic drawbar-pull test.
    #[serde(default)]
    pub drawbar: Option<DrawbarSpec>,
    /// What a run must show (`[expect]`): checked by `run` and the bundled-scenario test, no
    /// effect on the simulation.
    #[serde(default)]
    pub expect: super::ExpectSpec,
    /// An operator-training course (`[course]`): scored by every front end, no effect on the
    /// simulation.
    #[serde(default)]
    pub course: Option<super::CourseSpec>,
    /// Optional outputs (`[output]`) every front end writes for this scenario; no effect on
    /// the simulation.
    #[serde(default)]
    pub output: OutputSpec,
}

/// Optional outputs (`[output]`): written by every front end that writes a run (`run`,
/// `drive`, `compare`, `sweep`), on top of what it asks for.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Also write `run.mcap`, the run as a ROS 2 recording (default false; `tracksim run
    /// --mcap` asks for it for one run).
    #[serde(default)]
    pub mcap: bool,
}

/// A drawbar load (`[drawbar]`): a horizontal pull on a hitch of the chassis, backwards along
/// the vehicle's start heading, as a dynamometer car or a tether over a pulley with a weight
/// applies it. Exactly one of `pull_n` (a constant pull) and `stiffness_n_per_m` (a tether on a
/// spring anchored where the hitch started: the pull grows with the distance driven) is given.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DrawbarSpec {
    /// Constant pull, N (>= 0).
    #[serde(default)]
    pub pull_n: Option<f64>,
    /// Spring rate of the tether, N/m (> 0): pull = rate x distance the hitch moved forwards
    /// (never a push: a slack tether pulls nothing).
    #[serde(default)]
    pub stiffness_n_per_m: Option<f64>,
    /// Hitch point in the chassis frame, m (default: the chassis frame's origin).
    #[serde(default)]
    pub hitch_m: [f64; 3],
    /// Time the pull starts, s (default 0).
    #[serde(default)]
    pub start_s: f64,
    /// The pull rises linearly over this time from `start_s`, s (default 0: at once).
    #[serde(default)]
    pub ramp_s: f64,
}

/// One robot of a world with several (`[[vehicles]]`): the keys a one-robot file has at its
/// top level for its robot (`[vehicle]`, `[[commands]]`, `[outcome]`, `[drawbar]`,
/// `[expect]`), under the robot's name.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RobotSpec {
    /// The robot's name: unique in the file, ROS-safe (a lower-case letter, then lower-case
    /// letters, digits or `_`); it names its outputs, topics and frames.
    pub name: String,
    /// Which vehicle, and where it starts (the keys of a one-robot file's `[vehicle]`).
    pub vehicle: VehicleRefSpec,
    /// Its timed drive commands; each holds until the next.
    #[serde(default)]
    pub commands: Vec<CommandSpec>,
    /// Its success and failure conditions (default: the file's `[outcome]`).
    #[serde(default)]
    pub outcome: Option<OutcomeSpec>,
    /// A drawbar load on its chassis.
    #[serde(default)]
    pub drawbar: Option<DrawbarSpec>,
    /// What its run must show (checked by `run`).
    #[serde(default)]
    pub expect: super::ExpectSpec,
}

/// The vehicle of a scenario.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct VehicleRefSpec {
    /// Vehicle file, relative to the scenario file (give this or `inline`).
    #[serde(default)]
    pub file: Option<String>,
    /// The vehicle described in the scenario itself (same keys as a vehicle file).
    #[serde(default)]
    pub inline: Option<Box<VehicleSpec>>,
    /// Start x, m.
    #[serde(default)]
    pub x_m: f64,
    /// Start y, m.
    #[serde(default)]
    pub y_m: f64,
    /// Start height of the body frame, m. Default: lowest point 1 mm above the ground.
    #[serde(default)]
    pub z_m: Option<f64>,
    /// Start heading, degrees.
    #[serde(default)]
    pub yaw_deg: f64,
    /// Start pitch, degrees (positive: nose down, REP 103).
    #[serde(default)]
    pub pitch_deg: f64,
    /// Override the friction of every track.
    #[serde(default)]
    pub track_friction: Option<f64>,
    /// Override the grouser count of every track that has grousers (0 removes them).
    #[serde(default)]
    pub grouser_count: Option<usize>,
    /// Override the body mass, kg.
    #[serde(default)]
    pub body_mass_kg: Option<f64>,
    /// Override the belt mass of every track, kg.
    #[serde(default)]
    pub belt_mass_kg: Option<f64>,
    /// Override the contact compliance of every track (`[vehicle.compliance]`, the same keys
    /// as a vehicle file's `[tracks.compliance]`).
    #[serde(default)]
    pub compliance: Option<ComplianceSpec>,
}

/// When a run counts as a success or a failure, and whether it stops there.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct OutcomeSpec {
    /// Success when the body's x passes this value, m.
    #[serde(default)]
    pub success_x_m: Option<f64>,
    /// Success when the body's z reaches this value, m.
    #[serde(default)]
    pub success_z_m: Option<f64>,
    /// Failure (tip-over) when |roll| or |pitch| exceeds this, degrees.
    #[serde(default = "default_max_tilt")]
    pub max_tilt_deg: f64,
    /// Failure when the body leaves the terrain's extent (only for bounded terrains).
    #[serde(default = "default_true")]
    pub fail_off_terrain: bool,
    /// Stop the run as soon as the outcome is decided.
    #[serde(default = "default_true")]
    pub stop: bool,
    /// With several robots (`[[vehicles]]`), when the scenario is decided: `"all"` (default:
    /// a success once every robot has succeeded, a failure as soon as one fails, e.g. tips
    /// over) or `"first"` (a race: a success when the first robot succeeds, a failure once
    /// every robot has failed).
    #[serde(default)]
    pub team: Option<String>,
}

impl Default for OutcomeSpec {
    fn default() -> Self {
        OutcomeSpec {
            success_x_m: None,
            success_z_m: None,
            max_tilt_deg: default_max_tilt(),
            fail_off_terrain: true,
            stop: true,
            team: None,
        }
    }
}

fn default_max_tilt() -> f64 {
    75.0
}
fn default_true() -> bool {
    true
}

/// Time stepping and the solver settings that matter.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SimulationSpec {
    /// Time step, s.
    #[serde(default = "default_dt")]
    pub dt_s: f64,
    /// Simulated duration, s.
    #[serde(default = "default_duration")]
    pub duration_s: f64,
    /// Interval between trajectory rows, s.
    #[serde(default = "default_output_interval")]
    pub output_interval_s: f64,
    /// Solver iterations per step.
    #[serde(default = "default_iterations")]
    pub solver_iterations: usize,
    /// Position-correction (stabilization) passes per solver iteration (Rapier's
    /// `num_internal_stabilization_iterations`, default 2): the pass that pushes penetrations
    /// and joint errors out. Quince's Table IV climbs need 2 at 4 solver iterations, or 8
    /// solver iterations (BENCHMARKS.md, issue 16.6). With 1 a rigid vehicle's contacts can
    /// fall into a rocking at half the step rate whose phase depends on the start position
    /// (issue 38: yaw rates of a turn 0.430-0.445 rad/s by start x; 2: 0.428-0.437 over 41
    /// starts, the load share the solver order sets: docs/DESIGN.md).
    #[serde(default = "default_stabilization")]
    pub stabilization_iterations: usize,
    /// Share of the last step's contact and joint impulses the solver starts from (Rapier's
    /// `warmstart_coefficient`, default its 1). Issue 58: at 1 a PackBot tethered near the
    /// friction limit of friction 0.9 or 1.0 ground spins up within 4 s (the friction impulse
    /// carried over whole from the last step keeps its direction while the slip turns); at 0.8
    /// it is held at every friction and the whole accuracy suite passes at 1 ms and 4
    /// iterations, but at least 12 of the calibrated tests move (docs/ACCURACY.md): not yet the
    /// default.
    #[serde(default = "default_warmstart")]
    pub warmstart_coefficient: f64,
    /// Rapier contact clustering (merges coplanar contacts of compound shapes).
    #[serde(default)]
    pub contact_clustering: bool,
    /// Smallest mass of a track segment link, kg (light links hop under a heavy body).
    #[serde(default = "default_min_link_mass")]
    pub min_link_mass_kg: f64,
    /// Distance within which Rapier creates speculative contacts, m (Rapier's default 0.02).
    #[serde(default = "default_prediction")]
    pub prediction_distance_m: f64,
    /// Penetration of the vehicle (belts, grousers, wheels, plates, chassis) into the terrain
    /// that is left uncorrected, whatever the track method, m:
    /// ODE's `min_depth`, which the paper's simulator set to 0.01 to let grousers sink "to make
    /// contact more stable". 0 (the default) keeps Rapier's rigid contact: every penetration is
    /// pushed out. The bundled stairs set 0.001 (issue 38): with rigid contact the position
    /// correction kicked the grousers resting on the nosings into a chatter that stalled the
    /// climb for seconds in 3 of 16 perturbed starts; with 1 mm all 16 climb within 0.16 s
    /// (docs/ENSEMBLE.md). Not the default: on flat ground and parked on slopes 1 mm of slop
    /// broke the mirror symmetry and the braked hold (docs/DESIGN.md).
    #[serde(default = "default_contact_slop")]
    pub contact_slop_m: f64,
    /// While every belt is held at 0 m/s and the chassis is at rest (static friction), friction also acts in Rapier's
    /// position-correction (bias) pass (default true). Without it that pass, which pushes out
    /// penetrations and joint errors, moves the bodies with no friction: a braked PackBot on a
    /// 20 deg slope creeps 0.2 mm/s sideways and turns 0.02 deg/s. Not used while driving: there
    /// it drags (3-5 % lower speed on flat ground, docs/DESIGN.md).
    #[serde(default = "default_true")]
    pub held_friction_in_bias_pass: bool,
    /// Rapier's contact recycling (default true): a contact pair whose relative pose moved
    /// less than 5 cm since its last full update keeps its contacts, with anchors and normal
    /// frozen in world space (up to 11 deg of rotation of either body).
    #[serde(default = "default_true")]
    pub contact_recycling: bool,
    /// Keep the f32 Rapier world near the vehicle by whole-metre shifts (default true; see
    /// `world/origin.rs`). Off only to compare: far from the origin f32 rounding biases speeds.
    #[serde(default = "default_true")]
    pub floating_origin: bool,
    /// Inert colliders inserted before the terrain (default 0): they touch nothing, but shift
    /// Rapier's handles and broad-phase tree and so the order its solver visits contacts. Only
    /// the ensemble's perturbation of the solver order (docs/ENSEMBLE.md) sets it; a member's
    /// run is reproduced with its value.
    #[serde(default)]
    pub order_salt: usize,
    /// Damping ratio of the contacts with the terrain (Rapier's `static_contact_softness`, a
    /// spring of 60 Hz per contact; default: Rapier's 10, heavily overdamped). A rigid track on
    /// rigid ground carries its load in a statically indeterminate share along its length;
    /// overdamped contacts keep the share the solver's contact order set at the start, so a
    /// skid-steer turn's rate depends on the start position by up to 2.1 %; critically damped
    /// (1) the share settles and the spread is 0.23 % (issue 38, docs/DESIGN.md *The turn*).
    /// Not the default: the validated figures (Table IV, the drawbar's slip, soil) were
    /// measured with Rapier's.
    #[serde(default)]
    pub terrain_contact_damping_ratio: Option<f64>,
    /// A speculative contact manifold between the vehicle and the fixed ground that cannot act
    /// in a step (every point more than 3 mm plus twice its closing in a step apart, and no
    /// impulse carried from earlier steps) is not solved (issue 44,
    /// `world/speculative_cull.rs`). Only contacts that go through the contact hook anyway (a
    /// contact slop, compliance, a friction patch; not soil) are culled. The solver would give
    /// them no impulse (checked over whole runs), but the changed order of its visits moves
    /// trajectories at f32 rounding, and that flips verdicts that are coin tosses. So it is
    /// off by default and the bundled stairs, which climb 16 of 16 perturbed starts either
    /// way, turn it on: ~18 % less CPU time (docs/DESIGN.md, BENCHMARKS.md).
    #[serde(default)]
    pub cull_speculative_contacts: bool,
    /// Track method: "okada2020" (the paper's segment links with grousers).
    #[serde(default = "default_method")]
    pub method: String,
    /// Seed recorded with the run (`summary.json`); random terrain generators take their own
    /// `seed` keys. The simulation itself is deterministic.
    #[serde(default)]
    pub seed: u64,
}

fn default_contact_slop() -> f64 {
    DEFAULT_CONTACT_SLOP_M
}

/// Default `simulation.contact_slop_m`, m.
pub const DEFAULT_CONTACT_SLOP_M: f64 = 0.0;

fn default_prediction() -> f64 {
    0.02
}

fn default_method() -> String {
    "okada2020".into()
}

impl Default for SimulationSpec {
    fn default() -> Self {
        SimulationSpec {
            dt_s: default_dt(),
            duration_s: default_duration(),
            output_interval_s: default_output_interval(),
            solver_iterations: default_iterations(),
            stabilization_iterations: default_stabilization(),
            warmstart_coefficient: default_warmstart(),
            contact_clustering: false,
            min_link_mass_kg: default_min_link_mass(),
            prediction_distance_m: default_prediction(),
            contact_slop_m: default_contact_slop(),
            held_friction_in_bias_pass: true,
            contact_recycling: true,
            floating_origin: true,
            order_salt: 0,
            terrain_contact_damping_ratio: None,
            cull_speculative_contacts: false,
            method: default_method(),
            seed: 0,
        }
    }
}

fn default_stabilization() -> usize {
    2
}

fn default_warmstart() -> f64 {
    1.0
}

/// `model::MIN_LINK_MASS_KG` (this layer imports nothing; the model's doc says why 0.1 kg).
fn default_min_link_mass() -> f64 {
    0.1
}

fn default_dt() -> f64 {
    0.001
}
fn default_duration() -> f64 {
    10.0
}
fn default_output_interval() -> f64 {
    0.01
}
fn default_iterations() -> usize {
    4
}

/// Per-track values: one number for every track, or a table by track name.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(
    untagged,
    expecting = "a number (the same for every track) or a table of track name = number"
)]
pub enum PerTrack {
    /// The same value for every track.
    All(f64),
    /// Values by track name.
    ByName(BTreeMap<String, f64>),
}

/// A drive command that starts at `t_s` and holds until the next one.
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CommandSpec {
    /// Start time, s.
    #[serde(default)]
    pub t_s: f64,
    /// Belt speeds, m/s (positive drives forwards).
    #[serde(default)]
    pub belt_speed_mps: Option<PerTrack>,
    /// Sprocket angular speeds, rad/s (needs `sprocket_pitch_radius_m` on the track).
    #[serde(default)]
    pub sprocket_rad_s: Option<PerTrack>,
    /// Flipper target angles by flipper name, degrees.
    #[serde(default)]
    pub flipper_angle_deg: BTreeMap<String, f64>,
    /// Body-level command: forward speed, m/s (with `yaw_rate_rad_s`, turned into belt speeds
    /// by skid-steer kinematics: v_track = v - yaw_rate * y_track, or one speed per side with
    /// the vehicle's `[steering] one_speed_per_side`).
    #[serde(default)]
    pub forward_mps: Option<f64>,
    /// Body-level command: yaw rate, rad/s (positive turns left).
    #[serde(default)]
    pub yaw_rate_rad_s: Option<f64>,
    /// Motor duty cycle in [-1, 1] (tracks with `[tracks.motor]`): the driver applies this
    /// fraction of the supply, so the motor follows its torque-speed line scaled by it.
    #[serde(default)]
    pub motor_duty: Option<PerTrack>,
    /// Motor torque at the shaft, N m (tracks with `[tracks.motor]`): a current-controlled
    /// driver delivers it whatever the speed, within the torque-speed curve and its limit.
    #[serde(default)]
    pub motor_torque_nm: Option<PerTrack>,
    /// Faults set or cleared at this time (`fault`, issue 43: an instructor's injection):
    /// tracks stopped or unpowered, flippers jammed, latency, the video dropped.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fault: Option<super::FaultSpec>,
    /// `true`: the robot is put back at its start at this time, before the entry's controls
    /// (issue 43: the instructor's reset of one robot of several; its bodies, joints, belts,
    /// odometry and faults as at the start, its controls zeroed), while the clock and the other
    /// robots go on.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reset: Option<bool>,
}
