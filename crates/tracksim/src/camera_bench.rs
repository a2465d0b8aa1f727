//! `tracksim bench --camera`: what a colour camera costs (issue 41).
//!
//! 1. The paper's Table II case (PackBot on flat ground at 0.3 m/s, one thread) without and
//!    with a 160 x 120 colour camera at 10 Hz on the chassis, interleaved in one process: the
//!    camera's share of the step time (target: at most 15 %).
//! 2. Frame times: one camera render (`Sensor::update`) at 160 x 120, 320 x 240 and
//!    640 x 480, on flat ground and on the bundled stairs mid-climb, on one thread and on every
//!    core (`threads = 0`), medians of repeated renders of the same state.

use crate::error::Result;
use crate::model::{Mount, RgbCameraModel, Scenario, ScenarioTemplate, SensorKind, SensorModel};
use crate::render::Intrinsics;
use crate::sensor_bench::{Pair, pair};
use crate::sensors::build;
use crate::world::Simulation;
use std::path::Path;
use std::time::Instant;

/// A forward camera on the chassis: 0.26 m ahead, 0.12 m up, pitched 10 deg down.
pub fn front_camera(width: usize, height: usize, threads: usize) -> SensorModel {
    SensorModel {
        name: "front_rgb".into(),
        mount: Mount::Body,
        position: glam::DVec3::new(0.26, 0.0, 0.12),
        rotation: glam::DQuat::from_rotation_y(10f64.to_radians()),
        rate_hz: 10.0,
        frame_id: None,
        kind: SensorKind::RgbCamera(RgbCameraModel {
            intrinsics: Intrinsics {
                width,
                height,
                horizontal_fov: 80f64.to_radians(),
            },
            min_range: 0.05,
            max_range: 30.0,
            pixel_noise: 0.0,
            shadows: true,
            threads,
        }),
    }
}

/// One row of frame times.
#[derive(Clone, Debug, serde::Serialize)]
pub struct FrameTime {
    /// Scene.
    pub case: String,
    /// Width x height, pixels.
    pub size: (usize, usize),
    /// Render threads (0: every core).
    pub threads: usize,
    /// Median time of one frame, ms.
    pub ms: f64,
}

/// What [`bench_camera`] measured.
#[derive(Clone, Debug, serde::Serialize)]
pub struct CameraBench {
    /// Table II case without and with the 160 x 120 camera at 10 Hz.
    pub pair: Pair,
    /// Frame times.
    pub frames: Vec<FrameTime>,
}

/// `sc` with its vehicle carrying only `cameras`.
fn with_cameras(
    root: &Path,
    file: &str,
    duration: f64,
    cameras: Vec<SensorModel>,
) -> Result<Scenario> {
    let b = crate::bench::BenchLoad {
        path: root.join(file),
        duration_s: duration,
        solver_iterations: None,
    };
    let plain = b.scenario(None)?;
    let mut vehicle = plain.vehicle.clone();
    vehicle.sensors = cameras;
    ScenarioTemplate::load_for_vehicle(&b.path, &b.overrides(None), vehicle)?.file_scenario()
}

/// Median time of `repeat` renders of the state `sim` is in by a camera `m`, ms.
fn frame_ms(sim: &Simulation, m: &SensorModel, repeat: usize) -> f64 {
    let mut s = build(m, sim, 0);
    s.update(sim, 0.0); // warm: buffers grown, pool started
    let mut t: Vec<f64> = (0..repeat)
        .map(|_| {
            let t0 = Instant::now();
            s.update(sim, 0.1);
            t0.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[t.len() / 2]
}

/// The benchmark (see the module): the pair over `duration` simulated seconds `repeat` times,
/// frame times over `frames` renders each.
pub fn bench_camera(
    root: &Path,
    duration: f64,
    repeat: usize,
    frames: usize,
) -> Result<CameraBench> {
    let flat = with_cameras(root, "scenarios/packbot_flat.toml", duration, vec![])?;
    let seen = with_cameras(
        root,
        "scenarios/packbot_flat.toml",
        duration,
        vec![front_camera(160, 120, 1)],
    )?;
    let pair = pair(
        "packbot flat, 160 x 120 colour camera at 10 Hz",
        &flat,
        &seen,
        repeat,
    )?;
    let mut out = Vec::new();
    for (case, file, at) in [
        ("flat ground", "scenarios/packbot_flat.toml", 2.0),
        ("stairs mid-climb", "scenarios/packbot_stairs.toml", 9.0),
    ] {
        let sc = with_cameras(root, file, at + 1.0, vec![])?;
        let mut r = crate::run::Runner::new(&sc)?.unrecorded();
        while r.time() < at && !r.finished() {
            r.step()?;
        }
        for (w, h) in [(160, 120), (320, 240), (640, 480)] {
            for threads in [1, 0] {
                out.push(FrameTime {
                    case: case.into(),
                    size: (w, h),
                    threads,
                    ms: frame_ms(r.sim(), &front_camera(w, h, threads), frames),
                });
            }
        }
    }
    Ok(CameraBench { pair, frames: out })
}

/// The benchmark as markdown.
pub fn to_markdown(b: &CameraBench) -> String {
    let mut out = crate::sensor_bench::to_markdown(std::slice::from_ref(&b.pair));
    out += "### Frame times (median of repeated renders of one state)\n\n\
            | scene | size | threads | ms per frame |\n|---|---|---:|---:|\n";
    for f in &b.frames {
        let threads = if f.threads == 0 {
            format!("all ({})", rayon::current_num_threads())
        } else {
            f.threads.to_string()
        };
        out += &format!(
            "| {} | {} x {} | {} | {:.2} |\n",
            f.case, f.size.0, f.size.1, threads, f.ms
        );
    }
    out
}
