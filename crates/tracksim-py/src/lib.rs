//! `tracksim._tracksim`: the Python extension module of tracksim (PyO3), a thin layer over the
//! library: scenario files ([`tracksim::ScenarioTemplate`]), simulations
//! ([`tracksim::Simulation`]), and the learning environments of [`tracksim::env`]. Stepping
//! releases the GIL. Errors from files arrive as `tracksim.ScenarioError` (a `ValueError`)
//! with the CLI's message; an unstable simulation as `tracksim.UnstableError`; settings the
//! library refuses (environment configuration, array lengths, sweep plans) as `ValueError`
//! with the library's message, which names the key. Every check is the library's.

#![warn(clippy::too_many_lines)]

use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::{PyKeyError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex, MutexGuard};
use tracksim::env::{EnvConfig, EnvValue, SensorObs};
use tracksim::sensors::{Channel, SensorSet};
use tracksim::{Controls, ScenarioTemplate};

mod bundled;

pyo3::create_exception!(
    _tracksim,
    ScenarioError,
    PyValueError,
    "A scenario or vehicle file is wrong: the message names the file, the key and the fix."
);
pyo3::create_exception!(
    _tracksim,
    UnstableError,
    PyRuntimeError,
    "The simulation became unstable (non-finite state or a body flying off)."
);

/// `T` behind a mutex: a `#[pyclass]` must be `Sync`, and the library's sensors (in a
/// [`SensorSet`], and in every environment's runner) are `Send` only. `&mut self` methods reach
/// it without locking; a `&self` method locks it once per statement (never twice in one).
struct Shared<T>(Mutex<T>);

impl<T> Shared<T> {
    fn new(t: T) -> Self {
        Shared(Mutex::new(t))
    }

    /// The value, locked (a panic while it was locked does not poison it).
    fn get(&self) -> MutexGuard<'_, T> {
        self.0.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The value, without locking.
    fn get_mut(&mut self) -> &mut T {
        self.0.get_mut().unwrap_or_else(|e| e.into_inner())
    }
}

fn py_err(e: tracksim::Error) -> PyErr {
    match e {
        tracksim::Error::Unstable { .. } | tracksim::Error::Build(_) => {
            UnstableError::new_err(e.to_string())
        }
        tracksim::Error::Settings { .. } => PyValueError::new_err(e.to_string()),
        _ => ScenarioError::new_err(e.to_string()),
    }
}

/// A scenario file, loaded and checked (its `[randomize]` table too), ready to be instantiated
/// with any seed.
#[pyclass(name = "Scenario", module = "tracksim._tracksim", frozen)]
struct PyScenario {
    t: Arc<ScenarioTemplate>,
}

#[pymethods]
impl PyScenario {
    /// Loads `path`; raises `ScenarioError` with every problem (file, key, fix).
    ///
    /// `method` (a track method name, as `simulation.method`) and `solver_iterations` (as
    /// `simulation.solver_iterations`) override the file's values before every compilation,
    /// checked like the file's own: the training physics of `tracksim.TRAINING_PHYSICS` is
    /// `solver_iterations=2` (BENCHMARKS.md "Env steps per core" says what it keeps of the
    /// validated physics).
    #[new]
    #[pyo3(signature = (path, method = None, solver_iterations = None))]
    fn new(
        path: PathBuf,
        method: Option<&str>,
        solver_iterations: Option<usize>,
    ) -> PyResult<Self> {
        let method = match method {
            None => None,
            Some(name) => Some(tracksim::Method::parse("method", name).map_err(|issue| {
                PyValueError::new_err(format!("Scenario({}): {issue}", path.display()))
            })?),
        };
        if solver_iterations == Some(0) {
            return Err(PyValueError::new_err(format!(
                "Scenario({}): solver_iterations must be at least 1, got 0",
                path.display()
            )));
        }
        let overrides = tracksim::Overrides {
            method,
            solver_iterations,
            ..tracksim::Overrides::default()
        };
        let t = tracksim::ScenarioTemplate::load_with(&path, &overrides).map_err(py_err)?;
        Ok(PyScenario { t: Arc::new(t) })
    }

    /// The file, as given.
    #[getter]
    fn path(&self) -> String {
        self.t.path().display().to_string()
    }

    /// The file's `simulation.seed`.
    #[getter]
    fn file_seed(&self) -> u64 {
        self.t.file_seed()
    }

