//! What an ensemble shows ([`EnsembleReport`]): each member's outcome and final pose, the
//! outcome fraction and verdict, the spread of outcome times and final poses, in words
//! ([`EnsembleReport::text`]) and as `ensemble.json` / `ensemble.csv`; and the scenario's
//! `[expect]` ensemble bounds checked against it ([`check_ensemble`]).

use super::Member;
use crate::error::{Error, Result};
use crate::model::{EnsembleExpectation, Scenario};
use crate::run::RunResult;
use crate::world::PoseRpy;
use std::path::{Path, PathBuf};

/// One member's result.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct MemberResult {
    /// Its perturbation.
    pub member: Member,
    /// The file keys that reproduce it with `tracksim run` (key, value).
    pub keys: Vec<(String, f64)>,
    /// "success", "failure", "completed", "interrupted" or "unstable".
    pub outcome: String,
    /// Why.
    pub reason: String,
    /// When the outcome was decided (the end of the run if never), s (NaN, null in JSON, if
    /// unknown).
    #[serde(deserialize_with = "nan_if_null")]
    pub outcome_time_s: f64,
    /// The body's final pose, m and rad.
    pub final_pose: PoseRpy,
    /// Progress along the start heading, m (NaN, null in JSON, for an unstable member).
    #[serde(deserialize_with = "nan_if_null")]
    pub progress_m: f64,
    /// Its run folder, if written.
    pub dir: Option<PathBuf>,
    /// In a world of several robots: the robot ranked first on the course (a race's winner;
    /// none without a course, or when no robot finished).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub winner: Option<String>,
    /// In a world of several robots, each robot's own result, in the file's order (the
    /// member's `outcome` is the world's by its rule; its `final_pose` and `progress_m` are
    /// robot 0's). Empty for one robot.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub robots: Vec<RobotResult>,
    /// How close it came to its limits (robot 0's in a world of several; none for a member
    /// that blew up): issue 62, from its `summary.json` `margins`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub margins: Option<MemberMargins>,
}

/// A member's margins (`summary.json` `margins` in short).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MemberMargins {
    /// The largest |pitch|, deg.
    pub peak_abs_pitch_deg: f64,
    /// The largest |roll|, deg.
    pub peak_abs_roll_deg: f64,
    /// The tip limit less the larger of the two, deg.
    pub tilt_margin_deg: f64,
    /// The smallest normal load any track carried from 1 s on, N (NaN, null in JSON, when
    /// the run was shorter).
    #[serde(deserialize_with = "nan_if_null")]
    pub min_track_load_n: f64,
}

impl MemberMargins {
    /// A run's margins in short.
    pub fn of(m: &crate::run::Margins) -> Self {
        let peak = |p: Option<crate::run::Peak>| p.map_or(0.0, |p| p.value);
        MemberMargins {
            peak_abs_pitch_deg: peak(m.peak_abs_pitch_deg),
            peak_abs_roll_deg: peak(m.peak_abs_roll_deg),
            tilt_margin_deg: m.tilt_margin_deg,
            min_track_load_n: m
                .tracks
                .iter()
                .filter_map(|t| t.min_normal_load_n.map(|p| p.value))
                .fold(f64::NAN, f64::min),
        }
    }
}

/// One robot's result in a member of an ensemble of several robots.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct RobotResult {
    /// Its name.
    pub name: String,
    /// "success", "failure", "completed" or "interrupted".
    pub outcome: String,
    /// When it was decided (the end of the run if never), s.
    #[serde(deserialize_with = "nan_if_null")]
    pub outcome_time_s: f64,
    /// Its final pose, m and rad.
    pub final_pose: PoseRpy,
    /// Progress along its start heading, m.
    #[serde(deserialize_with = "nan_if_null")]
    pub progress_m: f64,
}

impl MemberResult {
    /// The result of a member that ran to its end.
    pub(super) fn of_run(m: Member, sc: &Scenario, r: &RunResult, dir: Option<PathBuf>) -> Self {
        let s = &r.summary;
        MemberResult {
            keys: m.keys(sc),
            member: m,
            outcome: s.outcome.clone(),
            reason: s.outcome_reason.clone(),
            outcome_time_s: s.outcome_time_s,
            final_pose: s.final_pose,
            progress_m: s.progress_m,
            dir,
            winner: None,
            robots: Vec::new(),
            margins: Some(MemberMargins::of(&s.margins)),
        }
    }

