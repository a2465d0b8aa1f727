//! One scenario run with several track methods (`tracksim compare`): a run folder per method,
//! `compare.csv`, a combined plot, and the table as text or JSON.

use crate::error::{Error, Result};
use crate::model::{Method, Overrides, ScenarioTemplate, load_scenario_with};
use crate::run::{RunResult, run_scenario_with};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// One method's line of the table: its run's figures, or the error that stopped it.
#[derive(Clone, Debug, Serialize)]
pub struct CompareRow {
    /// Track method.
    pub method: String,
    /// "success", "failure", "completed", or "error".
    pub outcome: String,
    /// Why, in words (or the error).
    pub reason: String,
    /// Progress along the start heading, m.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub progress_m: Option<f64>,
    /// Path length, m.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub distance_m: Option<f64>,
    /// Mean forward speed, m/s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mean_speed_mps: Option<f64>,
    /// Simulated seconds per second of stepping.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub real_time_factor: Option<f64>,
    /// Height of the body at the end, m.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub final_z_m: Option<f64>,
}

/// What `compare` produced.
#[derive(Debug)]
pub struct CompareReport {
    /// The scenario file.
    pub file: PathBuf,
    /// One row per method, in the order run.
    pub rows: Vec<CompareRow>,
    /// Files written (`compare.csv`, plots).
    pub written: Vec<PathBuf>,
    /// The last error, when no method produced a run.
    pub error: Option<Error>,
    /// Stopped by Ctrl-C or SIGTERM: the method then running is written as interrupted, the
    /// methods after it did not run.
    pub interrupted: bool,
}

/// Runs `file` with each of `methods` (and `duration_s` if given) and writes into `out`: a
/// folder per method (`summary.json`, `trajectory.csv`, replay data), `compare.csv` and the
/// combined plots. A method that cannot run the scenario is a row with its error.
/// `progress` is told each method before it runs. Once `stop` is set (a Ctrl-C or SIGTERM
/// handler), the running method ends interrupted and no other runs; what ran is written.
pub fn run_compare(
    file: &Path,
    methods: &[Method],
    duration_s: Option<f64>,
    out: &Path,
    stop: Option<&'static std::sync::atomic::AtomicBool>,
    mut progress: impl FnMut(Method),
) -> Result<CompareReport> {
    let stopped = || stop.is_some_and(|s| s.load(std::sync::atomic::Ordering::SeqCst));
    // The file's own problems stop everything (a method's problems are that method's row).
    let base = load_scenario_with(
        file,
        &Overrides {
            duration_s,
            ..Overrides::default()
        },
    )?;
    // A world with several robots runs with `tracksim run` (refused before anything is written).
    crate::run::one_robot(&base)?;
    std::fs::create_dir_all(out).map_err(|source| Error::Io {
        path: out.to_path_buf(),
        source,
    })?;
    let mut rows = Vec::new();
    let mut done: Vec<(String, RunResult)> = Vec::new();
    let mut error = None;
    for &m in methods {
        if stopped() {
            break;
        }
        progress(m);
        let o = Overrides {
            method: Some(m),
            duration_s,
            ..Overrides::default()
        };
        let ran = load_scenario_with(file, &o).and_then(|sc| {
            // The method's folder is marked while its run writes it (issue 45).
            let dir = out.join(m.name());
            crate::output::incomplete::mark_incomplete(&dir)?;
            let opts = crate::run::RunOptions {
                realtime: false,
                stop,
            };
            let r = run_scenario_with(&sc, opts, |_, _| {})?;
            let which = crate::output::Outputs {
                replay: true,
                plots: false,
                mcap: false,
                raw_images: false,
            };
            crate::output::write_outputs(&sc, &r, &dir, which)?;
            crate::output::incomplete::mark_complete(&dir)?;
            Ok(r)
        });
        match ran {
            Ok(r) => {
                rows.push(row_of(m, &r));
                done.push((m.name(), r));
            }
            Err(e) => {
                rows.push(CompareRow {
                    method: m.name(),
                    outcome: "error".into(),
                    reason: e.to_string(),
                    progress_m: None,
                    distance_m: None,
                    mean_speed_mps: None,
                    real_time_factor: None,
                    final_z_m: None,
                });
                error = Some(e);
            }
        }
    }
    let runs: Vec<(String, &RunResult)> = done.iter().map(|(n, r)| (n.clone(), r)).collect();
    let mut written = Vec::new();
    let csv_path = out.join("compare.csv");
    crate::files::write_atomic(&csv_path, compare_csv(&rows).as_bytes())?;
    written.push(csv_path);
    written.extend(crate::output::write_compare_plots(&base, &runs, out)?);
    Ok(CompareReport {
        file: file.to_path_buf(),
        rows,
        written,
        error: if done.is_empty() { error } else { None },
        interrupted: stopped(),
    })
}

