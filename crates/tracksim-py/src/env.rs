//! The `EnvCore` class (one learning environment) and the conversions the environments share
//! (settings, step info, sensor arrays).

use crate::common::{Shared, py_err};
use crate::scenario::template_of;
use numpy::PyArray1;
use numpy::PyArrayMethods;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::BTreeMap;
use tracksim::env::EnvConfig;
use tracksim::env::EnvValue;
use tracksim::env::SensorObs;

/// One Python value of a `config` entry as the library's [`EnvValue`] (by its Python type:
/// str, a pair of ints, a pair of numbers, a number); the library checks keys and values.
pub(crate) fn env_value(key: &str, v: &Bound<'_, PyAny>) -> PyResult<EnvValue> {
    if let Ok(s) = v.extract::<String>() {
        return Ok(EnvValue::Text(s));
    }
    if let Ok([a, b]) = v.extract::<Vec<i64>>().as_deref() {
        return Ok(EnvValue::IntPair(*a, *b));
    }
    if let Ok([a, b]) = v.extract::<Vec<f64>>().as_deref() {
        return Ok(EnvValue::Pair(*a, *b));
    }
    if let Ok(x) = v.extract::<f64>() {
        return Ok(EnvValue::Number(x));
    }
    Err(PyValueError::new_err(format!(
        "environment setting {key:?}: expected a number, a string or a pair, got {}",
        v.get_type().name()?
    )))
}

pub(crate) fn env_config(cfg: Option<&Bound<'_, PyDict>>) -> PyResult<EnvConfig> {
    let mut settings = Vec::new();
    for (k, v) in cfg.into_iter().flat_map(|d| d.iter()) {
        let k: String = k.extract()?;
        let v = env_value(&k, &v)?;
        settings.push((k, v));
    }
    EnvConfig::from_settings(settings).map_err(py_err)
}

pub(crate) fn info_dict<'py>(
    py: Python<'py>,
    i: &tracksim::env::StepInfo,
    env: &tracksim::env::Env,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("progress_delta_m", i.progress_delta_m)?;
    d.set_item("progress_m", i.progress_m)?;
    d.set_item("effort", i.effort)?;
    d.set_item("outcome", i.outcome.name())?;
    d.set_item("reason", i.outcome.reason())?;
    d.set_item("t_s", env.simulation().time())?;
    d.set_item("seed", env.simulation().seed())?;
    d.set_item("randomized", env.randomized().clone())?;
    if let Some(c) = env.course() {
        d.set_item("course", course_dict(py, &c)?)?;
    }
    Ok(d)
}

/// A course's score so far (`[course]`) as the step's `info["course"]`: the gates, the
/// repetitions, the faults by kind, the times (s) and the status, as `summary.json` has them.
fn course_dict<'py>(
    py: Python<'py>,
    c: &tracksim::run::CourseScore,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("name", &c.name)?;
    d.set_item("status", c.status)?;
    d.set_item("finished", c.finished)?;
    d.set_item("next_gate", c.next_gate)?;
    d.set_item("gates_passed", c.gates_passed)?;
    d.set_item("gates_total", c.gates_total)?;
    d.set_item("repetition", c.repetition)?;
    d.set_item("repetitions_done", c.repetitions_done)?;
    d.set_item("repetitions_required", c.repetitions_required)?;
    d.set_item("elapsed_s", c.elapsed_s)?;
    d.set_item("time_limit_s", c.time_limit_s)?;
    d.set_item("penalty_s", c.penalty_s)?;
    d.set_item("score_s", c.score.score_s)?;
    let f = PyDict::new(py);
    f.set_item("reset", c.faults.reset)?;
    f.set_item("tip_over", c.faults.tip_over)?;
    f.set_item("touch", c.faults.touch)?;
    d.set_item("faults", f)?;
    Ok(d)
}

/// The sensor entries of a dict observation from `flat` (`n` environments' values one after
/// the other, each as `spec` lays them out): {name: float32 array}, of shape `(n, *shape)`
/// with `batch`, else `shape` (`n` = 1).
pub(crate) fn sensor_obs_dict<'py>(
    py: Python<'py>,
    spec: &[SensorObs],
    flat: &[f32],
    n: usize,
    batch: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let per: usize = spec.iter().map(SensorObs::len).sum();
    let d = PyDict::new(py);
    let mut off = 0;
    for e in spec {
        let len = e.len();
        let mut v = Vec::with_capacity(n * len);
        for i in 0..n {
            v.extend_from_slice(&flat[i * per + off..i * per + off + len]);
        }
        off += len;
        let mut shape = e.shape.clone();
        if batch {
            shape.insert(0, n);
        }
        d.set_item(
            &e.name,
            PyArray1::from_vec(py, v).reshape(shape.as_slice())?,
        )?;
    }
    Ok(d)
}

/// The sensor entries' layout for Python: (name, kind, shape, low, high) each.
pub(crate) type SpecOut = Vec<(String, String, Vec<usize>, f64, f64)>;

pub(crate) fn spec_out(spec: Vec<SensorObs>) -> SpecOut {
    spec.into_iter()
        .map(|e| (e.name, e.kind.to_string(), e.shape, e.low, e.high))
        .collect()
}

/// The learner's entries for Python: (name, shape, low, high) each.
pub(crate) type LearnerSpecOut = Vec<(String, Vec<usize>, f64, f64)>;

pub(crate) fn learner_spec_out(env: &tracksim::env::Env) -> LearnerSpecOut {
    env.learner().map_or_else(Vec::new, |l| {
        l.entries()
            .iter()
            .map(|e| (e.name.to_string(), e.shape.clone(), e.low, e.high))
            .collect()
    })
}

