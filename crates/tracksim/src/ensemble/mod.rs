//! Ensemble verdicts (issue 38): a scenario run as N members, each with a small seeded
//! perturbation of what should not matter ([`Perturbations`]: start position and yaw, the
//! solver's order; in a world of several robots each robot's start on its own), on all cores; the outcome fraction, the spread of the outcome time and of
//! the final pose ([`EnsembleReport`]), each member's run folder, and the `[expect]` ensemble
//! bounds checked ([`check_ensemble`]).
//!
//! - `perturb.rs`: the perturbation model and the members;
//! - `report.rs`: the report, its verdict ("S 16/16", "marginal 9/16") and its files.

mod perturb;
mod report;

pub use perturb::{MAX_MEMBERS, Member, Perturbations, RobotOffset};
pub use report::{
    EnsembleReport, MarginSpreads, MemberMargins, MemberResult, RobotResult, check_ensemble,
};

use crate::error::{Error, Result};
use crate::model::{Scenario, ScenarioTemplate};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// How an ensemble is run.
#[derive(Clone, Debug)]
pub struct EnsembleOptions {
    /// Number of members (member 0 is the scenario as written).
    pub members: usize,
    /// Seed of the perturbations.
    pub seed: u64,
    /// Their sizes.
    pub perturbations: Perturbations,
    /// Threads (at most the members; 0: every core).
    pub jobs: usize,
    /// Folder to write each member's run into (`member-NNN/`) and the ensemble's files; None:
    /// nothing written.
    pub out: Option<PathBuf>,
    /// Also write each member's replay data (`scene.json`, `belts.csv`) for `tracksim view`.
    pub replay: bool,
    /// Set from outside (Ctrl-C) to start no further member.
    pub stop: Option<&'static AtomicBool>,
    /// Run only the members of this shard, (index, count): member `k` when `k % count ==
    /// index` (a task of a distributed ensemble; its report holds its members, and
    /// [`EnsembleReport::merge`] joins the shards'). A shard writes its members' folders but
    /// not `ensemble.json`, which the merge writes.
    pub shard: Option<(usize, usize)>,
}

impl EnsembleOptions {
    /// `members` members with the default perturbations, seed 0, every core, nothing written.
    pub fn new(members: usize) -> Self {
        EnsembleOptions {
            members,
            seed: 0,
            perturbations: Perturbations::default(),
            jobs: 0,
            out: None,
            replay: false,
            stop: None,
            shard: None,
        }
    }
}

/// The folder of member `k` inside an ensemble's output folder.
pub fn member_dir_name(k: usize) -> String {
    format!("member-{k:03}")
}

