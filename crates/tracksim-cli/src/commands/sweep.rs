//! `tracksim sweep`: argument parsing and printing over `tracksim::sweep`.

use super::{Failure, bad_arg, parse_method, scenario_file};
use std::path::PathBuf;
use tracksim::sweep::{Shard, SweepOptions, SweepPlan};

/// Arguments of `tracksim sweep`.
#[derive(clap::Args)]
pub struct SweepArgs {
    /// Scenario file (TOML), usually with a `[randomize]` table.
    pub file: PathBuf,
    /// Output folder: runs/run-NNNNNN/ per run and the manifest.
    #[arg(long, default_value = "out/sweep")]
    pub out: PathBuf,
    /// Number of runs (seeds SEED, SEED+1, ...); with --grid, runs per grid point.
    #[arg(long, default_value_t = 10)]
    pub runs: usize,
    /// First seed (default: the file's simulation.seed).
    #[arg(long)]
    pub seed: Option<u64>,
    /// A grid axis over a [randomize] parameter: NAME=V1,V2,... (repeat for more axes).
    #[arg(long)]
    pub grid: Vec<String>,
    /// Runs in parallel.
    #[arg(long, default_value_t = 1)]
    pub jobs: usize,
    /// This process's shard INDEX/COUNT (default: from SLURM_ARRAY_TASK_ID and
    /// SLURM_ARRAY_TASK_COUNT, or JOB_COMPLETION_INDEX with --shard-count).
    #[arg(long)]
    pub shard: Option<String>,
    /// Number of shards when the index comes from the environment (Kubernetes Indexed Job).
    #[arg(long)]
    pub shard_count: Option<usize>,
    /// Skip runs whose folder is complete.
    #[arg(long)]
    pub resume: bool,
    /// Track method, overriding the scenario's.
    #[arg(long)]
    pub method: Option<String>,
    /// Override the simulated duration of every run, s.
    #[arg(long)]
    pub duration: Option<f64>,
    /// No progress bar and no summary line.
    #[arg(long)]
    pub quiet: bool,
}

/// One `--grid NAME=V1,V2,...` (the syntax; the values are checked by
/// [`SweepPlan::grid`]).
fn grid_axis(s: &str) -> Result<(String, Vec<f64>), Failure> {
    let bad = || {
        bad_arg(
            "--grid",
            format!("{s:?}: write NAME=V1,V2,... with numbers, e.g. step_height_m=0.08,0.12"),
        )
    };
    let (name, vals) = s.split_once('=').ok_or_else(bad)?;
    let vals: Vec<f64> = vals
        .split(',')
        .map(|v| v.trim().parse::<f64>().ok())
        .collect::<Option<_>>()
        .ok_or_else(bad)?;
    Ok((name.trim().to_string(), vals))
}

/// `tracksim sweep`.
pub fn sweep(a: SweepArgs) -> Result<(), Failure> {
    let overrides = tracksim::Overrides {
        method: a
            .method
            .as_deref()
            .map(|m| parse_method("--method", m))
            .transpose()?,
        duration_s: a.duration,
        ..Default::default()
    };
    let shard = match &a.shard {
        Some(s) => Some(Shard::parse(s).map_err(|e| bad_arg("--shard", e))?),
        None => Shard::from_env(|k| std::env::var(k).ok(), a.shard_count)
            .map_err(|e| bad_arg("shard environment", e))?,
    };
    let opts = SweepOptions {
        out: a.out.clone(),
        jobs: a.jobs,
        shard,
        resume: a.resume,
        stop: Some(&super::STOP),
    };
    opts.check()?;
    let template = tracksim::ScenarioTemplate::load_with(&scenario_file(&a.file)?, &overrides)?;
    let seed = a.seed.unwrap_or(template.file_seed());
    let plan = if a.grid.is_empty() {
        SweepPlan::random(a.runs, seed)?
    } else {
        let axes = a
            .grid
            .iter()
            .map(|g| grid_axis(g))
            .collect::<Result<Vec<_>, _>>()?;
        SweepPlan::grid(&axes, a.runs, seed)?
    };
    for w in plan.warnings(&template) {
        eprintln!("warning: {w}");
    }
    let bar = (!a.quiet && std::io::IsTerminal::is_terminal(&std::io::stderr())).then(|| {
        let b = indicatif::ProgressBar::new(0);
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "{bar:40} {pos}/{len} runs  {elapsed} elapsed, {eta} left",
            )
            .expect("valid template"),
        );
        b
    });
    super::on_stop(|| eprintln!("stopping: the runs in progress finish, no other starts ..."));
    let report = tracksim::sweep::run_sweep(&template, &plan, &opts, |done, total| {
        if let Some(b) = &bar {
            b.set_length(total as u64);
            b.set_position(done as u64);
        }
    })?;
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    if !a.quiet {
        let count = |o: &str| report.lines.iter().filter(|l| l.outcome == o).count();
        let shard = shard.map_or(String::new(), |s| {
            format!(" (shard {}/{})", s.index, s.count)
        });
        out!(
            "{} runs{shard}: {} run now, {} already done; success {}, failure {}, completed {}, unstable {}; manifest {}",
            report.owned,
            report.ran,
            report.skipped,
            count("success"),
            count("failure"),
            count("completed"),
            count("unstable"),
            report.manifest.display()
        );
    }
    if report.interrupted {
        eprintln!(
            "interrupted: {} runs not done; `tracksim sweep ... --resume` completes the sweep",
            report.owned - report.ran - report.skipped
        );
        return Err(Failure::Interrupted);
    }
    Ok(())
}
