//! The compiled scenario: vehicle, start pose, terrain, solver settings, commands and outcome
//! conditions ([`Scenario`] sealing its [`ScenarioData`], [`SolverSettings`],
//! [`OutcomeModel`]).

use super::outcome::OutcomeModel;
use super::{Command, VehicleModel};
use crate::terrain::TerrainModel;
use std::path::PathBuf;

/// Solver settings.
#[derive(Clone, Debug)]
pub struct SolverSettings {
    /// Time step, s.
    pub dt: f64,
    /// Solver iterations.
    pub iterations: usize,
    /// Position-correction passes per solver iteration (Rapier's default 1).
    pub stabilization_iterations: usize,
    /// Share of the last step's impulses the solver starts from, (0, 1] (Rapier's
    /// `warmstart_coefficient`).
    pub warmstart: f64,
    /// Contact clustering on or off.
    pub contact_clustering: bool,
    /// Smallest segment link mass, kg.
    pub min_link_mass: f64,
    /// Speculative contact distance, m.
    pub prediction_distance: f64,
    /// Uncorrected vehicle-terrain penetration (ODE's `min_depth`), m; 0 = rigid contact.
    pub contact_slop: f64,
    /// While every belt is held, friction also acts in Rapier's position-correction (bias)
    /// pass: without it a braked vehicle creeps down a slope well inside the friction cone
    /// (docs/DESIGN.md).
    pub held_friction_in_bias_pass: bool,
    /// Rapier's contact recycling (`simulation.contact_recycling`).
    pub contact_recycling: bool,
    /// The floating origin (`simulation.floating_origin`).
    pub floating_origin: bool,
    /// Inert colliders inserted before the terrain (`simulation.order_salt`): the solver's
    /// order changes, nothing physical does.
    pub order_salt: usize,
    /// Damping ratio of the terrain's contacts (`simulation.terrain_contact_damping_ratio`;
    /// None: Rapier's 10, or what the track method sets).
    pub terrain_contact_damping_ratio: Option<f64>,
    /// Speculative contact manifolds with the ground that cannot act in a step are not solved
    /// (`simulation.cull_speculative_contacts`, issue 44).
    pub cull_speculative_contacts: bool,
}

impl Default for SolverSettings {
    fn default() -> Self {
        SolverSettings {
            dt: 0.001,
            iterations: 4,
            stabilization_iterations: 2,
            warmstart: 1.0,
            contact_clustering: false,
            min_link_mass: MIN_LINK_MASS_KG,
            prediction_distance: 0.02,
            contact_slop: crate::spec::DEFAULT_CONTACT_SLOP_M,
            held_friction_in_bias_pass: true,
            contact_recycling: true,
            floating_origin: true,
            order_salt: 0,
            terrain_contact_damping_ratio: None,
            cull_speculative_contacts: false,
        }
    }
}

/// Default smallest mass given to a segment link or wheel body, kg. 0.5 kg until issue 23: it
/// halved the per-step joint error of the PackBot's links on a step (0.8 against 1.5 mm,
/// snapped out every step), but since the floor is paid for out of the chassis it moved 2 kg of
/// the PackBot's 11 kg body into its belts, and with links that heavy the solver's unconverged
/// left/right coupling turned into a steady yaw: 2.7 % lateral drift over a 10-minute straight
/// drive (0.25 % at 0.1 kg), and the flipper PackBot stalled on the stairs. At 0.1 kg the
/// bundled vehicles' links carry the belt mass their files give (docs/DESIGN.md).
pub const MIN_LINK_MASS_KG: f64 = 0.1;

/// A compiled scenario, immutable after compile (issue 39): it reads as its [`ScenarioData`]
/// (`sc.vehicle`, `sc.solver.dt`, through [`Deref`](std::ops::Deref)) but only `model/` builds
/// or changes one. A variation of a file (another method, duration, solver order, start, ...) is
/// written into the file's keys before compiling, through [`super::Overrides`] or by editing
/// the [`crate::spec::ScenarioSpec`], so it is checked like the file's own values.
///
/// Outside `model/` a field cannot be assigned (there is no `DerefMut`), nor a field's value
/// changed through a method:
/// ```compile_fail,E0594
/// # fn f(sc: &mut tracksim::Scenario) {
/// sc.duration = 1.0;
/// # }
/// ```
/// ```compile_fail,E0596
/// # fn f(sc: &mut tracksim::Scenario) {
/// sc.commands.clear();
/// # }
/// ```
/// and a [`ScenarioData`] copied out and changed does not become a `Scenario` again:
/// ```compile_fail,E0423
/// # fn f(sc: &tracksim::Scenario) {
/// let mut data: tracksim::model::ScenarioData = (**sc).clone();
/// data.duration = 1.0;
/// let sc = tracksim::Scenario(data);
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct Scenario(pub(super) ScenarioData);

impl std::ops::Deref for Scenario {
    type Target = ScenarioData;

    fn deref(&self) -> &ScenarioData {
        &self.0
    }
}

/// What a compiled [`Scenario`] holds: read through it, never changed outside `model/`.
#[derive(Clone, Debug)]
pub struct ScenarioData {
    /// Where it was read from, if from a file.
    pub source: Option<PathBuf>,
    /// Description.
    pub description: String,
    /// The vehicle.
    pub vehicle: VehicleModel,
    /// Start position (x, y, optional z), m.
    pub start_xy: (f64, f64),
    /// Start height, m (None: rest on the ground).
    pub start_z: Option<f64>,
    /// Start yaw, rad.
    pub start_yaw: f64,
    /// Start pitch, rad.
    pub start_pitch: f64,
    /// The world.
    pub terrain: TerrainModel,
    /// Conveyors (`[[terrain.conveyors]]`).
    pub conveyors: Vec<super::ConveyorModel>,
    /// Loose boxes (`[[terrain.loose_boxes]]`).
    pub loose_boxes: Vec<super::LooseBoxModel>,
    /// Solver.
    pub solver: SolverSettings,
    /// Duration, s.
    pub duration: f64,
    /// Output interval, s.
    pub output_interval: f64,
    /// Commands, sorted by time.
    pub commands: Vec<Command>,
    /// Outcome conditions.
    pub outcome: OutcomeModel,
    /// What a run must show (`[expect]`; empty: nothing checked).
    pub expect: super::Expectation,
    /// The operator-training course (`[course]`), if any: scored by the run layer.
    pub course: Option<super::CourseModel>,
    /// A drawbar load on the chassis (`[drawbar]`), if any.
    pub drawbar: Option<super::Drawbar>,
    /// Track method (`simulation.method`).
    pub method: super::Method,
    /// The keys a caller's [`super::Overrides`] set over the file's values (e.g.
    /// `simulation.method`); empty for a file run as it is. A run of an overridden scenario is
    /// not checked against the file's `[expect]` table.
    pub overridden: Vec<String>,
    /// Seed.
    pub seed: u64,
    /// Write `run.mcap` whatever the front end asks for (`[output] mcap`).
    pub record_mcap: bool,
    /// The values drawn for the file's `[randomize]` parameters, by name, in the units of their
    /// keys (empty for a scenario without `[randomize]`).
    pub randomized: std::collections::BTreeMap<String, f64>,
    /// Several robots in one world (`[[vehicles]]`): every robot, the rule deciding the world
    /// and its `[expect]`; `None` for a one-robot file. The robot fields above (`vehicle`,
    /// `start_*`, `commands`, `outcome`, `drawbar`, `expect`) are then the first robot's.
    pub team: Option<Box<super::Team>>,
}
