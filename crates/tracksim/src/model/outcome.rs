//! A robot's success and failure conditions, compiled ([`OutcomeModel`], `[outcome]`).

/// Success and failure conditions, compiled.
#[derive(Clone, Debug)]
pub struct OutcomeModel {
    /// Success when body x passes this, m.
    pub success_x: Option<f64>,
    /// Success when body z reaches this, m.
    pub success_z: Option<f64>,
    /// Tip-over limit on |roll| and |pitch|, rad.
    pub max_tilt: f64,
    /// Fail when leaving a bounded terrain.
    pub fail_off_terrain: bool,
    /// Stop when decided.
    pub stop: bool,
}
