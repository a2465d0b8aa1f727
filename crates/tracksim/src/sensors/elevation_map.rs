//! The elevation map: a grid of terrain heights around the sensor, aligned with the sensor's
//! heading (the yaw of its x axis; level, not tilted with the body), relative to the sensor's
//! height. `height[i, j]` is at `x[i]` ahead and `y[j]` to the left of the sensor, cell centres
//! `(k + 0.5 - n / 2) * resolution_m`; a cell whose vertical ray (from `height_above_m` above
//! the sensor down to `depth_below_m` below it) meets nothing is NaN, and with `occlusion` so
//! is a cell whose surface the sensor cannot see (the straight line from the sensor to it is
//! blocked short of 1.5 cells from the surface point).
//!
//! Cost: the colliders under the map are found once per update (`scene.rs`), then each cell's
//! vertical ray is tested against those whose box it crosses.

use super::lidar::write_pose;
use super::mount::{sensor_frame, v32};
use super::scene::Reach;
use super::sensor::{Channel, Sensor, StreamFormat};
use crate::model::{ElevationMapModel, SensorModel};
use crate::world::Simulation;
use glam::DVec3;
use rapier3d::prelude::*;

/// An elevation map at run time.
pub struct ElevationMap {
    model: SensorModel,
    p: ElevationMapModel,
    x: Vec<f64>,
    y: Vec<f64>,
    /// What the rays may hit at this update.
    reach: Reach,
    channels: Vec<Channel>,
}

fn centres(n: usize, res: f64) -> Vec<f64> {
    (0..n)
        .map(|k| (k as f64 + 0.5 - n as f64 / 2.0) * res)
        .collect()
}

impl ElevationMap {
    /// The map of `model`.
    pub fn new(model: SensorModel, p: ElevationMapModel) -> Self {
        let [nx, ny] = p.cells;
        ElevationMap {
            model,
            x: centres(nx, p.resolution),
            y: centres(ny, p.resolution),
            p,
            reach: Reach::default(),
            channels: vec![
                Channel::zeros("height", "m", &[nx, ny]),
                Channel::zeros("position", "m", &[3]),
                Channel::zeros("orientation", "", &[4]),
            ],
        }
    }
}

impl Sensor for ElevationMap {
    fn model(&self) -> &SensorModel {
        &self.model
    }

    fn format(&self) -> StreamFormat {
        StreamFormat::Npz
    }

    fn update(&mut self, sim: &Simulation, _dt: f64) {
        let f = sensor_frame(sim, &self.model);
        let heading = f.rotation * DVec3::X;
        let yaw = heading.y.atan2(heading.x);
        let (s, c) = yaw.sin_cos();
        let top = f.position.z + self.p.height_above;
        let reach = (self.p.height_above + self.p.depth_below) as f32;
        let half = DVec3::new(
            self.x.last().copied().unwrap_or(0.0).abs() + self.p.resolution,
            self.y.last().copied().unwrap_or(0.0).abs() + self.p.resolution,
            0.0,
        );
        // The map's box in the world (its corners turned by the yaw).
        let ext = DVec3::new(
            c.abs() * half.x + s.abs() * half.y,
            s.abs() * half.x + c.abs() * half.y,
            0.0,
        );
        let lo = f.position - ext - DVec3::Z * self.p.depth_below;
        let hi = f.position + ext + DVec3::Z * self.p.height_above;
        self.reach.gather(sim, lo, hi);
        let ny = self.y.len();
        for (i, xi) in self.x.iter().enumerate() {
            for (j, yj) in self.y.iter().enumerate() {
                let wx = f.position.x + c * xi - s * yj;
                let wy = f.position.y + s * xi + c * yj;
                let toi = self
                    .reach
                    .cast_down(sim, wx as f32, wy as f32, top as f32, reach);
                let mut height = toi.map_or(f64::NAN, |t| self.p.height_above - t as f64);
                if self.p.occlusion && height.is_finite() {
                    let target = DVec3::new(wx, wy, f.position.z + height);
                    let to = target - f.position;
                    let dist = to.length();
                    let margin = 1.5 * self.p.resolution;
                    if dist > margin {
                        let r = Ray::new(v32(f.position), v32(to / dist));
                        if self.reach.cast(sim, &r, (dist - margin) as f32).is_some() {
                            height = f64::NAN;
                        }
                    }
                }
                self.channels[0].data[i * ny + j] = height;
            }
        }
        write_pose(&mut self.channels, sim, &f);
    }

    fn channels(&self) -> &[Channel] {
        &self.channels
    }

    fn axes(&self) -> Vec<Channel> {
        vec![
            Channel::vector("x", "m", &self.x),
            Channel::vector("y", "m", &self.y),
        ]
    }
}
