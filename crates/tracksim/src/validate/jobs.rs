//! The validation's runs: every case a scenario under a unique name ([`Jobs`]), run on
//! worker threads, each result looked up by its name ([`Runs`], [`Ran`]) and read
//! ([`pose_at`]).

use crate::error::{Error, Result};
use crate::model::Scenario;
use crate::run::{RunResult, run_scenario_with};
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

/// One run of the validation: a scenario under its unique case name.
struct Job {
    name: String,
    scenario: Scenario,
}

/// Every run of the validation, in the order they are started.
#[derive(Default)]
pub(super) struct Jobs {
    list: Vec<Job>,
}

impl Jobs {
    /// Adds the run `name`; a name given twice is an error.
    pub(super) fn add(&mut self, name: impl Into<String>, scenario: Scenario) -> Result<()> {
        let name = name.into();
        if self.scenario(&name).is_some() {
            return Err(Error::Build(format!(
                "validation case \"{name}\" is defined twice"
            )));
        }
        self.list.push(Job { name, scenario });
        Ok(())
    }

    /// The scenario of the run `name`, if there is one.
    pub(super) fn scenario(&self, name: &str) -> Option<&Scenario> {
        self.list
            .iter()
            .find(|j| j.name == name)
            .map(|j| &j.scenario)
    }

    /// Runs every job, `std::thread::available_parallelism` at a time.
    pub(super) fn run(
        &self,
        stop: Option<&'static AtomicBool>,
        progress: &mut impl FnMut(&str),
    ) -> Runs {
        let mut runs = run_parallel(&self.list, stop, progress);
        for j in &self.list {
            runs.entry(j.name.clone()).or_insert_with(|| Ran {
                result: Err(Error::Build(
                    "not run: the validation was interrupted, or its worker thread stopped".into(),
                )),
                wall_s: 0.0,
            });
        }
        Runs(runs)
    }
}

/// What one run gave, and its wall-clock time, s.
pub(super) struct Ran {
    /// The run, or why there is none.
    pub(super) result: Result<RunResult>,
    /// Wall-clock time of the run, s.
    pub(super) wall_s: f64,
}

/// The results of every run, keyed by case name.
pub(super) struct Runs(BTreeMap<String, Ran>);

impl Runs {
    /// Takes out the result of the run `name` (each result is used once); a name that was not
    /// run gives an error result.
    pub(super) fn take(&mut self, name: &str) -> Ran {
        self.0.remove(name).unwrap_or_else(|| Ran {
            result: Err(Error::Build(format!(
                "validation case \"{name}\" was not run"
            ))),
            wall_s: 0.0,
        })
    }
}

/// Runs `jobs` on worker threads; each result under its job's name. Once `stop` is set, the
/// running jobs end interrupted and no other starts.
fn run_parallel(
    jobs: &[Job],
    stop: Option<&'static AtomicBool>,
    progress: &mut impl FnMut(&str),
) -> BTreeMap<String, Ran> {
    let workers = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1)
        .clamp(1, jobs.len().max(1));
    let next = AtomicUsize::new(0);
    let (tx, rx) = std::sync::mpsc::channel::<(usize, Result<RunResult>, f64)>();
    let mut out = BTreeMap::new();
    std::thread::scope(|s| {
        for _ in 0..workers {
            let tx = tx.clone();
            let next = &next;
            s.spawn(move || {
                loop {
                    let i = next.fetch_add(1, Ordering::SeqCst);
                    if i >= jobs.len() || stop.is_some_and(|s| s.load(Ordering::SeqCst)) {
                        break;
                    }
                    let t0 = Instant::now();
                    let opts = crate::run::RunOptions {
                        realtime: false,
                        stop,
                    };
                    let r = run_scenario_with(&jobs[i].scenario, opts, |_, _| {});
                    if tx.send((i, r, t0.elapsed().as_secs_f64())).is_err() {
                        break;
                    }
                }
            });
        }
        drop(tx);
        for (done, (i, result, wall_s)) in rx.into_iter().enumerate() {
            progress(&format!(
                "[{}/{}] {}: {} [{wall_s:.1} s wall]",
                done + 1,
                jobs.len(),
                jobs[i].name,
                progress_words(&result)
            ));
            out.insert(jobs[i].name.clone(), Ran { result, wall_s });
        }
    });
    out
}

/// A finished run in words, for the progress line.
fn progress_words(r: &Result<RunResult>) -> String {
    match r {
        Ok(r) => format!(
            "{} after {:.1} s simulated ({})",
            r.outcome.name(),
            r.summary.sim_time_s,
            r.outcome.reason()
        ),
        Err(e) => format!("error: {e}"),
    }
}

/// Body pose at the first sample at or after time `t`.
pub(super) fn pose_at(r: &RunResult, t: f64) -> crate::world::PoseRpy {
    r.samples
        .iter()
        .find(|s| s.t >= t - 1e-6)
        .map(|s| s.pose)
        .or(r.samples.last().map(|s| s.pose))
        .unwrap_or_default()
}