    /// Names of the `[randomize]` parameters (sorted).
    #[getter]
    fn randomized_names(&self) -> Vec<String> {
        self.t
            .randomizer()
            .params
            .iter()
            .map(|p| p.name.clone())
            .collect()
    }

    /// The `[randomize]` values drawn from `seed`, by name (empty for a fixed scenario).
    fn sample(&self, seed: u64) -> PyResult<BTreeMap<String, f64>> {
        Ok(self.t.instantiate(seed).map_err(py_err)?.randomized)
    }

    /// Scenario facts for `seed`: description, duration_s, dt_s, solver_iterations, method,
    /// vehicle, track_names, flipper_names,
    /// track_offsets_m (lateral offset of each track), randomized.
    fn info<'py>(&self, py: Python<'py>, seed: u64) -> PyResult<Bound<'py, PyDict>> {
        let sc = self.t.instantiate(seed).map_err(py_err)?;
        let d = PyDict::new(py);
        d.set_item("description", &sc.description)?;
        d.set_item("duration_s", sc.duration)?;
        d.set_item("dt_s", sc.solver.dt)?;
        d.set_item("solver_iterations", sc.solver.iterations)?;
        d.set_item("method", sc.method.name())?;
        let v = &sc.vehicle;
        d.set_item("vehicle", &v.name)?;
        d.set_item(
            "track_names",
            v.tracks.iter().map(|t| t.name.clone()).collect::<Vec<_>>(),
        )?;
        d.set_item(
            "track_offsets_m",
            v.tracks
                .iter()
                .map(|t| t.lateral_offset())
                .collect::<Vec<_>>(),
        )?;
        d.set_item(
            "flipper_names",
            v.flippers
                .iter()
                .map(|f| f.name.clone())
                .collect::<Vec<_>>(),
        )?;
        d.set_item("randomized", sc.randomized.clone())?;
        Ok(d)
    }
}

fn template_of(obj: &Bound<'_, PyAny>) -> PyResult<Arc<ScenarioTemplate>> {
    if let Ok(s) = obj.cast::<PyScenario>() {
        return Ok(s.get().t.clone());
    }
    let path: PathBuf = obj.extract()?;
    Ok(Arc::new(tracksim::load_template(&path).map_err(py_err)?))
}

/// One simulation of a scenario: set controls, step, read the state and the sensors.
#[pyclass(name = "Simulation", module = "tracksim._tracksim")]
struct PySimulation {
    t: Arc<ScenarioTemplate>,
    sim: tracksim::Simulation,
    /// The vehicle's sensors (not recorded), updated after every step.
    sensors: Shared<SensorSet>,
}

/// A channel as a float64 numpy array of its shape.
fn channel_array<'py>(py: Python<'py>, c: &Channel) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_vec(py, c.data.clone())
        .reshape(c.shape.as_slice())?
        .into_any())
}

impl PySimulation {
    /// The index of the sensor called `name`, or a `KeyError` naming the known ones.
    fn sensor_index(&self, name: &str) -> PyResult<usize> {
        let names = self.sensor_names();
        names.iter().position(|n| n == name).ok_or_else(|| {
            PyKeyError::new_err(format!(
                "no sensor {name:?} on the vehicle; its sensors: {}",
                if names.is_empty() {
                    "none".to_string()
                } else {
                    names.join(", ")
                }
            ))
        })
    }

    /// Sensor `i`'s latest reading: t_s and one array per channel key.
    fn reading<'py>(&self, py: Python<'py>, i: usize) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let s = self.sensors.get();
        d.set_item("t_s", s.reading_time(i))?;
        for c in s.sensor(i).channels() {
            d.set_item(c.key(), channel_array(py, c)?)?;
        }
        Ok(d)
    }
}

#[pymethods]
impl PySimulation {
    /// A simulation of `scenario` (a `Scenario` or a path) with `seed` (default: the file's);
    /// the `[randomize]` values are drawn from the seed. Belts at rest, flippers at their
    /// initial angles; nothing of the file's `[[commands]]` is applied.
    #[new]
    #[pyo3(signature = (scenario, seed=None))]
    fn new(scenario: &Bound<'_, PyAny>, seed: Option<u64>) -> PyResult<Self> {
        let t = template_of(scenario)?;
        let sc = t
            .instantiate(seed.unwrap_or(t.file_seed()))
            .map_err(py_err)?;
        let sim = tracksim::Simulation::new(&sc).map_err(py_err)?;
        let sensors = Shared::new(SensorSet::new(&sim, false));
        Ok(PySimulation { t, sim, sensors })
    }

