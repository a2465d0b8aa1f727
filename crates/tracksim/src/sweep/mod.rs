//! Datasets: many runs of a (randomised) scenario ([`SweepPlan`]: N seeds, or a grid over named
//! `[randomize]` parameters), split into shards ([`Shard`], from `--shard i/n` or the job
//! array's environment), run on `jobs` threads, each run written into its own folder atomically
//! (a temporary folder renamed when complete), and a manifest of one JSON line per run
//! ([`ManifestLine`]); finished runs are skipped on resume and shards merge into one manifest.
//!
//! - `mod.rs`: the plan, shards and [`run_sweep`];
//! - `manifest.rs`: [`ManifestLine`], reading run folders, [`merge`].

mod manifest;

pub use manifest::{ManifestLine, merge, read_runs};

use crate::error::{Error, Result, SpecIssue};
use crate::model::ScenarioTemplate;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// One shard of a sweep: runs whose index `i` has `i % count == index`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// This shard, from 0.
    pub index: usize,
    /// Number of shards.
    pub count: usize,
}

impl Shard {
    /// Parses `i/n` (0 <= i < n).
    pub fn parse(s: &str) -> std::result::Result<Shard, String> {
        let bad = || format!("--shard {s:?}: write INDEX/COUNT with 0 <= INDEX < COUNT, e.g. 0/4");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count) = (
            i.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        Shard::new(index, count).map_err(|_| bad())
    }

    /// Shard `index` of `count` (0 <= index < count); others are refused (key `shard`).
    pub fn new(index: usize, count: usize) -> Result<Shard> {
        if index < count {
            return Ok(Shard { index, count });
        }
        let hint = if count == 0 {
            "there must be at least one shard".to_string()
        } else {
            format!("the index runs from 0 to {}", count - 1)
        };
        Err(Error::setting(
            PLAN,
            "shard",
            format!("shard {index} of {count}: need 0 <= index < count ({hint}), e.g. (0, 4)"),
        ))
    }

    /// The shard of a job array from its environment (`var` reads a variable): SLURM's
    /// `SLURM_ARRAY_TASK_ID` (less `SLURM_ARRAY_TASK_MIN`) of `SLURM_ARRAY_TASK_COUNT`, or
    /// Kubernetes' `JOB_COMPLETION_INDEX` of `count` (an Indexed Job sets no count; pass
    /// `--shard-count` or `TRACKSIM_SHARD_COUNT`). `None` outside a job array.
    pub fn from_env(
        var: impl Fn(&str) -> Option<String>,
        count: Option<usize>,
    ) -> std::result::Result<Option<Shard>, String> {
        let num = |name: &str| -> std::result::Result<Option<usize>, String> {
            match var(name) {
                None => Ok(None),
                Some(v) => v
                    .trim()
                    .parse()
                    .map(Some)
                    .map_err(|_| format!("{name}={v:?} is not a whole number")),
            }
        };
        let count = match count {
            Some(c) => Some(c),
            None => num("TRACKSIM_SHARD_COUNT")?,
        };
        if let Some(id) = num("SLURM_ARRAY_TASK_ID")? {
            let min = num("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
            let n = match count {
                Some(c) => c,
                None => num("SLURM_ARRAY_TASK_COUNT")?.ok_or(
                    "SLURM_ARRAY_TASK_ID is set without SLURM_ARRAY_TASK_COUNT; pass --shard-count",
                )?,
            };
            let i = id
                .checked_sub(min)
                .ok_or("SLURM_ARRAY_TASK_ID is below SLURM_ARRAY_TASK_MIN")?;
            return Shard::new(i, n).map(Some).map_err(|_| {
                format!(
                    "SLURM array task {i} (from 0) is not below the count {n}: use --array=0-{}",
                    n.max(1) - 1
                )
            });
        }
        if let Some(i) = num("JOB_COMPLETION_INDEX")? {
            let n = count.ok_or("JOB_COMPLETION_INDEX is set but no shard count: pass --shard-count N (the Job's completions) or set TRACKSIM_SHARD_COUNT")?;
            return Shard::new(i, n)
                .map(Some)
                .map_err(|_| format!("JOB_COMPLETION_INDEX {i} is not below the shard count {n}"));
        }
        Ok(None)
    }

    /// True if run `i` belongs to this shard.
    pub fn owns(&self, i: usize) -> bool {
        i % self.count == self.index
    }
}

/// One run of a sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSpec {
    /// Index in the sweep (the folder `runs/run-NNNNNN`).
    pub index: usize,
    /// Seed: the `[randomize]` values are drawn from it.
    pub seed: u64,
    /// Parameters fixed by the grid, by name.
    pub fixed: BTreeMap<String, f64>,
}

/// Every run of a sweep, whatever the shard.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SweepPlan {
    /// The runs in index order.
    pub runs: Vec<RunSpec>,
}

/// What [`Error::Settings`] calls a sweep's plan and options.
const PLAN: &str = "sweep plan";

/// Most runs of one sweep (a folder each): `runs`, or with a grid its points times `runs`.
pub const MAX_RUNS: usize = 10_000_000;
/// Most threads of one sweep (`jobs`).
pub const MAX_JOBS: usize = 1024;

fn check_runs(n: usize) -> Result<()> {
    if (1..=MAX_RUNS).contains(&n) {
        Ok(())
    } else {
        Err(Error::setting(
            PLAN,
            "runs",
            format!("must be from 1 to {MAX_RUNS}, got {n}"),
        ))
    }
}