fn row_of(m: Method, r: &RunResult) -> CompareRow {
    let s = &r.summary;
    CompareRow {
        method: m.name(),
        outcome: s.outcome.clone(),
        reason: s.outcome_reason.clone(),
        progress_m: Some(s.progress_m),
        distance_m: Some(s.distance_m),
        mean_speed_mps: Some(s.mean_speed_mps),
        real_time_factor: Some(s.real_time_factor),
        final_z_m: Some(s.final_pose.z),
    }
}

/// `compare.csv`: a row per method (numbers to 4 decimals, empty for a method that failed).
pub fn compare_csv(rows: &[CompareRow]) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    let num = |v: Option<f64>| v.map(|v| format!("{v:.4}")).unwrap_or_default();
    let header = [
        "method",
        "outcome",
        "progress_m",
        "distance_m",
        "mean_speed_mps",
        "real_time_factor",
        "final_z_m",
        "reason",
    ];
    w.write_record(header).expect("writes to memory");
    for r in rows {
        w.write_record([
            r.method.clone(),
            r.outcome.clone(),
            num(r.progress_m),
            num(r.distance_m),
            num(r.mean_speed_mps),
            num(r.real_time_factor),
            num(r.final_z_m),
            r.reason.clone(),
        ])
        .expect("writes to memory");
    }
    String::from_utf8(w.into_inner().expect("flushes to memory")).expect("UTF-8 fields")
}

impl CompareReport {
    /// The table as text: a line per method.
    pub fn to_table(&self) -> String {
        let mut t = format!("scenario {}\n", self.file.display());
        t.push_str(&format!(
            "{:<24} {:<10} {:>10} {:>10} {:>12} {:>8}  reason\n",
            "method", "outcome", "progress m", "distance m", "speed m/s", "RTF"
        ));
        let num = |v: Option<f64>, p: usize| v.map_or_else(|| "-".into(), |v| format!("{v:.p$}"));
        for r in &self.rows {
            t.push_str(&format!(
                "{:<24} {:<10} {:>10} {:>10} {:>12} {:>8}  {}\n",
                r.method,
                r.outcome,
                num(r.progress_m, 3),
                num(r.distance_m, 3),
                num(r.mean_speed_mps, 4),
                num(r.real_time_factor, 1),
                r.reason
            ));
        }
        t
    }

    /// The table as JSON: `{"methods": [row, ...]}`.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(&serde_json::json!({ "methods": self.rows }))
            .expect("rows serialise")
    }
}

/// One method's ensemble in `compare --ensemble` (its verdict, or why it could not run).
#[derive(Debug)]
pub struct EnsembleRow {
    /// Track method.
    pub method: String,
    /// The ensemble, or the method's problem with the scenario.
    pub report: Result<crate::ensemble::EnsembleReport>,
}

/// Runs `file` as an ensemble of `members` with each of `methods` (perturbations and seed as
/// `tracksim run --ensemble`, docs/ENSEMBLE.md), each written into `out/ensemble-<method>/`.
/// Stops starting methods once `stop` is set.
pub fn run_compare_ensembles(
    file: &Path,
    methods: &[Method],
    duration_s: Option<f64>,
    members: usize,
    out: &Path,
    stop: Option<&'static std::sync::atomic::AtomicBool>,
) -> Result<Vec<EnsembleRow>> {
    crate::ensemble::Perturbations::default().check(members)?;
    let mut rows = Vec::new();
    for &m in methods {
        if stop.is_some_and(|s| s.load(std::sync::atomic::Ordering::SeqCst)) {
            break;
        }
        let o = Overrides {
            method: Some(m),
            duration_s,
            ..Overrides::default()
        };
        let report = ScenarioTemplate::load_with(file, &o).and_then(|t| {
            let mut opts = crate::ensemble::EnsembleOptions::new(members);
            opts.out = Some(out.join(format!("ensemble-{}", m.name())));
            opts.stop = stop;
            crate::ensemble::run_ensemble(&t, &opts, |_, _| {})
        });
        rows.push(EnsembleRow {
            method: m.name(),
            report,
        });
    }
    Ok(rows)
}

/// The ensembles of [`run_compare_ensembles`] as a Markdown table: verdict, success fraction,
/// success times (median, range).
pub fn ensemble_table(rows: &[EnsembleRow]) -> String {
    let mut s = String::from(
        "| method | verdict | success fraction | success time median (range), s |\n|---|---|---|---|\n",
    );
    for r in rows {
        match &r.report {
            Ok(e) => {
                let t = e.success_times().map_or("-".into(), |t| {
                    format!("{:.2} ({:.2}-{:.2})", t.median, t.min, t.max)
                });
                s += &format!(
                    "| {} | {} | {:.3} | {t} |\n",
                    r.method,
                    e.verdict(),
                    e.success_fraction()
                );
            }
            Err(err) => {
                let msg = err.to_string().replace('\n', " ");
                s += &format!("| {} | error | - | {msg} |\n", r.method);
            }
        }
    }
    s
}
