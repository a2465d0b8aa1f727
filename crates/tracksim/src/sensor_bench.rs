//! `tracksim bench --sensors`: what sensing costs. The same scenario is timed without sensors
//! and with a sensor set, interleaved (without, with, without, with, ...), in one process; the
//! report gives the median real-time factor and us per step of each, the overhead as a
//! fraction of the step, and every sensor's mean cost per update (us) and per simulated second.
//!
//! Two pairs: the paper's Table II case (PackBot on flat ground at 0.3 m/s) with the typical
//! set of issue 25 (the IMU, encoders, 2-D lidar and elevation map of
//! `vehicles/packbot510_sensors.toml`), and the bundled stairs without and with every sensor of
//! that file (`packbot_stairs` against `packbot_sensors`, the same trajectory).

use crate::error::Result;
use crate::model::{Scenario, ScenarioTemplate, SensorKind, load_vehicle};
use crate::run::Runner;
use std::path::Path;

/// Sensor kinds of the typical set.
const TYPICAL: &[&str] = &["imu", "encoders", "lidar", "elevation_map"];

/// One timed variant.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Variant {
    /// What it is.
    pub name: String,
    /// Real-time factor (stepping and sensing), one per repeat.
    pub rtf_runs: Vec<f64>,
    /// Median real-time factor.
    pub rtf_median: f64,
    /// Median wall time per step, sensing included, us.
    pub us_per_step: f64,
    /// Every sensor: (name, kind, rate Hz, median us per update, us per simulated second).
    pub sensors: Vec<(String, String, f64, f64, f64)>,
}

/// A pair: without sensors, with them.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Pair {
    /// Case name.
    pub case: String,
    /// Without sensors.
    pub without: Variant,
    /// With sensors.
    pub with: Variant,
    /// (us per step with - without) / without: what sensing adds to the step.
    pub overhead: f64,
    /// Sum of the sensors' costs per simulated second over the step's cost per simulated
    /// second without sensors (the same fraction from the sensors' own timers).
    pub sensors_fraction: f64,
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// One run of `sc`: (RTF, us per step, per-sensor us per update).
fn time_one(sc: &Scenario) -> Result<(f64, f64, Vec<f64>)> {
    let mut r = Runner::new(sc)?.unrecorded();
    while !r.finished() {
        r.step()?;
    }
    let steps = r.sim().steps() as f64;
    let costs = (0..r.sensors().len())
        .map(|i| r.sensors().cost(i).1)
        .collect();
    Ok((r.time() / r.stepping(), r.stepping() * 1e6 / steps, costs))
}

/// Times `without` and `with` `repeat` times each, interleaved (without, with, without, ...).
pub fn pair(case: &str, without: &Scenario, with: &Scenario, repeat: usize) -> Result<Pair> {
    let mut runs = [Vec::new(), Vec::new()];
    for _ in 0..repeat {
        runs[0].push(time_one(without)?);
        runs[1].push(time_one(with)?);
    }
    let variant = |name: &str, sc: &Scenario, runs: &[(f64, f64, Vec<f64>)]| {
        let mut rtf: Vec<f64> = runs.iter().map(|r| r.0).collect();
        let rtf_runs = rtf.clone();
        let mut us: Vec<f64> = runs.iter().map(|r| r.1).collect();
        let sensors = sc
            .vehicle
            .sensors
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let mut c: Vec<f64> = runs.iter().map(|r| r.2[i]).collect();
                let per_update = median(&mut c);
                (
                    s.name.clone(),
                    s.kind.name().to_string(),
                    s.rate_hz,
                    per_update,
                    per_update * s.rate_hz,
                )
            })
            .collect();
        Variant {
            name: name.to_string(),
            rtf_median: median(&mut rtf),
            rtf_runs,
            us_per_step: median(&mut us),
            sensors,
        }
    };
    let a = variant("without sensors", without, &runs[0]);
    let b = variant("with sensors", with, &runs[1]);
    let step_per_s = a.us_per_step / without.solver.dt;
    let sensing: f64 = b.sensors.iter().map(|s| s.4).sum();
    Ok(Pair {
        case: case.to_string(),
        overhead: (b.us_per_step - a.us_per_step) / a.us_per_step,
        sensors_fraction: sensing / step_per_s,
        without: a,
        with: b,
    })
}

/// The two pairs (see the module), each `repeat` times over `duration` simulated seconds,
/// from the bundled files under `root`.
pub fn bench_sensors(root: &Path, duration: f64, repeat: usize) -> Result<Vec<Pair>> {
    let bench = |f: &str| crate::bench::BenchLoad {
        path: root.join(f),
        duration_s: duration,
        solver_iterations: None,
    };
    let load = |f: &str| bench(f).scenario(None);
    let flat = load("scenarios/packbot_flat.toml")?;
    let all = load_vehicle(&root.join("vehicles/packbot510_sensors.toml"))?.sensors;
    let mut vehicle = flat.vehicle.clone();
    vehicle.sensors = all
        .iter()
        .filter(|s| TYPICAL.contains(&s.kind.name()))
        .filter(|s| s.mount == crate::model::Mount::Body)
        .filter(|s| !matches!(s.kind, SensorKind::DepthCamera(_)))
        .cloned()
        .collect();
    let b = bench("scenarios/packbot_flat.toml");
    let typical = ScenarioTemplate::load_for_vehicle(&b.path, &b.overrides(None), vehicle)?
        .file_scenario()?;
    let stairs = load("scenarios/packbot_stairs.toml")?;
    let sensed = load("scenarios/packbot_sensors.toml")?;
    Ok(vec![
        pair("packbot flat, typical set", &flat, &typical, repeat)?,
        pair("packbot stairs, every sensor", &stairs, &sensed, repeat)?,
    ])
}

/// The pairs as markdown.
pub fn to_markdown(pairs: &[Pair]) -> String {
    let mut out = String::new();
    for p in pairs {
        out += &format!(
            "### {}\n\n| variant | RTF median | RTF runs | us/step |\n|---|---:|---|---:|\n",
            p.case
        );
        for v in [&p.without, &p.with] {
            let runs: Vec<String> = v.rtf_runs.iter().map(|r| format!("{r:.1}")).collect();
            out += &format!(
                "| {} | {:.2} | {} | {:.1} |\n",
                v.name,
                v.rtf_median,
                runs.join(", "),
                v.us_per_step
            );
        }
        out += &format!(
            "\nSensing adds {:.1} % to the step (us/step with against without); by the sensors' \
             own timers {:.1} %.\n\n| sensor | kind | rate Hz | us/update | ms per simulated s |\n\
             |---|---|---:|---:|---:|\n",
            100.0 * p.overhead,
            100.0 * p.sensors_fraction
        );
        for s in &p.with.sensors {
            out += &format!(
                "| {} | {} | {} | {:.1} | {:.2} |\n",
                s.0,
                s.1,
                s.2,
                s.3,
                s.4 / 1000.0
            );
        }
        out += "\n";
    }
    out
}
