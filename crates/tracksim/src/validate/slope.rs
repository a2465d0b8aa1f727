//! The slope limit: PackBot 510 on smooth plates at [`SLOPE_ANGLES_DEG`], one run each,
//! named `slope/<angle>deg`.

use super::compile::compile;
use super::jobs::{Jobs, Ran, Runs, pose_at};
use super::limits::{PACKBOT_SPEED_MPS, SLOPE_ANGLES_DEG, SLOPE_LIMIT_DEG, SLOPE_TOLERANCE_DEG};
use super::options::SolverSetting;
use super::report::{Case, PlotJob, SlopeRun, ValidationReport};
use crate::error::Result;
use crate::model::Method as TrackMethod;
use crate::model::{Scenario, VehicleModel};
use crate::output::SideLine;
use crate::run::RunResult;
use std::path::Path;

const SLOPE_SETTLE_S: f64 = 1.0;
const SLOPE_MEASURE_S: f64 = 3.0;

/// `slope/31deg`: the case name of the run at `deg`.
fn case_name(deg: f64) -> String {
    format!("slope/{deg:.0}deg")
}

/// Adds one run per slope angle.
pub(super) fn add_jobs(
    jobs: &mut Jobs,
    packbot: &VehicleModel,
    method: TrackMethod,
    root: &Path,
    setting: SolverSetting,
) -> Result<()> {
    for &deg in &SLOPE_ANGLES_DEG {
        jobs.add(
            case_name(deg),
            slope_scenario(packbot, deg, method, root, setting)?,
        )?;
    }
    Ok(())
}

/// Fills `report.slope_runs`, the slope-limit case and the slope plot.
pub(super) fn assemble(report: &mut ValidationReport, runs: &mut Runs) {
    let mut plot_runs = Vec::new();
    let mut lines = Vec::new();
    for &deg in &SLOPE_ANGLES_DEG {
        let name = case_name(deg);
        let (run, plotted) = measure(&name, deg, runs.take(&name));
        report.slope_runs.push(run);
        if let Some((label, r, line)) = plotted {
            plot_runs.push((label, r));
            lines.push(line);
        }
    }
    report.cases.push(limit_case(&report.slope_runs));
    if !plot_runs.is_empty() {
        report.plots.push(PlotJob {
            stem: "slope".into(),
            title: "PackBot 510 on smooth slopes, friction 0.6 (limit atan 0.6 = 31 deg)".into(),
            runs: plot_runs,
            profile: Vec::new(),
            outlines: lines,
        });
    }
}

/// The slope run `name` at `deg`; with a completed run, its plot label, the run and the
/// plate's surface line.
fn measure(name: &str, deg: f64, ran: Ran) -> (SlopeRun, Option<(String, RunResult, SideLine)>) {
    let th = deg.to_radians();
    match ran.result {
        Ok(r) => {
            let p1 = pose_at(&r, SLOPE_SETTLE_S);
            let p2 = pose_at(&r, SLOPE_SETTLE_S + SLOPE_MEASURE_S);
            let along = ((p2.x - p1.x) * th.cos() + (p2.z - p1.z) * th.sin()) / SLOPE_MEASURE_S;
            let run = SlopeRun {
                case: name.into(),
                angle_deg: deg,
                speed_along_mps: along,
                climbed: along >= 0.5 * PACKBOT_SPEED_MPS,
                error: None,
            };
            let xs = r.samples.iter().map(|s| s.pose.x);
            let (lo, hi) = xs.fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(x), b.max(x)));
            // The plate's top surface passes through the origin: z = x tan(theta).
            let line = vec![
                (lo - 0.3, (lo - 0.3) * th.tan()),
                (hi + 0.3, (hi + 0.3) * th.tan()),
            ];
            (
                run,
                Some((format!("{deg:.0} deg: {along:+.2} m/s"), r, line)),
            )
        }
        Err(e) => (
            SlopeRun {
                case: name.into(),
                angle_deg: deg,
                speed_along_mps: f64::NAN,
                climbed: false,
                error: Some(e.to_string()),
            },
            None,
        ),
    }
}

