//! The terrain as drawn under runs in the side view, and the plot files of one run and of a
//! comparison.

use crate::error::Result;
use crate::model::Scenario;
use crate::run::RunResult;
use std::path::Path;

/// Instants at which the side view draws the vehicle's outline.
const SNAPSHOTS: usize = 5;

pub use super::side_line::SideLine;

/// The terrain under runs as drawn in the side view: the height profile along the first run's
/// path (x, z) and the side outlines (x, z) of the terrain's boxes, m.
pub fn side_view_terrain(sc: &Scenario, runs: &[&RunResult]) -> (SideLine, Vec<SideLine>) {
    if runs.iter().all(|r| r.samples.is_empty()) {
        return (Vec::new(), Vec::new());
    }
    let (lo, hi) = runs
        .iter()
        .flat_map(|r| r.samples.iter())
        .fold((f64::MAX, f64::MIN), |(lo, hi), s| {
            (lo.min(s.pose.x), hi.max(s.pose.x))
        });
    let (lo, hi) = (lo - 0.5, hi + 0.5);
    let n = 400;
    let xs: Vec<f64> = (0..=n)
        .map(|i| lo + (hi - lo) * i as f64 / n as f64)
        .collect();
    // At each x, the y of the first run's sample nearest in x (the first of equals), found in
    // one pass over its samples (they may be on disk).
    let mut nearest: Vec<Option<(f64, f64)>> = vec![None; xs.len()];
    for s in runs[0].samples.iter() {
        for (x, best) in xs.iter().zip(nearest.iter_mut()) {
            let d = (s.pose.x - x).abs();
            if best.is_none_or(|(bd, _)| d.total_cmp(&bd).is_lt()) {
                *best = Some((d, s.pose.y));
            }
        }
    }
    let pts: Vec<(f64, f64)> = xs
        .iter()
        .zip(&nearest)
        .map(|(&x, best)| (x, best.map_or(0.0, |b| b.1)))
        .collect();
    let profile = xs
        .iter()
        .zip(sc.terrain.heights_at(&pts))
        .filter_map(|(&x, z)| z.map(|z| (x, z)))
        .collect();
    let outlines = sc
        .terrain
        .boxes
        .iter()
        .map(|b| {
            let r = b.rotation();
            [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                .iter()
                .map(|(sx, sz)| {
                    let p = b.centre + r * glam::DVec3::new(sx * b.half.x, 0.0, sz * b.half.z);
                    (p.x, p.z)
                })
                .collect()
        })
        .collect();
    (profile, outlines)
}

/// Writes `<stem>.png` and `<stem>.svg` with `runs` (label, result) drawn over the scenario's
/// terrain; nothing when there is no run.
fn write_runs(
    sc: &Scenario,
    runs: &[(String, &RunResult)],
    title: &str,
    stem: &str,
    dir: &Path,
) -> Result<Vec<std::path::PathBuf>> {
    if runs.is_empty() {
        return Ok(Vec::new());
    }
    let snapshots = super::vehicle_outline::snapshots(&sc.vehicle, runs[0].1, SNAPSHOTS);
    write_runs_with(sc, runs, &snapshots, title, stem, dir)
}

/// [`write_runs`] with the vehicle outlines drawn given.
fn write_runs_with(
    sc: &Scenario,
    runs: &[(String, &RunResult)],
    snapshots: &[super::vehicle_outline::Snapshot],
    title: &str,
    stem: &str,
    dir: &Path,
) -> Result<Vec<std::path::PathBuf>> {
    let results: Vec<&RunResult> = runs.iter().map(|(_, r)| *r).collect();
    let (profile, outlines) = side_view_terrain(sc, &results);
    let runs: Vec<super::plot::PlotRun> = runs
        .iter()
        .map(|(label, r)| super::plot::PlotRun {
            label: label.as_str(),
            result: r,
        })
        .collect();
    let mut written = super::plot::write_plots(
        &super::plot::PlotInput {
            title,
            runs: &runs,
            ground_profile: &profile,
            outlines: &outlines,
            snapshots,
        },
        dir,
        stem,
    )?;
    let signals = if stem == "plot" {
        "signals".to_string()
    } else {
        format!("{stem}_signals")
    };
    written.extend(super::signals::write_signals(title, &runs, dir, &signals)?);
    Ok(written)
}

/// Writes `plot.png` and `plot.svg` for one run into `dir`: side view over the terrain, top
/// view, pitch and roll against time.
pub fn write_run_plots(
    sc: &Scenario,
    result: &RunResult,
    dir: &Path,
) -> Result<Vec<std::path::PathBuf>> {
    let title = if sc.description.is_empty() {
        &result.summary.vehicle
    } else {
        &sc.description
    };
    write_runs(
        sc,
        &[(result.summary.method.clone(), result)],
        title,
        "plot",
        dir,
    )
}

/// Writes `compare.png` and `compare.svg`: every successful run of a comparison in one figure.
pub fn write_compare_plots(
    sc: &Scenario,
    results: &[(String, &RunResult)],
    dir: &Path,
) -> Result<Vec<std::path::PathBuf>> {
    let title = format!("{} (track methods compared)", sc.description);
    write_runs(sc, results, &title, "compare", dir)
}

/// Writes `team.png` / `team.svg` and `team_signals.*`: every robot of a world with several
/// (`runs`: name, the robot's own scenario, its run) in one figure, each drawn with its own
/// vehicle's outline.
pub fn write_team_plots(
    sc: &Scenario,
    runs: &[(String, &Scenario, &RunResult)],
    dir: &Path,
) -> Result<Vec<std::path::PathBuf>> {
    if runs.is_empty() {
        return Ok(Vec::new());
    }
    let snapshots: Vec<_> = runs
        .iter()
        .flat_map(|(_, view, r)| super::vehicle_outline::snapshots(&view.vehicle, r, SNAPSHOTS))
        .collect();
    let labelled: Vec<(String, &RunResult)> =
        runs.iter().map(|(n, _, r)| (n.clone(), *r)).collect();
    let title = if sc.description.is_empty() {
        "robots".to_string()
    } else {
        sc.description.clone()
    };
    write_runs_with(sc, &labelled, &snapshots, &title, "team", dir)
}
