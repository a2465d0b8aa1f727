//! A finished run in words: the lines `tracksim run` prints.

use crate::model::Scenario;
use crate::run::RunResult;
use std::path::{Path, PathBuf};

/// The report of a run of `sc` (from `file`): timing, speed, final pose, contacts, outcome,
/// the `[expect]` verdict and the files `written`, a line each, labels in a column.
pub fn run_report(file: &Path, sc: &Scenario, result: &RunResult, written: &[PathBuf]) -> String {
    let s = &result.summary;
    let p = &s.final_pose;
    let mut l = vec![
        format!("scenario   {}", file.display()),
        format!("vehicle    {} (method {})", s.vehicle, s.method),
    ];
    if s.paced {
        l.push(format!(
            "simulated  {:.3} s in {:.3} s wall, paced to the wall clock: {:.2} x real time",
            s.sim_time_s, s.elapsed_time_s, s.paced_real_time_factor
        ));
        l.push(format!(
            "compute    stepping alone took {:.3} s: it could run {:.1} x real time",
            s.wall_time_s, s.real_time_factor
        ));
    } else {
        l.push(format!(
            "simulated  {:.3} s in {:.3} s of stepping: real-time factor {:.1}",
            s.sim_time_s, s.wall_time_s, s.real_time_factor
        ));
    }
    l.push(format!(
        "mean speed {:.4} m/s, distance {:.3} m",
        s.mean_speed_mps, s.distance_m
    ));
    l.push(format!(
        "final pose x {:.4} y {:.4} z {:.4} m, roll {:.2} pitch {:.2} yaw {:.2} deg",
        p.x,
        p.y,
        p.z,
        p.roll.to_degrees(),
        p.pitch.to_degrees(),
        p.yaw.to_degrees()
    ));
    l.push(format!(
        "contacts   deepest penetration {:.1} mm (contact slop {:.1} mm)",
        s.max_penetration_m * 1000.0,
        s.solver.contact_slop_m * 1000.0
    ));
    l.push(margins_line(&s.margins));
    l.push(format!(
        "outcome    {}: {} (t = {:.3} s)",
        s.outcome, s.outcome_reason, s.outcome_time_s
    ));
    if let Some(c) = &s.course {
        l.push(course_line(c));
    }
    if let Some(v) = crate::run::expect_verdict(sc, result) {
        l.push(format!("expect     {v}"));
    }
    l.extend(
        written
            .iter()
            .map(|w| format!("wrote      {}", w.display())),
    );
    l.join("\n")
}

/// The margins line of a report: the peak tilt against the tip limit, and the track that came
/// nearest to leaving the ground (issue 62).
pub fn margins_line(m: &crate::run::Margins) -> String {
    let at = |p: Option<crate::run::Peak>| {
        p.map_or("-".to_string(), |p| {
            format!("{:.1} deg at {:.2} s", p.value, p.t_s)
        })
    };
    let mut line = format!(
        "margins    pitch {}, roll {}: {:.1} deg below the {:.0} deg tip limit",
        at(m.peak_abs_pitch_deg),
        at(m.peak_abs_roll_deg),
        m.tilt_margin_deg,
        m.tip_limit_deg
    );
    let lightest = m
        .tracks
        .iter()
        .filter_map(|t| t.min_normal_load_n.map(|p| (t, p)))
        .min_by(|a, b| a.1.value.total_cmp(&b.1.value));
    if let Some((t, p)) = lightest {
        line.push_str(&format!(
            "; lightest track {} {:.1} N at {:.2} s",
            t.name, p.value, p.t_s
        ));
    }
    line
}

/// The course line of a report: repetitions, times, faults, penalties, the score.
pub fn course_line(c: &crate::run::CourseScore) -> String {
    let reps: Vec<String> = c.rep_times_s.iter().map(|t| format!("{t:.2}")).collect();
    let f = &c.faults;
    format!(
        "course     {}: {} of {} repetitions ({}) [{} s], {} faults (touch {}, tip-over {}, \
         reset {}), penalty {:.1} s: score {:.2} s",
        c.name,
        c.repetitions_done,
        c.repetitions_required,
        c.status.replace('_', " "),
        if reps.is_empty() {
            "-".into()
        } else {
            reps.join(", ")
        },
        f.total(),
        f.touch,
        f.tip_over,
        f.reset,
        c.penalty_s,
        c.score.score_s
    )
}
