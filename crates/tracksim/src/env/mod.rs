//! Learning environments over the run loop: one [`Env`] (a [`Runner`] of a
//! [`ScenarioTemplate`] advanced one control period per action, its observation vector, the
//! progress it made and whether the episode ended), and [`VecEnv`], many of them stepped on
//! threads with autoreset. Rewards are left to the caller (the Python package computes them
//! from [`StepInfo`], so they can be replaced).
//!
//! - `config.rs`: [`EnvConfig`] (built from named settings and checked);
//! - `mod.rs`: [`Env`], [`StepInfo`], the state vector's layout and the actions;
//! - `frames.rs`: frames of the current state ([`Env::render`]: the chase camera or an
//!   rgb_camera sensor);
//! - `learner.rs`: the learner's observation ([`LearnerObs`], `observation = "learner"`);
//! - `record.rs`: episodes written as run folders (`record_dir`);
//! - `sensor_obs.rs`: the sensors' arrays of a dict observation ([`Env::observe_sensors`]);
//! - `vector.rs`: [`VecEnv`] (and the threads it shares with [`TeamVecEnv`]);
//! - `team.rs`: the robots of a `[[vehicles]]` world as agents: [`TeamEnv`], and
//!   [`TeamVecEnv`], many such worlds on threads with autoreset (issue 40).

mod config;
mod frames;
mod learner;
mod record;
mod seeds;
mod sensor_obs;
mod team;
mod vector;

pub use config::{
    ActionMode, CHASE_CAMERA, EnvConfig, EnvSpec, EnvValue, FlipperAction, MAX_GRID_CELLS,
    MAX_RENDER_PIXELS, ObservationMode,
};
pub use learner::{DEFAULT_GOAL_AHEAD_M, LearnerEntry, LearnerObs};
pub use seeds::{Seeds, next_seed};
pub use sensor_obs::{STATE_KEY, SensorObs};
pub use team::{
    AgentStep, TEAM_ACTION_SIZE, TEAM_OBS_SIZE, TEAM_OUTCOME_REWARD, TeamEnv, TeamSettings,
    TeamVecEnv, TeamVecStep,
};
pub use vector::{MAX_ENVS, VecEnv, VecStep};

use crate::error::Result;
use crate::model::{Controls, Scenario, ScenarioTemplate};
use crate::run::{End, Outcome, Runner, time_reached};
use crate::world::{PoseRpy, Simulation};
use glam::{DQuat, DVec3, EulerRot};
use std::collections::BTreeMap;
use std::sync::Arc;

/// What one control period produced, besides the observation.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StepInfo {
    /// Progress along the start heading during the period, m.
    pub progress_delta_m: f64,
    /// Progress along the start heading since the start, m.
    pub progress_m: f64,
    /// Mean of the squared (clipped, normalised) actions: the effort the energy penalty uses.
    pub effort: f64,
    /// The scenario's outcome was decided (success, failure, tip-over) or the simulation went
    /// unstable.
    pub terminated: bool,
    /// The scenario's duration ran out undecided.
    pub truncated: bool,
    /// How the episode stands after the period.
    pub outcome: EpisodeOutcome,
}

/// How an episode stands after a control period.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum EpisodeOutcome {
    /// Still running.
    #[default]
    Running,
    /// The scenario's outcome was decided (success, failure, tip-over): terminated.
    Decided(Outcome),
    /// The scenario's duration ran out undecided: truncated. The outcome at the end: a
    /// timeout failure if it had a success condition, else completed.
    TimeUp(Outcome),
    /// The simulation went unstable (the error's message): terminated.
    Unstable(String),
    /// The episode had already ended before this step (call reset).
    AlreadyEnded,
}

