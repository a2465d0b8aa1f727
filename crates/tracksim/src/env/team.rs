//! The robots of a `[[vehicles]]` world as agents (issue 40, docs/TEAMS.md): [`TeamEnv`], one
//! world advanced one control period per set of actions (each agent's observation, reward,
//! termination and truncation), and [`TeamVecEnv`], many such worlds stepped together on
//! threads (the machinery of [`super::VecEnv`]) with autoreset. The Python package's
//! `TeamParallelEnv` (PettingZoo) runs one [`TeamEnv`]; its `TeamVectorEnv` a [`TeamVecEnv`]:
//! one implementation, so world `i` of the vector is the lone environment with the same seed.

use super::MAX_ENVS;
use super::seeds::Seeds;
use super::vector::StepPool;
use crate::error::{Error, Result};
use crate::model::ScenarioTemplate;
use crate::run::{Outcome, check_outcome};
use crate::world::Simulation;
use std::sync::Arc;

/// Observation entries per agent (float32): its position relative to its start in its start
/// frame (x forward, y left, z up: 3, m), roll, pitch and yaw relative to its start heading (3,
/// rad), its velocity in its heading frame (forward, left, up: 3, m/s), its angular velocity
/// (3, rad/s, world frame), the nearest other robot's position in its heading frame (2, m; 0, 0
/// alone) and the fraction of the episode's time elapsed (1).
pub const TEAM_OBS_SIZE: usize = 15;
/// Action entries per agent: a twist `[forward, yaw_rate]` in [-1, 1].
pub const TEAM_ACTION_SIZE: usize = 2;
/// Reward added when an agent's own outcome is a success, and taken when it is a failure.
pub const TEAM_OUTCOME_REWARD: f64 = 10.0;

/// The settings of a team environment.
#[derive(Clone, Debug, PartialEq)]
pub struct TeamSettings {
    /// Control periods per second (each a whole number of physics steps, at least one).
    pub control_hz: f64,
    /// Forward speed of an action of 1, m/s.
    pub max_speed_mps: f64,
    /// Yaw rate of an action of 1, rad/s.
    pub max_yaw_rate_rad_s: f64,
    /// Episode length, s (default: the file's `simulation.duration_s`).
    pub max_time_s: Option<f64>,
}

impl Default for TeamSettings {
    fn default() -> Self {
        TeamSettings {
            control_hz: 10.0,
            max_speed_mps: 0.5,
            max_yaw_rate_rad_s: 1.0,
            max_time_s: None,
        }
    }
}

impl TeamSettings {
    /// Refuses a non-positive or non-finite `control_hz` or `max_time_s` and non-finite maxima.
    pub fn check(&self) -> Result<()> {
        let positive = |key: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(Error::setting(
                    "team environment",
                    key,
                    format!("must be positive, got {v}"),
                ))
            }
        };
        positive("control_hz", self.control_hz)?;
        if let Some(t) = self.max_time_s {
            positive("max_time_s", t)?;
        }
        for (key, v) in [
            ("max_speed_mps", self.max_speed_mps),
            ("max_yaw_rate_rad_s", self.max_yaw_rate_rad_s),
        ] {
            if !v.is_finite() {
                return Err(Error::setting(
                    "team environment",
                    key,
                    format!("must be finite, got {v}"),
                ));
            }
        }
        Ok(())
    }
}

/// What one control period gave one agent.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AgentStep {
    /// The agent acted in this period (it had not ended before, and it was not an autoreset).
    pub active: bool,
    /// Its progress along its start heading in the period (+-[`TEAM_OUTCOME_REWARD`] when its
    /// outcome was decided); 0 when not active.
    pub reward: f64,
    /// Its own outcome was decided in this period (a success or a failure, or the world went
    /// unstable): it is braked from then on.
    pub terminated: bool,
    /// The episode's time ran out in this period, its outcome undecided.
    pub truncated: bool,
    /// Its progress along its start heading since the start, m.
    pub progress_m: f64,
    /// Its outcome, once decided (in the period it terminated).
    pub outcome: Option<Outcome>,
}

/// One robot's state the observation reads.
#[derive(Clone, Copy, Debug, Default)]
struct RobotState {
    /// x, y, z, m; roll, pitch, yaw, rad.
    pose: [f64; 6],
    linvel: [f64; 3],
    angvel: [f64; 3],
}

