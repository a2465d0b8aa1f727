//! A sensor's readings over a run ([`SensorStream`]): the times and every channel's values,
//! appended at each update (scalar sensors in f64 for CSV, arrays in f32 for `.npz`).

use super::sensor::{Channel, Sensor, StreamFormat};
use crate::spill::SpillLog;

/// The values of one channel over a run (every reading's, concatenated:
/// [`SensorStream::channel_log`]).
#[derive(Clone, Debug, PartialEq)]
pub enum LogData {
    /// Full precision (CSV streams).
    F64(Vec<f64>),
    /// Single precision (array streams: the ray casts are f32).
    F32(Vec<f32>),
    /// One PNG per reading (a colour camera's `rgb`, rgb8, and `depth`, 16-bit mm).
    Png(Vec<Vec<u8>>),
}

/// One channel's values at one reading.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Values {
    /// Full precision (CSV streams).
    F64(Vec<f64>),
    /// Single precision (array streams: the ray casts are f32).
    F32(Vec<f32>),
    /// A PNG (a colour camera's `rgb`, rgb8, and `depth`, 16-bit mm).
    Png(Vec<u8>),
}

/// One reading of a sensor: its time and every channel's values, in channel order.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Reading {
    /// Time of the reading, s.
    pub t: f64,
    /// Each channel's values.
    pub values: Vec<Values>,
}

/// A sensor's readings over a run, the older ones spilled to disk as the run goes
/// ([`SpillLog`], issue 45: a 10-hour session's lidar holds the memory of a 10-minute one).
#[derive(Clone, Debug, PartialEq)]
pub struct SensorStream {
    /// Sensor name.
    pub name: String,
    /// Kind (`imu`, `lidar`, ...).
    pub kind: &'static str,
    /// Rate, Hz.
    pub rate_hz: f64,
    /// How it is written.
    pub format: StreamFormat,
    /// Every channel as described at the start (its `data` is the first reading).
    pub channels: Vec<Channel>,
    /// Every reading, in order.
    pub readings: SpillLog<Reading>,
    /// Fixed arrays (ray angles, cell centres).
    pub axes: Vec<Channel>,
    /// Mean wall time of an update, us.
    pub mean_cost_us: f64,
}

/// Bytes of readings a chunk of a stream's [`SpillLog`] holds at most (about: images counted
/// raw): a stream keeps at most two chunks in memory, so a lidar's or a camera's stream holds
/// about 8 MiB however long the run, a scalar sensor's up to [`crate::spill::SPILL_CHUNK`]
/// readings.
pub const CHUNK_BYTES: usize = 4 << 20;

impl SensorStream {
    /// An empty stream of `sensor`.
    pub fn new(sensor: &dyn Sensor) -> Self {
        let format = sensor.format();
        let bytes: usize = sensor
            .channels()
            .iter()
            .map(|c| {
                let per_value = match format {
                    StreamFormat::Png if c.shape.len() >= 2 => 1,
                    StreamFormat::Npz => 4,
                    StreamFormat::Csv | StreamFormat::Png => 8,
                };
                c.data.len() * per_value
            })
            .sum();
        let chunk = (CHUNK_BYTES / bytes.max(1)).clamp(1, crate::spill::SPILL_CHUNK);
        SensorStream {
            name: sensor.model().name.clone(),
            kind: sensor.model().kind.name(),
            rate_hz: sensor.model().rate_hz,
            format,
            channels: sensor.channels().to_vec(),
            readings: SpillLog::with_chunk(chunk),
            axes: sensor.axes(),
            mean_cost_us: 0.0,
        }
    }

    /// Whether channel `c` is written as one PNG per reading.
    pub fn is_image(&self, c: usize) -> bool {
        self.format == StreamFormat::Png && self.channels[c].shape.len() >= 2
    }

    /// Its file name in the run folder: `sensors/NAME.csv` or `sensors/NAME.npz`.
    pub fn file_name(&self) -> String {
        let ext = match self.format {
            StreamFormat::Csv | StreamFormat::Png => "csv",
            StreamFormat::Npz => "npz",
        };
        format!("sensors/{}.{ext}", self.name)
    }

    /// How many readings.
    pub fn len(&self) -> usize {
        self.readings.len()
    }

    /// Whether it has none.
    pub fn is_empty(&self) -> bool {
        self.readings.is_empty()
    }

    /// Time of every reading, s (memory grows with the run: for tests and short runs).
    pub fn times(&self) -> Vec<f64> {
        self.readings.iter().map(|r| r.t).collect()
    }

    /// Channel `c`'s values of every reading, concatenated (memory grows with the run: for
    /// tests, short runs and the `.npz` arrays, assembled a channel at a time).
    pub fn channel_log(&self, c: usize) -> LogData {
        let mut log = if self.is_image(c) {
            LogData::Png(Vec::new())
        } else if self.format == StreamFormat::Npz {
            LogData::F32(Vec::new())
        } else {
            LogData::F64(Vec::new())
        };
        for r in self.readings.iter() {
            match (&mut log, &r.values[c]) {
                (LogData::F64(v), Values::F64(x)) => v.extend_from_slice(x),
                (LogData::F32(v), Values::F32(x)) => v.extend_from_slice(x),
                (LogData::Png(v), Values::Png(x)) => v.push(x.clone()),
                _ => unreachable!("a channel's values keep their kind"),
            }
        }
        log
    }

    /// Appends a reading taken at `t` s.
    pub fn push(&mut self, t: f64, channels: &[Channel]) {
        let values = channels
            .iter()
            .enumerate()
            .map(|(c, ch)| match self.format {
                _ if self.is_image(c) => Values::Png(png_of(ch)),
                StreamFormat::Npz => Values::F32(ch.data.iter().map(|x| *x as f32).collect()),
                StreamFormat::Csv | StreamFormat::Png => Values::F64(ch.data.clone()),
            })
            .collect();
        self.readings.push(Reading { t, values });
    }
}

/// A colour camera's image channel as PNG bytes: `[H, W, 3]` 8-bit levels as rgb8, `[H, W]`
/// depths (m) as 16-bit millimetres.
fn png_of(c: &Channel) -> Vec<u8> {
    use crate::render::encode;
    let (h, w) = (c.shape[0], c.shape[1]);
    if c.shape.len() == 3 {
        let rgb: Vec<u8> = c
            .data
            .iter()
            .map(|v| v.round().clamp(0.0, 255.0) as u8)
            .collect();
        encode::rgb8_png(w, h, &rgb)
    } else {
        let d: Vec<f32> = c.data.iter().map(|v| *v as f32).collect();
        encode::depth16_png(w, h, &d)
    }
}
