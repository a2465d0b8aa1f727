//! The outputs of a world with several robots (`[[vehicles]]`): each robot's run folder
//! (`<dir>/<name>/`, everything a one-robot run writes, so `tracksim view <dir>` replays every
//! robot and `tracksim view <dir>/<name>` one), `team.json` (the world's outcome and each
//! robot's), the robots together in `team.png` / `team_signals.png`, and on request the world's
//! `run.mcap` (every robot's topics namespaced, as the ROS 2 node names them).

use super::{Outputs, write_outputs, write_team_plots};
use crate::error::Result;
use crate::model::Scenario;
use crate::run::TeamResult;
use std::path::{Path, PathBuf};

/// `team.json`: the world's outcome by its rule and each robot's outcome and final pose.
#[derive(Debug, serde::Serialize)]
pub struct TeamSummary {
    /// The scenario's description.
    pub description: String,
    /// The rule deciding the world (`all`, `first`).
    pub rule: String,
    /// The world's outcome (`success`, `failure`, `completed`, `interrupted`).
    pub outcome: String,
    /// Why.
    pub outcome_reason: String,
    /// When it was decided, s.
    pub outcome_time_s: f64,
    /// The run's seed (`simulation.seed`, or `tracksim run --seed`).
    pub seed: u64,
    /// The `[randomize]` values drawn from the seed, by parameter name, in their keys' units
    /// (absent for a file without `[randomize]`).
    #[serde(skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub randomized: std::collections::BTreeMap<String, f64>,
    /// Each robot, in file order.
    pub robots: Vec<RobotLine>,
    /// The race or team score on the course, best first (absent without `[course]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub standings: Option<crate::run::Standings>,
    /// Why the world stopped before its end, when it did (a blow-up, robots further apart
    /// than one world holds; issue 59); absent when it ended as it should.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stopped: Option<String>,
}

/// A robot's line in `team.json`.
#[derive(Debug, serde::Serialize)]
pub struct RobotLine {
    /// Its name (its folder).
    pub name: String,
    /// Its vehicle's name.
    pub vehicle: String,
    /// Its outcome.
    pub outcome: String,
    /// Why.
    pub outcome_reason: String,
    /// When it was decided, s.
    pub outcome_time_s: f64,
    /// Final chassis position [x, y, z], m, and yaw, rad.
    pub final_pose: [f64; 4],
    /// Path length driven, m.
    pub distance_m: f64,
    /// Its trainee (`tracksim drive --trainee ROBOT=NAME`), `null` when not given.
    pub trainee: Option<String>,
    /// Its score on the course (repetitions, time, faults, penalty, score; absent without
    /// `[course]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub score: Option<crate::run::ScoreSummary>,
}

impl TeamSummary {
    /// The summary of `r`, a run of `sc`.
    pub fn of(sc: &Scenario, r: &TeamResult) -> Self {
        TeamSummary {
            description: sc.description.clone(),
            rule: r.rule.name().into(),
            outcome: r.outcome.name().into(),
            outcome_reason: r.outcome.reason(),
            outcome_time_s: r.outcome_time,
            seed: sc.seed,
            randomized: sc.randomized.clone(),
            robots: r
                .robots
                .iter()
                .map(|(name, run)| {
                    let s = &run.summary;
                    let p = &s.final_pose;
                    RobotLine {
                        name: name.clone(),
                        vehicle: s.vehicle.clone(),
                        outcome: s.outcome.clone(),
                        outcome_reason: s.outcome_reason.clone(),
                        outcome_time_s: s.outcome_time_s,
                        final_pose: [p.x, p.y, p.z, p.yaw],
                        distance_m: s.distance_m,
                        trainee: s.trainee.clone(),
                        score: s.course.as_ref().map(|c| c.score),
                    }
                })
                .collect(),
            standings: r.standings.clone(),
            stopped: r.stopped.clone(),
        }
    }
}