/// One `[[vehicles]]` world as a multi-agent environment: an agent per robot, in the order of
/// [`Simulation::robot_names`]. Each period every running agent's twist is applied, the world
/// advances a whole number of physics steps, and each agent is observed and rewarded its
/// progress (see [`TEAM_OBS_SIZE`], [`AgentStep`]). An agent whose outcome is decided is
/// braked; every agent is truncated at the episode's length. Sensors are not simulated.
pub struct TeamEnv {
    template: Arc<ScenarioTemplate>,
    sim: Simulation,
    substeps: u64,
    max_time: f64,
    scale: [f64; 2],
    /// Each robot's start x, y (m) and yaw (rad).
    start: Vec<[f64; 3]>,
    progress: Vec<f64>,
    running: Vec<bool>,
    states: Vec<RobotState>,
}

impl TeamEnv {
    /// A world of `template` with `seed`, at the start of an episode.
    pub fn new(
        template: Arc<ScenarioTemplate>,
        settings: &TeamSettings,
        seed: u64,
    ) -> Result<Self> {
        settings.check()?;
        let sim = Simulation::new(&template.instantiate(seed)?)?;
        let substeps = ((1.0 / (settings.control_hz * sim.dt())).round_ties_even() as u64).max(1);
        let max_time = match settings.max_time_s {
            Some(t) => t,
            None => template.file_scenario()?.duration,
        };
        let mut env = TeamEnv {
            template,
            sim,
            substeps,
            max_time,
            scale: [settings.max_speed_mps, settings.max_yaw_rate_rad_s],
            start: Vec::new(),
            progress: Vec::new(),
            running: Vec::new(),
            states: Vec::new(),
        };
        env.begin();
        Ok(env)
    }

    /// Starts an episode with `seed` (default: the current one), the `[randomize]` values
    /// drawn anew from it.
    pub fn reset(&mut self, seed: Option<u64>) -> Result<()> {
        let sc = self.template.instantiate(seed.unwrap_or(self.sim.seed()))?;
        self.sim = Simulation::new(&sc)?;
        self.begin();
        Ok(())
    }

    /// Every agent running, its start taken from the world.
    fn begin(&mut self) {
        let n = self.sim.robot_count();
        self.refresh();
        self.start = self
            .states
            .iter()
            .map(|s| [s.pose[0], s.pose[1], s.pose[5]])
            .collect();
        self.progress = vec![0.0; n];
        self.running = vec![true; n];
    }

    /// Reads every robot's state.
    fn refresh(&mut self) {
        let selected = self.sim.selected();
        self.states = (0..self.sim.robot_count())
            .map(|k| {
                self.sim.select(k);
                let p = self.sim.body_pose();
                let (linvel, angvel) = self.sim.body_velocity();
                RobotState {
                    pose: [p.x, p.y, p.z, p.roll, p.pitch, p.yaw],
                    linvel,
                    angvel,
                }
            })
            .collect();
        self.sim.select(selected);
    }

    /// The world.
    pub fn simulation(&self) -> &Simulation {
        &self.sim
    }

    /// Agents (robots) in the world.
    pub fn agent_count(&self) -> usize {
        self.running.len()
    }

    /// Physics steps per control period.
    pub fn substeps(&self) -> u64 {
        self.substeps
    }

    /// The episode's length, s.
    pub fn max_time_s(&self) -> f64 {
        self.max_time
    }

    /// Which agents are still running (not terminated or truncated).
    pub fn running(&self) -> &[bool] {
        &self.running
    }

    /// True once every agent has ended: the episode is over.
    pub fn done(&self) -> bool {
        !self.running.iter().any(|r| *r)
    }

    /// Checks that `actions` holds [`TEAM_ACTION_SIZE`] values per agent.
    pub fn check_actions(&self, actions: &[f32]) -> Result<()> {
        let n = self.agent_count() * TEAM_ACTION_SIZE;
        if actions.len() == n {
            return Ok(());
        }
        Err(Error::setting(
            "step",
            "actions",
            format!(
                "expected {n} values ({} agents times {TEAM_ACTION_SIZE}), got {}",
                self.agent_count(),
                actions.len()
            ),
        ))
    }

