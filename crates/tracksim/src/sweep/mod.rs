//! Datasets: many runs of a (randomised) scenario ([`SweepPlan`]: N seeds, or a grid over named
//! `[randomize]` parameters), split into shards ([`Shard`], from `--shard i/n` or the job
//! array's environment), run on `jobs` threads, each run written into its own folder atomically
//! (a temporary folder renamed when complete), and a manifest of one JSON line per run
//! ([`ManifestLine`]); finished runs are skipped on resume and shards merge into one manifest.
//!
//! - `plan.rs`: the plan ([`SweepPlan`], [`RunSpec`]), shards ([`Shard`]), folder and manifest
//!   names;
//! - `run.rs`: [`run_sweep`] (threads, atomic run folders, resume, the manifest);
//! - `manifest.rs`: [`ManifestLine`], reading run folders, [`merge`].

mod manifest;
mod plan;
mod run;

pub use manifest::{ManifestLine, RobotRun, merge, read_runs};
pub use plan::{MAX_JOBS, MAX_RUNS, RunSpec, Shard, SweepPlan, manifest_name, run_dir_name};
pub use run::{SweepOptions, SweepReport, run_sweep};
