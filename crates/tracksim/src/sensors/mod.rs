//! Sensors (`[[sensors]]` of a vehicle file): what the robot senses, computed after a physics
//! step at each sensor's own rate, from the state the step left (its broad phase for the rays).
//! Sensing never changes the physics: a run with sensors has the trajectory of one without.
//!
//! Every kind is a file behind one interface, [`Sensor`]: it fills named [`Channel`]s (arrays of
//! numbers with a shape and a unit) at each update, into buffers allocated once.
//! [`SensorSet`] schedules them (update `k` at the first step at or after `k / rate_hz`), keeps
//! the latest reading, measures each update's cost and, when recording, logs every reading as a
//! [`SensorStream`] for `crate::output` (`sensors/NAME.csv` or `.npz`).
//!
//! - `mount.rs`: the sensor's frame and motion, the filter that keeps the robot out of its rays;
//! - `noise.rs`: seeded Gaussian noise;
//! - `scene.rs`: what a sensor's rays can hit at an update, gathered once through the broad phase;
//! - `imu.rs`, `encoders.rs`, `lidar.rs`, `depth_camera.rs`, `elevation_map.rs`: the kinds;
//! - `stream.rs`: the log of a run's readings.
//!
//! Frames: a sensor frame is REP 103 (x forward, y left, z up) placed by `xyz_m` and `rpy_deg`
//! in its mount's frame. Units SI.

mod depth_camera;
mod elevation_map;
mod encoders;
mod imu;
mod lidar;
pub mod mount;
mod noise;
pub mod scene;
mod stream;

pub use elevation_map::ElevationMap;
pub use mount::SensorFrame;
pub use stream::{LogData, SensorStream, StreamFormat};

use crate::model::{SensorKind, SensorModel};
use crate::world::Simulation;
use std::time::Instant;

/// One named array of a reading, row-major (C order).
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// Name (`accel`, `range`, `height`, ...): with `unit` it names the output key.
    pub name: &'static str,
    /// Unit (`m/s^2`, `m`, `rad`, ...).
    pub unit: &'static str,
    /// Shape (empty: a scalar).
    pub shape: Vec<usize>,
    /// Values, row-major; `shape` multiplied out long.
    pub data: Vec<f64>,
    /// Column names of a CSV-written sensor, one per value (empty for arrays).
    pub columns: Vec<String>,
}

impl Channel {
    /// A channel of `shape`, zero-filled.
    pub fn zeros(name: &'static str, unit: &'static str, shape: &[usize]) -> Self {
        Channel {
            name,
            unit,
            shape: shape.to_vec(),
            data: vec![0.0; shape.iter().product()],
            columns: Vec::new(),
        }
    }

    /// A one-dimensional channel holding `values` (a sensor's fixed axes).
    pub fn vector(name: &'static str, unit: &'static str, values: &[f64]) -> Self {
        Channel {
            name,
            unit,
            shape: vec![values.len()],
            data: values.to_vec(),
            columns: Vec::new(),
        }
    }

    /// A channel of CSV columns `columns` (one value each).
    pub fn columns(name: &'static str, unit: &'static str, columns: Vec<String>) -> Self {
        Channel {
            name,
            unit,
            shape: vec![columns.len()],
            data: vec![0.0; columns.len()],
            columns,
        }
    }

    /// The output key: name and unit (`range_m`, `accel_m_s2`).
    pub fn key(&self) -> String {
        let unit = self
            .unit
            .replace("^2", "2")
            .replace("^3", "3")
            .replace('/', "_");
        if unit.is_empty() {
            self.name.to_string()
        } else {
            format!("{}_{unit}", self.name)
        }
    }
}

/// What every sensor kind does.
pub trait Sensor: Send + Sync {
    /// The compiled sensor.
    fn model(&self) -> &SensorModel;
    /// How its readings are written.
    fn format(&self) -> StreamFormat;
    /// Takes a reading of the state `sim` is in (after a step), into its channels. `dt` is the
    /// time since its last reading, s (0 for the first one).
    fn update(&mut self, sim: &Simulation, dt: f64);
    /// The latest reading.
    fn channels(&self) -> &[Channel];
    /// Fixed arrays describing the reading (a lidar's ray angles, a map's cell centres).
    fn axes(&self) -> Vec<Channel> {
        Vec::new()
    }
}

