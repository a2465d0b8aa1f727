//! The `LiveView` class: an environment watched in the drive page (`render_mode="human"`).

use crate::common::{Shared, py_err};
use crate::env::PyEnvCore;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// A learning environment's live 3-D page (`render_mode="human"`): the drive page on
/// loopback, watch-only, fed the environment's state by `show`.
#[pyclass(name = "LiveView", module = "tracksim._tracksim")]
pub(crate) struct PyLiveView {
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
