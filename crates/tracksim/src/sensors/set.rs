//! The sensors of a vehicle ([`SensorSet`]): each kind built, scheduled at its rate, its
//! latest reading kept, its cost measured and, when recording, its readings logged.

use super::sensor::Sensor;
use super::stream::SensorStream;
use super::{depth_camera, elevation_map, encoders, imu, lidar, rgb_camera};
use crate::model::{SensorKind, SensorModel};
use crate::world::Simulation;
use std::time::Instant;

/// Builds the sensor of `m`, sensor `index` of the run `sim` is (its seed), without a first
/// reading (benchmarks time its updates alone).
pub fn build(m: &SensorModel, sim: &Simulation, index: usize) -> Box<dyn Sensor> {
    let seed = sim.seed();
    match m.kind {
        SensorKind::Imu(p) => Box::new(imu::Imu::new(m.clone(), p, seed, index)),
        SensorKind::Encoders(p) => Box::new(encoders::Encoders::new(m.clone(), p, sim)),
        SensorKind::Lidar(p) => Box::new(lidar::Lidar::new(m.clone(), p, seed, index)),
        SensorKind::DepthCamera(p) => {
            Box::new(depth_camera::DepthCamera::new(m.clone(), p, seed, index))
        }
        SensorKind::RgbCamera(p) => Box::new(rgb_camera::RgbCamera::new(m.clone(), p, seed, index)),
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
