//! The team environments' cores (issue 40, docs/TEAMS.md): `TeamEnvCore`, one `[[vehicles]]`
//! world whose robots are agents (what `tracksim.team_env.TeamParallelEnv` runs), and
//! `TeamVecEnvCore`, many such worlds stepped on Rust threads with the GIL released and
//! autoreset (what `tracksim.team_vector.TeamVectorEnv` runs). Both are the library's
//! [`tracksim::env::TeamEnv`]: world `i` of the vector is the lone world with its seed.

use crate::common::{Shared, py_err};
use crate::scenario::template_of;
use numpy::PyArray1;
use numpy::PyArrayMethods;
use numpy::PyReadonlyArray3;
use numpy::PyUntypedArrayMethods;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::BTreeMap;
use tracksim::env::{
    AgentStep, TEAM_ACTION_SIZE, TEAM_OBS_SIZE, TeamEnv, TeamSettings, TeamVecEnv, TeamVecStep,
};

/// Observations (worlds, agents, `TEAM_OBS_SIZE`) and the step's arrays.
type TeamOut<'py> = (Bound<'py, numpy::PyArray3<f32>>, Bound<'py, PyDict>);

/// `flat` observations of `worlds` worlds of `agents` agents as a float32 array (worlds,
/// agents, obs).
fn obs_array(
    py: Python<'_>,
    flat: Vec<f32>,
    worlds: usize,
    agents: usize,
) -> PyResult<Bound<'_, numpy::PyArray3<f32>>> {
    PyArray1::from_vec(py, flat).reshape([worlds, agents, TEAM_OBS_SIZE])
}

/// The agents' steps of every world (rows) as arrays (worlds, agents): reward, terminated,
/// truncated, active, progress_m, and nested lists outcome (None while undecided) and reason.
fn agent_arrays<'py>(py: Python<'py>, rows: &[&[AgentStep]]) -> PyResult<Bound<'py, PyDict>> {
    let shape = [rows.len(), rows.first().map_or(0, |r| r.len())];
    let d = PyDict::new(py);
    let num = |f: fn(&AgentStep) -> f64| -> PyResult<_> {
        let v: Vec<f64> = rows.iter().flat_map(|r| r.iter().map(f)).collect();
        PyArray1::from_vec(py, v).reshape(shape)
    };
    let flag = |f: fn(&AgentStep) -> bool| -> PyResult<_> {
        let v: Vec<bool> = rows.iter().flat_map(|r| r.iter().map(f)).collect();
        PyArray1::from_vec(py, v).reshape(shape)
    };
    d.set_item("reward", num(|a| a.reward)?)?;
    d.set_item("progress_m", num(|a| a.progress_m)?)?;
    d.set_item("terminated", flag(|a| a.terminated)?)?;
    d.set_item("truncated", flag(|a| a.truncated)?)?;
    d.set_item("active", flag(|a| a.active)?)?;
    let text = |f: fn(&tracksim::Outcome) -> String| {
        rows.iter()
            .map(|r| r.iter().map(|a| a.outcome.as_ref().map(f)).collect())
            .collect::<Vec<Vec<Option<String>>>>()
    };
    d.set_item("outcome", text(|o| o.name().to_string()))?;
    d.set_item("reason", text(tracksim::Outcome::reason))?;
    Ok(d)
}

/// The settings from the constructors' arguments.
fn settings(
    control_hz: f64,
    max_speed_mps: f64,
    max_yaw_rate_rad_s: f64,
    max_time_s: Option<f64>,
) -> TeamSettings {
    TeamSettings {
        control_hz,
        max_speed_mps,
        max_yaw_rate_rad_s,
        max_time_s,
    }
}

/// One team world: an agent per robot (see `tracksim.team_env.TeamParallelEnv`).
#[pyclass(name = "TeamEnvCore", module = "tracksim._tracksim")]
pub(crate) struct PyTeamEnvCore {
    env: Shared<TeamEnv>,
}