impl EpisodeOutcome {
    /// "success", "failure", "completed", "timeout" (time up with a success condition),
    /// "unstable", "ended" (already ended), or "" while running.
    pub fn name(&self) -> &'static str {
        match self {
            EpisodeOutcome::Running => "",
            EpisodeOutcome::Decided(o) => o.name(),
            EpisodeOutcome::TimeUp(Outcome::Failure(_)) => "timeout",
            EpisodeOutcome::TimeUp(o) => o.name(),
            EpisodeOutcome::Unstable(_) => "unstable",
            EpisodeOutcome::AlreadyEnded => "ended",
        }
    }

    /// Why, in words ("" while running).
    pub fn reason(&self) -> String {
        match self {
            EpisodeOutcome::Running => String::new(),
            EpisodeOutcome::Decided(o) | EpisodeOutcome::TimeUp(o) => o.reason(),
            EpisodeOutcome::Unstable(e) => e.clone(),
            EpisodeOutcome::AlreadyEnded => "the episode had already ended; call reset".into(),
        }
    }
}

/// One simulation of a scenario template driven one control period per action.
pub struct Env {
    template: Arc<ScenarioTemplate>,
    cfg: EnvConfig,
    scenario: Arc<Scenario>,
    runner: Runner,
    start: PoseRpy,
    progress: f64,
    done: bool,
    /// The learner's observation (`observation = "learner"`).
    learner: Option<LearnerObs>,
    /// The controls of the step (reused: no allocation per step).
    controls: Controls,
    /// Flipper targets in force, degrees (what a recorded command says; the physics gets
    /// their conversion to radians, as from a scenario's command).
    flipper_deg: Vec<f64>,
    /// The recording of the episode (`record_dir`).
    record: Option<record::EpisodeRecord>,
    /// Where [`Env::render`]'s frames come from (`render_camera`).
    frames: frames::FrameSource,
}

impl Env {
    /// An environment at the start of an episode with `seed` (the `[randomize]` values are drawn
    /// from it). A configuration that fails [`EnvConfig::check`] is refused.
    pub fn new(template: Arc<ScenarioTemplate>, cfg: EnvConfig, seed: u64) -> Result<Self> {
        Self::episode(template, cfg, seed, 0)
    }

    /// [`Env::new`] for the environment's episode number `episode` (named so in its recording).
    fn episode(
        template: Arc<ScenarioTemplate>,
        cfg: EnvConfig,
        seed: u64,
        episode: u64,
    ) -> Result<Self> {
        cfg.check()?;
        let scenario = Arc::new(template.instantiate(seed)?);
        let mut runner = Runner::from_shared(scenario.clone())?
            .without_commands()
            .unbounded();
        if cfg.record_dir.is_none() {
            runner = runner.unrecorded();
        }
        let frames = frames::FrameSource::of(&cfg, &scenario)?;
        if cfg.observation != ObservationMode::Dict && !frames.needs_sensors() {
            // Nothing reads the sensors: they cost nothing (the learner's map is its own).
            runner = runner.without_sensors();
        }
        if cfg.observation == ObservationMode::Dict {
            sensor_obs::check_names(runner.sensors())?;
        }
        let start = runner.sim().body_pose();
        let learner = (cfg.observation == ObservationMode::Learner)
            .then(|| LearnerObs::new(runner.sim(), &scenario, &cfg, &start));
        let v = &scenario.vehicle;
        let flipper_deg = (0..v.flippers.len())
            .map(|i| runner.sim().flipper_target(i).to_degrees())
            .collect();
        let record = cfg
            .record_dir
            .clone()
            .map(|d| record::EpisodeRecord::new(d, episode));
        Ok(Env {
            record,
            controls: Controls::keep(v),
            template,
            cfg,
            scenario,
            runner,
            start,
            progress: 0.0,
            done: false,
            learner,
            flipper_deg,
            frames,
        })
    }

    /// Starts a new episode with `seed` (with `record_dir`, the episode that ends here is
    /// written first).
    pub fn reset(&mut self, seed: u64) -> Result<()> {
        let episode = self.next_episode();
        let fresh = Env::episode(self.template.clone(), self.cfg.clone(), seed, episode)?;
        let old = std::mem::replace(self, fresh);
        old.write_record()?;
        Ok(())
    }

