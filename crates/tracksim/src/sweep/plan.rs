//! A sweep's plan: N seeds or a grid over named `[randomize]` parameters ([`SweepPlan`], its
//! runs [`RunSpec`]), split into shards ([`Shard`]), and the names of its run folders and
//! manifests.

use crate::error::{Error, Result, SpecIssue};
use crate::model::ScenarioTemplate;
use std::collections::BTreeMap;

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
/// What a plan's errors name.
pub(super) const PLAN: &str = "sweep plan";

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
