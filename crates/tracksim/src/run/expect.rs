//! A run checked against its scenario's `[expect]` table ([`check_expectations`]).

use super::RunResult;
use crate::model::{Expectation, Range};

/// Every way the run misses the scenario's expectation, one line each (empty: met).
pub fn check_expectations(e: &Expectation, r: &RunResult) -> Vec<String> {
    let s = &r.summary;
    let mut misses = Vec::new();
    if let Some(o) = &e.outcome
        && *o != s.outcome
    {
        misses.push(format!(
            "outcome {} ({}) where {o} was expected",
            s.outcome, s.outcome_reason
        ));
    }
    if let Some(want) = &e.reason_contains
        && !s.outcome_reason.contains(want.as_str())
    {
        misses.push(format!(
            "outcome reason {:?} does not contain {want:?}",
            s.outcome_reason
        ));
    }
    let p = &s.final_pose;
    let mut checks: Vec<(String, Option<Range>, f64, &str)> = vec![
        ("outcome time".into(), e.outcome_time, s.outcome_time_s, "s"),
        ("final x".into(), e.final_x, p.x, "m"),
        ("final y".into(), e.final_y, p.y, "m"),
        ("final z".into(), e.final_z, p.z, "m"),
        (
            "final yaw".into(),
            e.final_yaw.map(|r| r.map(f64::to_degrees)),
            p.yaw.to_degrees(),
            "deg",
        ),
        ("mean speed".into(), e.mean_speed, s.mean_speed_mps, "m/s"),
        ("progress".into(), e.progress, s.progress_m, "m"),
    ];
    let course = [e.course_repetitions, e.course_faults, e.course_score];
    match &s.course {
        Some(c) => {
            let sc = &c.score;
            checks.push((
                "course repetitions".into(),
                e.course_repetitions,
                f64::from(sc.repetitions),
                "",
            ));
            checks.push((
                "course faults".into(),
                e.course_faults,
                f64::from(sc.faults),
                "",
            ));
            checks.push(("course score".into(), e.course_score, sc.score_s, "s"));
        }
        None if course.iter().any(Option::is_some) => {
            misses.push("a course figure was expected but the scenario has no [course]".into());
        }
        None => {}
    }
    if let Some(last) = r.samples.last() {
        for (i, b) in last.loose_poses.iter().enumerate() {
            checks.push((
                format!("loose box {i} final x"),
                e.loose_box_final_x,
                b.x,
                "m",
            ));
            checks.push((
                format!("loose box {i} final z"),
                e.loose_box_final_z,
                b.z,
                "m",
            ));
        }
        let first = &r.samples.first().unwrap_or(last).conveyor_position;
        for (i, (a, b)) in first.iter().zip(&last.conveyor_position).enumerate() {
            checks.push((
                format!("conveyor {i} travel"),
                e.conveyor_travel,
                b - a,
                "m",
            ));
        }
    }
    for (name, range, v, unit) in checks {
        if let Some([lo, hi]) = range
            && !(lo..=hi).contains(&v)
        {
            misses.push(format!("{name} {v:.4} {unit} outside [{lo}, {hi}]"));
        }
    }
    misses
}

/// A run of `sc` checked against its `[expect]` table, in words: "met ...", "MISSED: ..." or
/// "not checked: ..." (the run was overridden, or interrupted); `None` without a table.
pub fn expect_verdict(sc: &crate::model::Scenario, r: &RunResult) -> Option<String> {
    if sc.expect.is_empty() {
        return None;
    }
    if !sc.overridden.is_empty() {
        return Some(format!(
            "not checked: the run overrides {}",
            sc.overridden.join(", ")
        ));
    }
    if matches!(r.outcome, super::Outcome::Interrupted(_)) {
        return Some("not checked: the run was interrupted".into());
    }
    let misses = check_expectations(&sc.expect, r);
    let mut words = if misses.is_empty() {
        "met (the file's [expect] table)".to_string()
    } else {
        format!("MISSED: {}", misses.join("; "))
    };
    if let Some(e) = &sc.expect.ensemble {
        words += &format!(
            "; its ensemble bounds need `--ensemble {}` (docs/ENSEMBLE.md)",
            e.members
        );
    }
    Some(words)
}
