//! A live session: the scenario simulated paced to the wall clock with the operator's controls
//! from the [`Hub`], recorded as a run.
//!
//! Determinism: a control from the page is applied only at a sample boundary (every
//! `output_interval_s`), before the next step, exactly as a scenario's `[[commands]]` entry
//! with that `t_s` is (`run::Timeline`), and through the same conversion (skid-steer twist,
//! degrees to radians). The session's `commands.toml` therefore replays it:
//! `tracksim run FILE --commands DIR/commands.toml --duration T` writes the same
//! `trajectory.csv`.

use super::hub::{DriveControl, Hub};
use crate::error::Result;
use crate::model::{Controls, Scenario};
use crate::run::{Outcome, RunResult, Summary, WallTimes, check_outcome, outcome};
use crate::spec::CommandSpec;
use crate::world::Simulation;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Shortest wall time between two published states, s (at most 60 states per second).
pub const PUBLISH_INTERVAL_S: f64 = 1.0 / 60.0;

/// Options of a session.
#[derive(Clone, Copy, Debug)]
pub struct DriveOptions {
    /// Simulated seconds per wall-clock second (1: real time; 0.5 slower, 2 faster).
    pub speed: f64,
    /// End the session at this simulated time, s (None: when the operator stops).
    pub max_time: Option<f64>,
    /// Start simulating only once a page has connected (the clock starts then).
    pub wait_for_page: bool,
}

impl Default for DriveOptions {
    fn default() -> Self {
        DriveOptions {
            speed: 1.0,
            max_time: None,
            wait_for_page: false,
        }
    }
}

/// A finished session: the run, and the controls the operator gave.
pub struct Session {
    /// The run (since the last reset), as `tracksim run` returns it.
    pub result: RunResult,
    /// Each control change with the simulated time it was applied at, s.
    pub commands: Vec<(f64, DriveControl)>,
    /// The controls in force at each sample of `result.samples`.
    pub controls: Vec<DriveControl>,
    /// Flipper names, by index.
    pub flipper_names: Vec<String>,
    /// Initial flipper angles, degrees (what an uncommanded flipper holds).
    pub flipper_initial_deg: Vec<f64>,
}

fn apply(sim: &mut Simulation, sc: &Scenario, c: &DriveControl) {
    // The same conversion as a scenario's command (model::compile_scenario).
    let mut controls = Controls::twist(&sc.vehicle, c.forward_mps, c.yaw_rate_rad_s);
    for (slot, a) in controls.flipper_angle.iter_mut().zip(&c.flipper_angle_deg) {
        if let Some(a) = a {
            *slot = Some(a.to_radians());
        }
    }
    sim.apply(&controls);
}

/// Mean forward speed of the body over the last 0.1 s of samples (along its heading), m/s.
fn mean_forward_speed(samples: &[crate::world::Sample], interval: f64) -> f64 {
    let k = ((0.1 / interval).round() as usize).max(1);
    let n = samples.len();
    if n <= k {
        return 0.0;
    }
    let (a, b) = (&samples[n - 1 - k].pose, &samples[n - 1].pose);
    let dt = samples[n - 1].t - samples[n - 1 - k].t;
    let heading = (
        b.yaw.cos() * b.pitch.cos(),
        b.yaw.sin() * b.pitch.cos(),
        -b.pitch.sin(),
    );
    ((b.x - a.x) * heading.0 + (b.y - a.y) * heading.1 + (b.z - a.z) * heading.2) / dt
}

/// The state streamed to the page (JSON); `forward` is the body's mean forward speed, m/s.
fn state_json(
    sim: &Simulation,
    control: &DriveControl,
    (rtf, forward): ((f64, f64), f64),
    speed: f64,
    decided: &Option<(Outcome, f64)>,
) -> String {
    let p = sim.body_pose();
    let n = sim.track_names().len();
    let nf = sim.flipper_names().len();
    serde_json::json!({
        "type": "state",
        "t": sim.time(),
        "pose": [p.x, p.y, p.z, p.roll, p.pitch, p.yaw],
        "forward_mps": forward,
        "belt_position": (0..n).map(|i| sim.belt_position(i)).collect::<Vec<_>>(),
        "belt_speed": (0..n).map(|i| sim.commanded_belt_speed(i)).collect::<Vec<_>>(),
        "flipper": (0..nf).map(|i| sim.flipper_angle(i)).collect::<Vec<_>>(),
        "rtf_paced": rtf.0,
        "rtf_compute": rtf.1,
        "speed": speed,
        "outcome": decided.as_ref().map(|(o, t)| serde_json::json!({
            "name": o.name(), "reason": o.reason(), "t": t
        })),
        "control": {
            "forward_mps": control.forward_mps,
            "yaw_rate_rad_s": control.yaw_rate_rad_s,
            "flipper_angle_deg": control.flipper_angle_deg,
        },
    })
    .to_string()
}

