//! The `Scenario` class: a scenario file loaded and checked, ready to be instantiated with any
//! seed.

use crate::common::py_err;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Arc;
use tracksim::ScenarioTemplate;

/// A scenario file, loaded and checked (its `[randomize]` table too), ready to be instantiated
/// with any seed.
#[pyclass(name = "Scenario", module = "tracksim._tracksim", frozen)]
pub(crate) struct PyScenario {
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

    /// The file's simulated duration (`simulation.duration_s`), s.
    #[getter]
    fn duration_s(&self) -> PyResult<f64> {
        Ok(self.t.file_scenario().map_err(py_err)?.duration)
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
        Ok(self.t.instantiate(seed).map_err(py_err)?.randomized.clone())
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

pub(crate) fn template_of(obj: &Bound<'_, PyAny>) -> PyResult<Arc<ScenarioTemplate>> {
    if let Ok(s) = obj.cast::<PyScenario>() {
        return Ok(s.get().t.clone());
    }
    let path: PathBuf = obj.extract()?;
    Ok(Arc::new(tracksim::load_template(&path).map_err(py_err)?))
}
