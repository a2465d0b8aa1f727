//! Running a sweep ([`run_sweep`]): a shard's runs on threads, each written into its own folder
//! atomically, finished runs skipped on resume, then the shard's manifest.

use super::manifest::{self, ManifestLine, read_runs};
use super::plan::{MAX_JOBS, PLAN, RunSpec, Shard, SweepPlan, manifest_name, run_dir_name};
use crate::error::{Error, Result, SpecIssue};
use crate::model::ScenarioTemplate;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

#[derive(Clone, Debug)]
pub struct SweepOptions {
    /// Output folder: `runs/run-NNNNNN/` per run and the manifest.
    pub out: PathBuf,
    /// Runs in parallel (threads).
    pub jobs: usize,
    /// This process's shard (`None`: every run).
    pub shard: Option<Shard>,
    /// Skip runs whose folder is complete instead of refusing to overwrite them.
    pub resume: bool,
    /// When set (by a Ctrl-C or SIGTERM handler), no further run starts; the runs in progress
    /// finish (each folder is whole or absent) and the manifest lists the finished runs.
    pub stop: Option<&'static std::sync::atomic::AtomicBool>,
}

impl SweepOptions {
    /// Checks the options: `jobs` from 1 to [`MAX_JOBS`] (key `jobs`). [`run_sweep`] calls it.
    pub fn check(&self) -> Result<()> {
        if (1..=MAX_JOBS).contains(&self.jobs) {
            return Ok(());
        }
        Err(Error::setting(
            PLAN,
            "jobs",
            format!("must be from 1 to {MAX_JOBS} threads, got {}", self.jobs),
        ))
    }
}

/// What a sweep did.
#[derive(Clone, Debug, Default)]
pub struct SweepReport {
    /// Runs of this shard.
    pub owned: usize,
    /// Runs simulated now.
    pub ran: usize,
    /// Runs found complete and skipped (`resume`).
    pub skipped: usize,
    /// The manifest written (this shard's runs).
    pub manifest: PathBuf,
    /// Its lines.
    pub lines: Vec<ManifestLine>,
    /// What the user should know ([`SweepPlan::warnings`]).
    pub warnings: Vec<String>,
    /// Stopped (`SweepOptions::stop`) before every run was done: `--resume` completes it.
    pub interrupted: bool,
}

