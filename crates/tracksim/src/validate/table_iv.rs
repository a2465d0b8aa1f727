//! Table IV (paper Sec. IV-B): Quince climbing a step, one run per row and column, named
//! `table_iv/<angle>deg_<height>mm/<column>`.

use super::compile::{compile, compile_with};
use super::drawing::full_side_view;
use super::jobs::{Jobs, Ran, Runs};
use super::limits::{
    QUINCE_MIN_LINK_MASS_KG, QUINCE_SOLVER_ITERATIONS, STEP_DEPTH_M, STEP_DURATION_S,
    STEP_EDGE_X_M, STEP_ON_TOP_Z_M, STEP_SPEED_MPS, STEP_SUCCESS_MARGIN_M, TABLE_IV_CONTACT_SLOP_M,
};
use super::options::ValidationOptions;
use super::report::{PlotJob, StepCase, StepRun, ValidationReport};
use super::rubber::with_rubber_of;
use crate::error::Result;
use crate::model::Method as TrackMethod;
use crate::model::{Scenario, VehicleModel};
use crate::run::{Outcome, RunResult};
use std::path::Path;

/// The paper's Table IV rows: front sub-track angle (deg), step height (mm), and the result of
/// the real robot (the paper's simulation agrees).
const TABLE: [(f64, f64, &str); 6] = [
    (0.0, 40.0, "S"),
    (0.0, 120.0, "S"),
    (0.0, 190.0, "F"),
    (45.0, 120.0, "S"),
    (45.0, 240.0, "S"),
    (45.0, 380.0, "F"),
];

/// A column of Table IV this simulator fills.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Column {
    /// With grousers, contact slop [`TABLE_IV_CONTACT_SLOP_M`]: the asserted column.
    Grousers,
    /// Without grousers, same slop (reported).
    NoGrousers,
    /// With grousers and rigid contact (reported).
    Rigid,
    /// Compliant grousers and belts ([`super::rubber`]), rigid terrain, no slop (reported).
    Compliant,
}

impl Column {
    /// The columns `opts` asks for, the asserted one first.
    fn selected(opts: ValidationOptions) -> Vec<Column> {
        let mut v = vec![Column::Grousers];
        if opts.without_grousers {
            v.push(Column::NoGrousers);
        }
        if opts.rigid_contact {
            v.push(Column::Rigid);
        }
        if opts.compliant_grousers {
            v.push(Column::Compliant);
        }
        v
    }

    fn grousers(self) -> bool {
        self != Column::NoGrousers
    }

    /// Contact slop, m.
    fn slop_m(self) -> f64 {
        match self {
            Column::Grousers | Column::NoGrousers => TABLE_IV_CONTACT_SLOP_M,
            Column::Rigid | Column::Compliant => 0.0,
        }
    }

    /// Last part of the case name.
    fn suffix(self) -> String {
        let slop_mm = TABLE_IV_CONTACT_SLOP_M * 1000.0;
        match self {
            Column::Grousers => format!("grousers_slop{slop_mm:.0}"),
            Column::NoGrousers => format!("no_grousers_slop{slop_mm:.0}"),
            Column::Rigid => "rigid".into(),
            Column::Compliant => "compliant_no_slop".into(),
        }
    }
}

/// `table_iv/00deg_120mm`: the prefix of a row's case names.
fn row_name(a: f64, h: f64) -> String {
    format!("table_iv/{a:02.0}deg_{h:03.0}mm")
}

/// `table_iv/00deg_120mm/grousers_slop10`: the case name of one cell.
fn case_name(a: f64, h: f64, column: Column) -> String {
    format!("{}/{}", row_name(a, h), column.suffix())
}

/// Adds one run per row of Table IV and column `opts` asks for.
pub(super) fn add_jobs(
    jobs: &mut Jobs,
    quince: &VehicleModel,
    method: TrackMethod,
    opts: ValidationOptions,
    root: &Path,
) -> Result<()> {
    let rubber = with_rubber_of(quince, opts.rubber_youngs_modulus_pa);
    for &(a, h, _) in &TABLE {
        for column in Column::selected(opts) {
            let vehicle = if column == Column::Compliant {
                &rubber
            } else {
                quince
            };
            let (text, v) = quince_step_text(
                vehicle,
                a,
                h / 1000.0,
                column.grousers(),
                column.slop_m(),
                method,
            );
            let sc = compile(&text, v.clone(), root, opts.setting)?;
            if column == Column::Grousers {
                let p = crate::ensemble::Perturbations::default();
                for k in 1..opts.ensemble {
                    let o = p.member(0, k).overrides(&sc);
                    jobs.add(
                        format!("{}/member-{k}", case_name(a, h, column)),
                        compile_with(&text, v.clone(), root, opts.setting, &o)?,
                    )?;
                }
            }
            jobs.add(case_name(a, h, column), sc)?;
        }
    }
    Ok(())
}

