//! Running a scenario to the end: trajectory, summary, and the files `tracksim run` writes.

use crate::error::{Error, Result};
use crate::model::{OutcomeModel, Scenario};
use crate::sim::{PoseRpy, Sample, Simulation};
use serde::Serialize;
use std::io::Write;
use std::path::Path;
use std::time::Instant;

/// What a run produced.
#[derive(Clone, Debug)]
pub struct RunResult {
    /// Samples at the output interval (the first at t = 0).
    pub samples: Vec<Sample>,
    /// Track names (column order of per-track values).
    pub track_names: Vec<String>,
    /// Flipper names.
    pub flipper_names: Vec<String>,
    /// Summary numbers.
    pub summary: Summary,
    /// How it ended.
    pub outcome: Outcome,
}

/// The numbers `summary.json` holds.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// Scenario file, if any.
    pub scenario: Option<String>,
    /// Vehicle name.
    pub vehicle: String,
    /// Track method.
    pub method: String,
    /// Time step, s.
    pub dt_s: f64,
    /// Steps taken.
    pub steps: u64,
    /// Simulated time, s.
    pub sim_time_s: f64,
    /// Wall-clock time spent stepping, s.
    pub wall_time_s: f64,
    /// sim_time_s / wall_time_s.
    pub real_time_factor: f64,
    /// Displacement along the start heading divided by simulated time, m/s.
    pub mean_speed_mps: f64,
    /// Horizontal path length of the body, m.
    pub distance_m: f64,
    /// Pose at the start (after placement).
    pub initial_pose: PoseRpy,
    /// Pose at the end.
    pub final_pose: PoseRpy,
    /// "success", "failure" or "completed" (no success condition was set and nothing failed).
    pub outcome: String,
    /// Why.
    pub outcome_reason: String,
    /// When the outcome was decided, s.
    pub outcome_time_s: f64,
    /// Solver settings that change the physics.
    pub solver: SolverSummary,
    /// Seed of the scenario.
    pub seed: u64,
    /// Largest link deviation from its exact pose after a physics step (joint error), m.
    pub max_link_error_m: f64,
    /// Same, as an angle, rad.
    pub max_link_error_rad: f64,
    /// Deepest contact penetration seen in the trajectory rows, m (how far grousers sank).
    pub max_penetration_m: f64,
}

/// Solver settings reported with every run.
#[derive(Clone, Debug, Serialize)]
pub struct SolverSummary {
    /// Time step, s.
    pub dt_s: f64,
    /// Solver iterations.
    pub iterations: usize,
    /// Contact clustering.
    pub contact_clustering: bool,
    /// Smallest segment link mass, kg.
    pub min_link_mass_kg: f64,
    /// Speculative contact distance, m.
    pub prediction_distance_m: f64,
    /// Uncorrected vehicle-terrain penetration (ODE's `min_depth`), m; 0 = rigid contact.
    pub contact_slop_m: f64,
}

/// How a run ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// A success condition was met.
    Success(String),
    /// A failure condition was met (tip-over, off the terrain, timeout).
    Failure(String),
    /// Ran to the end; no success condition was set.
    Completed,
}

impl Outcome {
    /// "success", "failure" or "completed".
    pub fn name(&self) -> &'static str {
        match self {
            Outcome::Success(_) => "success",
            Outcome::Failure(_) => "failure",
            Outcome::Completed => "completed",
        }
    }
}

/// Checks the outcome conditions at the current state; `None` while undecided.
pub fn check_outcome(o: &OutcomeModel, sim: &Simulation) -> Option<Outcome> {
    let p = sim.body_pose();
    if p.roll.abs() > o.max_tilt || p.pitch.abs() > o.max_tilt {
        return Some(Outcome::Failure(format!(
            "tipped over (roll {:.1} deg, pitch {:.1} deg, limit {:.1} deg)",
            p.roll.to_degrees(),
            p.pitch.to_degrees(),
            o.max_tilt.to_degrees()
        )));
    }
    if let Some(x) = o.success_x.filter(|x| p.x >= *x) {
        return Some(Outcome::Success(format!("body passed x = {x} m")));
    }
    if let Some(z) = o.success_z.filter(|z| p.z >= *z) {
        return Some(Outcome::Success(format!("body reached z = {z} m")));
    }
    if o.fail_off_terrain && sim.terrain_below(p.x, p.y).is_none() {
        return Some(Outcome::Failure(format!(
            "left the terrain at x = {:.3} m, y = {:.3} m",
            p.x, p.y
        )));
    }
    None
}

/// Options of a run.
#[derive(Clone, Copy, Debug, Default)]
pub struct RunOptions {
    /// Pace the simulation to the wall clock (never faster than real time).
    pub realtime: bool,
}

/// Runs a scenario for its duration (or until its outcome is decided, if it says to stop).
/// `progress` is called after every output sample with (simulated time, duration) in seconds.
pub fn run_scenario(sc: &Scenario, progress: impl FnMut(f64, f64)) -> Result<RunResult> {
    run_scenario_with(sc, RunOptions::default(), progress)
}