/// Runs the plan's runs of `opts.shard` on `opts.jobs` threads, writes each into
/// `out/runs/run-NNNNNN/` (`summary.json`, `trajectory.csv`, `run.json` = its manifest line)
/// through a temporary folder renamed when complete, then this shard's manifest, one line per
/// run in index order. `progress(done, owned)` is called after each run.
pub fn run_sweep(
    template: &ScenarioTemplate,
    plan: &SweepPlan,
    opts: &SweepOptions,
    progress: impl Fn(usize, usize) + Sync,
) -> Result<SweepReport> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| Error::Io { path, source }
    };
    opts.check()?;
    let runs_dir = opts.out.join("runs");
    std::fs::create_dir_all(&runs_dir).map_err(io(&runs_dir))?;
    let owned: Vec<&RunSpec> = plan
        .runs
        .iter()
        .filter(|r| opts.shard.is_none_or(|s| s.owns(r.index)))
        .collect();
    // Grid points are checked before anything runs (a value outside what the file allows).
    let mut seen = std::collections::BTreeSet::new();
    for r in &owned {
        if seen.insert(format!("{:?}", r.fixed)) {
            template.instantiate_with(r.seed, &r.fixed)?;
        }
    }
    let mut todo = Vec::new();
    let mut skipped = 0;
    for r in &owned {
        let dir = runs_dir.join(run_dir_name(r.index));
        if dir.join("run.json").is_file() {
            if !opts.resume {
                return Err(Error::Invalid {
                    path: opts.out.clone(),
                    issues: vec![SpecIssue::new(
                        "",
                        format!(
                            "{} already holds a finished run; pass --resume to skip finished runs, or choose another --out",
                            dir.display()
                        ),
                    )],
                });
            }
            skipped += 1;
        } else {
            todo.push(*r);
        }
    }
    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(skipped);
    let first_error: Mutex<Option<Error>> = Mutex::new(None);
    let total = owned.len();
    progress(skipped, total);
    std::thread::scope(|scope| {
        for _ in 0..opts.jobs.max(1).min(todo.len().max(1)) {
            scope.spawn(|| {
                loop {
                    if first_error.lock().map(|e| e.is_some()).unwrap_or(true)
                        || opts.stop.is_some_and(|s| s.load(Ordering::SeqCst))
                    {
                        return;
                    }
                    let k = next.fetch_add(1, Ordering::SeqCst);
                    let Some(r) = todo.get(k) else { return };
                    if let Err(e) = run_one(template, r, &runs_dir) {
                        if let Ok(mut slot) = first_error.lock() {
                            slot.get_or_insert(e);
                        }
                        return;
                    }
                    progress(done.fetch_add(1, Ordering::SeqCst) + 1, total);
                }
            });
        }
    });
    if let Some(e) = first_error.into_inner().ok().flatten() {
        return Err(e);
    }
    let ran = done.load(Ordering::SeqCst) - skipped;
    let indices: Vec<usize> = owned.iter().map(|r| r.index).collect();
    let lines = read_runs(&opts.out)?
        .into_iter()
        .filter(|l| indices.contains(&l.index))
        .collect::<Vec<_>>();
    let manifest = opts.out.join(manifest_name(opts.shard));
    manifest::write_lines(&manifest, &lines)?;
    Ok(SweepReport {
        owned: total,
        ran,
        skipped,
        interrupted: ran < todo.len(),
        manifest,
        lines,
        warnings: plan.warnings(template),
    })
}

/// Simulates one run and moves its complete folder into place.
fn run_one(template: &ScenarioTemplate, r: &RunSpec, runs_dir: &Path) -> Result<()> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| Error::Io { path, source }
    };
    let sc = template.instantiate_with(r.seed, &r.fixed)?;
    let final_dir = runs_dir.join(run_dir_name(r.index));
    let tmp = runs_dir.join(format!(
        ".{}.tmp-{}",
        run_dir_name(r.index),
        std::process::id()
    ));
    if tmp.exists() {
        std::fs::remove_dir_all(&tmp).map_err(io(&tmp))?;
    }
    std::fs::create_dir_all(&tmp).map_err(io(&tmp))?;
    let which = crate::output::Outputs {
        replay: false,
        plots: false,
        mcap: false,
        raw_images: false,
    };
    let line = if sc.team.is_some() {
        // Several robots: each robot's folder under the run's, and the world's `team.json`.
        match crate::run::run_team(&sc, Default::default()) {
            Ok(result) => {
                crate::output::write_team(&sc, &result, &tmp, which)?;
                ManifestLine::of_team(r, &sc, &result)
            }
            Err(e @ Error::Unstable { .. }) => ManifestLine::unstable(r, &sc, &e),
            Err(e) => return Err(e),
        }
    } else {
        match crate::run::run_scenario(&sc, |_, _| {}) {
            Ok(result) => {
                crate::output::write_outputs(&sc, &result, &tmp, which)?;
                ManifestLine::of_run(r, &sc, &result)
            }
            Err(e @ Error::Unstable { .. }) => ManifestLine::unstable(r, &sc, &e),
            Err(e) => return Err(e),
        }
    };
    manifest::write_run_json(&tmp.join("run.json"), &line)?;
    if final_dir.exists() {
        // An unfinished folder (no run.json) from an older attempt.
        std::fs::remove_dir_all(&final_dir).map_err(io(&final_dir))?;
    }
    std::fs::rename(&tmp, &final_dir).map_err(io(&final_dir))?;
    Ok(())
}
