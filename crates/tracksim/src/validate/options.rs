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
}

impl Group {
    /// The names `--only` accepts.
    pub const NAMES: [&'static str; 5] = ["table_iv", "slope", "turning", "figures", "soil"];

    /// The group named `name`.
    pub fn from_name(name: &str) -> Option<Group> {
        Some(match name {
            "table_iv" => Group::TableIv,
            "slope" => Group::Slope,
            "turning" => Group::Turning,
            "figures" => Group::Figures,
            "soil" => Group::Soil,
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
        }
    }
}