/// [`run_scenario`] with options.
pub fn run_scenario_with(
    sc: &Scenario,
    opts: RunOptions,
    mut progress: impl FnMut(f64, f64),
) -> Result<RunResult> {
    let mut sim = Simulation::new(sc)?;
    let dt = sc.solver.dt;
    let steps = (sc.duration / dt).round().max(1.0) as u64;
    let every = ((sc.output_interval / dt).round() as u64).max(1);
    let mut samples = vec![sim.sample()];
    let wall = Instant::now();
    let mut stepping = 0.0;
    let mut outcome = None;
    let mut outcome_time = 0.0;
    for i in 1..=steps {
        let t0 = Instant::now();
        sim.step()?;
        stepping += t0.elapsed().as_secs_f64();
        let sample_now = i % every == 0 || i == steps;
        if outcome.is_none() && sample_now {
            outcome = check_outcome(&sc.outcome, &sim);
            outcome_time = sim.time();
        }
        if sample_now || (outcome.is_some() && sc.outcome.stop) {
            samples.push(sim.sample());
            progress(sim.time(), sc.duration);
        }
        if outcome.is_some() && sc.outcome.stop {
            break;
        }
        if opts.realtime {
            let ahead = sim.time() - wall.elapsed().as_secs_f64();
            if ahead > 0.002 {
                std::thread::sleep(std::time::Duration::from_secs_f64(ahead));
            }
        }
    }
    let outcome = outcome.unwrap_or_else(|| {
        outcome_time = sim.time();
        match (sc.outcome.success_x, sc.outcome.success_z) {
            (None, None) => Outcome::Completed,
            _ => Outcome::Failure(format!(
                "timeout: no success condition met in {:.3} s",
                sim.time()
            )),
        }
    });
    let first = samples[0].pose;
    let last = samples.last().map(|s| s.pose).unwrap_or(first);
    let (c, s) = (first.yaw.cos(), first.yaw.sin());
    let forward = (last.x - first.x) * c + (last.y - first.y) * s;
    let distance = samples
        .windows(2)
        .map(|w| ((w[1].pose.x - w[0].pose.x).powi(2) + (w[1].pose.y - w[0].pose.y).powi(2)).sqrt())
        .sum();
    let (err_m, err_rad) = sim.max_link_error();
    let sim_time = sim.time();
    let summary = Summary {
        scenario: sc.source.as_ref().map(|p| p.display().to_string()),
        vehicle: sc.vehicle.name.clone(),
        method: sc.method.name(),
        dt_s: dt,
        steps: sim.steps(),
        sim_time_s: sim_time,
        wall_time_s: stepping,
        real_time_factor: sim_time / stepping.max(1e-12),
        mean_speed_mps: forward / sim_time,
        distance_m: distance,
        initial_pose: first,
        final_pose: last,
        outcome: outcome.name().to_string(),
        outcome_reason: match &outcome {
            Outcome::Success(r) | Outcome::Failure(r) => r.clone(),
            Outcome::Completed => "ran to the end".into(),
        },
        outcome_time_s: outcome_time,
        solver: SolverSummary {
            dt_s: dt,
            iterations: sc.solver.iterations,
            contact_clustering: sc.solver.contact_clustering,
            min_link_mass_kg: sc.solver.min_link_mass,
            prediction_distance_m: sc.solver.prediction_distance,
            contact_slop_m: sc.solver.contact_slop,
        },
        seed: sc.seed,
        max_link_error_m: err_m,
        max_link_error_rad: err_rad,
        max_penetration_m: samples.iter().map(|s| s.penetration).fold(0.0, f64::max),
    };
    Ok(RunResult {
        samples,
        track_names: sim.track_names().to_vec(),
        flipper_names: sim.flipper_names().to_vec(),
        summary,
        outcome,
    })
}