/// Builds the sensor of `m`, sensor `index` of a run with `seed`.
fn build(m: &SensorModel, sim: &Simulation, index: usize) -> Box<dyn Sensor> {
    let seed = sim.seed();
    match m.kind {
        SensorKind::Imu(p) => Box::new(imu::Imu::new(m.clone(), p, seed, index)),
        SensorKind::Encoders(p) => Box::new(encoders::Encoders::new(m.clone(), p, sim)),
        SensorKind::Lidar(p) => Box::new(lidar::Lidar::new(m.clone(), p, seed, index)),
        SensorKind::DepthCamera(p) => {
            Box::new(depth_camera::DepthCamera::new(m.clone(), p, seed, index))
        }
        SensorKind::ElevationMap(p) => Box::new(elevation_map::ElevationMap::new(m.clone(), p)),
    }
}

/// A sensor with its schedule, cost and log.
struct Slot {
    sensor: Box<dyn Sensor>,
    /// Updates taken (the first at t = 0).
    updates: u64,
    /// Time of the latest reading, s.
    last_t: f64,
    /// Wall time spent in updates, s.
    cost: f64,
    log: Option<SensorStream>,
}

/// The sensors of a vehicle, run after every step.
pub struct SensorSet {
    slots: Vec<Slot>,
    dt: f64,
}

impl SensorSet {
    /// The sensors of `sim`'s vehicle, each with a first reading at the state now (t = 0: the
    /// IMU reads gravity alone); `record` logs every reading for the outputs.
    pub fn new(sim: &Simulation, record: bool) -> Self {
        let slots = sim
            .scenario()
            .vehicle
            .sensors
            .iter()
            .enumerate()
            .map(|(i, m)| {
                let mut sensor = build(m, sim, i);
                let t0 = Instant::now();
                sensor.update(sim, 0.0);
                let cost = t0.elapsed().as_secs_f64();
                let mut log = record.then(|| SensorStream::new(sensor.as_ref()));
                if let Some(l) = &mut log {
                    l.push(sim.time(), sensor.channels());
                }
                Slot {
                    sensor,
                    updates: 1,
                    last_t: sim.time(),
                    cost,
                    log,
                }
            })
            .collect();
        SensorSet {
            slots,
            dt: sim.dt(),
        }
    }

    /// No sensors at all (a front end that reads none).
    pub fn none() -> Self {
        SensorSet {
            slots: Vec::new(),
            dt: 0.0,
        }
    }

    /// Updates every sensor that is due after the step `sim` has just taken.
    pub fn update(&mut self, sim: &Simulation) {
        let t = sim.time();
        for s in &mut self.slots {
            let due = s.updates as f64 / s.sensor.model().rate_hz;
            if t + 0.5 * self.dt < due {
                continue;
            }
            let t0 = Instant::now();
            s.sensor.update(sim, t - s.last_t);
            s.cost += t0.elapsed().as_secs_f64();
            s.updates += 1;
            s.last_t = t;
            if let Some(l) = &mut s.log {
                l.push(t, s.sensor.channels());
            }
        }
    }

    /// No sensors.
    pub fn is_empty(&self) -> bool {
        self.slots.is_empty()
    }

    /// Number of sensors.
    pub fn len(&self) -> usize {
        self.slots.len()
    }

    /// Sensor `i` (file order).
    pub fn sensor(&self, i: usize) -> &dyn Sensor {
        self.slots[i].sensor.as_ref()
    }

    /// The sensor called `name`.
    pub fn find(&self, name: &str) -> Option<&dyn Sensor> {
        self.slots
            .iter()
            .find(|s| s.sensor.model().name == name)
            .map(|s| s.sensor.as_ref())
    }

    /// Time of sensor `i`'s latest reading, s.
    pub fn reading_time(&self, i: usize) -> f64 {
        self.slots[i].last_t
    }

    /// Updates sensor `i` has taken, and their mean wall cost, us.
    pub fn cost(&self, i: usize) -> (u64, f64) {
        let s = &self.slots[i];
        (s.updates, s.cost / s.updates.max(1) as f64 * 1e6)
    }

    /// The logs of the run (empty when not recording), each with its update count and cost.
    pub fn into_streams(self) -> Vec<SensorStream> {
        self.slots
            .into_iter()
            .filter_map(|s| {
                let updates = s.updates;
                let cost = s.cost / updates.max(1) as f64 * 1e6;
                s.log.map(|mut l| {
                    l.mean_cost_us = cost;
                    l
                })
            })
            .collect()
    }
}
