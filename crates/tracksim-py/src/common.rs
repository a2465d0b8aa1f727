//! Shared pieces of the bindings: the exceptions, errors mapped to them, and `Shared`.

use pyo3::exceptions::PyRuntimeError;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::sync::Mutex;
use std::sync::MutexGuard;

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
pub(crate) struct Shared<T>(Mutex<T>);

impl<T> Shared<T> {
    pub(crate) fn new(t: T) -> Self {
        Shared(Mutex::new(t))
    }

    /// The value, locked (a panic while it was locked does not poison it).
    pub(crate) fn get(&self) -> MutexGuard<'_, T> {
        self.0.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The value, without locking.
    pub(crate) fn get_mut(&mut self) -> &mut T {
        self.0.get_mut().unwrap_or_else(|e| e.into_inner())
    }
}

pub(crate) fn py_err(e: tracksim::Error) -> PyErr {
    match e {
        tracksim::Error::Unstable { .. }
        | tracksim::Error::Limit { .. }
        | tracksim::Error::Build(_) => UnstableError::new_err(e.to_string()),
        tracksim::Error::Settings { .. } => PyValueError::new_err(e.to_string()),
        _ => ScenarioError::new_err(e.to_string()),
    }
}
