//! The `VecEnvCore` class: many environments stepped on threads with autoreset.

use crate::common::{Shared, py_err};
use crate::env::{
    LearnerSpecOut, SpecOut, env_config, learner_spec_out, sensor_obs_dict, spec_out,
};
use crate::scenario::template_of;
use numpy::PyArray1;
use numpy::PyArrayMethods;
use numpy::PyReadonlyArray2;
use numpy::PyUntypedArrayMethods;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::BTreeMap;
use tracksim::env::SensorObs;

/// N environments stepped on Rust threads (GIL released), with autoreset ("next step").
#[pyclass(name = "VecEnvCore", module = "tracksim._tracksim")]
pub(crate) struct PyVecEnvCore {
    v: Shared<tracksim::env::VecEnv>,
    obs_dim: usize,
    action_dim: usize,
}

pub(crate) type VecOut<'py> = (Bound<'py, numpy::PyArray2<f32>>, Bound<'py, PyDict>);

#[pymethods]
impl PyVecEnvCore {
    /// `num_envs` environments of `scenario`, environment `i` seeded `seed + i`, stepped on
    /// `threads` threads.
    #[new]
    #[pyo3(signature = (scenario, num_envs, seed=0, threads=1, config=None))]
    fn new(
        scenario: &Bound<'_, PyAny>,
        num_envs: usize,
        seed: u64,
        threads: usize,
        config: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let t = template_of(scenario)?;
        let v = tracksim::env::VecEnv::new(t, env_config(config)?, num_envs, seed, threads)
            .map_err(py_err)?;
        let (obs_dim, action_dim) = (v.obs_dim(), v.action_dim());
        Ok(PyVecEnvCore {
            v: Shared::new(v),
            obs_dim,
            action_dim,
        })
    }