/// Writes a team run of `sc` into `dir`: each robot's outputs (`which`) in `dir/<name>/` (a
/// robot reset during the run: each attempt a reset ended in `dir/<name>/attempts/N/`),
/// `team.json`, (with `which.plots`) the robots in one figure, and (with `which.mcap` or the
/// file's `[output] mcap`) the world's `run.mcap` with every robot's topics and frames in its
/// namespace ([`super::mcap::team_mcap_bytes`]) besides each robot's own. Returns the paths
/// written.
pub fn write_team(
    sc: &Scenario,
    r: &TeamResult,
    dir: &Path,
    which: Outputs,
) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    let views: Vec<Scenario> = (0..r.robots.len()).map(|k| sc.robot_view(k)).collect();
    for ((name, run), view) in r.robots.iter().zip(&views) {
        written.extend(write_outputs(view, run, &dir.join(name), which)?);
    }
    // A robot reset during the run: each attempt a reset ended in `<name>/attempts/N/`.
    for (((name, _), view), kept) in r.robots.iter().zip(&views).zip(&r.attempts) {
        for (i, a) in kept.iter().enumerate() {
            let sub = dir.join(name).join(crate::run::attempt_folder(i + 1));
            written.extend(write_outputs(view, a, &sub, which)?);
        }
    }
    let json = serde_json::to_string_pretty(&TeamSummary::of(sc, r)).expect("team serialises");
    let path = dir.join("team.json");
    crate::files::write_atomic(&path, (json + "\n").as_bytes())?;
    written.push(path);
    if which.mcap || sc.record_mcap {
        let opts = super::mcap::McapOptions {
            raw_images: which.raw_images,
        };
        written.push(super::mcap::write_team_mcap(sc, r, dir, opts)?);
    }
    if which.plots {
        let runs: Vec<(String, &Scenario, &crate::run::RunResult)> = r
            .robots
            .iter()
            .zip(&views)
            .map(|((n, run), v)| (n.clone(), v, run))
            .collect();
        written.extend(write_team_plots(sc, &runs, dir)?);
    }
    Ok(written)
}

/// Writes a session of several robots: what [`write_team`] writes (`which`) and every robot's
/// controls as one `commands.toml` (`logs`, by robot name in file order, under `header`:
/// [`crate::run::write_team_log`]; its replay command runs `scenario_file` for the session's
/// duration). Returns the paths written. `drive` and `ros` of a file with several robots write
/// through here.
pub fn write_team_session(
    sc: &Scenario,
    r: &TeamResult,
    (logs, header): (&[(&str, &crate::run::CommandLog)], crate::run::LogHeader),
    scenario_file: &Path,
    dir: &Path,
    which: Outputs,
) -> Result<Vec<PathBuf>> {
    let mut written = write_team(sc, r, dir, which)?;
    let duration = r
        .robots
        .first()
        .and_then(|(_, run)| run.samples.last())
        .map_or(0.0, |s| s.t);
    written.push(crate::run::write_team_log(
        logs,
        header,
        scenario_file,
        dir,
        duration,
    )?);
    Ok(written)
}

/// A team run in words: the world's outcome, then a line per robot, and the `[expect]`
/// verdict.
pub fn team_report(file: &Path, sc: &Scenario, r: &TeamResult, out: &Path) -> String {
    team_report_of(file, sc, r, out, None)
}

/// [`team_report`] of a session whose commands came from outside (`commands_from`, e.g. "ROS 2
/// topics"): the file's `[expect]` is not checked.
pub fn team_report_of(
    file: &Path,
    sc: &Scenario,
    r: &TeamResult,
    out: &Path,
    commands_from: Option<&str>,
) -> String {
    let mut l = vec![
        format!("scenario   {}", file.display()),
        format!(
            "robots     {} in one world (outcome rule `{}`)",
            r.robots.len(),
            r.rule.name()
        ),
    ];
    for (name, run) in &r.robots {
        let s = &run.summary;
        let p = &s.final_pose;
        l.push(format!(
            "  {name:<12} {} ({}): {} at t = {:.3} s ({}); final x {:.3} y {:.3} z {:.3} m, \
             yaw {:.1} deg",
            s.vehicle,
            s.method,
            s.outcome,
            s.outcome_time_s,
            s.outcome_reason,
            p.x,
            p.y,
            p.z,
            p.yaw.to_degrees()
        ));
    }
    if let Some(st) = &r.standings {
        l.extend(st.lines());
    }
    l.push(format!(
        "outcome    {}: {} (t = {:.3} s)",
        r.outcome.name(),
        r.outcome.reason(),
        r.outcome_time
    ));
    if let Some(why) = &r.stopped {
        l.push(format!("stopped    {why}"));
    }
    let has_expect = sc
        .team
        .as_ref()
        .is_some_and(|t| !t.expect.is_empty() || t.robots.iter().any(|x| !x.expect.is_empty()));
    if has_expect {
        let misses = crate::run::team::team_misses(sc, r);
        l.push(if let Some(from) = commands_from {
            format!("expect     not checked: the commands came from {from}")
        } else if !sc.overridden.is_empty() {
            format!(
                "expect     not checked: the run overrides {}",
                sc.overridden.join(", ")
            )
        } else if matches!(r.outcome, crate::run::Outcome::Interrupted(_)) {
            "expect     not checked: the run was interrupted".into()
        } else if misses.is_empty() {
            "expect     met (the file's [expect] tables)".into()
        } else {
            format!("expect     MISSED: {}", misses.join("; "))
        });
    }
    l.push(format!(
        "outputs    {}/team.json, a folder per robot ({}); `tracksim view {}` replays them all",
        out.display(),
        r.robots
            .iter()
            .map(|(n, _)| n.as_str())
            .collect::<Vec<_>>()
            .join(", "),
        out.display()
    ));
    l.join("\n")
}
