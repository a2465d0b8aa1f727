//! What `tracksim validate` found: the report's types, its Markdown and its files.

use super::limits::{
    STEP_DURATION_S, STEP_EDGE_X_M, STEP_ON_TOP_Z_M, STEP_SPEED_MPS, STEP_SUCCESS_MARGIN_M,
    TABLE_IV_CONTACT_SLOP_M,
};
use crate::error::{Error, Result};
use crate::model::Method as TrackMethod;
use crate::output::SideLine;
use crate::run::RunResult;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// One Table IV case: front sub-track angle and step height, with and without grousers.
#[derive(Clone, Debug, Serialize)]
pub struct StepCase {
    /// Case name, e.g. `quince_00deg_120mm`.
    pub name: String,
    /// Validation case prefix of its runs, e.g. `table_iv/00deg_120mm`.
    pub case: String,
    /// Front sub-track angle, degrees (positive raises the tips).
    pub front_angle_deg: f64,
    /// Step height, mm.
    pub step_height_mm: f64,
    /// The real robot's result (paper Table IV): "S" or "F".
    pub reality: String,
    /// The paper's simulation's result (Table IV): "S" or "F".
    pub paper: String,
    /// This simulator, with grousers (the method under test), contact slop
    /// [`TABLE_IV_CONTACT_SLOP_M`] as in the paper's simulator: "S" or "F" (or "error").
    pub with_grousers: StepRun,
    /// With `--ensemble N`: the verdict of the row's ensemble with grousers ("S 8/8",
    /// "marginal 5/8"; reported, not asserted).
    pub ensemble: Option<String>,
    /// This simulator without grousers, same contact slop (reported, not asserted); `None` if
    /// not run.
    pub without_grousers: Option<StepRun>,
    /// This simulator with grousers and rigid contact (no slop; reported, not asserted);
    /// `None` if not run.
    pub with_grousers_rigid: Option<StepRun>,
    /// This simulator with compliant grousers and belts (the rubber of
    /// [`super::rubber::rubber_compliance`]), rigid terrain and no slop (reported, not asserted);
    /// `None` if not run.
    pub compliant_grousers: Option<StepRun>,
    /// `with_grousers` agrees with reality.
    pub passed: bool,
    /// Plot file stem.
    pub plot: String,
}

/// The rubber of the compliant Table IV column and the springs it gives each track.
#[derive(Clone, Debug, Serialize)]
pub struct RubberNote {
    /// Young's modulus, Pa.
    pub youngs_modulus_pa: f64,
    /// Loss factor.
    pub loss_factor: f64,
    /// Per track: name, grouser stiffness N/m and damping N s/m, belt stiffness N/m and
    /// damping N s/m (0 when the part is rigid).
    pub springs: Vec<(String, f64, f64, f64, f64)>,
}

/// One step attempt.
#[derive(Clone, Debug, Serialize)]
pub struct StepRun {
    /// Validation case name of the run, e.g. `table_iv/00deg_120mm/grousers_slop10`.
    pub case: String,
    /// "S" (on top of the step), "F" (did not get there) or "error" (the run failed).
    pub result: String,
    /// The run's outcome name ("success", "failure") or "error".
    pub outcome: String,
    /// Why, in words.
    pub reason: String,
    /// Simulated time at the end of the run, s.
    pub time_s: f64,
    /// Final body origin x, m.
    pub final_x_m: f64,
    /// Final body origin height above the step top (negative: below it), m.
    pub final_z_above_step_m: f64,
    /// Largest body pitch magnitude during the run, degrees.
    pub max_pitch_deg: f64,
    /// Deepest vehicle-terrain penetration in the trajectory rows (every 10 ms), mm.
    pub max_penetration_mm: f64,
    /// Wall-clock time of the run, s.
    pub wall_time_s: f64,
}

