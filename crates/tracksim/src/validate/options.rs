//! Which parts of the validation run ([`ValidationOptions`], [`Group`]).

use super::rubber::TRACK_RUBBER_YOUNGS_MODULUS_PA;

/// Which optional parts of the validation to run.
#[derive(Clone, Copy, Debug)]
pub struct ValidationOptions {
    /// Also run the six Table IV cases without grousers (reported, not asserted).
    pub without_grousers: bool,
    /// Also run the six Table IV cases with grousers and rigid contact (reported, not asserted).
    pub rigid_contact: bool,
    /// Also run the six Table IV cases with compliant grousers and belts (rubber, see
    /// [`super::rubber::rubber_compliance`]), rigid terrain and no slop (reported, not asserted).
    pub compliant_grousers: bool,
    /// Young's modulus of the track rubber in the compliant column, Pa (default
    /// [`TRACK_RUBBER_YOUNGS_MODULUS_PA`]).
    pub rubber_youngs_modulus_pa: f64,
    /// When set (by a Ctrl-C or SIGTERM handler), the runs stop at their next step and the
    /// runs not started are skipped; the report is marked interrupted.
    pub stop: Option<&'static std::sync::atomic::AtomicBool>,
    /// Only this group of cases (None: every group).
    pub only: Option<Group>,
    /// Members of an ensemble per Table IV row with grousers (0: none; docs/ENSEMBLE.md):
    /// member 0 is the asserted run, the others perturbed as `tracksim run --ensemble`; the
    /// row reports "S 8/8" or "marginal 5/8" (reported, the nominal run stays the asserted one).
    pub ensemble: usize,
    /// The accuracy suite (issue 58): Table IV, slope, turning and the accuracy rows.
    pub accuracy: bool,
    /// The solver setting every case runs at (None in a field: each case's file's own value).
    pub setting: SolverSetting,
}

/// A solver setting written into every validation case's `[simulation]` keys (`tracksim
/// validate --dt S --iterations N --stabilization-iterations N`): the accuracy suite asks how
/// accurate a setting is. A field left `None` keeps each case's own value (the Table IV cases
/// run Quince at 8 solver iterations, the others at the default 4).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SolverSetting {
    /// Time step, s (`simulation.dt_s`).
    pub dt_s: Option<f64>,
    /// Solver iterations (`simulation.solver_iterations`).
    pub iterations: Option<usize>,
    /// Position-correction passes (`simulation.stabilization_iterations`).
    pub stabilization: Option<usize>,
    /// Share of the last step's impulses the solver starts from
    /// (`simulation.warmstart_coefficient`).
    pub warmstart: Option<f64>,
}

impl SolverSetting {
    /// The setting as overrides of a scenario file's keys.
    pub fn overrides(&self) -> crate::model::Overrides {
        crate::model::Overrides {
            dt_s: self.dt_s,
            solver_iterations: self.iterations,
            stabilization_iterations: self.stabilization,
            warmstart_coefficient: self.warmstart,
            ..Default::default()
        }
    }

    /// The setting in words, e.g. "dt 4 ms, 8 iterations, each file's stabilization".
    pub fn words(&self) -> String {
        let dt = self
            .dt_s
            .map_or("each file's dt".into(), |d| format!("dt {} ms", d * 1e3));
        let it = self
            .iterations
            .map_or("each file's iterations".into(), |n| {
                format!("{n} iterations")
            });
        let st = self
            .stabilization
            .map_or("each file's stabilization passes".into(), |n| {
                format!("{n} stabilization passes")
            });
        let ws = self.warmstart.map_or("each file's warm start".into(), |w| {
            format!("warm start {w}")
        });
        format!("{dt}, {it}, {st}, {ws}")
    }
}

/// A group of validation cases (`tracksim validate --only GROUP`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Group {
    /// The paper's Table IV (Quince steps).
    TableIv,
    /// The slope limit on a rigid plate.
    Slope,
    /// Skid steering.
    Turning,
    /// The paper's Figs. 2 and 3.
    Figures,
    /// Deformable soil against terramechanics.
    Soil,
    /// The accuracy rows of issue 58 (`accuracy.rs`): tether and drawbar at friction 0.3-1.0,
    /// slope limits against atan(mu), the step-climb limit, long drives, invariances.
    Accuracy,
}

impl Group {
    /// The names `--only` accepts.
    pub const NAMES: [&'static str; 6] = [
        "table_iv", "slope", "turning", "figures", "soil", "accuracy",
    ];

    /// The group named `name`.
    pub fn from_name(name: &str) -> Option<Group> {
        Some(match name {
            "table_iv" => Group::TableIv,
            "slope" => Group::Slope,
            "turning" => Group::Turning,
            "figures" => Group::Figures,
            "soil" => Group::Soil,
            "accuracy" => Group::Accuracy,
            _ => return None,
        })
    }
}

impl Default for ValidationOptions {
    fn default() -> Self {
        ValidationOptions {
            without_grousers: true,
            rigid_contact: true,
            compliant_grousers: true,
            rubber_youngs_modulus_pa: TRACK_RUBBER_YOUNGS_MODULUS_PA,
            stop: None,
            only: None,
            ensemble: 0,
            accuracy: false,
            setting: SolverSetting::default(),
        }
    }
}
