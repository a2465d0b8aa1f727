//! The sensor part of a dict observation (`observation = "dict"`): one float32 array per sensor
//! of the vehicle, named as the sensor, from its latest reading, with what is not a number made
//! one so that a learner can take it:
//!
//! - `imu`: `[10]`, accel (m/s^2, specific force), gyro (rad/s), orientation (x, y, z, w);
//! - `encoders`: `[2 * tracks + flippers]`, belt positions (m), belt speeds (m/s), flipper
//!   angles (rad);
//! - `lidar`: `[E, A]` ranges (m), no return (`+inf`) as `max_range_m`, too close (`-inf`) as 0;
//! - `depth_camera`: `[H, W]` depths (m), likewise;
//! - `elevation_map`: `[nx, ny]` heights relative to the sensor (m), a cell without terrain
//!   (NaN) as the setting `no_terrain_m`.

use super::EnvConfig;
use crate::error::{Error, Result};
use crate::model::SensorKind;
use crate::sensors::{Channel, Sensor, SensorSet};

/// The name of the state vector's entry of a dict observation (no sensor may take it).
pub const STATE_KEY: &str = "state";

/// One sensor's entry of a dict observation: its name, shape and bounds.
#[derive(Clone, Debug, PartialEq)]
pub struct SensorObs {
    /// The sensor's name (the entry's key).
    pub name: String,
    /// The sensor's kind (`imu`, `lidar`, ...).
    pub kind: &'static str,
    /// Shape of the array (row-major).
    pub shape: Vec<usize>,
    /// Least value an entry can take (ranges and depths: 0 m; else `-inf`).
    pub low: f64,
    /// Greatest value an entry can take (ranges and depths: `max_range_m`; else `+inf`).
    pub high: f64,
}

impl SensorObs {
    /// Number of values.
    pub fn len(&self) -> usize {
        self.shape.iter().product()
    }

    /// No values.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The channel of `s` called `name` (every kind has the ones asked for here).
fn channel<'a>(s: &'a dyn Sensor, name: &str) -> &'a Channel {
    s.channels()
        .iter()
        .find(|c| c.name == name)
        .expect("the kind has the channel")
}

/// The entry of sensor `s`.
fn spec_of(s: &dyn Sensor) -> SensorObs {
    let m = s.model();
    let (names, low, high): (&[&str], f64, f64) = match m.kind {
        SensorKind::Imu(_) => (
            &["accel", "gyro", "orientation"],
            f64::NEG_INFINITY,
            f64::INFINITY,
        ),
        SensorKind::Encoders(_) => (
            &["belt_position", "belt_speed", "flipper_angle"],
            f64::NEG_INFINITY,
            f64::INFINITY,
        ),
        SensorKind::Lidar(p) => (&["range"], 0.0, p.max_range),
        SensorKind::DepthCamera(p) => (&["depth"], 0.0, p.max_range),
        SensorKind::RgbCamera(_) => (&["rgb"], 0.0, 255.0),
        SensorKind::ElevationMap(_) => (&["height"], f64::NEG_INFINITY, f64::INFINITY),
    };
    let shape = match names {
        [one] => channel(s, one).shape.clone(),
        _ => vec![names.iter().map(|n| channel(s, n).data.len()).sum()],
    };
    SensorObs {
        name: m.name.clone(),
        kind: m.kind.name(),
        shape,
        low,
        high,
    }
}

/// The entries of `set`'s sensors, in file order.
pub(super) fn specs(set: &SensorSet) -> Vec<SensorObs> {
    (0..set.len()).map(|i| spec_of(set.sensor(i))).collect()
}

/// Refuses a dict observation of a vehicle with a sensor called [`STATE_KEY`].
pub(super) fn check_names(set: &SensorSet) -> Result<()> {
    match (0..set.len()).find(|i| set.sensor(*i).model().name == STATE_KEY) {
        None => Ok(()),
        Some(_) => Err(Error::setting(
            "environment settings",
            "observation",
            format!(
                "\"dict\" names the state vector {STATE_KEY:?}, and a sensor of the vehicle has \
                 that name: rename the sensor"
            ),
        )),
    }
}

/// Writes sensor `s`'s entry into `out` (its length).
fn fill(s: &dyn Sensor, cfg: &EnvConfig, out: &mut [f32]) {
    let m = s.model();
    // The channels, what `+inf` becomes and what NaN becomes.
    let (names, max, nan): (&[&str], f64, f64) = match m.kind {
        SensorKind::Imu(_) => (&["accel", "gyro", "orientation"], f64::INFINITY, f64::NAN),
        SensorKind::Encoders(_) => (
            &["belt_position", "belt_speed", "flipper_angle"],
            f64::INFINITY,
            f64::NAN,
        ),
        SensorKind::Lidar(p) => (&["range"], p.max_range, f64::NAN),
        SensorKind::DepthCamera(p) => (&["depth"], p.max_range, f64::NAN),
        SensorKind::RgbCamera(_) => (&["rgb"], 255.0, f64::NAN),
        SensorKind::ElevationMap(_) => (&["height"], f64::INFINITY, cfg.no_terrain_m),
    };
    let mut k = 0;
    for n in names {
        for v in &channel(s, n).data {
            let x = if v.is_nan() {
                nan
            } else if *v == f64::INFINITY {
                max
            } else if *v == f64::NEG_INFINITY && max.is_finite() {
                0.0
            } else {
                *v
            };
            out[k] = x as f32;
            k += 1;
        }
    }
}

/// The readings of every sensor of `set`, one after the other in the order of [`specs`] (each
/// row-major), into `out` (length the sum of their lengths); see
/// [`super::Env::observe_sensors`].
pub(super) fn observe(set: &SensorSet, cfg: &EnvConfig, out: &mut [f32]) {
    let mut at = 0;
    for i in 0..set.len() {
        let s = set.sensor(i);
        let n = spec_of(s).len();
        fill(s, cfg, &mut out[at..at + n]);
        at += n;
    }
}