/// One slope angle.
#[derive(Clone, Debug, Serialize)]
pub struct SlopeRun {
    /// Validation case name of the run, e.g. `slope/31deg`.
    pub case: String,
    /// Slope, degrees.
    pub angle_deg: f64,
    /// Mean speed along the slope from 1 s to 4 s (positive uphill), m/s.
    pub speed_along_mps: f64,
    /// Climbed: uphill speed at least half the belt speed.
    pub climbed: bool,
    /// Error message if the run failed.
    pub error: Option<String>,
}

/// A checked figure (slope limit, turning, paper figures).
#[derive(Clone, Debug, Serialize)]
pub struct Case {
    /// Group: "slope", "turning", "paper figures".
    pub group: String,
    /// Case name.
    pub name: String,
    /// Validation case names of the runs the figure is judged on, e.g. `["turning/spin"]`.
    pub runs: Vec<String>,
    /// Run outcome(s), in words.
    pub outcome: String,
    /// What was measured.
    pub measured: String,
    /// What was expected.
    pub expected: String,
    /// Pass or fail.
    pub passed: bool,
    /// How the figure was obtained and why the expectation holds.
    pub note: String,
    /// Plot file stem.
    pub plot: String,
}

impl Case {
    /// The figure `name` of `group` whose run `run` failed with `e`.
    pub(super) fn error(group: &str, name: &str, run: &str, e: &Error) -> Case {
        Case {
            group: group.into(),
            name: name.into(),
            runs: vec![run.into()],
            outcome: "error".into(),
            measured: e.to_string(),
            expected: "a run".into(),
            passed: false,
            note: "the run did not complete".into(),
            plot: String::new(),
        }
    }
}

/// A figure to draw when the report is written.
#[derive(Clone, Debug)]
pub(super) struct PlotJob {
    pub(super) stem: String,
    pub(super) title: String,
    pub(super) runs: Vec<(String, RunResult)>,
    /// Terrain profile and outlines for the side view.
    pub(super) profile: SideLine,
    pub(super) outlines: Vec<SideLine>,
}

impl PlotJob {
    /// A plot of `runs` without terrain.
    pub(super) fn bare(stem: &str, title: String, runs: Vec<(String, RunResult)>) -> PlotJob {
        PlotJob {
            stem: stem.into(),
            title,
            runs,
            profile: Vec::new(),
            outlines: Vec::new(),
        }
    }
}

/// Everything `tracksim validate` found.
#[derive(Clone, Debug, Serialize)]
pub struct ValidationReport {
    /// Track method under test.
    pub method: String,
    /// Table IV (Quince step climbing).
    pub table_iv: Vec<StepCase>,
    /// Slope runs, one per angle.
    pub slope_runs: Vec<SlopeRun>,
    /// Slope limit, turning and paper-figure cases.
    pub cases: Vec<Case>,
    /// Wall-clock time of the whole validation, s.
    pub wall_time_s: f64,
    /// The solver setting every case ran at, in words (`--dt`, `--iterations`,
    /// `--stabilization-iterations`; "each file's" where not given).
    pub setting: String,
    /// The rubber of the compliant Table IV column, if it was run.
    pub rubber: Option<RubberNote>,
    /// Stopped by Ctrl-C or SIGTERM: the runs then running ended early, the others did not
    /// run (their cases fail).
    pub interrupted: bool,
    #[serde(skip)]
    pub(super) plots: Vec<PlotJob>,
}

impl ValidationReport {
    /// An empty report for `method`.
    pub(super) fn new(method: TrackMethod) -> ValidationReport {
        ValidationReport {
            method: method.name(),
            table_iv: Vec::new(),
            slope_runs: Vec::new(),
            cases: Vec::new(),
            wall_time_s: 0.0,
            setting: String::new(),
            interrupted: false,
            rubber: None,
            plots: Vec::new(),
        }
    }

    /// Every asserted case passed (the Table IV column with grousers, the slope limit, the
    /// turning figures and the paper figures). The no-grouser column is not asserted.
    pub fn passed(&self) -> bool {
        !self.interrupted
            && self.table_iv.iter().all(|c| c.passed)
            && self.cases.iter().all(|c| c.passed)
    }