/// Fills `report.table_iv` (and its plots), row by row.
pub(super) fn assemble(
    report: &mut ValidationReport,
    jobs: &Jobs,
    runs: &mut Runs,
    method: TrackMethod,
    opts: ValidationOptions,
) {
    for &(a, h, reality) in &TABLE {
        let (case, plot) = assemble_row(jobs, runs, method, opts, (a, h, reality));
        report.table_iv.push(case);
        report.plots.extend(plot);
    }
}

/// One row of Table IV, and its plot if any run completed.
fn assemble_row(
    jobs: &Jobs,
    runs: &mut Runs,
    method: TrackMethod,
    opts: ValidationOptions,
    (a, h, reality): (f64, f64, &str),
) -> (StepCase, Option<PlotJob>) {
    let mut take = |column: Column| {
        let name = case_name(a, h, column);
        let ran = runs.take(&name);
        let judged = judge(&name, &ran, h / 1000.0);
        (ran.result, judged)
    };
    let (rg, with_grousers) = take(Column::Grousers);
    let (without, without_grousers) = opts
        .without_grousers
        .then(|| take(Column::NoGrousers))
        .unzip();
    let (rigid, with_grousers_rigid) = opts.rigid_contact.then(|| take(Column::Rigid)).unzip();
    let (compliant, compliant_grousers) = opts
        .compliant_grousers
        .then(|| take(Column::Compliant))
        .unzip();
    // The row's ensemble: member 0 is the asserted run, then the perturbed members.
    let ensemble = (opts.ensemble >= 2).then(|| {
        let mut results = vec![with_grousers.result.clone()];
        for k in 1..opts.ensemble {
            let name = format!("{}/member-{k}", case_name(a, h, Column::Grousers));
            let ran = runs.take(&name);
            results.push(judge(&name, &ran, h / 1000.0).result);
        }
        let n = results.len();
        let s = results.iter().filter(|r| *r == "S").count();
        let f = results.iter().filter(|r| *r == "F").count();
        if s == n {
            format!("S {n}/{n}")
        } else if f == n {
            format!("F {n}/{n}")
        } else {
            format!("marginal {s}/{n}")
        }
    });

    let mut plot_runs = Vec::new();
    if let Ok(r) = rg {
        plot_runs.push((
            format!(
                "{} (grousers, contact slop {:.0} mm): {}",
                method.name(),
                TABLE_IV_CONTACT_SLOP_M * 1000.0,
                with_grousers.result
            ),
            r,
        ));
    }
    if let (Some(Ok(r)), Some(w)) = (without, &without_grousers) {
        plot_runs.push((format!("no grousers: {}", w.result), r));
    }
    if let (Some(Ok(r)), Some(w)) = (rigid, &with_grousers_rigid) {
        plot_runs.push((format!("grousers, rigid contact: {}", w.result), r));
    }
    if let (Some(Ok(r)), Some(w)) = (compliant, &compliant_grousers) {
        plot_runs.push((
            format!("compliant grousers, rigid terrain, no slop: {}", w.result),
            r,
        ));
    }
    let stem = format!("table_iv_{a:02.0}deg_{h:03.0}mm");
    let plot = jobs
        .scenario(&case_name(a, h, Column::Grousers))
        .filter(|_| !plot_runs.is_empty())
        .map(|sc| {
            let refs: Vec<&RunResult> = plot_runs.iter().map(|(_, r)| r).collect();
            let (profile, outlines) = full_side_view(sc, &refs);
            PlotJob {
                stem: stem.clone(),
                title: format!(
                    "Table IV: Quince, front sub-tracks {a:.0} deg, {h:.0} mm step (reality {reality})"
                ),
                runs: plot_runs,
                profile,
                outlines,
            }
        });
    let case = StepCase {
        name: format!("quince_{a:02.0}deg_{h:03.0}mm"),
        case: row_name(a, h),
        front_angle_deg: a,
        step_height_mm: h,
        reality: reality.into(),
        paper: reality.into(),
        passed: with_grousers.result == reality,
        ensemble,
        with_grousers,
        without_grousers,
        with_grousers_rigid,
        compliant_grousers,
        plot: stem,
    };
    (case, plot)
}

