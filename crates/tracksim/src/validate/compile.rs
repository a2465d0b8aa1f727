//! A validation case written as TOML text, compiled for the validation's vehicle.

use crate::error::Result;
use crate::model::{Scenario, VehicleModel};
use std::path::Path;

/// Compiles a validation scenario written as TOML, for `vehicle`.
pub(super) fn compile(text: &str, vehicle: VehicleModel, root: &Path) -> Result<Scenario> {
    compile_with(text, vehicle, root, &crate::model::Overrides::default())
}

/// [`compile`] with `overrides` written into the text's keys (an ensemble member's).
pub(super) fn compile_with(
    text: &str,
    vehicle: VehicleModel,
    root: &Path,
    overrides: &crate::model::Overrides,
) -> Result<Scenario> {
    crate::model::compile_scenario_text(
        "<validation scenario>",
        text,
        vehicle,
        &root.join("scenarios"),
        overrides,
    )
}