    /// The report as Markdown.
    pub fn to_markdown(&self) -> String {
        let verdict = if self.passed() { "PASSED" } else { "FAILED" };
        let mut s = format!(
            "# Validation report\n\nTrack method: `{}`. Setting: {}. Overall: **{verdict}** ({} of {} asserted checks passed). Wall time {:.0} s.\n\n",
            self.method,
            self.setting,
            self.table_iv.iter().filter(|c| c.passed).count()
                + self.cases.iter().filter(|c| c.passed).count(),
            self.table_iv.len() + self.cases.len(),
            self.wall_time_s
        );
        if self.interrupted {
            s += "**Interrupted** (Ctrl-C or SIGTERM): the runs then running ended early and the others did not run; their cases fail.\n\n";
        }
        s += &self.table_iv_markdown();
        s += &self.cases_markdown();
        s += &self.slope_markdown();
        s
    }

    /// The compliant column's rubber in words (empty if it was not run).
    fn rubber_words(&self) -> String {
        let Some(r) = &self.rubber else {
            return String::new();
        };
        let mut s = format!(
            " Compliant grousers: each grouser and each belt link against the terrain is a spring and damper along the contact normal, from track rubber of Young's modulus {:.1} MPa and loss factor {} (grouser: tapered lug bent and sheared by a load at its tip; belt: its thickness compressed over one grouser pitch; VALIDATION.md), rigid terrain, no slop:",
            r.youngs_modulus_pa / 1e6,
            r.loss_factor
        );
        let mut seen = Vec::new();
        for (name, kg, cg, kb, cb) in &r.springs {
            let key = format!("{kg:.0}/{kb:.0}");
            if seen.contains(&key) {
                continue;
            }
            seen.push(key);
            s += &format!(
                " `{name}` (and alike) grouser {:.1} kN/m, {cg:.0} N s/m, belt {:.0} kN/m, {cb:.0} N s/m;",
                kg / 1e3,
                kb / 1e3
            );
        }
        s.pop();
        s.push('.');
        s
    }

    /// The Table IV section.
    fn table_iv_markdown(&self) -> String {
        let mut s = String::from("## Table IV: Quince climbing a step (paper Sec. IV-B)\n\n");
        s += &format!(
            "Quince (`vehicles/quince.toml`, 33 kg) drives at {STEP_SPEED_MPS} m/s towards a step whose edge is {:.2} m ahead of its body centre; friction 0.6 on ground, step and tracks; rear sub-tracks flat (0 deg). **S** = within {STEP_DURATION_S:.0} s the body centre is {STEP_SUCCESS_MARGIN_M:.2} m past the step edge (the whole main track on top) and at least {STEP_ON_TOP_Z_M:.2} m above the step's top surface, without tipping over (75 deg); otherwise **F**. Contact slop {:.0} mm (vehicle-terrain penetration left uncorrected, the `min_depth` of the paper's ODE simulator) unless the column says rigid or no slop.{} Only the column with grousers and slop is asserted; the paper says the grousers decide 120 mm @ 0 deg and 240 mm @ 45 deg.\n\n",
            STEP_EDGE_X_M,
            TABLE_IV_CONTACT_SLOP_M * 1000.0,
            self.rubber_words()
        );
        s += "| front sub-tracks | step | reality | paper | with grousers | without grousers | with grousers, rigid contact | compliant grousers, rigid terrain, no slop | pass | plot |\n";
        s += "|---|---|---|---|---|---|---|---|---|---|\n";
        let optional = |r: &Option<StepRun>| {
            r.as_ref()
                .map(|w| format!("{} ({})", w.result, run_words(w)))
                .unwrap_or_else(|| "not run".into())
        };
        for c in &self.table_iv {
            s += &format!(
                "| {:.0} deg | {:.0} mm | {} | {} | **{}** ({}) | {} | {} | {} | {} | [{}.png]({}.png) |\n",
                c.front_angle_deg,
                c.step_height_mm,
                c.reality,
                c.paper,
                c.with_grousers.result,
                match &c.ensemble {
                    Some(e) => format!("{}; ensemble {e}", run_words(&c.with_grousers)),
                    None => run_words(&c.with_grousers),
                },
                optional(&c.without_grousers),
                optional(&c.with_grousers_rigid),
                optional(&c.compliant_grousers),
                if c.passed { "yes" } else { "**NO**" },
                c.plot,
                c.plot
            );
        }
        s
    }

