//! Datasets: `sweep`, `ensemble` and `merge` (the library's, on its threads, the GIL released).

use crate::common::py_err;
use crate::scenario::template_of;
use pyo3::prelude::*;
use std::path::PathBuf;

/// Runs a sweep of `scenario` (see `tracksim sweep`) into `out`: `runs` runs with seeds from
/// `seed` (default: the file's), or `grid` ({name: [values]}, `runs` per point); this process's
/// shard `shard` = (index, count) or all; `jobs` threads; GIL released. Returns the manifest
/// lines of the shard as JSON strings.
#[pyfunction]
#[pyo3(signature = (scenario, out, runs=10, seed=None, grid=None, shard=None, jobs=1, resume=false))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn sweep(
    py: Python<'_>,
    scenario: &Bound<'_, PyAny>,
    out: PathBuf,
    runs: usize,
    seed: Option<u64>,
    grid: Option<Vec<(String, Vec<f64>)>>,
    shard: Option<(usize, usize)>,
    jobs: usize,
    resume: bool,
) -> PyResult<Vec<String>> {
    use tracksim::sweep::{Shard, SweepOptions, SweepPlan};
    let t = template_of(scenario)?;
    let seed = seed.unwrap_or(t.file_seed());
    let plan = match grid {
        Some(axes) if !axes.is_empty() => SweepPlan::grid(&axes, runs, seed),
        _ => SweepPlan::random(runs, seed),
    }
    .map_err(py_err)?;
    let shard = shard
        .map(|(i, n)| Shard::new(i, n))
        .transpose()
        .map_err(py_err)?;
    for w in plan.warnings(&t) {
        PyErr::warn(
            py,
            &py.get_type::<pyo3::exceptions::PyUserWarning>(),
            &std::ffi::CString::new(w).unwrap_or_default(),
            1,
        )?;
    }
    let opts = SweepOptions {
        out,
        jobs,
        shard,
        resume,
        stop: None,
    };
    let report = py
        .detach(|| tracksim::sweep::run_sweep(&t, &plan, &opts, |_, _| {}))
        .map_err(py_err)?;
    Ok(report
        .lines
        .iter()
        .map(|l| serde_json::to_string(l).expect("serialises"))
        .collect())
}

/// Runs `scenario` (at its file's seed) as an ensemble of `members` perturbed runs (see
/// `tracksim run --ensemble`, docs/ENSEMBLE.md) on `jobs` threads (0: every core), GIL
/// released; each member written into `out` if given. Returns the report as JSON (verdict,
/// success fraction, success times, every member with its perturbation and outcome).
#[pyfunction]
#[pyo3(signature = (scenario, members=16, out=None, seed=0, start_mm=1.0, yaw_deg=0.05, keep_order=false, jobs=0, shard=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn ensemble(
    py: Python<'_>,
    scenario: &Bound<'_, PyAny>,
    members: usize,
    out: Option<PathBuf>,
    seed: u64,
    start_mm: f64,
    yaw_deg: f64,
    keep_order: bool,
    jobs: usize,
    shard: Option<(usize, usize)>,
) -> PyResult<String> {
    use tracksim::ensemble::{EnsembleOptions, Perturbations, run_ensemble};
    let t = template_of(scenario)?;
    let mut opts = EnsembleOptions::new(members);
    opts.seed = seed;
    opts.jobs = jobs;
    opts.out = out;
    opts.replay = true;
    opts.shard = shard;
    opts.perturbations = Perturbations {
        start_m: start_mm * 1e-3,
        yaw_deg,
        solver_order: !keep_order,
    };
    let report = py
        .detach(|| run_ensemble(&t, &opts, |_, _| {}))
        .map_err(py_err)?;
    report.to_json().map_err(py_err)
}

/// Joins the JSON reports of an ensemble's shards into the ensemble's report (JSON), written as
/// `ensemble.json` and `ensemble.csv` into `out` if given.
#[pyfunction]
#[pyo3(signature = (reports, out=None))]
pub(crate) fn ensemble_merge(reports: Vec<String>, out: Option<PathBuf>) -> PyResult<String> {
    use tracksim::ensemble::EnsembleReport;
    let parts = reports
        .iter()
        .map(|r| EnsembleReport::from_json(r))
        .collect::<tracksim::Result<Vec<_>>>()
        .map_err(py_err)?;
    let all = EnsembleReport::merge(parts).map_err(py_err)?;
    if let Some(out) = &out {
        all.write(out).map_err(py_err)?;
    }
    all.to_json().map_err(py_err)
}

/// Merges sweep folders (shards) into the sweep folder `out` (see `tracksim merge`); returns
/// the number of runs.
#[pyfunction]
pub(crate) fn merge(py: Python<'_>, dirs: Vec<PathBuf>, out: PathBuf) -> PyResult<usize> {
    py.detach(|| tracksim::sweep::merge(&dirs, &out))
        .map(|l| l.len())
        .map_err(py_err)
}
