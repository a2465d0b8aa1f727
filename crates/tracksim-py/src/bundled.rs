//! The bundled scenario files from Python (`tracksim.bundled_names`, `tracksim.bundled_path`):
//! the library embeds every file of `scenarios/` and `vehicles/` ([`tracksim::bundled`]), so an
//! installed wheel finds them by name without the source tree (the task suite's files, say).

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use tracksim::bundled::{self, Kind};

/// The names of the bundled scenarios, sorted by path: `packbot_flat`,
/// `random/packbot_step_random`, `tasks/packbot_battens`, ...
#[pyfunction]
fn bundled_names() -> Vec<String> {
    bundled::list()
        .into_iter()
        .filter(|f| f.kind == Kind::Scenario)
        .map(|f| f.name)
        .collect()
}

/// The path of the bundled scenario (or vehicle) file called `name` (`tasks/packbot_battens`,
/// with or without `.toml`), extracted with the whole bundle (its vehicles and assets) into
/// the data folder once per version (`TRACKSIM_DATA_DIR`, else `~/.cache/tracksim/VERSION`).
/// Raises `ValueError` for a name that is not bundled, `ScenarioError` if the folder cannot
/// be written.
#[pyfunction]
fn bundled_path(py: Python<'_>, name: &str) -> PyResult<String> {
    match py
        .detach(|| bundled::resolve(name))
        .map_err(crate::common::py_err)?
    {
        Some(p) => Ok(p.display().to_string()),
        None => {
            let shown: String = name.chars().take(100).collect();
            Err(PyValueError::new_err(format!(
                "no bundled scenario or vehicle is called {shown:?}: tracksim.bundled_names() \
                 lists the bundled scenarios (e.g. \"tasks/packbot_flat\"); give a file path to \
                 tracksim.Scenario for a file of your own"
            )))
        }
    }
}

/// Adds the functions of this file to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(bundled_names, m)?)?;
    m.add_function(wrap_pyfunction!(bundled_path, m)?)?;
    Ok(())
}