    /// The result of a member of several robots that ran to its end: the world's outcome,
    /// its winner on the course, and each robot's.
    pub(super) fn of_team(
        m: Member,
        sc: &Scenario,
        r: &crate::run::TeamResult,
        dir: Option<PathBuf>,
    ) -> Self {
        let robots: Vec<RobotResult> = r
            .robots
            .iter()
            .map(|(name, run)| RobotResult {
                name: name.clone(),
                outcome: run.summary.outcome.clone(),
                outcome_time_s: run.summary.outcome_time_s,
                final_pose: run.summary.final_pose,
                progress_m: run.summary.progress_m,
            })
            .collect();
        let first = robots.first();
        MemberResult {
            keys: m.keys(sc),
            member: m,
            outcome: r.outcome.name().to_string(),
            reason: r.outcome.reason().to_string(),
            outcome_time_s: r.outcome_time,
            final_pose: first.map(|x| x.final_pose).unwrap_or_default(),
            progress_m: first.map_or(f64::NAN, |x| x.progress_m),
            dir,
            winner: r.standings.as_ref().and_then(|s| s.winner.clone()),
            robots,
            margins: r
                .robots
                .first()
                .map(|(_, run)| MemberMargins::of(&run.summary.margins)),
        }
    }

    /// A member that blew up (`Error::Unstable`).
    pub(super) fn unstable(m: Member, sc: &Scenario, e: &Error, dir: Option<PathBuf>) -> Self {
        let t = match e {
            Error::Unstable { time_s, .. } => *time_s,
            _ => f64::NAN,
        };
        MemberResult {
            keys: m.keys(sc),
            member: m,
            outcome: "unstable".into(),
            reason: e.to_string(),
            outcome_time_s: t,
            final_pose: PoseRpy::default(),
            progress_m: f64::NAN,
            dir,
            winner: None,
            robots: Vec::new(),
            margins: None,
        }
    }
}

/// The spread of each margin over an ensemble's members (`ensemble.json` `margins`).
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct MarginSpreads {
    /// Peak |pitch|, deg.
    pub peak_abs_pitch_deg: Option<Spread>,
    /// Peak |roll|, deg.
    pub peak_abs_roll_deg: Option<Spread>,
    /// Tilt margin, deg.
    pub tilt_margin_deg: Option<Spread>,
    /// Smallest track load, N.
    pub min_track_load_n: Option<Spread>,
}

/// Smallest, median and largest of some values (None: no value).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Spread {
    /// Smallest.
    pub min: f64,
    /// Median (mean of the middle two for an even count).
    pub median: f64,
    /// Largest.
    pub max: f64,
}

impl Spread {
    /// The spread of `values` (None if empty).
    pub fn of(values: &[f64]) -> Option<Spread> {
        let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
        if v.is_empty() {
            return None;
        }
        v.sort_by(f64::total_cmp);
        let n = v.len();
        let median = if n % 2 == 1 {
            v[n / 2]
        } else {
            0.5 * (v[n / 2 - 1] + v[n / 2])
        };
        Some(Spread {
            min: v[0],
            median,
            max: v[n - 1],
        })
    }

    /// max - min.
    pub fn width(&self) -> f64 {
        self.max - self.min
    }
}

/// A final-pose coordinate in the report: name, how to read it, scale to the unit, unit.
type Coordinate = (&'static str, fn(&PoseRpy) -> f64, f64, &'static str);

