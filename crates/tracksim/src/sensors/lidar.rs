//! The lidar: rays over azimuth x elevation from the sensor's origin (a 2-D scanner is one
//! scan line), cast against what is within range (`scene.rs`: found through the broad phase the
//! step built, the robot's own colliders excluded). Per ray the range (m) and the hit point in the sensor frame
//! (m); REP 117 for what is not a detection: `+inf` nothing within `max_range_m`, `-inf` closer
//! than `min_range_m`, the point then NaN. Optional Gaussian range noise (kept within range).
//!
//! Ray order: `range[e, a]`, elevation from the lowest scan line up, azimuth counter-clockwise
//! from `-fov / 2` (a full turn: `fov / n` apart, the last ray not repeating the first; else
//! `fov / (n - 1)` apart, both ends included). Direction `(cos e cos a, cos e sin a, sin e)`.

use super::mount::{sensor_frame, v32};
use super::noise::Noise;
use super::scene::Reach;
use super::sensor::{Channel, Sensor, StreamFormat};
use crate::model::{LidarModel, SensorModel};
use crate::world::Simulation;
use glam::DVec3;
use rapier3d::prelude::*;
use std::f64::consts::TAU;

/// Evenly spread angles over `fov` (rad) centred on 0: `n` of them.
pub(crate) fn spread(n: usize, fov: f64, full_turn: bool) -> Vec<f64> {
    if n == 1 {
        return vec![0.0];
    }
    let step = if full_turn {
        fov / n as f64
    } else {
        fov / (n - 1) as f64
    };
    (0..n).map(|i| -fov / 2.0 + i as f64 * step).collect()
}

/// A lidar at run time.
pub struct Lidar {
    model: SensorModel,
    p: LidarModel,
    noise: Noise,
    azimuth: Vec<f64>,
    elevation: Vec<f64>,
    /// Unit ray directions in the sensor frame, `[e * A + a]`.
    dirs: Vec<DVec3>,
    reach: Reach,
    channels: Vec<Channel>,
}

impl Lidar {
    /// The lidar of `model`, sensor `index` of a run with `seed`.
    pub fn new(model: SensorModel, p: LidarModel, seed: u64, index: usize) -> Self {
        let full = (p.azimuth_fov - TAU).abs() < 1e-9;
        let azimuth = spread(p.azimuth_rays, p.azimuth_fov, full);
        let elevation = spread(p.elevation_rays, p.elevation_fov, false);
        let dirs = elevation
            .iter()
            .flat_map(|e| {
                azimuth
                    .iter()
                    .map(move |a| DVec3::new(e.cos() * a.cos(), e.cos() * a.sin(), e.sin()))
            })
            .collect();
        let (ne, na) = (p.elevation_rays, p.azimuth_rays);
        Lidar {
            model,
            p,
            noise: Noise::new(seed, index),
            azimuth,
            elevation,
            dirs,
            reach: Reach::default(),
            channels: vec![
                Channel::zeros("range", "m", &[ne, na]),
                Channel::zeros("points", "m", &[ne, na, 3]),
                Channel::zeros("position", "m", &[3]),
                Channel::zeros("orientation", "", &[4]),
            ],
        }
    }
}

/// The sensor's pose in world coordinates (floating origin added) into the last two channels.
pub(crate) fn write_pose(
    channels: &mut [Channel],
    sim: &Simulation,
    f: &super::mount::SensorFrame,
) {
    let n = channels.len();
    let p = f.position + sim.origin();
    channels[n - 2].data.copy_from_slice(&p.to_array());
    let q = f.rotation;
    channels[n - 1].data.copy_from_slice(&[q.x, q.y, q.z, q.w]);
}

impl Sensor for Lidar {
    fn model(&self) -> &SensorModel {
        &self.model
    }

    fn format(&self) -> StreamFormat {
        StreamFormat::Npz
    }

    fn update(&mut self, sim: &Simulation, _dt: f64) {
        let f = sensor_frame(sim, &self.model);
        let origin = v32(f.position);
        let (min, max) = (self.p.min_range, self.p.max_range);
        self.reach.gather_sphere(sim, f.position, max);
        for (i, d) in self.dirs.iter().enumerate() {
            let ray = Ray::new(origin, v32(f.rotation * *d));
            let hit = self.reach.cast(sim, &ray, max as f32).map(|t| t as f64);
            let (range, point) = match hit {
                None => (f64::INFINITY, [f64::NAN; 3]),
                Some(t) if t < min => (f64::NEG_INFINITY, [f64::NAN; 3]),
                Some(t) => {
                    let r = (t + self.noise.gaussian(self.p.range_noise)).clamp(min, max);
                    (r, (*d * r).to_array())
                }
            };
            self.channels[0].data[i] = range;
            self.channels[1].data[3 * i..3 * i + 3].copy_from_slice(&point);
        }
        write_pose(&mut self.channels, sim, &f);
    }

    fn channels(&self) -> &[Channel] {
        &self.channels
    }

    fn axes(&self) -> Vec<Channel> {
        vec![
            Channel::vector("azimuth", "rad", &self.azimuth),
            Channel::vector("elevation", "rad", &self.elevation),
        ]
    }
}
