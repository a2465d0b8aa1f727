//! What more robots in one world cost (issue 40): N PackBot 510s (the Table II vehicle, 40
//! grousers a track) apart on flat ground, each driving at 0.3 m/s, timed for N = 1, 2, 4, ...
//! in interleaved rounds in one process, so the ratios compare like with like. The figure is
//! the step time per robot against one robot's. The robots are solved on one thread: Rapier's
//! `parallel` feature is the opt-in cargo feature `parallel`, measured slower and not
//! deterministic, so not shipped (docs/TEAMS.md, cost section).

use crate::error::{Error, Result};
use crate::model::MAX_ROBOTS;
use crate::world::Simulation;
use std::path::Path;
use std::time::Instant;

/// Spacing of the robots' grid, m (PackBot is 0.69 m long, 0.51 m wide).
const SPACING_M: f64 = 1.5;

/// One count's timing.
#[derive(Clone, Debug, serde::Serialize)]
pub struct TeamTiming {
    /// Robots in the world.
    pub robots: usize,
    /// Median wall time of one step over the rounds, ms.
    pub step_ms: f64,
    /// `step_ms` / robots, ms.
    pub per_robot_ms: f64,
    /// `per_robot_ms` over one robot's (the first count's), 1 = no overhead.
    pub per_robot_ratio: f64,
    /// Simulated seconds per wall second of the whole world.
    pub real_time_factor: f64,
}

/// The scenario text of `n` PackBots on a grid of 4 columns, 1.5 m apart, driving forward.
fn scenario_text(root: &Path, n: usize, duration: f64) -> String {
    let vehicle = root.join("vehicles/packbot510.toml");
    let mut text = format!(
        "description = \"{n} PackBots apart on flat ground (bench)\"\n[terrain.ground]\n\
         friction = 1.0\n[simulation]\nduration_s = {duration}\n"
    );
    for k in 0..n {
        let (x, y) = ((k % 4) as f64 * SPACING_M, (k / 4) as f64 * SPACING_M);
        text += &format!(
            "[[vehicles]]\nname = \"r{k}\"\n[vehicles.vehicle]\nfile = {:?}\nx_m = {x}\n\
             y_m = {y}\n[[vehicles.commands]]\nt_s = 0.0\nbelt_speed_mps = 0.3\n",
            vehicle.display().to_string()
        );
    }
    if n == 1 {
        // A one-robot file: the robot at the top level, as every other run has it.
        text = format!(
            "description = \"1 PackBot (bench)\"\n[vehicle]\nfile = {:?}\n[terrain.ground]\n\
             friction = 1.0\n[simulation]\nduration_s = {duration}\n[[commands]]\nt_s = 0.0\n\
             belt_speed_mps = 0.3\n",
            vehicle.display().to_string()
        );
    }
    text
}

/// Steps `sim` for `duration` s with every robot's belts at 0.3 m/s; wall seconds.
fn time_world(mut sim: Simulation, duration: f64) -> Result<f64> {
    for k in 0..sim.robot_count() {
        sim.select(k);
        for t in 0..sim.track_names().len() {
            sim.set_belt_speed(t, 0.3);
        }
    }
    sim.select(0);
    let steps = (duration / sim.dt()).round() as u64;
    let t0 = Instant::now();
    for _ in 0..steps {
        sim.step()?;
    }
    Ok(t0.elapsed().as_secs_f64())
}

/// Times worlds of each of `counts` robots for `duration` simulated s, `rounds` times
/// interleaved; `root` is the repository (its `vehicles/`).
pub fn bench_team(
    root: &Path,
    counts: &[usize],
    duration: f64,
    rounds: usize,
) -> Result<Vec<TeamTiming>> {
    if let Some(&n) = counts.iter().find(|&&n| n == 0 || n > MAX_ROBOTS) {
        return Err(Error::Build(format!(
            "robots: {n}; give counts from 1 to {MAX_ROBOTS}"
        )));
    }
    let root = &root.canonicalize().map_err(|source| Error::Io {
        path: root.to_path_buf(),
        source,
    })?;
    let dir = std::env::temp_dir().join(format!("tracksim_team_bench_{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|source| Error::Io {
        path: dir.clone(),
        source,
    })?;
    let mut scenarios = Vec::new();
    for &n in counts {
        let path = dir.join(format!("robots_{n}.toml"));
        crate::files::write_atomic(&path, scenario_text(root, n, duration).as_bytes())?;
        scenarios.push(std::sync::Arc::new(crate::model::load_scenario(&path)?));
    }
    let _ = std::fs::remove_dir_all(&dir);
    let mut times: Vec<Vec<f64>> = vec![Vec::new(); counts.len()];
    for _ in 0..rounds.max(1) {
        for (i, sc) in scenarios.iter().enumerate() {
            let sim = Simulation::from_shared(sc.clone())?;
            times[i].push(time_world(sim, duration)?);
        }
    }
    let steps = (duration / scenarios[0].solver.dt).round().max(1.0);
    let mut out: Vec<TeamTiming> = Vec::new();
    for (i, &n) in counts.iter().enumerate() {
        let mut t = times[i].clone();
        t.sort_by(f64::total_cmp);
        let wall = t[t.len() / 2];
        let step_ms = 1e3 * wall / steps;
        let per_robot_ms = step_ms / n as f64;
        let base = out.first().map_or(per_robot_ms, |b| b.per_robot_ms);
        out.push(TeamTiming {
            robots: n,
            step_ms,
            per_robot_ms,
            per_robot_ratio: per_robot_ms / base,
            real_time_factor: duration / wall,
        });
    }
    Ok(out)
}

/// The timings as a markdown table.
pub fn to_markdown(rows: &[TeamTiming]) -> String {
    let mut s = String::from(
        "| robots | step, ms | per robot, ms | per robot / one robot | real-time factor |\n\
         |---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        s += &format!(
            "| {} | {:.3} | {:.3} | {:.3} | {:.2} |\n",
            r.robots, r.step_ms, r.per_robot_ms, r.per_robot_ratio, r.real_time_factor
        );
    }
    s
}