#[pymethods]
impl PyTeamEnvCore {
    /// A world of `scenario` with `seed` (default: the file's) at the start of an episode.
    #[new]
    #[pyo3(signature = (scenario, seed=None, control_hz=10.0, max_speed_mps=0.5,
                        max_yaw_rate_rad_s=1.0, max_time_s=None))]
    fn new(
        scenario: &Bound<'_, PyAny>,
        seed: Option<u64>,
        control_hz: f64,
        max_speed_mps: f64,
        max_yaw_rate_rad_s: f64,
        max_time_s: Option<f64>,
    ) -> PyResult<Self> {
        let t = template_of(scenario)?;
        let seed = seed.unwrap_or(t.file_seed());
        let s = settings(control_hz, max_speed_mps, max_yaw_rate_rad_s, max_time_s);
        let env = TeamEnv::new(t, &s, seed).map_err(py_err)?;
        Ok(PyTeamEnvCore {
            env: Shared::new(env),
        })
    }

    /// Starts an episode with `seed` (default: the current one); returns the observations
    /// (1, agents, obs_dim).
    #[pyo3(signature = (seed=None))]
    fn reset<'py>(
        &mut self,
        py: Python<'py>,
        seed: Option<u64>,
    ) -> PyResult<Bound<'py, numpy::PyArray3<f32>>> {
        let env = self.env.get_mut();
        py.detach(|| env.reset(seed)).map_err(py_err)?;
        self.obs(py)
    }

    /// The current observations (1, agents, obs_dim).
    fn obs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray3<f32>>> {
        let env = self.env.get();
        let n = env.agent_count();
        let mut o = vec![0f32; n * TEAM_OBS_SIZE];
        env.observe(&mut o);
        obs_array(py, o, 1, n)
    }

    /// One control period with `actions` (1, agents, 2) (GIL released); returns (observations
    /// (1, agents, obs_dim), arrays (1, agents): reward, terminated, truncated, active,
    /// progress_m, outcome, reason).
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        actions: PyReadonlyArray3<'py, f32>,
    ) -> PyResult<TeamOut<'py>> {
        let a: Vec<f32> = actions.as_array().iter().copied().collect();
        let env = self.env.get_mut();
        env.check_actions(&a).map_err(py_err)?;
        let steps = py.detach(|| env.step(&a));
        let d = agent_arrays(py, &[&steps])?;
        d.set_item("t_s", self.env.get().simulation().time())?;
        Ok((self.obs(py)?, d))
    }

    /// The agents (robots) in order.
    #[getter]
    fn robot_names(&self) -> Vec<String> {
        self.env.get().simulation().robot_names()
    }

    /// Which agents are still running.
    #[getter]
    fn running(&self) -> Vec<bool> {
        self.env.get().running().to_vec()
    }

    /// Simulated time of the episode, s.
    #[getter]
    fn time(&self) -> f64 {
        self.env.get().simulation().time()
    }

    /// Seed of the episode.
    #[getter]
    fn seed(&self) -> u64 {
        self.env.get().simulation().seed()
    }

    /// The `[randomize]` values of the episode, by parameter name (empty for a fixed file).
    #[getter]
    fn randomized(&self) -> BTreeMap<String, f64> {
        self.env.get().simulation().scenario().randomized.clone()
    }

    /// The control period actually used (a whole number of physics steps), s.
    #[getter]
    fn control_period_s(&self) -> f64 {
        let env = self.env.get();
        env.substeps() as f64 * env.simulation().dt()
    }

    /// Observation length per agent.
    #[getter]
    fn obs_dim(&self) -> usize {
        TEAM_OBS_SIZE
    }

    /// Action length per agent.
    #[getter]
    fn action_dim(&self) -> usize {
        TEAM_ACTION_SIZE
    }
}

/// Many team worlds stepped on Rust threads (GIL released) with autoreset ("next step").
#[pyclass(name = "TeamVecEnvCore", module = "tracksim._tracksim")]
pub(crate) struct PyTeamVecEnvCore {
    v: Shared<TeamVecEnv>,
}