    /// Starts again at t = 0 with `seed` (default: the current one), the `[randomize]` values
    /// drawn anew from it; the sensors start again too (a first reading at t = 0).
    #[pyo3(signature = (seed=None))]
    fn reset(&mut self, seed: Option<u64>) -> PyResult<()> {
        let sc = self
            .t
            .instantiate(seed.unwrap_or(self.sim.seed()))
            .map_err(py_err)?;
        self.sim = tracksim::Simulation::new(&sc).map_err(py_err)?;
        self.sensors = Shared::new(SensorSet::new(&self.sim, false));
        Ok(())
    }

    /// Advances `n` physics steps (GIL released), the sensors that are due updated after
    /// each; raises `UnstableError` if it blows up.
    #[pyo3(signature = (n=1))]
    fn step(&mut self, py: Python<'_>, n: u64) -> PyResult<()> {
        let (sim, sensors) = (&mut self.sim, self.sensors.get_mut());
        py.detach(|| {
            for _ in 0..n {
                sim.step()?;
                sensors.update(sim);
            }
            Ok(())
        })
        .map_err(py_err)
    }

    /// Names of the vehicle's sensors (`[[sensors]]` order).
    #[getter]
    fn sensor_names(&self) -> Vec<String> {
        let s = self.sensors.get();
        (0..s.len())
            .map(|i| s.sensor(i).model().name.clone())
            .collect()
    }