/// What a session has recorded since its start or last reset.
struct Record {
    samples: Vec<crate::world::Sample>,
    controls: Vec<DriveControl>,
    commands: Vec<(f64, DriveControl)>,
    decided: Option<(Outcome, f64)>,
    stepping: f64,
    wall: Instant,
}

impl Record {
    fn new(sim: &Simulation, c: &DriveControl) -> Self {
        Record {
            samples: vec![sim.sample()],
            controls: vec![c.clone()],
            commands: Vec::new(),
            decided: None,
            stepping: 0.0,
            wall: Instant::now(),
        }
    }
}

/// Runs a session until the hub is asked to stop (or `opts.max_time`): paced to the wall
/// clock at `opts.speed`, controls from the hub applied at sample boundaries, the state
/// published at most every [`PUBLISH_INTERVAL_S`]. Never waits for a client.
pub fn run_session(sc: &Scenario, hub: &Hub, opts: DriveOptions) -> Result<Session> {
    let mut sim = Simulation::new(sc)?;
    let dt = sc.solver.dt;
    let every = ((sc.output_interval / dt).round() as u64).max(1);
    let idle = DriveControl {
        flipper_angle_deg: vec![None; sc.vehicle.flippers.len()],
        ..DriveControl::default()
    };
    let mut current = idle.clone();
    while opts.wait_for_page && hub.connections() == 0 && !hub.stop_requested() {
        std::thread::sleep(Duration::from_millis(10));
    }
    let mut rec = Record::new(&sim, &current);
    let mut last_publish: Option<Instant> = None;
    loop {
        // A sample boundary: stop, reset and control changes happen only here.
        if hub.stop_requested() || opts.max_time.is_some_and(|m| sim.time() >= m - 0.5 * dt) {
            break;
        }
        if hub.take_reset() {
            sim.reset(None)?;
            current = idle.clone();
            rec = Record::new(&sim, &current);
        }
        if let Some(c) = hub.take_control()
            && c != current
        {
            apply(&mut sim, sc, &c);
            rec.commands.push((sim.time(), c.clone()));
            current = c;
        }
        for _ in 0..every {
            let ahead = sim.time() / opts.speed - rec.wall.elapsed().as_secs_f64();
            if ahead > 0.002 {
                std::thread::sleep(Duration::from_secs_f64(ahead));
            }
            let t0 = Instant::now();
            sim.step()?;
            rec.stepping += t0.elapsed().as_secs_f64();
            if last_publish.is_none_or(|l| l.elapsed().as_secs_f64() >= PUBLISH_INTERVAL_S) {
                last_publish = Some(Instant::now());
                let rtf = (
                    sim.time() / rec.wall.elapsed().as_secs_f64().max(1e-9),
                    sim.time() / rec.stepping.max(1e-9),
                );
                let forward = mean_forward_speed(&rec.samples, sc.output_interval);
                hub.publish(state_json(
                    &sim,
                    &current,
                    (rtf, forward),
                    opts.speed,
                    &rec.decided,
                ));
            }
        }
        rec.samples.push(sim.sample());
        rec.controls.push(current.clone());
        if rec.decided.is_none() {
            rec.decided = check_outcome(&sc.outcome, &sim).map(|o| (o, sim.time()));
        }
    }
    let (outcome, outcome_t) = rec
        .decided
        .clone()
        .unwrap_or_else(|| (outcome::at_end(&sc.outcome, sim.time()), sim.time()));
    let times = WallTimes {
        stepping: rec.stepping,
        elapsed: rec.wall.elapsed().as_secs_f64(),
        paced: true,
    };
    let summary = Summary::new(sc, &sim, &rec.samples, (&outcome, outcome_t), times);
    hub.publish(state_json(
        &sim,
        &current,
        (
            (summary.paced_real_time_factor, summary.real_time_factor),
            mean_forward_speed(&rec.samples, sc.output_interval),
        ),
        opts.speed,
        &Some((outcome.clone(), outcome_t)),
    ));
    Ok(Session {
        result: RunResult {
            samples: rec.samples,
            track_names: sim.track_names().to_vec(),
            flipper_names: sim.flipper_names().to_vec(),
            summary,
            outcome,
        },
        commands: rec.commands,
        controls: rec.controls,
        flipper_names: sim.flipper_names().to_vec(),
        flipper_initial_deg: sc
            .vehicle
            .flippers
            .iter()
            .map(|f| f.initial_angle.to_degrees())
            .collect(),
    })
}