    /// One control period: each running agent `k` drives with `actions[2k..2k + 2]` (clipped
    /// to [-1, 1], scaled by the maxima; the rows of ended agents are ignored); returns what
    /// each agent got. A world that goes unstable ends the episode: every running agent
    /// terminates with a failure naming the error. `actions` of the wrong length panic (see
    /// [`TeamEnv::check_actions`]).
    pub fn step(&mut self, actions: &[f32]) -> Vec<AgentStep> {
        assert_eq!(actions.len(), self.agent_count() * TEAM_ACTION_SIZE);
        for k in 0..self.agent_count() {
            if self.running[k] {
                let a = |j: usize| f64::from(actions[2 * k + j]).clamp(-1.0, 1.0) * self.scale[j];
                let (forward, yaw_rate) = (a(0), a(1));
                self.sim.select(k);
                self.sim.set_twist(forward, yaw_rate);
            }
        }
        let stepped = (0..self.substeps).try_for_each(|_| self.sim.step());
        self.refresh();
        let time_up = self.sim.time() >= self.max_time - 0.5 * self.sim.dt();
        let mut out = Vec::with_capacity(self.agent_count());
        for k in 0..self.agent_count() {
            if !self.running[k] {
                out.push(AgentStep {
                    progress_m: self.progress[k],
                    ..AgentStep::default()
                });
                continue;
            }
            let forward = self.forward(k);
            let mut reward = forward - self.progress[k];
            self.progress[k] = forward;
            self.sim.select(k);
            let outcome = match &stepped {
                Err(e) => Some(Outcome::Failure(e.to_string())),
                Ok(()) => check_outcome(&self.sim.scenario().outcome, &self.sim),
            };
            if let Some(o) = &outcome {
                reward += match o {
                    Outcome::Success(_) => TEAM_OUTCOME_REWARD,
                    _ => -TEAM_OUTCOME_REWARD,
                };
                self.sim.set_twist(0.0, 0.0);
            }
            let terminated = outcome.is_some();
            let truncated = time_up && !terminated;
            self.running[k] = !(terminated || truncated);
            out.push(AgentStep {
                active: true,
                reward,
                terminated,
                truncated,
                progress_m: forward,
                outcome,
            });
        }
        out
    }

    /// Agent `k`'s progress along its start heading, m.
    fn forward(&self, k: usize) -> f64 {
        let [x0, y0, yaw0] = self.start[k];
        let p = &self.states[k].pose;
        (p[0] - x0) * yaw0.cos() + (p[1] - y0) * yaw0.sin()
    }

    /// Writes every agent's observation ([`TEAM_OBS_SIZE`] values each, agent after agent)
    /// into `obs`; ended agents are observed too.
    pub fn observe(&self, obs: &mut [f32]) {
        let t = self.sim.time() / self.max_time;
        for (k, o) in obs.chunks_mut(TEAM_OBS_SIZE).enumerate() {
            let s = &self.states[k];
            let [x0, y0, yaw0] = self.start[k];
            let (c0, s0) = (yaw0.cos(), yaw0.sin());
            let [x, y, z, roll, pitch, yaw] = s.pose;
            let (dx, dy) = (x - x0, y - y0);
            let (c, sn) = (yaw.cos(), yaw.sin());
            let v = s.linvel;
            let near = self.nearest(k).map_or([0.0, 0.0], |q| {
                let (ex, ey) = (q[0] - x, q[1] - y);
                [ex * c + ey * sn, -ex * sn + ey * c]
            });
            let values = [
                dx * c0 + dy * s0,
                -dx * s0 + dy * c0,
                z,
                roll,
                pitch,
                wrap(yaw - yaw0),
                v[0] * c + v[1] * sn,
                -v[0] * sn + v[1] * c,
                v[2],
                s.angvel[0],
                s.angvel[1],
                s.angvel[2],
                near[0],
                near[1],
                t,
            ];
            for (o, v) in o.iter_mut().zip(values) {
                *o = v as f32;
            }
        }
    }

    /// The position of the robot nearest to robot `k` in the plane (the first of equals), if
    /// there is another.
    fn nearest(&self, k: usize) -> Option<[f64; 2]> {
        let p = &self.states[k].pose;
        let mut best: Option<([f64; 2], f64)> = None;
        for (j, s) in self.states.iter().enumerate() {
            if j == k {
                continue;
            }
            let q = [s.pose[0], s.pose[1]];
            let d = (q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]);
            if best.is_none_or(|(_, b)| d < b) {
                best = Some((q, d));
            }
        }
        best.map(|(q, _)| q)
    }
}

/// An angle wrapped to [-pi, pi).
fn wrap(a: f64) -> f64 {
    use std::f64::consts::PI;
    (a + PI).rem_euclid(2.0 * PI) - PI
}

/// `n` team worlds of one template stepped together on threads, with autoreset as Gymnasium's
/// "next step" mode: the step after a world's episode ended (every agent terminated or
/// truncated) resets that world with the next seed of its sequence ([`super::next_seed`]) and ignores
/// its actions. Each world is advanced by one thread and owns its state, so results do not
/// depend on the thread count, and world `i` equals a lone [`TeamEnv`] with its seed.
pub struct TeamVecEnv {
    envs: Vec<TeamEnv>,
    seeds: Seeds,
    ended: Vec<bool>,
    pool: StepPool,
}

/// What one world's step gave.
#[derive(Clone, Debug)]
pub struct TeamVecStep {
    /// Each agent's step (inactive, zero, for an autoreset).
    pub agents: Vec<AgentStep>,
    /// This step reset the world (its actions were ignored).
    pub reset: bool,
    /// The episode seed in effect after the step.
    pub seed: u64,
    /// The world's time after the step, s.
    pub t_s: f64,
}