impl SweepPlan {
    /// `n` runs (1 to [`MAX_RUNS`]) with seeds `seed, seed + 1, ...`.
    pub fn random(n: usize, seed: u64) -> Result<Self> {
        check_runs(n)?;
        Ok(SweepPlan {
            runs: (0..n)
                .map(|i| RunSpec {
                    index: i,
                    seed: seed.wrapping_add(i as u64),
                    fixed: BTreeMap::new(),
                })
                .collect(),
        })
    }

    /// Every combination of the grid's values (the last axis varying fastest), each `repeats`
    /// times; run `i` has seed `seed + i` (the parameters not on the grid are drawn from it).
    /// Each axis names a `[randomize]` parameter once and has at least one finite value;
    /// `repeats` is at least 1 and the runs at most [`MAX_RUNS`] (keys `grid`, `grid.NAME`,
    /// `runs`). Whether the names are the file's parameters is checked by [`run_sweep`].
    pub fn grid(axes: &[(String, Vec<f64>)], repeats: usize, seed: u64) -> Result<Self> {
        check_grid(axes, repeats)?;
        let mut points: Vec<BTreeMap<String, f64>> = vec![BTreeMap::new()];
        for (name, values) in axes {
            points = points
                .into_iter()
                .flat_map(|p| {
                    values.iter().map(move |v| {
                        let mut q = p.clone();
                        q.insert(name.clone(), *v);
                        q
                    })
                })
                .collect();
        }
        let runs = points
            .into_iter()
            .flat_map(|p| std::iter::repeat_n(p, repeats))
            .enumerate()
            .map(|(i, fixed)| RunSpec {
                index: i,
                seed: seed.wrapping_add(i as u64),
                fixed,
            })
            .collect();
        Ok(SweepPlan { runs })
    }

    /// What a user should know before running the plan of `template`: a plan of more than one
    /// run of a file without `[randomize]` (and no grid) runs the same simulation every time
    /// (the simulation is deterministic; the seed only draws `[randomize]` values).
    pub fn warnings(&self, template: &ScenarioTemplate) -> Vec<String> {
        let mut w = Vec::new();
        let fixed = self.runs.iter().all(|r| r.fixed.is_empty());
        if self.runs.len() > 1 && fixed && template.randomizer().params.is_empty() {
            w.push(format!(
                "{} has no [randomize] table: its {} runs will be identical (the seed only \
                 draws [randomize] values); add a [randomize] table (see \
                 scenarios/random/) or run it once with `tracksim run`",
                template.path().display(),
                self.runs.len()
            ));
        }
        w
    }
}

fn check_grid(axes: &[(String, Vec<f64>)], repeats: usize) -> Result<()> {
    let mut issues = Vec::new();
    if axes.is_empty() {
        issues.push(SpecIssue::new(
            "grid",
            "a grid needs at least one axis (NAME, [values]); without one, use a random plan",
        ));
    }
    let mut seen = std::collections::BTreeSet::new();
    for (name, values) in axes {
        let key = format!("grid.{}", crate::check::echoed(name));
        if name.trim().is_empty() {
            issues.push(SpecIssue::new(
                "grid",
                "an axis has an empty name: name a [randomize] parameter",
            ));
            continue;
        }
        if !seen.insert(name.as_str()) {
            issues.push(SpecIssue::new(
                &key,
                "this axis is given twice: give each parameter once, with all its values",
            ));
        }
        if values.is_empty() {
            issues.push(SpecIssue::new(
                &key,
                "has no values: give at least one, e.g. [0.08, 0.12]",
            ));
        }
        if let Some(v) = values.iter().find(|v| !v.is_finite()) {
            issues.push(SpecIssue::new(
                &key,
                format!("values must be finite numbers, got {v}"),
            ));
        }
    }
    if let Err(e) = check_runs(repeats) {
        issues.extend(e.issues().iter().cloned());
    } else if axes
        .iter()
        .try_fold(repeats, |n, (_, v)| n.checked_mul(v.len()))
        .is_none_or(|n| n > MAX_RUNS)
    {
        issues.push(SpecIssue::new(
            "grid",
            format!("the grid points times `runs` must be at most {MAX_RUNS} runs"),
        ));
    }
    if issues.is_empty() {
        Ok(())
    } else {
        Err(Error::Settings {
            what: PLAN.into(),
            issues,
        })
    }
}

/// How a sweep runs.
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

/// Folder name of run `i`.
pub fn run_dir_name(i: usize) -> String {
    format!("run-{i:06}")
}

/// Manifest file name of a shard (`manifest.jsonl` without shards).
pub fn manifest_name(shard: Option<Shard>) -> String {
    match shard {
        None => "manifest.jsonl".into(),
        Some(s) => format!("manifest-shard-{}-of-{}.jsonl", s.index, s.count),
    }
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
    let line = match crate::run::run_scenario(&sc, |_, _| {}) {
        Ok(result) => {
            let which = crate::output::Outputs {
                replay: false,
                plots: false,
                mcap: false,
            };
            crate::output::write_outputs(&sc, &result, &tmp, which)?;
            ManifestLine::of_run(r, &sc, &result)
        }
        Err(e @ Error::Unstable { .. }) => ManifestLine::unstable(r, &sc, &e),
        Err(e) => return Err(e),
    };
    manifest::write_run_json(&tmp.join("run.json"), &line)?;
    if final_dir.exists() {
        // An unfinished folder (no run.json) from an older attempt.
        std::fs::remove_dir_all(&final_dir).map_err(io(&final_dir))?;
    }
    std::fs::rename(&tmp, &final_dir).map_err(io(&final_dir))?;
    Ok(())
}