/// Judges the step attempt `name` on a step `h` m high.
fn judge(name: &str, ran: &Ran, h: f64) -> StepRun {
    match &ran.result {
        Err(e) => StepRun {
            case: name.into(),
            result: "error".into(),
            outcome: "error".into(),
            reason: e.to_string(),
            time_s: f64::NAN,
            final_x_m: f64::NAN,
            final_z_above_step_m: f64::NAN,
            max_pitch_deg: f64::NAN,
            max_penetration_mm: f64::NAN,
            wall_time_s: ran.wall_s,
        },
        Ok(r) => {
            let last = r.summary.final_pose;
            let on_top = last.z - h >= STEP_ON_TOP_Z_M;
            let success = matches!(r.outcome, Outcome::Success(_)) && on_top;
            let reason = match &r.outcome {
                Outcome::Success(_) if !on_top => {
                    format!("passed x but only {:.3} m above the step top", last.z - h)
                }
                other => other.reason(),
            };
            StepRun {
                case: name.into(),
                result: if success { "S" } else { "F" }.into(),
                outcome: r.outcome.name().into(),
                reason,
                time_s: r.summary.sim_time_s,
                final_x_m: last.x,
                final_z_above_step_m: last.z - h,
                max_pitch_deg: r
                    .samples
                    .iter()
                    .map(|s| s.pose.pitch.abs().to_degrees())
                    .fold(0.0, f64::max),
                max_penetration_mm: r.summary.max_penetration_m * 1000.0,
                wall_time_s: ran.wall_s,
            }
        }
    }
}

/// The Table IV scenario: Quince at x = 0 facing a step of height `h` m whose edge is at
/// [`STEP_EDGE_X_M`], front flippers at `front_deg`, rear flippers flat, vehicle-terrain
/// penetration up to `contact_slop_m` (m) left uncorrected.
pub fn quince_step_scenario(
    quince: &VehicleModel,
    front_deg: f64,
    h: f64,
    grousers: bool,
    contact_slop_m: f64,
    method: TrackMethod,
    root: &Path,
) -> Result<Scenario> {
    let (text, v) = quince_step_text(quince, front_deg, h, grousers, contact_slop_m, method);
    compile(&text, v, root, Default::default())
}

/// The file text of [`quince_step_scenario`] and its vehicle (Quince with the front flippers
/// at `front_deg`).
pub fn quince_step_text(
    quince: &VehicleModel,
    front_deg: f64,
    h: f64,
    grousers: bool,
    contact_slop_m: f64,
    method: TrackMethod,
) -> (String, VehicleModel) {
    let mut v = quince.clone();
    for f in &mut v.flippers {
        if f.name.starts_with("front") {
            f.initial_angle = front_deg.to_radians();
        }
    }
    let flippers: Vec<String> = v
        .flippers
        .iter()
        .map(|f| {
            let a = if f.name.starts_with("front") {
                front_deg
            } else {
                0.0
            };
            format!("{} = {a}", f.name)
        })
        .collect();
    let text = format!(
        r#"
description = "Quince (paper Table IV): front sub-tracks {front_deg:.0} deg, {hmm:.0} mm step, 0.1 m/s{ng}"
[vehicle]
file = "../vehicles/quince.toml"
x_m = 0.0
{gc}
[terrain.ground]
friction = 0.6
[[terrain.boxes]]
centre_m = [{cx}, 0.0, {cz}]
size_m = [{STEP_DEPTH_M}, 3.0, {h}]
friction = 0.6
[simulation]
dt_s = 0.001
duration_s = {STEP_DURATION_S}
min_link_mass_kg = {QUINCE_MIN_LINK_MASS_KG}
solver_iterations = {QUINCE_SOLVER_ITERATIONS}
contact_slop_m = {contact_slop_m}
method = "{method}"
[outcome]
success_x_m = {sx}
max_tilt_deg = 75.0
[[commands]]
t_s = 0.0
belt_speed_mps = {STEP_SPEED_MPS}
flipper_angle_deg = {{ {fl} }}
"#,
        hmm = h * 1000.0,
        ng = if grousers { "" } else { ", no grousers" },
        gc = if grousers { "" } else { "grouser_count = 0" },
        cx = STEP_EDGE_X_M + STEP_DEPTH_M / 2.0,
        cz = h / 2.0,
        sx = STEP_EDGE_X_M + STEP_SUCCESS_MARGIN_M,
        method = method.name(),
        fl = flippers.join(", "),
    );
    (text, v)
}