/// Runs the ensemble of the scenario `t` gives with its file's seed (`sc`): every member (`sc`
/// compiled again with its perturbation written into the file's keys) to its end on `opts.jobs` threads, each written
/// into its folder when `opts.out` is set, then `ensemble.json` and `ensemble.csv` there.
/// A member that blows up counts as `unstable`; any other error stops the ensemble.
/// `progress(done, total)` is called after each member.
pub fn run_ensemble(
    t: &ScenarioTemplate,
    opts: &EnsembleOptions,
    progress: impl Fn(usize, usize) + Sync,
) -> Result<EnsembleReport> {
    opts.perturbations.check(opts.members)?;
    let sc = &t.file_scenario()?;
    if let Some((i, count)) = opts.shard
        && (count == 0 || i >= count)
    {
        return Err(Error::setting(
            "ensemble settings",
            "shard",
            format!("must be (index, count) with 0 <= index < count, got ({i}, {count})"),
        ));
    }
    let n = opts.members;
    let robots = sc.robot_count();
    let members: Vec<Member> = (0..n)
        .filter(|k| opts.shard.is_none_or(|(i, c)| k % c == i))
        .map(|k| {
            if robots > 1 {
                opts.perturbations.team_member(opts.seed, k, robots)
            } else {
                opts.perturbations.member(opts.seed, k)
            }
        })
        .collect();
    if members.is_empty() {
        return Err(Error::setting(
            "ensemble settings",
            "shard",
            format!("{:?} holds none of the {n} members", opts.shard),
        ));
    }
    let jobs = if opts.jobs == 0 {
        std::thread::available_parallelism().map_or(1, |p| p.get())
    } else {
        opts.jobs
    }
    .clamp(1, members.len());
    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<MemberResult>>> = Mutex::new(vec![None; members.len()]);
    let first_error: Mutex<Option<Error>> = Mutex::new(None);
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| {
                loop {
                    let failed = first_error.lock().map_or(true, |e| e.is_some());
                    if failed || opts.stop.is_some_and(|s| s.load(Ordering::SeqCst)) {
                        return;
                    }
                    let k = next.fetch_add(1, Ordering::SeqCst);
                    let Some(m) = members.get(k) else { return };
                    match run_member(t, sc, m, opts.out.as_deref(), opts.replay, opts.stop) {
                        // Stopped from outside mid-run: not a member.
                        Ok(None) => return,
                        Ok(Some(r)) => {
                            if let Ok(mut v) = results.lock() {
                                v[k] = Some(r);
                            }
                            progress(done.fetch_add(1, Ordering::SeqCst) + 1, members.len());
                        }
                        Err(e) => {
                            if let Ok(mut slot) = first_error.lock() {
                                slot.get_or_insert(e);
                            }
                            return;
                        }
                    }
                }
            });
        }
    });
    if let Some(e) = first_error.into_inner().ok().flatten() {
        return Err(e);
    }
    let results: Vec<MemberResult> = results
        .into_inner()
        .unwrap_or_default()
        .into_iter()
        .flatten()
        .collect();
    let report = EnsembleReport {
        scenario: sc.source.as_ref().map(|p| p.display().to_string()),
        method: sc.method.name(),
        seed: opts.seed,
        perturbations: opts.perturbations,
        requested: n,
        members: results,
    };
    if let (Some(out), None) = (&opts.out, opts.shard) {
        report.write(out)?;
    }
    Ok(report)
}

/// Runs one member to its end (and writes its folder); None if `stop` ended it first.
fn run_member(
    t: &ScenarioTemplate,
    sc: &Scenario,
    m: &Member,
    out: Option<&Path>,
    replay: bool,
    stop: Option<&'static AtomicBool>,
) -> Result<Option<MemberResult>> {
    let msc = m.scenario(t, sc)?;
    let dir = out.map(|o| o.join(member_dir_name(m.index)));
    let opts = crate::run::RunOptions {
        realtime: false,
        stop,
    };
    // A member's folder is marked while its run writes it (issue 45); the mark stays on a
    // member that was interrupted or went unstable (its folder holds no result of this run).
    if let Some(dir) = &dir {
        crate::output::incomplete::mark_incomplete(dir)?;
    }
    let which = crate::output::Outputs::data(replay);
    let interrupted = |o: &crate::run::Outcome| matches!(o, crate::run::Outcome::Interrupted(_));
    let ran = if msc.robot_count() > 1 {
        // A world of several robots: its outcome by its rule, each robot's in the member.
        crate::run::run_team(&msc, opts).and_then(|r| {
            if interrupted(&r.outcome) {
                return Ok(None);
            }
            if let Some(dir) = &dir {
                crate::output::write_team(&msc, &r, dir, which)?;
                crate::output::incomplete::mark_complete(dir)?;
            }
            Ok(Some(MemberResult::of_team(m.clone(), sc, &r, dir.clone())))
        })
    } else {
        crate::run::run_scenario_with(&msc, opts, |_, _| {}).and_then(|r| {
            if interrupted(&r.outcome) {
                return Ok(None);
            }
            if let Some(dir) = &dir {
                crate::output::write_outputs(&msc, &r, dir, which)?;
                crate::output::incomplete::mark_complete(dir)?;
            }
            Ok(Some(MemberResult::of_run(m.clone(), sc, &r, dir.clone())))
        })
    };
    // Stopped from outside mid-run: not a member (None); blown up: an unstable member.
    match ran {
        Err(e @ Error::Unstable { .. }) => Ok(Some(MemberResult::unstable(m.clone(), sc, &e, dir))),
        other => other,
    }
}