impl RunResult {
    /// The CSV header of `trajectory.csv`.
    pub fn csv_header(&self) -> Vec<String> {
        let mut h: Vec<String> = [
            "t_s",
            "x_m",
            "y_m",
            "z_m",
            "roll_rad",
            "pitch_rad",
            "yaw_rad",
            "vx_mps",
            "vy_mps",
            "vz_mps",
            "wx_rad_s",
            "wy_rad_s",
            "wz_rad_s",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        for n in &self.track_names {
            h.push(format!("belt_speed_{n}_mps"));
        }
        for n in &self.track_names {
            h.push(format!("belt_phase_{n}_m"));
        }
        for n in &self.flipper_names {
            h.push(format!("flipper_{n}_rad"));
        }
        h.push("contacts".into());
        h.push("penetration_m".into());
        h
    }

    /// Writes `summary.json` and `trajectory.csv` into `dir` (created if needed).
    pub fn write(&self, dir: &Path) -> Result<()> {
        let io = |path: &Path| {
            let path = path.to_path_buf();
            move |source| Error::Io { path, source }
        };
        std::fs::create_dir_all(dir).map_err(io(dir))?;
        let sp = dir.join("summary.json");
        let json = serde_json::to_string_pretty(&self.summary).expect("summary serialises");
        std::fs::write(&sp, json + "\n").map_err(io(&sp))?;
        let tp = dir.join("trajectory.csv");
        let mut out = std::io::BufWriter::new(std::fs::File::create(&tp).map_err(io(&tp))?);
        let mut text = self.csv_header().join(",");
        text.push('\n');
        for s in &self.samples {
            let p = &s.pose;
            let mut row = vec![
                s.t,
                p.x,
                p.y,
                p.z,
                p.roll,
                p.pitch,
                p.yaw,
                s.linvel[0],
                s.linvel[1],
                s.linvel[2],
                s.angvel[0],
                s.angvel[1],
                s.angvel[2],
            ];
            row.extend(&s.belt_speed);
            row.extend(&s.belt_phase);
            row.extend(&s.flipper_angle);
            let mut line = row
                .iter()
                .map(|v| format!("{v:.6}"))
                .collect::<Vec<_>>()
                .join(",");
            line.push_str(&format!(",{},{:.6}\n", s.contacts, s.penetration));
            text.push_str(&line);
        }
        out.write_all(text.as_bytes()).map_err(io(&tp))?;
        out.flush().map_err(io(&tp))?;
        Ok(())
    }
}

/// A polyline in the side view: (x, z) points, m.
pub type SideLine = Vec<(f64, f64)>;

/// The terrain under runs as drawn in the side view: the height profile along the first run's
/// path (x, z) and the side outlines (x, z) of the terrain's boxes, m.
pub fn side_view_terrain(sc: &Scenario, runs: &[&RunResult]) -> (SideLine, Vec<SideLine>) {
    let samples: Vec<&Sample> = runs.iter().flat_map(|r| r.samples.iter()).collect();
    if samples.is_empty() {
        return (Vec::new(), Vec::new());
    }
    let (lo, hi) = samples.iter().fold((f64::MAX, f64::MIN), |(lo, hi), s| {
        (lo.min(s.pose.x), hi.max(s.pose.x))
    });
    let (lo, hi) = (lo - 0.5, hi + 0.5);
    let n = 400;
    let first = &runs[0].samples;
    let y_at = |x: f64| {
        first
            .iter()
            .min_by(|a, b| (a.pose.x - x).abs().total_cmp(&(b.pose.x - x).abs()))
            .map(|s| s.pose.y)
            .unwrap_or(0.0)
    };
    let xs: Vec<f64> = (0..=n)
        .map(|i| lo + (hi - lo) * i as f64 / n as f64)
        .collect();
    let pts: Vec<(f64, f64)> = xs.iter().map(|&x| (x, y_at(x))).collect();
    let profile = xs
        .iter()
        .zip(sc.terrain.heights_at(&pts))
        .filter_map(|(&x, z)| z.map(|z| (x, z)))
        .collect();
    let outlines = sc
        .terrain
        .boxes
        .iter()
        .map(|b| {
            let r = b.rotation();
            [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                .iter()
                .map(|(sx, sz)| {
                    let p = b.centre + r * glam::DVec3::new(sx * b.half.x, 0.0, sz * b.half.z);
                    (p.x, p.z)
                })
                .collect()
        })
        .collect();
    (profile, outlines)
}

/// Writes `<stem>.png` and `<stem>.svg` with `runs` (label, result) drawn over the scenario's
/// terrain; nothing when there is no run.
fn write_runs(
    sc: &Scenario,
    runs: &[(String, &RunResult)],
    title: &str,
    stem: &str,
    dir: &Path,
) -> Result<Vec<std::path::PathBuf>> {
    if runs.is_empty() {
        return Ok(Vec::new());
    }
    let results: Vec<&RunResult> = runs.iter().map(|(_, r)| *r).collect();
    let (profile, outlines) = side_view_terrain(sc, &results);
    let runs: Vec<crate::plot::PlotRun> = runs
        .iter()
        .map(|(label, r)| crate::plot::PlotRun {
            label: label.as_str(),
            result: r,
        })
        .collect();
    crate::plot::write_plots(
        &crate::plot::PlotInput {
            title,
            runs: &runs,
            ground_profile: &profile,
            outlines: &outlines,
        },
        dir,
        stem,
    )
}

/// Writes `plot.png` and `plot.svg` for one run into `dir`: side view over the terrain, top
/// view, pitch and roll against time.
pub fn write_run_plots(
    sc: &Scenario,
    result: &RunResult,
    dir: &Path,
) -> Result<Vec<std::path::PathBuf>> {
    let title = if sc.description.is_empty() {
        &result.summary.vehicle
    } else {
        &sc.description
    };
    write_runs(
        sc,
        &[(result.summary.method.clone(), result)],
        title,
        "plot",
        dir,
    )
}

/// Writes `compare.png` and `compare.svg`: every successful run of a comparison in one figure.
pub fn write_compare_plots(
    sc: &Scenario,
    results: &[(String, &RunResult)],
    dir: &Path,
) -> Result<Vec<std::path::PathBuf>> {
    let title = format!("{} (track methods compared)", sc.description);
    write_runs(sc, results, &title, "compare", dir)
}
