//! Encoders: what the robot's own controller reads. Per track the belt position (unwrapped,
//! m; quantised down to `belt_resolution_m` like counts of an incremental encoder) and the
//! measured belt speed (m/s); per flipper its joint angle (rad, quantised to
//! `angle_resolution_deg`).

use super::sensor::{Channel, Sensor, StreamFormat};
use crate::model::{EncodersModel, SensorModel};
use crate::world::Simulation;

/// Encoders at run time.
pub struct Encoders {
    model: SensorModel,
    p: EncodersModel,
    channels: Vec<Channel>,
}

fn quantised(x: f64, step: f64) -> f64 {
    if step > 0.0 {
        (x / step).floor() * step
    } else {
        x
    }
}

impl Encoders {
    /// The encoders of `sim`'s vehicle.
    pub fn new(model: SensorModel, p: EncodersModel, sim: &Simulation) -> Self {
        let tracks = sim.track_names();
        let per = |prefix: &str, names: &[String]| -> Vec<String> {
            names.iter().map(|n| format!("{prefix}_{n}")).collect()
        };
        Encoders {
            model,
            p,
            channels: vec![
                Channel::columns("belt_position", "m", per("belt_position_m", tracks)),
                Channel::columns("belt_speed", "m/s", per("belt_speed_m_s", tracks)),
                Channel::columns(
                    "flipper_angle",
                    "rad",
                    per("flipper_angle_rad", sim.flipper_names()),
                ),
            ],
        }
    }
}

impl Sensor for Encoders {
    fn model(&self) -> &SensorModel {
        &self.model
    }

    fn format(&self) -> StreamFormat {
        StreamFormat::Csv
    }

    fn update(&mut self, sim: &Simulation, _dt: f64) {
        for i in 0..sim.track_names().len() {
            self.channels[0].data[i] = quantised(sim.belt_position(i), self.p.belt_resolution);
            self.channels[1].data[i] = sim.measured_belt_speed(i);
        }
        for i in 0..sim.flipper_names().len() {
            self.channels[2].data[i] = quantised(sim.flipper_angle(i), self.p.angle_resolution);
        }
    }

    fn channels(&self) -> &[Channel] {
        &self.channels
    }
}