    /// Writes the episode so far as a run folder (with `record_dir`; see the `record_dir`
    /// setting) and starts recording it afresh as if just reset with its seed: what closing a
    /// recording environment does. Returns the folder written (`None`: not recording, or no
    /// step yet).
    pub fn flush_record(&mut self) -> Result<Option<std::path::PathBuf>> {
        if self.record.is_none() {
            return Ok(None);
        }
        let seed = self.runner.sim().seed();
        let episode = self.next_episode();
        let fresh = Env::episode(self.template.clone(), self.cfg.clone(), seed, episode)?;
        std::mem::replace(self, fresh).write_record()
    }

    /// The recorded number of the next episode: this one's plus one, unless this one was
    /// never stepped (it writes nothing, and the next takes its number).
    fn next_episode(&self) -> u64 {
        self.record
            .as_ref()
            .map_or(0, |r| r.episode + u64::from(self.runner.sim().steps() > 0))
    }

    /// Writes this episode's folder if recording (consumes the episode).
    fn write_record(self) -> Result<Option<std::path::PathBuf>> {
        let Some(rec) = self.record else {
            return Ok(None);
        };
        let seed = self.runner.sim().seed();
        rec.write(
            self.runner,
            &self.scenario,
            self.template.path(),
            seed,
            self.done,
        )
    }

    /// The configuration.
    pub fn config(&self) -> &EnvConfig {
        &self.cfg
    }

    /// The episode's course score (`[course]`; `None` without one): so far while it runs, and
    /// once it has ended (terminated or truncated) as the episode's recording's `summary.json`
    /// has it ([`Runner::course_as_ended`]).
    pub fn course(&self) -> Option<crate::run::CourseScore> {
        if self.done {
            self.runner.course_as_ended()
        } else {
            self.runner.course()
        }
    }

    /// The running simulation.
    pub fn simulation(&self) -> &Simulation {
        self.runner.sim()
    }

    /// The run loop of the episode (its simulation, outcome so far, course score).
    pub fn runner(&self) -> &Runner {
        &self.runner
    }

