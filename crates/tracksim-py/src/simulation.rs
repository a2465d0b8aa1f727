//! The `Simulation` class: one simulation stepped from Python (the GIL released while stepping).

use crate::common::{Shared, py_err};
use crate::scenario::template_of;
use numpy::PyArray1;
use numpy::PyArray2;
use numpy::PyArrayMethods;
use pyo3::exceptions::PyKeyError;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::BTreeMap;
use std::sync::Arc;
use tracksim::Controls;
use tracksim::ScenarioTemplate;
use tracksim::sensors::Channel;
use tracksim::sensors::SensorSet;

/// One simulation of a scenario: set controls, step, read the state and the sensors.
#[pyclass(name = "Simulation", module = "tracksim._tracksim")]
pub(crate) struct PySimulation {
    t: Arc<ScenarioTemplate>,
    sim: tracksim::Simulation,
    /// Each robot's sensors (not recorded), updated after every step.
    sensors: Shared<Vec<SensorSet>>,
}

/// Each robot's sensor set (not recorded); robot 0 selected after.
fn sensor_sets(sim: &mut tracksim::Simulation) -> Vec<SensorSet> {
    let sets = (0..sim.robot_count())
        .map(|k| {
            sim.select(k);
            SensorSet::new(sim, false)
        })
        .collect();
    sim.select(0);
    sets
}

/// A channel as a float64 numpy array of its shape.
pub(crate) fn channel_array<'py>(py: Python<'py>, c: &Channel) -> PyResult<Bound<'py, PyAny>> {
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
        let all = self.sensors.get();
        let s = &all[self.sim.selected()];
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
        let mut sim = tracksim::Simulation::new(&sc).map_err(py_err)?;
        let sensors = Shared::new(sensor_sets(&mut sim));
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
        let selected = self.sim.selected();
        self.sim = tracksim::Simulation::new(&sc).map_err(py_err)?;
        self.sensors = Shared::new(sensor_sets(&mut self.sim));
        self.sim.select(selected);
        Ok(())
    }

    /// Advances `n` physics steps (GIL released), the sensors that are due updated after
    /// each; raises `UnstableError` if it blows up.
    #[pyo3(signature = (n=1))]
    fn step(&mut self, py: Python<'_>, n: u64) -> PyResult<()> {
        let (sim, sensors) = (&mut self.sim, self.sensors.get_mut());
        let selected = sim.selected();
        let r = py.detach(|| {
            for _ in 0..n {
                sim.step()?;
                for (k, s) in sensors.iter_mut().enumerate() {
                    sim.select(k);
                    s.update(sim);
                }
            }
            Ok(())
        });
        sim.select(selected);
        r.map_err(py_err)
    }

    /// Names of the vehicle's sensors (`[[sensors]]` order).
    #[getter]
    fn sensor_names(&self) -> Vec<String> {
        let all = self.sensors.get();
        let s = &all[self.sim.selected()];
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
        for c in self.sensors.get()[self.sim.selected()].sensor(i).axes() {
            d.set_item(c.key(), channel_array(py, &c)?)?;
        }
        Ok(d)
    }

    /// The robots' names in file order (`["robot"]` for a one-robot file; `[[vehicles]]`'s
    /// names, docs/TEAMS.md).
    #[getter]
    fn robot_names(&self) -> Vec<String> {
        self.sim.robot_names()
    }

    /// The selected robot's name: the one the controls, `observe`, `sensors`, `outcome` and the
    /// names of tracks and flippers act on (the first robot until `select`).
    #[getter]
    fn selected(&self) -> String {
        self.sim.robot_name().to_string()
    }

    /// Selects a robot by name (or index) for the controls and queries; `KeyError` naming the
    /// robots for an unknown one.
    fn select(&mut self, robot: &Bound<'_, PyAny>) -> PyResult<()> {
        let names = self.sim.robot_names();
        let k = if let Ok(i) = robot.extract::<usize>() {
            (i < names.len()).then_some(i)
        } else {
            let name: String = robot.extract()?;
            names.iter().position(|n| *n == name)
        };
        let k = k.ok_or_else(|| {
            PyKeyError::new_err(format!(
                "no robot {robot} in the world; its robots: {}",
                names.join(", ")
            ))
        })?;
        self.sim.select(k);
        Ok(())
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
