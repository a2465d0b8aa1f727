//! `tracksim._tracksim`: the Python extension module of tracksim (PyO3), a thin layer over the
//! library: scenario files ([`tracksim::ScenarioTemplate`]), simulations
//! ([`tracksim::Simulation`]), and the learning environments of [`tracksim::env`]. Stepping
//! releases the GIL. Errors from files arrive as `tracksim.ScenarioError` (a `ValueError`)
//! with the CLI's message; an unstable simulation as `tracksim.UnstableError`; settings the
//! library refuses (environment configuration, array lengths, sweep plans) as `ValueError`
//! with the library's message, which names the key. Every check is the library's.

#![warn(clippy::too_many_lines)]

mod bundled;
mod common;
mod datasets;
mod env;
mod live_view;
mod scenario;
mod simulation;
mod team_env;
mod vec_env;
mod video;

use common::{ScenarioError, UnstableError};
use datasets::{ensemble, ensemble_merge, merge, sweep};
use env::PyEnvCore;
use live_view::PyLiveView;
use pyo3::prelude::*;
use scenario::PyScenario;
use simulation::PySimulation;
use team_env::{PyTeamEnvCore, PyTeamVecEnvCore};
use vec_env::PyVecEnvCore;

/// The extension module.
#[pymodule]
fn _tracksim(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyScenario>()?;
    m.add_class::<PySimulation>()?;
    m.add_class::<PyEnvCore>()?;
    m.add_class::<PyVecEnvCore>()?;
    m.add_class::<PyTeamEnvCore>()?;
    m.add_class::<PyTeamVecEnvCore>()?;
    m.add_class::<PyLiveView>()?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(ensemble, m)?)?;
    m.add_function(wrap_pyfunction!(ensemble_merge, m)?)?;
    m.add_function(wrap_pyfunction!(merge, m)?)?;
    m.add_function(wrap_pyfunction!(video::write_video, m)?)?;
    bundled::register(m)?;
    m.add("ScenarioError", m.py().get_type::<ScenarioError>())?;
    m.add("UnstableError", m.py().get_type::<UnstableError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
