//! Validation against the paper and against textbook physics (`tracksim validate`).
//!
//! Cases:
//! - **Table IV** (Okada et al. 2020): Quince (`vehicles/quince.toml`) climbs a step at 0.1 m/s,
//!   friction 0.6 everywhere, front sub-tracks at 0 deg (steps 40, 120, 190 mm) or 45 deg
//!   (120, 240, 380 mm), rear sub-tracks flat. Expected S, S, F, S, S, F. The same six cases
//!   without grousers are reported beside them (not asserted).
//! - **Slope limit**: PackBot 510 on a smooth plane, friction 0.6; the steepest slope it climbs
//!   must lie within 2 deg of atan(0.6) = 30.96 deg (Coulomb friction).
//! - **Skid steering**: PackBot 510 spinning on the spot (belts at +-v): yaw rate against the
//!   no-slip value 2v/B; driving straight: longitudinal slip 1 - v_body / v_belt.
//! - **Paper Figs. 2 and 3**: the named cases `fig2_bump` and `fig3_wall`
//!   ([`crate::cases`]), when their files are present.
//! - **Soil** (issue 30, `soil.rs`): sinkage (Bekker), drawbar pull against slip (Wong),
//!   grousers against a smooth belt, the slope limit on lunar regolith, multi-pass sinkage.
//!
//! Every run is an ordinary scenario run ([`crate::run_scenario`]) under a unique case name
//! (`table_iv/00deg_120mm/grousers_slop10`, `slope/31deg`, `turning/spin`, `fig2/okada2020`,
//! ...); they run in parallel on the machine's cores and the report looks each result up by
//! its name. The stages live in one file each under `validate/`: `table_iv.rs`, `slope.rs`,
//! `turning.rs`, `figures.rs`, `soil.rs`; the report in `report.rs`; the rubber of the
//! compliant column in `rubber.rs`. What they share sits below them, a concept per file:
//! `limits.rs` (the cases' limits and settings), `options.rs` (what to run), `jobs.rs` (the
//! runs by name, run on threads), `compile.rs` (a case written as TOML), `drawing.rs` (the
//! terrain under a side view). This file only runs them: the files import downward, never
//! `mod.rs`.

mod accuracy;
mod compile;
mod drawing;
mod figures;
mod jobs;
mod limits;
mod options;
mod report;
mod rubber;
mod slope;
mod soil;
mod table_iv;
mod turning;

pub use accuracy::{
    REFERENCE_DT_S, REFERENCE_ITERATIONS, SLOPE_MU, STEP_HEIGHTS_M, STEP_HEIGHTS_NO_GROUSERS_M,
    TETHER_MU,
};
pub use limits::{
    PACKBOT_SPEED_MPS, QUINCE_MIN_LINK_MASS_KG, QUINCE_SOLVER_ITERATIONS, SLOPE_ANGLES_DEG,
    SLOPE_LIMIT_DEG, SLOPE_TOLERANCE_DEG, STEP_DEPTH_M, STEP_DURATION_S, STEP_EDGE_X_M,
    STEP_ON_TOP_Z_M, STEP_SPEED_MPS, STEP_SUCCESS_MARGIN_M, STRAIGHT_SLIP_LIMIT,
    TABLE_IV_CONTACT_SLOP_M, TURN_RATIO_BAND,
};
pub use options::{Group, SolverSetting, ValidationOptions};

pub use report::{Case, RubberNote, SlopeRun, StepCase, StepRun, ValidationReport};
pub use rubber::{
    TRACK_RUBBER_LOSS_FACTOR, TRACK_RUBBER_POISSON, TRACK_RUBBER_YOUNGS_MODULUS_PA,
    rubber_compliance, rubber_compliance_with, with_rubber, with_rubber_of,
};
pub use table_iv::{quince_step_scenario, quince_step_text};
pub use turning::spin_ratio_coulomb;

use crate::error::Result;
use crate::model::Method as TrackMethod;
use crate::model::load_vehicle;
use jobs::Jobs;
use std::path::Path;
use std::sync::atomic::Ordering;
use std::time::Instant;

/// Runs every validation case with the track method `method` (the Table IV column "with
/// grousers", the slope, turning and paper-figure cases). `root` is the folder holding
/// `vehicles/` and `scenarios/`. `progress` receives one line per finished run.
pub fn run_validation(
    root: &Path,
    method: TrackMethod,
    progress: impl FnMut(&str),
) -> Result<ValidationReport> {
    run_validation_with(root, method, ValidationOptions::default(), progress)
}

/// [`run_validation`] with options.
pub fn run_validation_with(
    root: &Path,
    method: TrackMethod,
    opts: ValidationOptions,
    mut progress: impl FnMut(&str),
) -> Result<ValidationReport> {
    let wall = Instant::now();
    let quince = load_vehicle(&root.join("vehicles/quince.toml"))?;
    let packbot = load_vehicle(&root.join("vehicles/packbot510.toml"))?;

    // `--only` picks one group; `--accuracy` the suite of issue 58 (Table IV, slope, turning
    // and the accuracy rows); by default every group but the accuracy rows.
    let on = |g: Group| match (opts.only, opts.accuracy) {
        (Some(o), _) => o == g,
        (None, true) => matches!(
            g,
            Group::TableIv | Group::Slope | Group::Turning | Group::Accuracy
        ),
        (None, false) => g != Group::Accuracy,
    };
    let mut jobs = Jobs::default();
    if on(Group::TableIv) {
        table_iv::add_jobs(&mut jobs, &quince, method, opts, root)?;
    }
    if on(Group::Slope) {
        slope::add_jobs(&mut jobs, &packbot, method, root, opts.setting)?;
    }
    if on(Group::Turning) {
        turning::add_jobs(&mut jobs, &packbot, method, root, opts.setting)?;
    }
    if on(Group::Figures) {
        figures::add_jobs(&mut jobs, method, root, opts.setting)?;
    }
    if on(Group::Soil) {
        soil::add_jobs(&mut jobs, &packbot, root, opts.setting)?;
    }
    if on(Group::Accuracy) {
        accuracy::add_jobs(&mut jobs, &packbot, method, root, opts.setting)?;
    }

    let mut runs = jobs.run(opts.stop, &mut progress);

    let mut report = ValidationReport::new(method);
    if on(Group::TableIv) {
        table_iv::assemble(&mut report, &jobs, &mut runs, method, opts);
        if opts.compliant_grousers {
            report.rubber = Some(rubber::note(&quince, opts.rubber_youngs_modulus_pa));
        }
    }
    if on(Group::Slope) {
        slope::assemble(&mut report, &mut runs);
    }
    if on(Group::Turning) {
        turning::assemble(&mut report, &mut runs, &packbot, method);
    }
    if on(Group::Figures) {
        figures::assemble(&mut report, &jobs, &mut runs, method);
    }
    if on(Group::Soil) {
        soil::assemble(&mut report, &mut runs, &packbot);
    }
    if on(Group::Accuracy) {
        accuracy::assemble(&mut report, &mut runs, &packbot);
    }
    report.setting = opts.setting.words();
    report.wall_time_s = wall.elapsed().as_secs_f64();
    report.interrupted = opts.stop.is_some_and(|s| s.load(Ordering::SeqCst));
    Ok(report)
}
