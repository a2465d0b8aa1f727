//! A validation case written as TOML text, compiled for the validation's vehicle with the
//! solver setting under test ([`SolverSetting`]) written into its keys.

use super::options::SolverSetting;
use crate::error::Result;
use crate::model::{Overrides, Scenario, VehicleModel};
use std::path::Path;

/// Compiles a validation scenario written as TOML, for `vehicle`, with `setting` written into
/// its `[simulation]` keys.
pub(super) fn compile(
    text: &str,
    vehicle: VehicleModel,
    root: &Path,
    setting: SolverSetting,
) -> Result<Scenario> {
    compile_with(text, vehicle, root, setting, &Overrides::default())
}

/// [`compile`] with `overrides` written into the text's keys too (an ensemble member's).
pub(super) fn compile_with(
    text: &str,
    vehicle: VehicleModel,
    root: &Path,
    setting: SolverSetting,
    overrides: &Overrides,
) -> Result<Scenario> {
    crate::model::compile_scenario_text(
        "<validation scenario>",
        text,
        vehicle,
        &root.join("scenarios"),
        &setting.overrides().merged(overrides),
    )
}
