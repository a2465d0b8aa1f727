//! The IMU: specific force (what an accelerometer reads: the acceleration of its point minus
//! gravity, so +9.81 m/s^2 along z at rest on flat ground), angular rate and orientation, in the
//! sensor frame; optional white noise and bias random walk in datasheet units.
//!
//! The acceleration is the mean over the update interval, `(v(t) - v(t - T)) / T` of the
//! sensor's material point (what a real IMU's integrating front end reports as delta-velocity
//! over its sample period): it needs the velocity at the last update only, not every step, and
//! includes the lever arm (`v` is the velocity at the point). Discrete noise per update
//! (Kalibr's model): white `sigma = density * sqrt(rate)`, bias `b += walk * sqrt(T) * N(0, 1)`.

use super::mount::sensor_frame;
use super::noise::Noise;
use super::sensor::{Channel, Sensor, StreamFormat};
use crate::model::{ImuModel, SensorModel};
use crate::world::Simulation;
use glam::DVec3;

/// An IMU at run time.
pub struct Imu {
    model: SensorModel,
    p: ImuModel,
    noise: Noise,
    /// Velocity of the sensor point at the last update, m/s (world frame).
    last_velocity: Option<DVec3>,
    accel_bias: DVec3,
    gyro_bias: DVec3,
    channels: Vec<Channel>,
}

fn xyz(prefix: &str, unit: &str) -> Vec<String> {
    ["x", "y", "z"]
        .iter()
        .map(|a| format!("{prefix}_{a}_{unit}"))
        .collect()
}

impl Imu {
    /// The IMU of `model`, sensor `index` of a run with `seed`.
    pub fn new(model: SensorModel, p: ImuModel, seed: u64, index: usize) -> Self {
        Imu {
            model,
            p,
            noise: Noise::new(seed, index),
            last_velocity: None,
            accel_bias: DVec3::ZERO,
            gyro_bias: DVec3::ZERO,
            channels: vec![
                Channel::columns("accel", "m/s^2", xyz("accel", "m_s2")),
                Channel::columns("gyro", "rad/s", xyz("gyro", "rad_s")),
                Channel::columns(
                    "orientation",
                    "",
                    ["qx", "qy", "qz", "qw"]
                        .iter()
                        .map(|s| s.to_string())
                        .collect(),
                ),
            ],
        }
    }

    fn gaussian3(&mut self, sigma: f64) -> DVec3 {
        DVec3::new(
            self.noise.gaussian(sigma),
            self.noise.gaussian(sigma),
            self.noise.gaussian(sigma),
        )
    }
}

impl Sensor for Imu {
    fn model(&self) -> &SensorModel {
        &self.model
    }

    fn format(&self) -> StreamFormat {
        StreamFormat::Csv
    }

    fn update(&mut self, sim: &Simulation, dt: f64) {
        let f = sensor_frame(sim, &self.model);
        let g = sim.world.gravity;
        let gravity = DVec3::new(g.x as f64, g.y as f64, g.z as f64);
        let accel = match self.last_velocity {
            Some(v0) if dt > 0.0 => (f.velocity - v0) / dt,
            _ => DVec3::ZERO,
        };
        self.last_velocity = Some(f.velocity);
        let rate = self.model.rate_hz;
        let period = if dt > 0.0 { dt } else { 1.0 / rate };
        let walk_a = self.gaussian3(self.p.accel_bias_random_walk * period.sqrt());
        let walk_g = self.gaussian3(self.p.gyro_bias_random_walk * period.sqrt());
        self.accel_bias += walk_a;
        self.gyro_bias += walk_g;
        let inv = f.rotation.inverse();
        let white_a = self.gaussian3(self.p.accel_noise_density * rate.sqrt());
        let white_g = self.gaussian3(self.p.gyro_noise_density * rate.sqrt());
        let specific = inv * (accel - gravity) + self.accel_bias + white_a;
        let rate_b = inv * f.angvel + self.gyro_bias + white_g;
        let q = f.rotation;
        self.channels[0].data.copy_from_slice(&specific.to_array());
        self.channels[1].data.copy_from_slice(&rate_b.to_array());
        self.channels[2].data.copy_from_slice(&[q.x, q.y, q.z, q.w]);
    }

    fn channels(&self) -> &[Channel] {
        &self.channels
    }
}
