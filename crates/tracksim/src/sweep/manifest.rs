//! The manifest of a sweep: one JSON line per run ([`ManifestLine`]), each also kept in its run
//! folder as `run.json`, and the merge of shards' folders into one manifest.

use super::plan::{RunSpec, manifest_name, run_dir_name};
use crate::error::{Error, Result, SpecIssue};
use crate::model::Scenario;
use crate::run::RunResult;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// One run of a sweep: what it was (index, seed, parameters) and how it went. Wall-clock times
/// are left out (they are in the run's `summary.json`), so a manifest depends only on the
/// sweep, never on the machine, the shards or the job count.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ManifestLine {
    /// Run index.
    pub index: usize,
    /// Folder, relative to the sweep's output folder.
    pub dir: String,
    /// Seed.
    pub seed: u64,
    /// The `[randomize]` values, by name (drawn or fixed by the grid).
    pub params: BTreeMap<String, f64>,
    /// "success", "failure", "completed" or "unstable".
    pub outcome: String,
    /// Why.
    pub reason: String,
    /// When the outcome was decided, s.
    pub outcome_time_s: f64,
    /// Simulated time, s.
    pub sim_time_s: f64,
    /// Progress along the start heading, m.
    pub progress_m: f64,
    /// Horizontal path length, m.
    pub distance_m: f64,
    /// Final pose: x, y, z (m), roll, pitch, yaw (rad).
    pub final_pose: [f64; 6],
    /// Largest |roll| and |pitch| over the trajectory rows, rad.
    pub max_tilt_rad: f64,
}

impl ManifestLine {
    /// The line of a finished run.
    pub fn of_run(r: &RunSpec, sc: &Scenario, res: &RunResult) -> Self {
        let s = &res.summary;
        let p = s.final_pose;
        ManifestLine {
            index: r.index,
            dir: format!("runs/{}", run_dir_name(r.index)),
            seed: r.seed,
            params: sc.randomized.clone(),
            outcome: s.outcome.clone(),
            reason: s.outcome_reason.clone(),
            outcome_time_s: s.outcome_time_s,
            sim_time_s: s.sim_time_s,
            progress_m: s.progress_m,
            distance_m: s.distance_m,
            final_pose: [p.x, p.y, p.z, p.roll, p.pitch, p.yaw],
            max_tilt_rad: res
                .samples
                .iter()
                .map(|x| x.pose.roll.abs().max(x.pose.pitch.abs()))
                .fold(0.0, f64::max),
        }
    }

    /// The line of a run that went unstable.
    pub fn unstable(r: &RunSpec, sc: &Scenario, e: &Error) -> Self {
        let t = match e {
            Error::Unstable { time_s, .. } => *time_s,
            _ => 0.0,
        };
        ManifestLine {
            index: r.index,
            dir: format!("runs/{}", run_dir_name(r.index)),
            seed: r.seed,
            params: sc.randomized.clone(),
            outcome: "unstable".into(),
            reason: e.to_string(),
            outcome_time_s: t,
            sim_time_s: t,
            progress_m: f64::NAN,
            distance_m: f64::NAN,
            final_pose: [f64::NAN; 6],
            max_tilt_rad: f64::NAN,
        }
    }
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> Error {
    let path = path.to_path_buf();
    move |source| Error::Io { path, source }
}

pub(super) fn write_run_json(path: &Path, line: &ManifestLine) -> Result<()> {
    let text = serde_json::to_string(line).expect("manifest line serialises");
    crate::files::write_atomic(path, (text + "\n").as_bytes())
}

/// Writes lines to a JSON-lines file (through a temporary file renamed into place).
pub(super) fn write_lines(path: &Path, lines: &[ManifestLine]) -> Result<()> {
    let text: String = lines
        .iter()
        .map(|l| serde_json::to_string(l).expect("manifest line serialises") + "\n")
        .collect();
    crate::files::write_atomic(path, text.as_bytes())
}

/// Every finished run in a sweep folder (`runs/run-*/run.json`), in index order.
pub fn read_runs(dir: &Path) -> Result<Vec<ManifestLine>> {
    let runs = dir.join("runs");
    let mut out = Vec::new();
    let entries = match std::fs::read_dir(&runs) {
        Ok(e) => e,
        Err(source) => return Err(Error::Io { path: runs, source }),
    };
    for e in entries {
        let e = e.map_err(io(&runs))?;
        let name = e.file_name().to_string_lossy().to_string();
        let f = e.path().join("run.json");
        if !name.starts_with("run-") || !f.is_file() {
            continue;
        }
        let text = std::fs::read_to_string(&f).map_err(io(&f))?;
        let line: ManifestLine = serde_json::from_str(&text).map_err(|e| Error::Parse {
            path: f.clone(),
            message: format!("not a run record of `tracksim sweep` ({e})"),
        })?;
        out.push(line);
    }
    out.sort_by_key(|l| l.index);
    Ok(out)
}

/// Merges the finished runs of sweep folders (shards written to one folder or to several) into
/// the sweep folder `out`: run folders not yet there are copied into `out/runs/`, and
/// `out/manifest.jsonl` lists every run in index order, exactly as one unsharded sweep would
/// have. A run index found twice with different records is an error. Returns the lines.
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<Vec<ManifestLine>> {
    let mut by_index: BTreeMap<usize, (ManifestLine, PathBuf)> = BTreeMap::new();
    for d in dirs {
        for l in read_runs(d)? {
            if let Some((old, from)) = by_index.get(&l.index) {
                if old != &l {
                    return Err(Error::Invalid {
                        path: d.clone(),
                        issues: vec![SpecIssue::new(
                            "",
                            format!(
                                "run {} is also in {} with other values: these folders are not shards of one sweep",
                                l.index,
                                from.display()
                            ),
                        )],
                    });
                }
                continue;
            }
            by_index.insert(l.index, (l, d.clone()));
        }
    }
    let runs = out.join("runs");
    std::fs::create_dir_all(&runs).map_err(io(&runs))?;
    for (l, from) in by_index.values() {
        let dst = out.join(&l.dir);
        if dst.join("run.json").is_file() {
            continue;
        }
        let src = from.join(&l.dir);
        let tmp = runs.join(format!(".merge-{}.tmp-{}", l.index, std::process::id()));
        std::fs::create_dir_all(&tmp).map_err(io(&tmp))?;
        for e in std::fs::read_dir(&src).map_err(io(&src))? {
            let e = e.map_err(io(&src))?;
            let to = tmp.join(e.file_name());
            std::fs::copy(e.path(), &to).map_err(io(&to))?;
        }
        std::fs::rename(&tmp, &dst).map_err(io(&dst))?;
    }
    let lines: Vec<ManifestLine> = by_index.into_values().map(|(l, _)| l).collect();
    write_lines(&out.join(manifest_name(None)), &lines)?;
    Ok(lines)
}