/// A number that JSON wrote as null (serde_json writes NaN so): NaN.
fn nan_if_null<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<f64, D::Error> {
    Ok(<Option<f64> as serde::Deserialize>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// An ensemble's results.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct EnsembleReport {
    /// The scenario file, if any.
    pub scenario: Option<String>,
    /// Track method.
    pub method: String,
    /// Seed of the perturbations.
    pub seed: u64,
    /// Their sizes.
    pub perturbations: super::Perturbations,
    /// Members asked for.
    pub requested: usize,
    /// Members that ran, in index order (fewer than asked if stopped).
    pub members: Vec<MemberResult>,
}

impl EnsembleReport {
    /// Members whose outcome is `name`.
    pub fn count(&self, name: &str) -> usize {
        self.members.iter().filter(|m| m.outcome == name).count()
    }

    /// Successes over the members that ran (0 if none ran).
    pub fn success_fraction(&self) -> f64 {
        if self.members.is_empty() {
            0.0
        } else {
            self.count("success") as f64 / self.members.len() as f64
        }
    }

    /// The verdict: `S 16/16` (every member succeeded), `F 16/16` (every member failed),
    /// `C 16/16` (every member completed without a success condition), otherwise
    /// `marginal 9/16` (successes over members); `interrupted 5/16` if not every member ran.
    pub fn verdict(&self) -> String {
        let n = self.members.len();
        if n < self.requested {
            return format!("interrupted {n}/{}", self.requested);
        }
        for (name, letter) in [("success", "S"), ("failure", "F"), ("completed", "C")] {
            if self.count(name) == n {
                return format!("{letter} {n}/{n}");
            }
        }
        format!("marginal {}/{n}", self.count("success"))
    }

    /// In a world of several robots on a course: how many members each robot won (ranked
    /// first), most first, then by name; `none` counts the members no robot won. Empty for
    /// one robot or without a course.
    pub fn winners(&self) -> Vec<(String, usize)> {
        if !self.members.iter().any(|m| m.winner.is_some()) {
            return Vec::new();
        }
        let mut counts: Vec<(String, usize)> = Vec::new();
        for m in &self.members {
            let w = m.winner.clone().unwrap_or_else(|| "none".into());
            match counts.iter_mut().find(|(n, _)| *n == w) {
                Some(c) => c.1 += 1,
                None => counts.push((w, 1)),
            }
        }
        counts.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        counts
    }

    /// The winner's verdict: `red 16/16` when one robot won every member, else `marginal: red
    /// 9/16, blue 7/16`; None without winners ([`EnsembleReport::winners`]).
    pub fn winner_verdict(&self) -> Option<String> {
        let w = self.winners();
        let n = self.members.len();
        match w.as_slice() {
            [] => None,
            [(name, k)] => Some(format!("{name} {k}/{n}")),
            _ => Some(format!(
                "marginal: {}",
                w.iter()
                    .map(|(name, k)| format!("{name} {k}/{n}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
        }
    }

    /// In a world of several robots: each robot's verdict over the members (as
    /// [`EnsembleReport::verdict`], of its own outcome) and the spread of its success times.
    pub fn robot_verdicts(&self) -> Vec<(String, String, Option<Spread>)> {
        let Some(first) = self.members.iter().find(|m| !m.robots.is_empty()) else {
            return Vec::new();
        };
        let n = self.members.len();
        first
            .robots
            .iter()
            .enumerate()
            .map(|(r, robot)| {
                let mine: Vec<&RobotResult> = self
                    .members
                    .iter()
                    .filter_map(|m| m.robots.get(r))
                    .collect();
                let count = |o: &str| mine.iter().filter(|x| x.outcome == o).count();
                let verdict = [("success", "S"), ("failure", "F"), ("completed", "C")]
                    .iter()
                    .find(|(o, _)| count(o) == n)
                    .map_or_else(
                        || format!("marginal {}/{n}", count("success")),
                        |(_, l)| format!("{l} {n}/{n}"),
                    );
                let times: Vec<f64> = mine
                    .iter()
                    .filter(|x| x.outcome == "success")
                    .map(|x| x.outcome_time_s)
                    .collect();
                (robot.name.clone(), verdict, Spread::of(&times))
            })
            .collect()
    }

    /// Outcome times of the members that succeeded, s.
    pub fn success_times(&self) -> Option<Spread> {
        let t: Vec<f64> = self
            .members
            .iter()
            .filter(|m| m.outcome == "success")
            .map(|m| m.outcome_time_s)
            .collect();
        Spread::of(&t)
    }

    /// Spread of one final-pose coordinate over the members that did not blow up.
    pub fn final_spread(&self, pick: impl Fn(&PoseRpy) -> f64) -> Option<Spread> {
        let v: Vec<f64> = self
            .members
            .iter()
            .filter(|m| m.outcome != "unstable")
            .map(|m| pick(&m.final_pose))
            .collect();
        Spread::of(&v)
    }

    /// Spread of one margin over the members that have margins (issue 62).
    pub fn margin_spread(&self, pick: impl Fn(&MemberMargins) -> f64) -> Option<Spread> {
        let v: Vec<f64> = self
            .members
            .iter()
            .filter_map(|m| m.margins.as_ref().map(&pick))
            .collect();
        Spread::of(&v)
    }

    /// The margins' spreads: peak |pitch|, peak |roll|, tilt margin, smallest track load.
    pub fn margin_spreads(&self) -> MarginSpreads {
        MarginSpreads {
            peak_abs_pitch_deg: self.margin_spread(|m| m.peak_abs_pitch_deg),
            peak_abs_roll_deg: self.margin_spread(|m| m.peak_abs_roll_deg),
            tilt_margin_deg: self.margin_spread(|m| m.tilt_margin_deg),
            min_track_load_n: self.margin_spread(|m| m.min_track_load_n),
        }
    }

    /// The report in words: verdict, counts, outcome times, final pose spread, perturbations.
    pub fn text(&self) -> String {
        let p = &self.perturbations;
        let mut s = format!(
            "ensemble of {} members ({}): {}\n",
            self.requested,
            self.method,
            self.verdict()
        );
        let counts: Vec<String> = ["success", "failure", "completed", "unstable", "interrupted"]
            .iter()
            .filter(|n| self.count(n) > 0)
            .map(|n| format!("{} {n}", self.count(n)))
            .collect();
        s += &format!(
            "  outcomes: {} (success fraction {:.3})\n",
            counts.join(", "),
            self.success_fraction()
        );
        if let Some(t) = self.success_times() {
            s += &format!(
                "  success time: median {:.2} s, {:.2}-{:.2} s (spread {:.2} s)\n",
                t.median,
                t.min,
                t.max,
                t.width()
            );
        }
        let coords: [Coordinate; 4] = [
            ("x", |p| p.x, 1.0, "m"),
            ("y", |p| p.y, 1.0, "m"),
            ("z", |p| p.z, 1.0, "m"),
            ("yaw", |p| p.yaw, 1f64.to_degrees(), "deg"),
        ];
        let parts: Vec<String> = coords
            .iter()
            .filter_map(|(name, pick, scale, unit)| {
                self.final_spread(pick)
                    .map(|sp| format!("{name} {:.3}..{:.3} {unit}", sp.min * scale, sp.max * scale))
            })
            .collect();
        if !parts.is_empty() {
            s += &format!("  final pose: {}\n", parts.join(", "));
        }
        let ms = self.margin_spreads();
        if let (Some(p), Some(m)) = (ms.peak_abs_pitch_deg, ms.tilt_margin_deg) {
            let load = ms.min_track_load_n.map_or(String::new(), |l| {
                format!(", lightest track {:.1}..{:.1} N", l.min, l.max)
            });
            s += &format!(
                "  margins: peak pitch {:.1}..{:.1} deg, tilt margin {:.1}..{:.1} deg{load}\n",
                p.min, p.max, m.min, m.max
            );
        }
        if let Some(w) = self.winner_verdict() {
            s += &format!("  winner: {w}\n");
        }
        for (name, verdict, times) in self.robot_verdicts() {
            let t = times.map_or(String::new(), |t| {
                format!(
                    ", success time median {:.2} s, {:.2}-{:.2} s",
                    t.median, t.min, t.max
                )
            });
            s += &format!("  robot {name}: {verdict}{t}\n");
        }
        let each = if self.members.iter().any(|m| !m.robots.is_empty()) {
            "each robot's start "
        } else {
            "start "
        };
        s += &format!(
            "  perturbations (seed {}): {each}+-{} mm in x and y, yaw +-{} deg, solver order {}; member 0 as written\n",
            self.seed,
            p.start_m * 1e3,
            p.yaw_deg,
            if p.solver_order { "varied" } else { "kept" }
        );
        for m in &self.members {
            if m.outcome != "success" && self.count("success") * 2 >= self.members.len() {
                s += &format!(
                    "  member {}: {} ({})\n",
                    m.member.index, m.outcome, m.reason
                );
            }
        }
        s
    }

    /// The report as JSON (`ensemble.json`): verdict, success fraction, success times, the
    /// perturbations and every member with its keys.
    pub fn to_json(&self) -> Result<String> {
        #[derive(serde::Serialize)]
        struct Json<'a> {
            verdict: String,
            success_fraction: f64,
            success_time_s: Option<Spread>,
            #[serde(skip_serializing_if = "Option::is_none")]
            winner_verdict: Option<String>,
            #[serde(skip_serializing_if = "Vec::is_empty")]
            winners: Vec<(String, usize)>,
            #[serde(skip_serializing_if = "Vec::is_empty")]
            robot_verdicts: Vec<RobotVerdict>,
            margins: MarginSpreads,
            #[serde(flatten)]
            report: &'a EnsembleReport,
        }
        #[derive(serde::Serialize)]
        struct RobotVerdict {
            name: String,
            verdict: String,
            success_time_s: Option<Spread>,
        }
        serde_json::to_string_pretty(&Json {
            verdict: self.verdict(),
            success_fraction: self.success_fraction(),
            success_time_s: self.success_times(),
            winner_verdict: self.winner_verdict(),
            winners: self.winners(),
            robot_verdicts: self
                .robot_verdicts()
                .into_iter()
                .map(|(name, verdict, success_time_s)| RobotVerdict {
                    name,
                    verdict,
                    success_time_s,
                })
                .collect(),
            margins: self.margin_spreads(),
            report: self,
        })
        .map_err(|e| Error::Build(format!("ensemble.json: {e}")))
    }

    /// A report read back from its JSON ([`EnsembleReport::to_json`], e.g. a shard's sent from
    /// another machine); the verdict and spreads are recomputed from the members.
    pub fn from_json(text: &str) -> Result<Self> {
        serde_json::from_str(text).map_err(|e| {
            Error::setting(
                "ensemble merge",
                "report",
                format!("not an ensemble report's JSON: {e}"),
            )
        })
    }

    /// The reports of an ensemble's shards ([`super::EnsembleOptions::shard`]) as one: the
    /// same scenario, method, seed, perturbations and size, members joined in index order
    /// (each once); refused, naming what differs, otherwise.
    pub fn merge(parts: Vec<EnsembleReport>) -> Result<EnsembleReport> {
        let bad = |m: String| Error::setting("ensemble merge", "reports", m);
        let mut parts = parts.into_iter();
        let Some(mut all) = parts.next() else {
            return Err(bad("no report to merge".into()));
        };
        for p in parts {
            let same = p.scenario == all.scenario
                && p.method == all.method
                && p.seed == all.seed
                && p.perturbations == all.perturbations
                && p.requested == all.requested;
            if !same {
                return Err(bad(format!(
                    "the shards are of different ensembles: {:?} {} seed {} ({} members) and \
                     {:?} {} seed {} ({} members)",
                    all.scenario,
                    all.method,
                    all.seed,
                    all.requested,
                    p.scenario,
                    p.method,
                    p.seed,
                    p.requested
                )));
            }
            all.members.extend(p.members);
        }
        all.members.sort_by_key(|m| m.member.index);
        if let Some(w) = all
            .members
            .windows(2)
            .find(|w| w[0].member.index == w[1].member.index)
        {
            return Err(bad(format!(
                "member {} is in two shards",
                w[0].member.index
            )));
        }
        Ok(all)
    }

    /// Writes `ensemble.json` (the report, each member with its keys) and `ensemble.csv`
    /// (one row per member) into `out`.
    pub fn write(&self, out: &Path) -> Result<()> {
        let io = |path: &Path| {
            let path = path.to_path_buf();
            move |source| Error::Io { path, source }
        };
        std::fs::create_dir_all(out).map_err(io(out))?;
        let json = self.to_json()?;
        let path = out.join("ensemble.json");
        crate::files::write_atomic(&path, json.as_bytes())?;
        let mut w = csv::Writer::from_writer(Vec::new());
        let csv_err = |e: csv::Error| Error::Build(format!("ensemble.csv: {e}"));
        // A world of several robots: the winner and each robot's figures after the world's.
        let names: Vec<String> = self
            .members
            .iter()
            .find(|m| !m.robots.is_empty())
            .map(|m| m.robots.iter().map(|r| r.name.clone()).collect())
            .unwrap_or_default();
        let mut header: Vec<String> = [
            "member",
            "dx_m",
            "dy_m",
            "dyaw_deg",
            "order_salt",
            "outcome",
            "outcome_time_s",
            "final_x_m",
            "final_y_m",
            "final_z_m",
            "final_yaw_rad",
            "progress_m",
            "reason",
            "peak_abs_pitch_deg",
            "peak_abs_roll_deg",
            "tilt_margin_deg",
            "min_track_load_n",
        ]
        .map(String::from)
        .to_vec();
        if !names.is_empty() {
            header.push("winner".into());
            for n in &names {
                for col in [
                    "outcome",
                    "outcome_time_s",
                    "final_x_m",
                    "final_y_m",
                    "progress_m",
                ] {
                    header.push(format!("{n}.{col}"));
                }
            }
        }
        w.write_record(&header).map_err(csv_err)?;
        for m in &self.members {
            let p = &m.final_pose;
            let mut row = vec![
                m.member.index.to_string(),
                m.member.dx_m.to_string(),
                m.member.dy_m.to_string(),
                m.member.dyaw_deg.to_string(),
                m.member.order_salt.to_string(),
                m.outcome.clone(),
                m.outcome_time_s.to_string(),
                p.x.to_string(),
                p.y.to_string(),
                p.z.to_string(),
                p.yaw.to_string(),
                m.progress_m.to_string(),
                m.reason.clone(),
            ];
            match &m.margins {
                Some(g) => row.extend(
                    [
                        g.peak_abs_pitch_deg,
                        g.peak_abs_roll_deg,
                        g.tilt_margin_deg,
                        g.min_track_load_n,
                    ]
                    .map(|v| v.to_string()),
                ),
                None => row.extend(std::iter::repeat_n(String::new(), 4)),
            }
            if !names.is_empty() {
                row.push(m.winner.clone().unwrap_or_default());
                for k in 0..names.len() {
                    match m.robots.get(k) {
                        Some(r) => row.extend([
                            r.outcome.clone(),
                            r.outcome_time_s.to_string(),
                            r.final_pose.x.to_string(),
                            r.final_pose.y.to_string(),
                            r.progress_m.to_string(),
                        ]),
                        // An unstable member has no robot results.
                        None => row.extend(std::iter::repeat_n(String::new(), 5)),
                    }
                }
            }
            w.write_record(&row).map_err(csv_err)?;
        }
        let bytes = w
            .into_inner()
            .map_err(|e| Error::Build(format!("ensemble.csv: {e}")))?;
        crate::files::write_atomic(&out.join("ensemble.csv"), &bytes)
    }
}

/// Every way the ensemble misses the scenario's `[expect]` ensemble bounds, one line each
/// (empty: met).
pub fn check_ensemble(e: &EnsembleExpectation, r: &EnsembleReport) -> Vec<String> {
    let mut misses = Vec::new();
    if r.members.len() < r.requested {
        misses.push(format!(
            "only {} of {} members ran",
            r.members.len(),
            r.requested
        ));
    }
    if let Some([lo, hi]) = e.success_fraction {
        let f = r.success_fraction();
        if !(lo..=hi).contains(&f) {
            misses.push(format!(
                "success fraction {f:.3} ({}) outside [{lo}, {hi}]",
                r.verdict()
            ));
        }
    }
    if let Some([lo, hi]) = e.outcome_time_spread {
        match r.success_times() {
            Some(t) if !(lo..=hi).contains(&t.width()) => misses.push(format!(
                "success times spread {:.3} s ({:.2}-{:.2} s) outside [{lo}, {hi}] s",
                t.width(),
                t.min,
                t.max
            )),
            Some(_) => {}
            None => {
                misses.push("a spread of success times was expected but no member succeeded".into())
            }
        }
    }
    misses
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_and_median() {
        let s = Spread::of(&[3.0, 1.0, 2.0, f64::NAN]).unwrap();
        assert_eq!((s.min, s.median, s.max), (1.0, 2.0, 3.0));
        assert_eq!(Spread::of(&[1.0, 2.0]).unwrap().median, 1.5);
        assert!(Spread::of(&[]).is_none());
    }
}
