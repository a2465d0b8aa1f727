//! The paper's Figs. 2 and 3, from the named cases `fig2_bump` and `fig3_wall`
//! ([`crate::cases`]) when their files are present: the bump with the method under test
//! (`fig2/<method>`) and with 4 wheels (`fig2/wheels4`), the wall with the method under test
//! (`fig3/<method>`).

use super::drawing::full_side_view;
use super::jobs::{Jobs, Ran, Runs};
use super::report::{Case, PlotJob, ValidationReport};
use crate::error::Result;
use crate::model::Method as TrackMethod;
use crate::model::Overrides;
use crate::run::{Outcome, RunResult};
use std::path::Path;

/// Named case of paper Fig. 2 (a bump the track climbs and 4 wheels do not).
const BUMP: &str = "fig2_bump";
/// Named case of paper Fig. 3 (a low-friction wall nothing should climb).
const WALL: &str = "fig3_wall";
/// The reference method of Fig. 2.
const WHEELS: TrackMethod = TrackMethod::Wheels(4);
/// Members of the 4-wheel reference's ensemble (issue 38): with 2 position-correction passes
/// the 4 wheels climb the bump from some starts and stall from others (2 of 8 climbed at seed 0,
/// 6 of 8 at seed 2: a margin), so the reference is judged by its ensemble: it must fail from
/// at least one start, where the track climbs from every one (`tests/suite/methods.rs`).
const WHEELS_MEMBERS: usize = 8;
/// Seed of the reference's perturbations.
const WHEELS_SEED: u64 = 2;

/// Case names of the Fig. 2 runs: the method under test, then the 4-wheel reference (named
/// `fig2/wheels4_reference` when the method under test is itself `wheels4`).
fn bump_names(method: TrackMethod) -> (String, String) {
    let tested = format!("fig2/{}", method.name());
    let reference = format!("fig2/{}", WHEELS.name());
    if tested == reference {
        (tested, format!("{reference}_reference"))
    } else {
        (tested, reference)
    }
}

/// Case name of the Fig. 3 run.
fn wall_name(method: TrackMethod) -> String {
    format!("fig3/{}", method.name())
}

/// The named case `name`'s file exists under `root`.
fn present(root: &Path, name: &str) -> bool {
    crate::cases::case(name).is_some_and(|c| c.path(root).is_file())
}

/// Adds the Fig. 2 and Fig. 3 runs whose files are present.
pub(super) fn add_jobs(
    jobs: &mut Jobs,
    method: TrackMethod,
    root: &Path,
    setting: super::options::SolverSetting,
) -> Result<()> {
    let with = |m: TrackMethod| Overrides {
        method: Some(m),
        ..setting.overrides()
    };
    if present(root, BUMP) {
        let sc = crate::cases::template(root, BUMP, &with(method))?.file_scenario()?;
        let wt = crate::cases::template(root, BUMP, &with(WHEELS))?;
        let w = wt.file_scenario()?;
        let (tested, reference) = bump_names(method);
        jobs.add(tested, sc)?;
        let p = crate::ensemble::Perturbations::default();
        for k in 1..WHEELS_MEMBERS {
            jobs.add(
                format!("{reference}/member-{k}"),
                p.member(WHEELS_SEED, k).scenario(&wt, &w)?,
            )?;
        }
        jobs.add(reference, w)?;
    }
    if present(root, WALL) {
        let sc = crate::cases::template(root, WALL, &with(method))?.file_scenario()?;
        jobs.add(wall_name(method), sc)?;
    }
    Ok(())
}