    /// The episode's compiled scenario.
    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }

    /// The `[randomize]` values of this episode, by name.
    pub fn randomized(&self) -> &BTreeMap<String, f64> {
        &self.scenario.randomized
    }

    /// Physics steps per action.
    pub fn substeps(&self) -> u64 {
        ((self.cfg.control_period_s / self.runner.sim().dt()).round() as u64).max(1)
    }

    /// Number of actions: 2 (twist) or one per track, then one per flipper.
    pub fn action_dim(&self) -> usize {
        let v = &self.scenario.vehicle;
        let drive = match self.cfg.action {
            ActionMode::Twist => 2,
            ActionMode::Belts => v.tracks.len(),
        };
        drive + v.flippers.len()
    }

    /// The learner's observation (`observation = "learner"`), its layout and cost.
    pub fn learner(&self) -> Option<&LearnerObs> {
        self.learner.as_ref()
    }

    /// Length of the observation vector (see [`Env::observe`]).
    pub fn obs_dim(&self) -> usize {
        if let Some(l) = &self.learner {
            return l.len();
        }
        let v = &self.scenario.vehicle;
        10 + v.flippers.len() + v.tracks.len() + self.cfg.grid_shape.0 * self.cfg.grid_shape.1
    }

    /// Names of the observation entries, in order.
    pub fn obs_names(&self) -> Vec<String> {
        if let Some(l) = &self.learner {
            return l.value_names();
        }
        let mut n: Vec<String> = [
            "roll_rad",
            "pitch_rad",
            "yaw_rad",
            "height_m",
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
        n.extend(
            self.runner
                .sim()
                .flipper_names()
                .iter()
                .map(|f| format!("flipper_{f}_rad")),
        );
        n.extend(
            self.runner
                .sim()
                .track_names()
                .iter()
                .map(|t| format!("belt_{t}_mps")),
        );
        let (nx, ny) = self.cfg.grid_shape;
        for i in 0..nx {
            for j in 0..ny {
                n.push(format!("terrain_{i}_{j}_m"));
            }
        }
        n
    }

    /// The observation, written to `out` (length [`Env::obs_dim`]): roll, pitch (rad), yaw
    /// relative to the start heading (rad, wrapped to ±pi), height of the body above its start
    /// (m); linear (m/s) and angular (rad/s) velocity in the body frame (x forward, y left, z
    /// up); flipper angles (rad); measured belt speeds (m/s); then the terrain height relative
    /// to the body origin (m) at each point of the grid ahead (rows along the heading from
    /// `grid_ahead_m`, columns from right to left, centred), by downward ray casts;
    /// `no_terrain_m` where there is none. With `observation = "learner"`, the learner's
    /// entries one after the other instead ([`LearnerObs`]).
    pub fn observe(&self, out: &mut [f32]) {
        if let Some(l) = &self.learner {
            out.copy_from_slice(l.values());
            return;
        }
        let s = self.runner.sim().sample();
        let p = s.pose;
        let q = DQuat::from_euler(EulerRot::ZYX, p.yaw, p.pitch, p.roll);
        let v = q.inverse() * DVec3::from_array(s.linvel);
        let w = q.inverse() * DVec3::from_array(s.angvel);
        let yaw_rel = (p.yaw - self.start.yaw + std::f64::consts::PI)
            .rem_euclid(2.0 * std::f64::consts::PI)
            - std::f64::consts::PI;
        let mut vals: Vec<f64> = vec![
            p.roll,
            p.pitch,
            yaw_rel,
            p.z - self.start.z,
            v.x,
            v.y,
            v.z,
            w.x,
            w.y,
            w.z,
        ];
        vals.extend(&s.flipper_angle);
        vals.extend(&s.belt_speed);
        let (nx, ny) = self.cfg.grid_shape;
        let (dx, dy) = self.cfg.grid_spacing_m;
        let (c, sn) = (p.yaw.cos(), p.yaw.sin());
        for i in 0..nx {
            for j in 0..ny {
                let ax = self.cfg.grid_ahead_m + i as f64 * dx;
                let ay = (j as f64 - (ny as f64 - 1.0) / 2.0) * dy;
                let (x, y) = (p.x + c * ax - sn * ay, p.y + sn * ax + c * ay);
                vals.push(
                    self.runner
                        .sim()
                        .terrain_below(x, y)
                        .map_or(self.cfg.no_terrain_m, |z| z - p.z),
                );
            }
        }
        for (o, v) in out.iter_mut().zip(vals) {
            *o = v as f32;
        }
    }

    /// Progress along the start heading since the start, m.
    pub fn progress(&self) -> f64 {
        self.progress
    }

    /// Refuses an action whose length is not [`Env::action_dim`] (the order: drive actions,
    /// then one per flipper).
    pub fn check_action(&self, action: &[f32]) -> Result<()> {
        let n = self.action_dim();
        if action.len() == n {
            return Ok(());
        }
        Err(crate::error::Error::setting(
            "step",
            "action",
            format!(
                "expected {n} actions ({} drive, then one per flipper), got {}",
                n - self.scenario.vehicle.flippers.len(),
                action.len()
            ),
        ))
    }

    /// The controls of a normalised action (clipped to `[-1, 1]`; missing entries are 0):
    /// the drive actions scaled by the maxima; each flipper's target angle, with
    /// `flipper_action = "position"` its action mapped linearly onto `flipper_range_rad`, with
    /// `"velocity"` its target in force moved by the action times `max_flipper_rate_rad_s` over
    /// the control period, clamped to `flipper_range_rad` and the joint's limits. Targets are
    /// rounded through degrees (as a scenario's `flipper_angle_deg` is: a recorded episode
    /// replays exactly).
    pub fn controls(&self, action: &[f32]) -> Controls {
        let mut c = Controls::keep(&self.scenario.vehicle);
        let mut deg = self.flipper_deg.clone();
        self.write_controls(action, &mut c, &mut deg);
        c
    }

    /// [`Env::controls`] into `c` (sized for the vehicle), the flipper targets in degrees into
    /// `deg` (holding those in force).
    fn write_controls(&self, action: &[f32], c: &mut Controls, deg: &mut [f64]) {
        let a = |i: usize| action.get(i).map_or(0.0, |x| (*x as f64).clamp(-1.0, 1.0));
        let v = &self.scenario.vehicle;
        let n = match self.cfg.action {
            ActionMode::Twist => {
                let (fwd, yaw) = (
                    a(0) * self.cfg.max_forward_mps,
                    a(1) * self.cfg.max_yaw_rate_rad_s,
                );
                for (i, b) in c.belt_speed.iter_mut().enumerate() {
                    *b = Some(v.twist_belt_speed(i, fwd, yaw));
                }
                2
            }
            ActionMode::Belts => {
                for (i, b) in c.belt_speed.iter_mut().enumerate() {
                    *b = Some(a(i) * self.cfg.max_belt_speed_mps);
                }
                v.tracks.len()
            }
        };
        let (lo, hi) = self.cfg.flipper_range_rad;
        let period = self.substeps() as f64 * self.runner.sim().dt();
        for (i, fl) in v.flippers.iter().enumerate() {
            let target = match self.cfg.flipper_action {
                FlipperAction::Position => lo + (a(n + i) + 1.0) / 2.0 * (hi - lo),
                FlipperAction::Velocity => {
                    let t =
                        deg[i].to_radians() + a(n + i) * self.cfg.max_flipper_rate_rad_s * period;
                    let t = t.clamp(lo.min(hi), hi.max(lo));
                    match fl.limits {
                        Some([l, h]) => t.clamp(l, h),
                        None => t,
                    }
                }
            };
            deg[i] = target.to_degrees();
            c.flipper_angle[i] = Some(deg[i].to_radians());
        }
    }

    /// Applies `action` (normalised, see [`Env::controls`]) for one control period and says
    /// what happened. After the episode ended, call [`Env::reset`]; stepping on changes
    /// nothing and repeats the end.
    pub fn step(&mut self, action: &[f32]) -> StepInfo {
        let n = self.action_dim();
        let effort = (0..n)
            .map(|i| {
                action
                    .get(i)
                    .map_or(0.0, |x| (*x as f64).clamp(-1.0, 1.0).powi(2))
            })
            .sum::<f64>()
            / n.max(1) as f64;
        let mut info = StepInfo {
            effort,
            progress_m: self.progress,
            ..StepInfo::default()
        };
        if self.done {
            info.terminated = true;
            info.outcome = EpisodeOutcome::AlreadyEnded;
            return info;
        }
        let mut controls = std::mem::take(&mut self.controls);
        let mut deg = std::mem::take(&mut self.flipper_deg);
        self.write_controls(action, &mut controls, &mut deg);
        self.runner.apply(&controls);
        if let Some(r) = &mut self.record {
            let drive = match self.cfg.action {
                ActionMode::Twist => {
                    let a = |i: usize| action.get(i).map_or(0.0, |x| (*x as f64).clamp(-1.0, 1.0));
                    record::Drive::Twist(
                        a(0) * self.cfg.max_forward_mps,
                        a(1) * self.cfg.max_yaw_rate_rad_s,
                    )
                }
                ActionMode::Belts => record::Drive::Belts,
            };
            let belts: Vec<f64> = controls
                .belt_speed
                .iter()
                .map(|b| b.unwrap_or(0.0))
                .collect();
            r.push(&self.scenario, self.runner.time(), drive, &belts, &deg);
        }
        self.controls = controls;
        self.flipper_deg = deg;
        for _ in 0..self.substeps() {
            if let Err(e) = self.runner.step() {
                self.done = true;
                info.terminated = true;
                info.outcome = EpisodeOutcome::Unstable(e.to_string());
                return info;
            }
        }
        let p = self.runner.sim().body_pose();
        let (c, s) = (self.start.yaw.cos(), self.start.yaw.sin());
        let progress = (p.x - self.start.x) * c + (p.y - self.start.y) * s;
        info.progress_delta_m = progress - self.progress;
        info.progress_m = progress;
        self.progress = progress;
        if let Some(l) = &mut self.learner {
            l.update(self.runner.sim());
        }
        // Decided at every output interval of the period and at its end (the runner's check).
        self.runner.decide();
        let (t, dt) = (self.runner.time(), self.runner.sim().dt());
        info.outcome = match self.runner.decided() {
            Some((o, _)) => EpisodeOutcome::Decided(o.clone()),
            None if time_reached(t, self.scenario.duration, dt) => {
                EpisodeOutcome::TimeUp(self.runner.outcome(&End::Reached).0)
            }
            None => EpisodeOutcome::Running,
        };
        info.terminated = matches!(info.outcome, EpisodeOutcome::Decided(_));
        info.truncated = matches!(info.outcome, EpisodeOutcome::TimeUp(_));
        self.done = info.terminated || info.truncated;
        info
    }
}