    /// Resets every environment (`i` with `seed + i`; `None` keeps their seeds); returns the
    /// observations (num_envs, obs_dim).
    /// `seeds` (one per environment) replaces `seed`.
    #[pyo3(signature = (seed=None, seeds=None))]
    fn reset<'py>(
        &mut self,
        py: Python<'py>,
        seed: Option<u64>,
        seeds: Option<Vec<u64>>,
    ) -> PyResult<Bound<'py, numpy::PyArray2<f32>>> {
        let v = self.v.get_mut();
        py.detach(|| match &seeds {
            Some(s) => v.reset_seeds(s),
            None => v.reset(seed),
        })
        .map_err(py_err)?;
        let mut o = vec![0f32; self.v.get().len() * self.obs_dim];
        self.v.get().observe(&mut o);
        PyArray1::from_vec(py, o).reshape([self.v.get().len(), self.obs_dim])
    }

    /// One control period of every environment with `actions` (num_envs, action_dim), GIL
    /// released; returns (observations, arrays) where arrays holds progress_delta_m,
    /// progress_m, effort, terminated, truncated, autoreset (this step reset the env), seed,
    /// and lists outcome and reason.
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        actions: PyReadonlyArray2<'py, f32>,
    ) -> PyResult<VecOut<'py>> {
        let n = self.v.get_mut().len();
        self.v
            .get_mut()
            .check_actions_shape(actions.shape())
            .map_err(py_err)?;
        let a: Vec<f32> = actions
            .as_slice()
            .map(|s| s.to_vec())
            .unwrap_or_else(|_| actions.as_array().iter().copied().collect());
        let mut o = vec![0f32; n * self.obs_dim];
        let v = self.v.get_mut();
        let steps = py.detach(|| v.step(&a, &mut o)).map_err(py_err)?;
        let d = PyDict::new(py);
        let col =
            |f: &dyn Fn(&tracksim::env::VecStep) -> f64| steps.iter().map(f).collect::<Vec<f64>>();
        d.set_item(
            "progress_delta_m",
            PyArray1::from_vec(py, col(&|s| s.info.progress_delta_m)),
        )?;
        d.set_item(
            "progress_m",
            PyArray1::from_vec(py, col(&|s| s.info.progress_m)),
        )?;
        d.set_item("effort", PyArray1::from_vec(py, col(&|s| s.info.effort)))?;
        let flag = |f: &dyn Fn(&tracksim::env::VecStep) -> bool| {
            steps.iter().map(f).collect::<Vec<bool>>()
        };
        d.set_item(
            "terminated",
            PyArray1::from_vec(py, flag(&|s| s.info.terminated)),
        )?;
        d.set_item(
            "truncated",
            PyArray1::from_vec(py, flag(&|s| s.info.truncated)),
        )?;
        d.set_item("autoreset", PyArray1::from_vec(py, flag(&|s| s.reset)))?;
        d.set_item(
            "seed",
            PyArray1::from_vec(py, steps.iter().map(|s| s.seed).collect::<Vec<u64>>()),
        )?;
        d.set_item(
            "outcome",
            steps
                .iter()
                .map(|s| s.info.outcome.name().to_string())
                .collect::<Vec<_>>(),
        )?;
        d.set_item(
            "reason",
            steps
                .iter()
                .map(|s| s.info.outcome.reason())
                .collect::<Vec<_>>(),
        )?;
        // A course (`[course]`): each environment's score so far (of the episode that ended
        // at a terminating step; the next step's autoreset starts a new one).
        let v = self.v.get();
        let envs = v.envs();
        if envs.first().is_some_and(|e| e.course().is_some()) {
            let scores: Vec<_> = envs.iter().map(|e| e.course()).collect();
            let num = |f: &dyn Fn(&tracksim::run::CourseScore) -> f64| {
                scores
                    .iter()
                    .map(|c| c.as_ref().map_or(f64::NAN, f))
                    .collect::<Vec<f64>>()
            };
            d.set_item(
                "course_gates_passed",
                PyArray1::from_vec(py, num(&|c| f64::from(c.gates_passed))),
            )?;
            d.set_item(
                "course_repetitions_done",
                PyArray1::from_vec(py, num(&|c| f64::from(c.repetitions_done))),
            )?;
            d.set_item(
                "course_faults",
                PyArray1::from_vec(py, num(&|c| f64::from(c.faults.total()))),
            )?;
            d.set_item(
                "course_penalty_s",
                PyArray1::from_vec(py, num(&|c| c.penalty_s)),
            )?;
            d.set_item(
                "course_score_s",
                PyArray1::from_vec(py, num(&|c| c.score.score_s)),
            )?;
            d.set_item(
                "course_status",
                scores
                    .iter()
                    .map(|c| c.as_ref().map_or("", |c| c.status))
                    .collect::<Vec<_>>(),
            )?;
        }
        Ok((PyArray1::from_vec(py, o).reshape([n, self.obs_dim])?, d))
    }

    /// The `[randomize]` values of environment `i`'s current episode.
    fn randomized(&self, i: usize) -> PyResult<BTreeMap<String, f64>> {
        self.v
            .get()
            .envs()
            .get(i)
            .map(|e| e.randomized().clone())
            .ok_or_else(|| PyValueError::new_err("no such environment"))
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

    /// Observation length.
    #[getter]
    fn obs_dim(&self) -> usize {
        self.obs_dim
    }

    /// The setting `observation`: "vector", "dict" or "learner".
    #[getter]
    fn observation(&self) -> &'static str {
        self.v.get().envs()[0].config().observation.name()
    }

    /// The sensor entries of a dict observation of one environment (see
    /// `EnvCore.sensor_obs_spec`).
    #[getter]
    fn sensor_obs_spec(&self) -> SpecOut {
        spec_out(self.v.get().sensor_obs_spec())
    }

    /// The sensor entries of every environment's current dict observation: {name: float32
    /// array (num_envs, *shape)}; empty unless `observation` is "dict".
    fn sensor_obs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let spec = self.v.get().sensor_obs_spec();
        let per: usize = spec.iter().map(SensorObs::len).sum();
        let mut o = vec![0f32; self.v.get().len() * per];
        self.v.get().observe_sensors(&mut o);
        sensor_obs_dict(py, &spec, &o, self.v.get().len(), true)
    }

    /// The learner's entries of one environment (see `EnvCore.learner_obs_spec`).
    #[getter]
    fn learner_obs_spec(&self) -> LearnerSpecOut {
        learner_spec_out(&self.v.get().envs()[0])
    }

    /// With `record_dir`: writes every environment's episode so far as a run folder (what
    /// `close()` calls); returns the folders.
    fn flush_records(&mut self, py: Python<'_>) -> PyResult<Vec<String>> {
        let v = self.v.get_mut();
        let dirs = py.detach(|| v.flush_records()).map_err(py_err)?;
        Ok(dirs.iter().map(|d| d.display().to_string()).collect())
    }

    /// Every environment's frame of its current state as a uint8 array (num_envs, height,
    /// width, 3), rgb (see `EnvCore.render`), rendered on the threads with the GIL released.
    fn render<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray4<u8>>> {
        let v = self.v.get_mut();
        let n = v.len();
        let mut out = Vec::new();
        let (w, h) = py.detach(|| v.render(&mut out)).map_err(py_err)?;
        PyArray1::from_vec(py, out).reshape([n, h, w, 3])
    }

    /// Width and height of the rendered frames, pixels.
    #[getter]
    fn render_size(&self) -> (usize, usize) {
        self.v.get().render_size()
    }

    /// Action length.
    #[getter]
    fn action_dim(&self) -> usize {
        self.action_dim
    }

    /// Number of environments.
    #[getter]
    fn num_envs(&self) -> usize {
        self.v.get().len()
    }

    /// Observation entry names.
    #[getter]
    fn obs_names(&self) -> Vec<String> {
        self.v.get().envs()[0].obs_names()
    }

    /// Control period used, s.
    #[getter]
    fn control_period_s(&self) -> f64 {
        let v = self.v.get();
        let e = &v.envs()[0];
        e.substeps() as f64 * e.simulation().dt()
    }
}