    /// Every sensor's latest reading: {name: {"t_s": time of the reading (s), channel key
    /// (`accel_m_s2`, `range_m`, `height_m`, ...): float64 array of the channel's shape}}.
    fn sensors<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (i, name) in self.sensor_names().iter().enumerate() {
            d.set_item(name, self.reading(py, i)?)?;
        }
        Ok(d)
    }

    /// The latest reading of the sensor `name` (as in `sensors()`); `KeyError` naming the
    /// vehicle's sensors for an unknown name.
    fn sensor<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyDict>> {
        let i = self.sensor_index(name)?;
        self.reading(py, i)
    }

    /// The fixed arrays of the sensor `name` (float64, by key): a lidar's `azimuth_rad` and
    /// `elevation_rad`, an elevation map's cell centres `x_m` and `y_m`, a depth camera's
    /// `focal_length_px`; empty for an IMU or encoders. `KeyError` for an unknown name.
    fn sensor_axes<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyDict>> {
        let i = self.sensor_index(name)?;
        let d = PyDict::new(py);
        for c in self.sensors.get().sensor(i).axes() {
            d.set_item(c.key(), channel_array(py, &c)?)?;
        }
        Ok(d)
    }

    /// Body-level command: forward speed m/s and yaw rate rad/s (skid steering).
    fn set_twist(&mut self, forward_mps: f64, yaw_rate_rad_s: f64) {
        self.sim.set_twist(forward_mps, yaw_rate_rad_s);
    }

    /// Belt speed per track, m/s (track order of `track_names`).
    fn set_belt_speeds(&mut self, speeds: Vec<f64>) -> PyResult<()> {
        let c = Controls::belt_speeds(&self.sim.scenario().vehicle, &speeds).map_err(py_err)?;
        self.sim.apply(&c);
        Ok(())
    }

    /// Flipper target angles, rad (order of `flipper_names`).
    fn set_flipper_angles(&mut self, angles: Vec<f64>) -> PyResult<()> {
        let c = Controls::flipper_angles(&self.sim.scenario().vehicle, &angles).map_err(py_err)?;
        self.sim.apply(&c);
        Ok(())
    }

    /// Simulated time, s.
    #[getter]
    fn time(&self) -> f64 {
        self.sim.time()
    }

    /// Time step, s.
    #[getter]
    fn dt(&self) -> f64 {
        self.sim.dt()
    }

    /// Seed of this run.
    #[getter]
    fn seed(&self) -> u64 {
        self.sim.seed()
    }

    /// Track names.
    #[getter]
    fn track_names(&self) -> Vec<String> {
        self.sim.track_names().to_vec()
    }

    /// Flipper names.
    #[getter]
    fn flipper_names(&self) -> Vec<String> {
        self.sim.flipper_names().to_vec()
    }

    /// The `[randomize]` values of this run, by name.
    #[getter]
    fn randomized(&self) -> BTreeMap<String, f64> {
        self.sim.scenario().randomized.clone()
    }

    /// The state as numpy arrays: t_s, pose ([x, y, z] m, [roll, pitch, yaw] rad in
    /// `rpy_rad`), linvel_mps and angvel_rad_s (world frame), belt_speed_mps, belt_phase_m,
    /// flipper_angle_rad, contacts, penetration_m; on soil also per track sinkage_m,
    /// soil_normal_n and soil_thrust_n.
    fn observe<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = self.sim.sample();
        let d = PyDict::new(py);
        let p = s.pose;
        d.set_item("t_s", s.t)?;
        d.set_item("position_m", PyArray1::from_vec(py, vec![p.x, p.y, p.z]))?;
        d.set_item(
            "rpy_rad",
            PyArray1::from_vec(py, vec![p.roll, p.pitch, p.yaw]),
        )?;
        d.set_item("linvel_mps", PyArray1::from_vec(py, s.linvel.to_vec()))?;
        d.set_item("angvel_rad_s", PyArray1::from_vec(py, s.angvel.to_vec()))?;
        d.set_item("belt_speed_mps", PyArray1::from_vec(py, s.belt_speed))?;
        d.set_item("belt_phase_m", PyArray1::from_vec(py, s.belt_phase))?;
        d.set_item("flipper_angle_rad", PyArray1::from_vec(py, s.flipper_angle))?;
        d.set_item("contacts", s.contacts)?;
        d.set_item("penetration_m", s.penetration)?;
        if !s.soil.is_empty() {
            // Deformable soil (issue 30), per track: sinkage m, soil normal load N, thrust N.
            let col = |f: fn(&tracksim::world::TrackSoil) -> f64| {
                s.soil.iter().map(f).collect::<Vec<f64>>()
            };
            d.set_item("sinkage_m", PyArray1::from_vec(py, col(|g| g.sinkage_m)))?;
            d.set_item("soil_normal_n", PyArray1::from_vec(py, col(|g| g.normal_n)))?;
            d.set_item("soil_thrust_n", PyArray1::from_vec(py, col(|g| g.thrust_n)))?;
        }
        Ok(d)
    }

    /// The soil's ruts now (empty without soil): one row per loaded cell, `[x m, y m,
    /// surface_z m, depth m, cell m, first loaded s]`, as numpy array of shape (n, 6).
    fn ruts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let rows: Vec<Vec<f64>> = self
            .sim
            .ruts()
            .iter()
            .map(|c| vec![c.x_m, c.y_m, c.surface_z_m, c.depth_m, c.cell_m, c.t_s])
            .collect();
        if rows.is_empty() {
            return Ok(PyArray2::zeros(py, [0, 6], false));
        }
        PyArray2::from_vec2(py, &rows).map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// The scenario's outcome now: `None` while undecided, else (`"success"` or `"failure"`,
    /// reason).
    fn outcome(&self) -> Option<(String, String)> {
        tracksim::run::check_outcome(&self.sim.scenario().outcome, &self.sim)
            .map(|o| (o.name().to_string(), o.reason()))
    }

    /// Terrain height below each world point (x, y), m, by downward ray casts; NaN where there
    /// is no terrain.
    fn terrain_heights<'py>(
        &self,
        py: Python<'py>,
        xs: Vec<f64>,
        ys: Vec<f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let h = self.sim.terrain_heights(&xs, &ys).map_err(py_err)?;
        Ok(PyArray1::from_vec(py, h))
    }
}

/// One Python value of a `config` entry as the library's [`EnvValue`] (by its Python type:
/// str, a pair of ints, a pair of numbers, a number); the library checks keys and values.
fn env_value(key: &str, v: &Bound<'_, PyAny>) -> PyResult<EnvValue> {
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

fn env_config(cfg: Option<&Bound<'_, PyDict>>) -> PyResult<EnvConfig> {
    let mut settings = Vec::new();
    for (k, v) in cfg.into_iter().flat_map(|d| d.iter()) {
        let k: String = k.extract()?;
        let v = env_value(&k, &v)?;
        settings.push((k, v));
    }
    EnvConfig::from_settings(settings).map_err(py_err)
}

fn info_dict<'py>(
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
    Ok(d)
}