    /// The slope limit, turning and paper-figure section, with its notes.
    fn cases_markdown(&self) -> String {
        let mut s =
            String::from("\n## Slope limit, skid steering, paper figures, soil, accuracy\n\n");
        s += "| group | case | outcome | measured | expected | pass | plot |\n";
        s += "|---|---|---|---|---|---|---|\n";
        for c in &self.cases {
            s += &format!(
                "| {} | {} | {} | {} | {} | {} | {} |\n",
                c.group,
                c.name,
                c.outcome,
                c.measured,
                c.expected,
                if c.passed { "yes" } else { "**NO**" },
                if c.plot.is_empty() {
                    "-".to_string()
                } else {
                    format!("[{}.png]({}.png)", c.plot, c.plot)
                }
            );
        }
        s += "\nNotes:\n";
        for c in &self.cases {
            s += &format!("- *{}*: {}\n", c.name, c.note);
        }
        s
    }

    /// The table of slope runs (empty without them).
    fn slope_markdown(&self) -> String {
        if self.slope_runs.is_empty() {
            return String::new();
        }
        let mut s = String::from(
            "\nSlope runs (PackBot 510, belts at 0.3 m/s uphill, mean speed along the slope from 1 s to 4 s; climbed = at least half the belt speed uphill):\n\n",
        );
        s += "| slope | tan | speed along the slope | climbed |\n|---|---|---|---|\n";
        for r in &self.slope_runs {
            s += &format!(
                "| {:.0} deg | {:.3} | {} | {} |\n",
                r.angle_deg,
                r.angle_deg.to_radians().tan(),
                match &r.error {
                    Some(e) => format!("error: {e}"),
                    None => format!("{:+.3} m/s", r.speed_along_mps),
                },
                if r.climbed { "yes" } else { "no" }
            );
        }
        s
    }

    /// Writes `report.md`, `report.json` and one plot (PNG + SVG) per case into `dir`; returns
    /// the paths written.
    pub fn write(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        let io = |path: &Path| {
            let path = path.to_path_buf();
            move |source| Error::Io { path, source }
        };
        std::fs::create_dir_all(dir).map_err(io(dir))?;
        let mut written = Vec::new();
        let md = dir.join("report.md");
        crate::files::write_atomic(&md, self.to_markdown().as_bytes())?;
        written.push(md);
        let js = dir.join("report.json");
        let json = serde_json::to_string_pretty(self).expect("report serialises");
        crate::files::write_atomic(&js, (json + "\n").as_bytes())?;
        written.push(js);
        for p in &self.plots {
            let runs: Vec<crate::output::plot::PlotRun> = p
                .runs
                .iter()
                .map(|(label, result)| crate::output::plot::PlotRun {
                    label: label.as_str(),
                    result,
                })
                .collect();
            written.extend(crate::output::plot::write_plots(
                &crate::output::plot::PlotInput {
                    title: &p.title,
                    runs: &runs,
                    ground_profile: &p.profile,
                    outlines: &p.outlines,
                    snapshots: &[],
                },
                dir,
                &p.stem,
            )?);
        }
        Ok(written)
    }
}

/// A step attempt in words, for the Table IV cells.
fn run_words(r: &StepRun) -> String {
    if r.result == "S" {
        format!(
            "on top at {:.1} s, deepest penetration {:.1} mm",
            r.time_s, r.max_penetration_mm
        )
    } else if r.result == "error" {
        r.reason.clone()
    } else {
        format!(
            "x {:.2} m, {:+.3} m vs step top, deepest penetration {:.1} mm",
            r.final_x_m, r.final_z_above_step_m, r.max_penetration_mm
        )
    }
}