/// The slope-limit case: the steepest slope climbed against atan(0.6).
fn limit_case(slope_runs: &[SlopeRun]) -> Case {
    let climbed: Vec<f64> = slope_runs
        .iter()
        .filter(|r| r.climbed)
        .map(|r| r.angle_deg)
        .collect();
    let highest = climbed.iter().copied().fold(f64::NAN, f64::max);
    let monotonic = slope_runs
        .iter()
        .all(|r| r.climbed == (r.angle_deg <= highest));
    let slope_ok = highest.is_finite() && (highest - SLOPE_LIMIT_DEG).abs() <= SLOPE_TOLERANCE_DEG;
    Case {
        group: "slope".into(),
        name: "PackBot slope limit".into(),
        runs: slope_runs.iter().map(|r| r.case.clone()).collect(),
        outcome: format!(
            "climbed {} of {} slopes{}",
            climbed.len(),
            slope_runs.len(),
            if monotonic { "" } else { " (not monotonic)" }
        ),
        measured: if highest.is_finite() {
            format!(
                "steepest climbed {highest:.0} deg, first failed {}",
                slope_runs
                    .iter()
                    .find(|r| !r.climbed)
                    .map(|r| format!("{:.0} deg", r.angle_deg))
                    .unwrap_or("none".into())
            )
        } else {
            "none climbed".into()
        },
        expected: format!(
            "within {SLOPE_TOLERANCE_DEG:.0} deg of atan(0.6) = {SLOPE_LIMIT_DEG:.2} deg"
        ),
        passed: slope_ok && monotonic,
        note: format!(
            "PackBot 510 (`vehicles/packbot510.toml`) starts on a smooth plate (friction 0.6 on plate and belts) inclined at {:.0}..{:.0} deg in 1 deg steps, belts at {PACKBOT_SPEED_MPS} m/s uphill. Coulomb friction holds the vehicle while tan(slope) <= 0.6, whatever the load distribution, so the limit is atan(0.6) = 30.96 deg; the grousers cannot dig into the rigid plate.",
            SLOPE_ANGLES_DEG[0],
            SLOPE_ANGLES_DEG[SLOPE_ANGLES_DEG.len() - 1]
        ),
        plot: "slope".into(),
    }
}

/// PackBot 510 at the origin on a 20 m plate inclined at `deg` (top surface through the
/// origin, rising towards +x), belts at [`PACKBOT_SPEED_MPS`] for 4 s.
fn slope_scenario(
    packbot: &VehicleModel,
    deg: f64,
    method: TrackMethod,
    root: &Path,
    setting: SolverSetting,
) -> Result<Scenario> {
    let d = SLOPE_SETTLE_S + SLOPE_MEASURE_S;
    compile(
        &plate_text(deg, 0.6, method, d, ""),
        packbot.clone(),
        root,
        setting,
    )
}

/// The scenario text of [`slope_scenario`] for `duration` s, plate and belts of friction `mu`
/// (the vehicle's belts are the caller's), with `plate` (e.g. a `[terrain.boxes.soil]` table)
/// after the plate's keys.
pub(super) fn plate_text(
    deg: f64,
    mu: f64,
    method: TrackMethod,
    duration: f64,
    plate: &str,
) -> String {
    let th = deg.to_radians();
    format!(
        r#"
description = "PackBot 510 on a {deg:.0} deg slope, friction {mu}"
[vehicle]
file = "../vehicles/packbot510.toml"
pitch_deg = {p}
[[terrain.boxes]]
centre_m = [{cx}, 0.0, {cz}]
size_m = [20.0, 4.0, 1.0]
pitch_deg = {p}
friction = {mu}
{plate}
[simulation]
duration_s = {duration}
method = "{m}"
[outcome]
fail_off_terrain = false
[[commands]]
t_s = 0.0
belt_speed_mps = {PACKBOT_SPEED_MPS}
"#,
        p = -deg,
        cx = 0.5 * th.sin(),
        cz = -0.5 * th.cos(),
        m = method.name(),
    )
}