impl TeamVecEnv {
    /// `n` worlds (at least 1, at most [`MAX_ENVS`]), world `i` starting with seed `seed + i`,
    /// stepped on `threads` threads (0 is taken as 1).
    pub fn new(
        template: Arc<ScenarioTemplate>,
        settings: &TeamSettings,
        n: usize,
        seed: u64,
        threads: usize,
    ) -> Result<Self> {
        if !(1..=MAX_ENVS).contains(&n) {
            return Err(Error::setting(
                "team vector environment",
                "num_envs",
                format!("must be from 1 to {MAX_ENVS} worlds, got {n}"),
            ));
        }
        settings.check()?;
        let seeds = Seeds::from_base(n, seed);
        let envs = seeds
            .as_slice()
            .iter()
            .map(|s| TeamEnv::new(template.clone(), settings, *s))
            .collect::<Result<Vec<_>>>()?;
        Ok(TeamVecEnv {
            envs,
            ended: vec![false; n],
            seeds,
            pool: StepPool::new(threads),
        })
    }

    /// Number of worlds.
    pub fn len(&self) -> usize {
        self.envs.len()
    }

    /// True without worlds (never: at least one is built).
    pub fn is_empty(&self) -> bool {
        self.envs.is_empty()
    }

    /// The worlds.
    pub fn envs(&self) -> &[TeamEnv] {
        &self.envs
    }

    /// Agents per world.
    pub fn agent_count(&self) -> usize {
        self.envs[0].agent_count()
    }

    /// Threads used per step.
    pub fn threads(&self) -> usize {
        self.pool.threads()
    }

    /// Sets the threads used per step (at least 1): the pool of the old count stops, one of the
    /// new count starts at the next step.
    pub fn set_threads(&mut self, t: usize) {
        self.pool.set_threads(t);
    }

    /// Resets every world, `i` with seed `seed + i` (or its current seed with `None`), on the
    /// threads.
    pub fn reset(&mut self, seed: Option<u64>) -> Result<()> {
        if let Some(s) = seed {
            self.seeds.rebase(s);
        }
        let seeds = self.seeds.as_slice();
        self.pool
            .run(&mut self.envs, |i, env| env.reset(Some(seeds[i])))?;
        self.ended.iter_mut().for_each(|e| *e = false);
        Ok(())
    }

    /// Resets world `i` with `seeds[i]` (one seed per world).
    pub fn reset_seeds(&mut self, seeds: &[u64]) -> Result<()> {
        self.seeds.replace(seeds, "world")?;
        self.reset(None)
    }

    /// Observation values of all worlds: `len() * agent_count() * TEAM_OBS_SIZE`.
    pub fn obs_len(&self) -> usize {
        self.len() * self.agent_count() * TEAM_OBS_SIZE
    }

    /// Steps every world with its agents' actions (world after world, agent after agent,
    /// [`TEAM_ACTION_SIZE`] each), writing the observations into `obs` (laid out likewise,
    /// [`TEAM_OBS_SIZE`] each); other lengths are refused (keys `actions`, `obs`).
    pub fn step(&mut self, actions: &[f32], obs: &mut [f32]) -> Result<Vec<TeamVecStep>> {
        let per = self.agent_count() * TEAM_ACTION_SIZE;
        let n = self.len();
        for (key, len, want) in [
            ("actions", actions.len(), n * per),
            ("obs", obs.len(), self.obs_len()),
        ] {
            if len != want {
                return Err(Error::setting(
                    "step",
                    key,
                    format!("expected {want} values ({n} worlds), got {len}"),
                ));
            }
        }
        let ended = self.ended.clone();
        let seeds = self.seeds.after(&ended);
        let out = self.pool.run(&mut self.envs, |i, env| {
            let (agents, reset) = if ended[i] {
                env.reset(Some(seeds.as_slice()[i]))?;
                (vec![AgentStep::default(); env.agent_count()], true)
            } else {
                (env.step(&actions[i * per..(i + 1) * per]), false)
            };
            Ok(TeamVecStep {
                agents,
                reset,
                seed: seeds.as_slice()[i],
                t_s: env.simulation().time(),
            })
        })?;
        self.seeds = seeds;
        self.observe(obs);
        for (e, env) in self.ended.iter_mut().zip(&self.envs) {
            *e = env.done();
        }
        Ok(out)
    }

    /// Writes every world's observations into `obs` ([`TeamVecEnv::obs_len`] values).
    pub fn observe(&self, obs: &mut [f32]) {
        let per = self.agent_count() * TEAM_OBS_SIZE;
        for (e, o) in self.envs.iter().zip(obs.chunks_mut(per)) {
            e.observe(o);
        }
    }
}