impl Env {
    /// A frame of the current state, rgb8 rows from the top (`3 * width * height` bytes, see
    /// [`Env::render_size`]): with `render_camera = "chase"` (the default) the chase camera
    /// traced now (behind and above the robot, turning with its heading, `render_size_px`
    /// pixels, 70 deg across; a few ms at 160 x 120); with the name of an rgb_camera sensor,
    /// its latest frame (taken at its own rate). Rendering changes nothing in the simulation.
    pub fn render(&mut self) -> &crate::render::Frame {
        static EMPTY: std::sync::OnceLock<crate::render::Frame> = std::sync::OnceLock::new();
        match self.frames.render(self.runner.sim(), self.runner.sensors()) {
            Some(f) => f,
            None => EMPTY.get_or_init(|| crate::render::Frame::new(0, 0)),
        }
    }

    /// Width and height of [`Env::render`]'s frames, pixels.
    pub fn render_size(&self) -> (usize, usize) {
        self.frames.size(&self.scenario)
    }

    /// The sensor entries of the observation (empty unless `observation = "dict"`), in the
    /// order of the vehicle's `[[sensors]]`; see [`Env::observe_sensors`].
    pub fn sensor_obs_spec(&self) -> Vec<SensorObs> {
        match self.cfg.observation {
            ObservationMode::Vector | ObservationMode::Learner => Vec::new(),
            ObservationMode::Dict => sensor_obs::specs(self.runner.sensors()),
        }
    }

    /// Number of values of [`Env::observe_sensors`].
    pub fn sensor_obs_dim(&self) -> usize {
        self.sensor_obs_spec().iter().map(SensorObs::len).sum()
    }

    /// The sensors' latest readings as float32 arrays, one after the other in the order of
    /// [`Env::sensor_obs_spec`] (each row-major), into `out` (length [`Env::sensor_obs_dim`]):
    /// an IMU as accel (m/s^2), gyro (rad/s), orientation (x, y, z, w); encoders as belt
    /// positions (m), belt speeds (m/s), flipper angles (rad); a lidar's ranges and a depth
    /// camera's depths (m) with no return as their `max_range_m` and too close as 0; an
    /// elevation map's heights relative to the sensor (m) with `no_terrain_m` where there is
    /// no terrain.
    pub fn observe_sensors(&self, out: &mut [f32]) {
        if self.cfg.observation != ObservationMode::Dict {
            return;
        }
        sensor_obs::observe(self.runner.sensors(), &self.cfg, out);
    }

    /// The vehicle's sensors and their latest readings.
    pub fn sensors(&self) -> &crate::sensors::SensorSet {
        self.runner.sensors()
    }
}
