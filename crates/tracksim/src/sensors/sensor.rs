//! The one interface of every sensor kind ([`Sensor`]): named [`Channel`]s filled at each
//! update into buffers allocated once, and the format its stream is written in
//! ([`StreamFormat`]).

use crate::model::SensorModel;
use crate::world::Simulation;

/// How a sensor's stream is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StreamFormat {
    /// `sensors/NAME.csv`: `t_s` and one column per value (IMU, encoders).
    Csv,
    /// `sensors/NAME.npz`: `t_s` (N), each channel (N x its shape, float32) and the axes.
    Npz,
    /// `sensors/NAME/NNNNNN.png` (rgb8) and `NNNNNN_depth.png` (16-bit, mm) per reading, and
    /// `sensors/NAME.csv` (`t_s`, the frame's file, position and orientation): colour cameras.
    Png,
}

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
    /// The latest image of a colour camera (rgb8 and depth), `None` for other kinds.
    fn frame(&self) -> Option<&crate::render::Frame> {
        None
    }
}