/// Adds the paper-figure cases (and their plots) of the runs that were added.
pub(super) fn assemble(
    report: &mut ValidationReport,
    jobs: &Jobs,
    runs: &mut Runs,
    method: TrackMethod,
) {
    let (tested, reference) = bump_names(method);
    if let Some(sc) = jobs.scenario(&tested) {
        let mut plot_runs = Vec::new();
        // The reference's perturbed members: how many climbed.
        let members: Vec<bool> = (1..WHEELS_MEMBERS)
            .filter_map(|k| {
                runs.take(&format!("{reference}/member-{k}"))
                    .result
                    .ok()
                    .map(|r| matches!(r.outcome, Outcome::Success(_)))
            })
            .collect();
        for (run, label, expect_success) in [
            (&tested, method.name(), true),
            (&reference, WHEELS.name(), false),
        ] {
            let (mut case, r) = bump_case(run, runs.take(run), &label, expect_success);
            if !expect_success && !members.is_empty() {
                let nominal = matches!(r.as_ref().map(|r| &r.outcome), Some(Outcome::Success(_)));
                let climbed = members.iter().filter(|&&s| s).count() + usize::from(nominal);
                let n = members.len() + 1;
                case.measured = format!(
                    "{} ({climbed} of {n} perturbed members climbed)",
                    case.measured
                );
                case.expected = format!(
                    "failure from some of {n} perturbed starts (the track climbs from every one); the paper's single run fails"
                );
                case.passed = r.is_some() && climbed < n;
            }
            report.cases.push(case);
            plot_runs.extend(r.map(|r| (format!("{label}: {}", r.outcome.name()), r)));
        }
        if !plot_runs.is_empty() {
            let refs: Vec<&RunResult> = plot_runs.iter().map(|(_, r)| r).collect();
            let (profile, outlines) = full_side_view(sc, &refs);
            report.plots.push(PlotJob {
                stem: "fig2_bump".into(),
                title: "Paper Fig. 2: a 0.075 m bump, track vs 4 wheels".into(),
                runs: plot_runs,
                profile,
                outlines,
            });
        }
    }
    let wall = wall_name(method);
    if let Some(sc) = jobs.scenario(&wall) {
        let (case, r) = wall_case(&wall, runs.take(&wall), method);
        report.cases.push(case);
        if let Some(r) = r {
            let (profile, outlines) = full_side_view(sc, &[&r]);
            report.plots.push(PlotJob {
                stem: "fig3_wall".into(),
                title: "Paper Fig. 3: vertical wall, friction 0.2".into(),
                runs: vec![(method.name(), r)],
                profile,
                outlines,
            });
        }
    }
}

/// The Fig. 2 run `run` with method `label`, which should climb the bump if `expect_success`;
/// the run itself when it completed.
fn bump_case(run: &str, ran: Ran, label: &str, expect_success: bool) -> (Case, Option<RunResult>) {
    let name = format!("Fig. 2 bump: {label}");
    let r = match ran.result {
        Ok(r) => r,
        Err(e) => return (Case::error("paper figures", &name, run, &e), None),
    };
    let case = Case {
        group: "paper figures".into(),
        name,
        runs: vec![run.into()],
        outcome: r.outcome.name().into(),
        measured: format!(
            "{} (x {:.2} m at {:.1} s)",
            r.summary.outcome_reason, r.summary.final_pose.x, r.summary.outcome_time_s
        ),
        expected: if expect_success {
            "success (climbs the 0.075 m bump)".into()
        } else {
            "failure (stalls astride the bump)".into()
        },
        passed: matches!(r.outcome, Outcome::Success(_)) == expect_success,
        note: format!(
            "`scenarios/bump_wheels_vs_track.toml` with method {label}: paper Fig. 2, adjacent wheels' traction forces oppose on a bump shorter than the wheel spacing; a real track climbs it."
        ),
        plot: "fig2_bump".into(),
    };
    (case, Some(r))
}

/// The Fig. 3 run `run`, which should not climb the wall; the run itself when it completed.
fn wall_case(run: &str, ran: Ran, method: TrackMethod) -> (Case, Option<RunResult>) {
    let name = format!("Fig. 3 low-friction wall: {}", method.name());
    let r = match ran.result {
        Ok(r) => r,
        Err(e) => return (Case::error("paper figures", &name, run, &e), None),
    };
    let case = Case {
        group: "paper figures".into(),
        name,
        runs: vec![run.into()],
        outcome: r.outcome.name().into(),
        measured: format!(
            "{} (max body z {:.3} m)",
            r.summary.outcome_reason,
            r.samples.iter().map(|s| s.pose.z).fold(f64::MIN, f64::max)
        ),
        expected: "does not climb (friction 0.2 on wall and ground)".into(),
        passed: !matches!(r.outcome, Outcome::Success(_)),
        note: "`scenarios/wall_low_friction.toml`: paper Fig. 3; upward friction at the wall is at most 0.2 x the push, the push at most 0.2 x the weight, so no real track climbs it (the paper says the constraint-to-ground model may; on Rapier it does not either, see docs/METHODS.md).".into(),
        plot: "fig3_wall".into(),
    };
    (case, Some(r))
}
