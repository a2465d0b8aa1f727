//! Running a scenario to the end: trajectory, summary, and the files `tracksim run` writes.

use crate::error::{Error, Result};
use crate::model::Scenario;
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
    /// Largest link deviation from its exact pose after a physics step (joint error), m.
    pub max_link_error_m: f64,
    /// Same, as an angle, rad.
    pub max_link_error_rad: f64,
}

/// Runs a scenario for its duration. `progress` is called after every output sample with
/// (simulated time, duration) in seconds.
pub fn run_scenario(sc: &Scenario, mut progress: impl FnMut(f64, f64)) -> Result<RunResult> {
    let mut sim = Simulation::new(sc)?;
    let dt = sc.solver.dt;
    let steps = (sc.duration / dt).round().max(1.0) as u64;
    let every = ((sc.output_interval / dt).round() as u64).max(1);
    let mut samples = vec![sim.sample()];
    let wall = Instant::now();
    let mut stepping = 0.0;
    for i in 1..=steps {
        let t0 = Instant::now();
        sim.step()?;
        stepping += t0.elapsed().as_secs_f64();
        if i % every == 0 || i == steps {
            samples.push(sim.sample());
            progress(sim.time(), sc.duration);
        }
    }
    let _ = wall;
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
        method: "okada2020".into(),
        dt_s: dt,
        steps,
        sim_time_s: sim_time,
        wall_time_s: stepping,
        real_time_factor: sim_time / stepping.max(1e-12),
        mean_speed_mps: forward / sim_time,
        distance_m: distance,
        initial_pose: first,
        final_pose: last,
        max_link_error_m: err_m,
        max_link_error_rad: err_rad,
    };
    Ok(RunResult {
        samples,
        track_names: sim.track_names().to_vec(),
        flipper_names: sim.flipper_names().to_vec(),
        summary,
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
            line.push_str(&format!(",{}\n", s.contacts));
            text.push_str(&line);
        }
        out.write_all(text.as_bytes()).map_err(io(&tp))?;
        out.flush().map_err(io(&tp))?;
        Ok(())
    }
}