/// The sensor entries of a dict observation from `flat` (`n` environments' values one after
/// the other, each as `spec` lays them out): {name: float32 array}, of shape `(n, *shape)`
/// with `batch`, else `shape` (`n` = 1).
fn sensor_obs_dict<'py>(
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
type SpecOut = Vec<(String, String, Vec<usize>, f64, f64)>;

fn spec_out(spec: Vec<SensorObs>) -> SpecOut {
    spec.into_iter()
        .map(|e| (e.name, e.kind.to_string(), e.shape, e.low, e.high))
        .collect()
}

/// The learner's entries for Python: (name, shape, low, high) each.
type LearnerSpecOut = Vec<(String, Vec<usize>, f64, f64)>;

fn learner_spec_out(env: &tracksim::env::Env) -> LearnerSpecOut {
    env.learner().map_or_else(Vec::new, |l| {
        l.entries()
            .iter()
            .map(|e| (e.name.to_string(), e.shape.clone(), e.low, e.high))
            .collect()
    })
}

/// What `EnvCore.step` returns: observation, terminated, truncated, info.
type StepOut<'py> = (Bound<'py, PyArray1<f32>>, bool, bool, Bound<'py, PyDict>);

/// The core of the Gymnasium environment: one simulation advanced one control period per
/// normalised action (see `tracksim.TracksimEnv`).
#[pyclass(name = "EnvCore", module = "tracksim._tracksim")]
struct PyEnvCore {
    env: Shared<tracksim::env::Env>,
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

/// N environments stepped on Rust threads (GIL released), with autoreset ("next step").
#[pyclass(name = "VecEnvCore", module = "tracksim._tracksim")]
struct PyVecEnvCore {
    v: Shared<tracksim::env::VecEnv>,
    obs_dim: usize,
    action_dim: usize,
}

type VecOut<'py> = (Bound<'py, numpy::PyArray2<f32>>, Bound<'py, PyDict>);

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

/// A learning environment's live 3-D page (`render_mode="human"`): the drive page on
/// loopback, watch-only, fed the environment's state by `show`.
#[pyclass(name = "LiveView", module = "tracksim._tracksim")]
struct PyLiveView {
    w: Shared<tracksim::live::Watch>,
}

#[pymethods]
impl PyLiveView {
    /// Serves the page of `core`'s scenario on 127.0.0.1:`port` (0: a free port); `speed`
    /// paces `show` (simulated seconds per wall second; None: never waits).
    #[new]
    #[pyo3(signature = (core, port=0, speed=None))]
    fn new(core: &PyEnvCore, port: u16, speed: Option<f64>) -> PyResult<Self> {
        if let Some(s) = speed
            && !(s.is_finite() && s > 0.0 && s <= 1000.0)
        {
            return Err(PyValueError::new_err(format!(
                "render speed: must be a finite number > 0 and at most 1000 (simulated seconds per wall second; None: unpaced), got {s}"
            )));
        }
        let w = tracksim::live::Watch::start(
            &core.env.get(),
            std::net::IpAddr::V4(std::net::Ipv4Addr::LOCALHOST),
            port,
            speed,
        )
        .map_err(py_err)?;
        Ok(PyLiveView { w: Shared::new(w) })
    }

    /// The page's URL.
    #[getter]
    fn url(&self) -> String {
        self.w.get().url()
    }

    /// Pages connected.
    #[getter]
    fn connections(&self) -> u64 {
        self.w.get().connections()
    }

    /// A new episode of `core` starts (its scene, if it changed; pacing restarts).
    fn new_episode(&mut self, core: &PyEnvCore) {
        self.w.get_mut().new_episode(&core.env.get());
    }

    /// Publishes `core`'s state, after waiting (GIL released) for the wall clock when paced.
    fn show(&mut self, py: Python<'_>, core: &PyEnvCore) {
        let t = core.env.get().simulation().time();
        let wait = self.w.get_mut().wait(t);
        if !wait.is_zero() {
            py.detach(|| std::thread::sleep(wait));
        }
        self.w.get_mut().publish(&core.env.get());
    }