/// What `EnvCore.step` returns: observation, terminated, truncated, info.
pub(crate) type StepOut<'py> = (Bound<'py, PyArray1<f32>>, bool, bool, Bound<'py, PyDict>);

/// The core of the Gymnasium environment: one simulation advanced one control period per
/// normalised action (see `tracksim.TracksimEnv`).
#[pyclass(name = "EnvCore", module = "tracksim._tracksim")]
pub(crate) struct PyEnvCore {
    pub(crate) env: Shared<tracksim::env::Env>,
}

#[pymethods]
impl PyEnvCore {
    /// An environment of `scenario` at the start of an episode with `seed`; `config` holds the
    /// settings of `tracksim.env.EnvConfig` (control_period_s, action, maxima, grid...).
    #[new]
    #[pyo3(signature = (scenario, seed=0, config=None))]
    fn new(
        scenario: &Bound<'_, PyAny>,
        seed: u64,
        config: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let t = template_of(scenario)?;
        let env = tracksim::env::Env::new(t, env_config(config)?, seed).map_err(py_err)?;
        Ok(PyEnvCore {
            env: Shared::new(env),
        })
    }

    /// Starts an episode with `seed`; returns the observation (float32).
    fn reset<'py>(&mut self, py: Python<'py>, seed: u64) -> PyResult<Bound<'py, PyArray1<f32>>> {
        let env = self.env.get_mut();
        py.detach(|| env.reset(seed)).map_err(py_err)?;
        Ok(self.obs(py))
    }

    /// The current observation (float32, length `obs_dim`).
    fn obs<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        let mut o = vec![0f32; self.env.get().obs_dim()];
        self.env.get().observe(&mut o);
        PyArray1::from_vec(py, o)
    }

    /// One control period with `action` (normalised to [-1, 1]; GIL released); returns
    /// (observation, terminated, truncated, info).
    fn step<'py>(&mut self, py: Python<'py>, action: Vec<f32>) -> PyResult<StepOut<'py>> {
        self.env.get().check_action(&action).map_err(py_err)?;
        let env = self.env.get_mut();
        let i = py.detach(|| env.step(&action));
        Ok((
            self.obs(py),
            i.terminated,
            i.truncated,
            info_dict(py, &i, &self.env.get())?,
        ))
    }

    /// Observation length.
    #[getter]
    fn obs_dim(&self) -> usize {
        self.env.get().obs_dim()
    }

    /// The setting `observation`: "vector", "dict" or "learner".
    #[getter]
    fn observation(&self) -> &'static str {
        self.env.get().config().observation.name()
    }

    /// The sensor entries of a dict observation, in `[[sensors]]` order: (name, kind, shape,
    /// low, high) each; empty unless `observation` is "dict".
    #[getter]
    fn sensor_obs_spec(&self) -> SpecOut {
        spec_out(self.env.get().sensor_obs_spec())
    }

    /// The sensor entries of the current dict observation: {name: float32 array} (see
    /// `tracksim.TracksimEnv`); empty unless `observation` is "dict".
    fn sensor_obs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let mut o = vec![0f32; self.env.get().sensor_obs_dim()];
        self.env.get().observe_sensors(&mut o);
        sensor_obs_dict(py, &self.env.get().sensor_obs_spec(), &o, 1, false)
    }

    /// The learner's entries, in the order of the observation vector (`observation` =
    /// "learner"): (name, shape, low, high) each; empty otherwise.
    #[getter]
    fn learner_obs_spec(&self) -> LearnerSpecOut {
        learner_spec_out(&self.env.get())
    }

    /// The learner observation's updates this episode and their mean wall time, us ((0, 0)
    /// unless `observation` is "learner").
    #[getter]
    fn learner_cost_us(&self) -> (u64, f64) {
        self.env.get().learner().map_or((0, 0.0), |l| l.cost())
    }

    /// With `record_dir`: writes the episode so far as a run folder and starts it afresh
    /// (what `close()` calls); returns the folder, or None (not recording, or no step yet).
    fn flush_record(&mut self, py: Python<'_>) -> PyResult<Option<String>> {
        let env = self.env.get_mut();
        let dir = py.detach(|| env.flush_record()).map_err(py_err)?;
        Ok(dir.map(|d| d.display().to_string()))
    }

    /// A frame of the current state as a uint8 array (height, width, 3), rgb (the setting
    /// `render_camera`: the chase camera traced now, or an rgb_camera sensor's latest frame;
    /// GIL released while tracing).
    fn render<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray3<u8>>> {
        let env = self.env.get_mut();
        let (rgb, w, h) = py.detach(|| {
            let f = env.render();
            (f.rgb.clone(), f.width, f.height)
        });
        PyArray1::from_vec(py, rgb).reshape([h, w, 3])
    }

    /// Width and height of the rendered frames, pixels.
    #[getter]
    fn render_size(&self) -> (usize, usize) {
        self.env.get().render_size()
    }

    /// Action length.
    #[getter]
    fn action_dim(&self) -> usize {
        self.env.get().action_dim()
    }

    /// Observation entry names.
    #[getter]
    fn obs_names(&self) -> Vec<String> {
        self.env.get().obs_names()
    }

    /// Simulated time of the episode, s.
    #[getter]
    fn time(&self) -> f64 {
        self.env.get().simulation().time()
    }

    /// The control period actually used (a whole number of physics steps), s.
    #[getter]
    fn control_period_s(&self) -> f64 {
        let env = self.env.get();
        env.substeps() as f64 * env.simulation().dt()
    }

    /// The episode's `[randomize]` values.
    #[getter]
    fn randomized(&self) -> BTreeMap<String, f64> {
        self.env.get().randomized().clone()
    }
}
