//! The manifest of a sweep: one JSON line per run ([`ManifestLine`]), each also kept in its run
//! folder as `run.json`, and the merge of shards' folders into one manifest.

use super::plan::{RunSpec, manifest_name, run_dir_name};
use crate::error::{Error, Result, SpecIssue};
use crate::model::Scenario;
use crate::run::{RunResult, TeamResult};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// One run of a sweep: what it was (index, seed, parameters) and how it went. Wall-clock times
/// are left out (they are in the run's `summary.json`), so a manifest depends only on the
/// sweep, never on the machine, the shards or the job count. A figure that does not exist (a
/// run that went unstable, the world of a file with several robots) is `NaN`, written `null`.
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
    #[serde(deserialize_with = "nan_if_null")]
    pub outcome_time_s: f64,
    /// Simulated time, s.
    #[serde(deserialize_with = "nan_if_null")]
    pub sim_time_s: f64,
    /// Progress along the start heading, m.
    #[serde(deserialize_with = "nan_if_null")]
    pub progress_m: f64,
    /// Horizontal path length, m.
    #[serde(deserialize_with = "nan_if_null")]
    pub distance_m: f64,
    /// Final pose: x, y, z (m), roll, pitch, yaw (rad).
    #[serde(deserialize_with = "nan_if_null_6")]
    pub final_pose: [f64; 6],
    /// Largest |roll| and |pitch| over the trajectory rows, rad.
    #[serde(deserialize_with = "nan_if_null")]
    pub max_tilt_rad: f64,
    /// A file with several robots (`[[vehicles]]`): each robot's figures, in file order, its
    /// outputs in `DIR/NAME/`; the line's outcome is the world's by its rule, and its
    /// progress, distance, final pose and tilt are `null`. Absent for one robot.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub robots: Vec<RobotRun>,
}

/// One robot's figures in a [`ManifestLine`] of a file with several robots.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RobotRun {
    /// Its name (its folder under the run's).
    pub name: String,
    /// "success", "failure" or "completed".
    pub outcome: String,
    /// Why.
    pub reason: String,
    /// When its outcome was decided, s.
    pub outcome_time_s: f64,
    /// Progress along its start heading, m.
    pub progress_m: f64,
    /// Horizontal path length, m.
    pub distance_m: f64,
    /// Final pose: x, y, z (m), roll, pitch, yaw (rad).
    pub final_pose: [f64; 6],
    /// Largest |roll| and |pitch| over its trajectory rows, rad.
    pub max_tilt_rad: f64,
}

impl RobotRun {
    /// The figures of one robot's run `res`, named `name`.
    fn of(name: &str, res: &RunResult) -> Self {
        let s = &res.summary;
        let p = s.final_pose;
        RobotRun {
            name: name.to_string(),
            outcome: s.outcome.clone(),
            reason: s.outcome_reason.clone(),
            outcome_time_s: s.outcome_time_s,
            progress_m: s.progress_m,
            distance_m: s.distance_m,
            final_pose: [p.x, p.y, p.z, p.roll, p.pitch, p.yaw],
            max_tilt_rad: max_tilt(res),
        }
    }
}

/// Largest |roll| and |pitch| over a run's samples, rad.
fn max_tilt(res: &RunResult) -> f64 {
    res.samples
        .iter()
        .map(|x| x.pose.roll.abs().max(x.pose.pitch.abs()))
        .fold(0.0, f64::max)
}

/// A number of a line, `null` read as `NaN` (what `serde_json` writes for it).
fn nan_if_null<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// [`nan_if_null`] for a pose.
fn nan_if_null_6<'de, D: serde::Deserializer<'de>>(
    d: D,
) -> std::result::Result<[f64; 6], D::Error> {
    let v = <[Option<f64>; 6]>::deserialize(d)?;
    Ok(v.map(|x| x.unwrap_or(f64::NAN)))
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
            max_tilt_rad: max_tilt(res),
            robots: Vec::new(),
        }
    }

    /// The line of a finished run of a file with several robots: the world's outcome, each
    /// robot's figures in [`ManifestLine::robots`].
    pub fn of_team(r: &RunSpec, sc: &Scenario, res: &TeamResult) -> Self {
        ManifestLine {
            index: r.index,
            dir: format!("runs/{}", run_dir_name(r.index)),
            seed: r.seed,
            params: sc.randomized.clone(),
            outcome: res.outcome.name().into(),
            reason: res.outcome.reason(),
            outcome_time_s: res.outcome_time,
            sim_time_s: res
                .robots
                .first()
                .map_or(0.0, |(_, run)| run.summary.sim_time_s),
            progress_m: f64::NAN,
            distance_m: f64::NAN,
            final_pose: [f64::NAN; 6],
            max_tilt_rad: f64::NAN,
            robots: res
                .robots
                .iter()
                .map(|(name, run)| RobotRun::of(name, run))
                .collect(),
        }
    }

    /// Whether `other` records the same run: equal, `NaN` equal to `NaN` (as both are written).
    pub fn same_as(&self, other: &ManifestLine) -> bool {
        serde_json::to_value(self).ok() == serde_json::to_value(other).ok()
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
            robots: Vec::new(),
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
                if !old.same_as(&l) {
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
        copy_tree(&src, &tmp)?;
        std::fs::rename(&tmp, &dst).map_err(io(&dst))?;
    }
    let lines: Vec<ManifestLine> = by_index.into_values().map(|(l, _)| l).collect();
    write_lines(&out.join(manifest_name(None)), &lines)?;
    Ok(lines)
}

/// Copies the folder `src` into `dst` (created), its subfolders too (a run of several robots
/// has one per robot).
fn copy_tree(src: &Path, dst: &Path) -> Result<()> {
    std::fs::create_dir_all(dst).map_err(io(dst))?;
    for e in std::fs::read_dir(src).map_err(io(src))? {
        let e = e.map_err(io(src))?;
        let to = dst.join(e.file_name());
        if e.file_type().map_err(io(&e.path()))?.is_dir() {
            copy_tree(&e.path(), &to)?;
        } else {
            std::fs::copy(e.path(), &to).map_err(io(&to))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A line with `NaN` figures (an unstable run) reads back as it was written: `resume`,
    /// the manifest and `merge` read every finished run's `run.json`.
    #[test]
    fn an_unstable_line_reads_back() {
        let line = ManifestLine {
            index: 3,
            dir: "runs/run-000003".into(),
            seed: 7,
            params: BTreeMap::from([("friction".to_string(), 0.5)]),
            outcome: "unstable".into(),
            reason: "blew up".into(),
            outcome_time_s: 1.25,
            sim_time_s: 1.25,
            progress_m: f64::NAN,
            distance_m: f64::NAN,
            final_pose: [f64::NAN; 6],
            max_tilt_rad: f64::NAN,
            robots: Vec::new(),
        };
        let dir = std::env::temp_dir().join(format!("tracksim_manifest_{}", std::process::id()));
        let run = dir.join("runs/run-000003");
        std::fs::create_dir_all(&run).unwrap();
        write_run_json(&run.join("run.json"), &line).unwrap();
        let back = read_runs(&dir).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        assert_eq!(back.len(), 1);
        assert!(back[0].progress_m.is_nan() && back[0].final_pose.iter().all(|x| x.is_nan()));
        assert_eq!(back[0].sim_time_s, 1.25);
        assert!(back[0].same_as(&line));
        assert!(!back[0].same_as(&ManifestLine { seed: 8, ..line }));
    }
}