#[pymethods]
impl PyTeamVecEnvCore {
    /// `num_envs` worlds of `scenario`, world `i` seeded `seed + i`, stepped on `threads`
    /// threads.
    #[new]
    #[pyo3(signature = (scenario, num_envs, seed=0, threads=1, control_hz=10.0,
                        max_speed_mps=0.5, max_yaw_rate_rad_s=1.0, max_time_s=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        scenario: &Bound<'_, PyAny>,
        num_envs: usize,
        seed: u64,
        threads: usize,
        control_hz: f64,
        max_speed_mps: f64,
        max_yaw_rate_rad_s: f64,
        max_time_s: Option<f64>,
    ) -> PyResult<Self> {
        let t = template_of(scenario)?;
        let s = settings(control_hz, max_speed_mps, max_yaw_rate_rad_s, max_time_s);
        let v = TeamVecEnv::new(t, &s, num_envs, seed, threads).map_err(py_err)?;
        Ok(PyTeamVecEnvCore { v: Shared::new(v) })
    }

    /// Resets every world (`i` with `seed + i`; `None` keeps their seeds; `seeds`, one per
    /// world, replaces `seed`) on the threads; returns the observations (num_envs, agents,
    /// obs_dim).
    #[pyo3(signature = (seed=None, seeds=None))]
    fn reset<'py>(
        &mut self,
        py: Python<'py>,
        seed: Option<u64>,
        seeds: Option<Vec<u64>>,
    ) -> PyResult<Bound<'py, numpy::PyArray3<f32>>> {
        let v = self.v.get_mut();
        py.detach(|| match &seeds {
            Some(s) => v.reset_seeds(s),
            None => v.reset(seed),
        })
        .map_err(py_err)?;
        let v = self.v.get();
        let mut o = vec![0f32; v.obs_len()];
        v.observe(&mut o);
        obs_array(py, o, v.len(), v.agent_count())
    }

    /// One control period of every world with `actions` (num_envs, agents, 2), GIL released;
    /// returns (observations (num_envs, agents, obs_dim), arrays): per agent (num_envs,
    /// agents) reward, terminated, truncated, active, progress_m, outcome, reason; per world
    /// (num_envs,) autoreset (this step reset the world), seed, t_s.
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        actions: PyReadonlyArray3<'py, f32>,
    ) -> PyResult<TeamOut<'py>> {
        let v = self.v.get_mut();
        let (n, na) = (v.len(), v.agent_count());
        if actions.shape() != [n, na, TEAM_ACTION_SIZE] {
            return Err(py_err(tracksim::Error::setting(
                "step",
                "actions",
                format!(
                    "expected shape ({n}, {na}, {TEAM_ACTION_SIZE}) (a row per agent of each \
                     world), got {:?}",
                    actions.shape()
                ),
            )));
        }
        let a: Vec<f32> = actions.as_array().iter().copied().collect();
        let mut o = vec![0f32; v.obs_len()];
        let steps = py.detach(|| v.step(&a, &mut o)).map_err(py_err)?;
        let rows: Vec<&[AgentStep]> = steps.iter().map(|s| s.agents.as_slice()).collect();
        let d = agent_arrays(py, &rows)?;
        let col = |f: fn(&TeamVecStep) -> bool| steps.iter().map(f).collect::<Vec<_>>();
        d.set_item("autoreset", PyArray1::from_vec(py, col(|s| s.reset)))?;
        let seeds: Vec<u64> = steps.iter().map(|s| s.seed).collect();
        d.set_item("seed", PyArray1::from_vec(py, seeds))?;
        let t: Vec<f64> = steps.iter().map(|s| s.t_s).collect();
        d.set_item("t_s", PyArray1::from_vec(py, t))?;
        Ok((obs_array(py, o, n, na)?, d))
    }

    /// The agents (robots) of each world, in order.
    #[getter]
    fn robot_names(&self) -> Vec<String> {
        self.v.get().envs()[0].simulation().robot_names()
    }

    /// Number of worlds.
    #[getter]
    fn num_envs(&self) -> usize {
        self.v.get().len()
    }

    /// The `[randomize]` values of world `i`'s current episode.
    fn randomized(&self, i: usize) -> PyResult<BTreeMap<String, f64>> {
        self.v
            .get()
            .envs()
            .get(i)
            .map(|e| e.simulation().scenario().randomized.clone())
            .ok_or_else(|| PyValueError::new_err("no such world"))
    }

    /// Threads used per step.
    #[getter]
    fn threads(&self) -> usize {
        self.v.get().threads()
    }

    #[setter]
    fn set_threads(&mut self, t: usize) {
        self.v.get_mut().set_threads(t);
    }

    /// The control period actually used (a whole number of physics steps), s.
    #[getter]
    fn control_period_s(&self) -> f64 {
        let v = self.v.get();
        let e = &v.envs()[0];
        e.substeps() as f64 * e.simulation().dt()
    }

    /// Observation length per agent.
    #[getter]
    fn obs_dim(&self) -> usize {
        TEAM_OBS_SIZE
    }

    /// Action length per agent.
    #[getter]
    fn action_dim(&self) -> usize {
        TEAM_ACTION_SIZE
    }
}
