//! A sensor's readings over a run ([`SensorStream`]): the times and every channel's values,
//! appended at each update (scalar sensors in f64 for CSV, arrays in f32 for `.npz`).

use super::sensor::{Channel, Sensor, StreamFormat};

/// The values of one channel over a run.
#[derive(Clone, Debug, PartialEq)]
pub enum LogData {
    /// Full precision (CSV streams).
    F64(Vec<f64>),
    /// Single precision (array streams: the ray casts are f32).
    F32(Vec<f32>),
    /// One PNG per reading (a colour camera's `rgb`, rgb8, and `depth`, 16-bit mm).
    Png(Vec<Vec<u8>>),
}

/// One channel's log: its description and values, reading after reading.
#[derive(Clone, Debug, PartialEq)]
pub struct ChannelLog {
    /// The channel as described at the start (its `data` is the first reading).
    pub channel: Channel,
    /// Every reading's values, concatenated.
    pub values: LogData,
}

/// A sensor's readings over a run.
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
    /// Time of every reading, s.
    pub times: Vec<f64>,
    /// Every channel's log.
    pub channels: Vec<ChannelLog>,
    /// Fixed arrays (ray angles, cell centres).
    pub axes: Vec<Channel>,
    /// Mean wall time of an update, us.
    pub mean_cost_us: f64,
}

impl SensorStream {
    /// An empty stream of `sensor`.
    pub fn new(sensor: &dyn Sensor) -> Self {
        let format = sensor.format();
        SensorStream {
            name: sensor.model().name.clone(),
            kind: sensor.model().kind.name(),
            rate_hz: sensor.model().rate_hz,
            format,
            times: Vec::new(),
            channels: sensor
                .channels()
                .iter()
                .map(|c| ChannelLog {
                    channel: c.clone(),
                    values: match format {
                        StreamFormat::Png if c.shape.len() >= 2 => LogData::Png(Vec::new()),
                        StreamFormat::Csv | StreamFormat::Png => LogData::F64(Vec::new()),
                        StreamFormat::Npz => LogData::F32(Vec::new()),
                    },
                })
                .collect(),
            axes: sensor.axes(),
            mean_cost_us: 0.0,
        }
    }

    /// Its file name in the run folder: `sensors/NAME.csv` or `sensors/NAME.npz`.
    pub fn file_name(&self) -> String {
        let ext = match self.format {
            StreamFormat::Csv | StreamFormat::Png => "csv",
            StreamFormat::Npz => "npz",
        };
        format!("sensors/{}.{ext}", self.name)
    }

    /// Appends a reading taken at `t` s.
    pub fn push(&mut self, t: f64, channels: &[Channel]) {
        self.times.push(t);
        for (log, c) in self.channels.iter_mut().zip(channels) {
            match &mut log.values {
                LogData::F64(v) => v.extend_from_slice(&c.data),
                LogData::F32(v) => v.extend(c.data.iter().map(|x| *x as f32)),
                LogData::Png(v) => v.push(png_of(c)),
            }
        }
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