    /// Stops serving.
    fn close(&mut self) {
        self.w.get_mut().close();
    }
}

/// Runs a sweep of `scenario` (see `tracksim sweep`) into `out`: `runs` runs with seeds from
/// `seed` (default: the file's), or `grid` ({name: [values]}, `runs` per point); this process's
/// shard `shard` = (index, count) or all; `jobs` threads; GIL released. Returns the manifest
/// lines of the shard as JSON strings.
#[pyfunction]
#[pyo3(signature = (scenario, out, runs=10, seed=None, grid=None, shard=None, jobs=1, resume=false))]
#[allow(clippy::too_many_arguments)]
fn sweep(
    py: Python<'_>,
    scenario: &Bound<'_, PyAny>,
    out: PathBuf,
    runs: usize,
    seed: Option<u64>,
    grid: Option<Vec<(String, Vec<f64>)>>,
    shard: Option<(usize, usize)>,
    jobs: usize,
    resume: bool,
) -> PyResult<Vec<String>> {
    use tracksim::sweep::{Shard, SweepOptions, SweepPlan};
    let t = template_of(scenario)?;
    let seed = seed.unwrap_or(t.file_seed());
    let plan = match grid {
        Some(axes) if !axes.is_empty() => SweepPlan::grid(&axes, runs, seed),
        _ => SweepPlan::random(runs, seed),
    }
    .map_err(py_err)?;
    let shard = shard
        .map(|(i, n)| Shard::new(i, n))
        .transpose()
        .map_err(py_err)?;
    for w in plan.warnings(&t) {
        PyErr::warn(
            py,
            &py.get_type::<pyo3::exceptions::PyUserWarning>(),
            &std::ffi::CString::new(w).unwrap_or_default(),
            1,
        )?;
    }
    let opts = SweepOptions {
        out,
        jobs,
        shard,
        resume,
        stop: None,
    };
    let report = py
        .detach(|| tracksim::sweep::run_sweep(&t, &plan, &opts, |_, _| {}))
        .map_err(py_err)?;
    Ok(report
        .lines
        .iter()
        .map(|l| serde_json::to_string(l).expect("serialises"))
        .collect())
}

/// Runs `scenario` (at its file's seed) as an ensemble of `members` perturbed runs (see
/// `tracksim run --ensemble`, docs/ENSEMBLE.md) on `jobs` threads (0: every core), GIL
/// released; each member written into `out` if given. Returns the report as JSON (verdict,
/// success fraction, success times, every member with its perturbation and outcome).
#[pyfunction]
#[pyo3(signature = (scenario, members=16, out=None, seed=0, start_mm=1.0, yaw_deg=0.05, keep_order=false, jobs=0))]
#[allow(clippy::too_many_arguments)]
fn ensemble(
    py: Python<'_>,
    scenario: &Bound<'_, PyAny>,
    members: usize,
    out: Option<PathBuf>,
    seed: u64,
    start_mm: f64,
    yaw_deg: f64,
    keep_order: bool,
    jobs: usize,
) -> PyResult<String> {
    use tracksim::ensemble::{EnsembleOptions, Perturbations, run_ensemble};
    let t = template_of(scenario)?;
    let sc = t.file_scenario().map_err(py_err)?;
    let mut opts = EnsembleOptions::new(members);
    opts.seed = seed;
    opts.jobs = jobs;
    opts.out = out;
    opts.replay = true;
    opts.perturbations = Perturbations {
        start_m: start_mm * 1e-3,
        yaw_deg,
        solver_order: !keep_order,
    };
    let report = py
        .detach(|| run_ensemble(&sc, &opts, |_, _| {}))
        .map_err(py_err)?;
    report.to_json().map_err(py_err)
}

/// Merges sweep folders (shards) into the sweep folder `out` (see `tracksim merge`); returns
/// the number of runs.
#[pyfunction]
fn merge(py: Python<'_>, dirs: Vec<PathBuf>, out: PathBuf) -> PyResult<usize> {
    py.detach(|| tracksim::sweep::merge(&dirs, &out))
        .map(|l| l.len())
        .map_err(py_err)
}

/// The extension module.
#[pymodule]
fn _tracksim(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyScenario>()?;
    m.add_class::<PySimulation>()?;
    m.add_class::<PyEnvCore>()?;
    m.add_class::<PyVecEnvCore>()?;
    m.add_class::<PyLiveView>()?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(ensemble, m)?)?;
    m.add_function(wrap_pyfunction!(merge, m)?)?;
    bundled::register(m)?;
    m.add("ScenarioError", m.py().get_type::<ScenarioError>())?;
    m.add("UnstableError", m.py().get_type::<UnstableError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