impl Session {
    /// The session's duration, s (the last sample's time).
    pub fn duration(&self) -> f64 {
        self.result.samples.last().map_or(0.0, |s| s.t)
    }

    /// `commands.toml` (to be written at `commands_file`): the control changes as a
    /// scenario's `[[commands]]`.
    pub fn commands_toml(&self, scenario_file: &Path, commands_file: &Path) -> String {
        #[derive(serde::Serialize)]
        struct File {
            commands: Vec<CommandSpec>,
        }
        let commands = self
            .commands
            .iter()
            .map(|(t, c)| CommandSpec {
                t_s: *t,
                forward_mps: Some(c.forward_mps),
                yaw_rate_rad_s: Some(c.yaw_rate_rad_s),
                flipper_angle_deg: self
                    .flipper_names
                    .iter()
                    .zip(&c.flipper_angle_deg)
                    .filter_map(|(n, a)| a.map(|a| (n.clone(), a)))
                    .collect(),
                ..CommandSpec::default()
            })
            .collect();
        let body = toml::to_string(&File { commands }).expect("commands serialise");
        format!(
            "# The operator's controls of a `tracksim drive` session, applied at these simulated\n\
             # times. This run reproduces the session's trajectory.csv:\n\
             #   tracksim run {} --commands {} --duration {}\n{body}",
            scenario_file.display(),
            commands_file.display(),
            self.duration()
        )
    }

    /// `controls.csv`: the controls in force at each sample (`t_s`, m/s, rad/s, flipper
    /// targets in degrees).
    pub fn controls_csv(&self) -> String {
        let mut text = String::from("t_s,forward_mps,yaw_rate_rad_s");
        for n in &self.flipper_names {
            text.push_str(&format!(",flipper_{n}_target_deg"));
        }
        text.push('\n');
        let mut held = self.flipper_initial_deg.clone();
        for (s, c) in self.result.samples.iter().zip(&self.controls) {
            text.push_str(&format!(
                "{:.6},{:.6},{:.6}",
                s.t, c.forward_mps, c.yaw_rate_rad_s
            ));
            for (h, a) in held.iter_mut().zip(&c.flipper_angle_deg) {
                if let Some(a) = a {
                    *h = *a;
                }
                text.push_str(&format!(",{h:.6}"));
            }
            text.push('\n');
        }
        text
    }

    /// Writes everything `tracksim run` writes (summary, trajectory, replay data, plots unless
    /// `plots` is false) and `commands.toml`, `controls.csv` into `dir`; returns the paths.
    pub fn write(
        &self,
        sc: &Scenario,
        scenario_file: &Path,
        dir: &Path,
        plots: bool,
    ) -> Result<Vec<PathBuf>> {
        crate::output::write_run(&self.result, dir)?;
        let mut written = vec![dir.join("summary.json"), dir.join("trajectory.csv")];
        written.extend(crate::output::write_replay(sc, &self.result, dir)?);
        if plots {
            written.extend(crate::output::write_run_plots(sc, &self.result, dir)?);
        }
        for (name, text) in [
            (
                "commands.toml",
                self.commands_toml(scenario_file, &dir.join("commands.toml")),
            ),
            ("controls.csv", self.controls_csv()),
        ] {
            let p = dir.join(name);
            crate::files::write_atomic(&p, text.as_bytes())?;
            written.push(p);
        }
        Ok(written)
    }
}
