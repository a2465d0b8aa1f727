//! The depth camera: a pinhole camera looking along the sensor's x axis, one ray per pixel
//! against what is within range (`scene.rs`, the robot excluded). `depth[v, u]` is the distance along
//! the optical (x) axis to what the pixel sees, m: row `v` from the top of the image (+z),
//! column `u` from its left (+y). Focal length `f = (width / 2) / tan(hfov / 2)` pixels, square
//! pixels; REP 117 for what is not a detection (`+inf` beyond `max_range_m`, `-inf` nearer than
//! `min_range_m`). Optional Gaussian depth noise.

use super::lidar::write_pose;
use super::mount::{sensor_frame, v32};
use super::noise::Noise;
use super::scene::Reach;
use super::sensor::{Channel, Sensor, StreamFormat};
use crate::model::{DepthCameraModel, SensorModel};
use crate::world::Simulation;
use glam::DVec3;
use rapier3d::prelude::*;

/// A depth camera at run time.
pub struct DepthCamera {
    model: SensorModel,
    p: DepthCameraModel,
    noise: Noise,
    /// Ray directions in the sensor frame with x = 1 (so a ray's time of impact is the
    /// depth), `[v * width + u]`.
    dirs: Vec<DVec3>,
    reach: Reach,
    channels: Vec<Channel>,
}

impl DepthCamera {
    /// The camera of `model`, sensor `index` of a run with `seed`.
    pub fn new(model: SensorModel, p: DepthCameraModel, seed: u64, index: usize) -> Self {
        let dirs = intrinsics(&p).pixel_rays();
        DepthCamera {
            model,
            p,
            noise: Noise::new(seed, index),
            dirs,
            reach: Reach::default(),
            channels: vec![
                Channel::zeros("depth", "m", &[p.height, p.width]),
                Channel::zeros("position", "m", &[3]),
                Channel::zeros("orientation", "", &[4]),
            ],
        }
    }
}

/// The camera's image (the colour camera's pinhole model, `crate::render::Intrinsics`).
fn intrinsics(p: &DepthCameraModel) -> crate::render::Intrinsics {
    crate::render::Intrinsics {
        width: p.width,
        height: p.height,
        horizontal_fov: p.horizontal_fov,
    }
}

/// Focal length of the camera, pixels.
pub(crate) fn focal_px(p: &DepthCameraModel) -> f64 {
    intrinsics(p).focal_px()
}

impl Sensor for DepthCamera {
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
        // The farthest pixel ray reaches `max` depth at the image corner.
        let corner = self.dirs.iter().map(|d| d.length()).fold(1.0, f64::max);
        self.reach.gather_sphere(sim, f.position, max * corner);
        for (i, d) in self.dirs.iter().enumerate() {
            let ray = Ray::new(origin, v32(f.rotation * *d));
            let depth = match self.reach.cast(sim, &ray, max as f32) {
                None => f64::INFINITY,
                Some(t) if (t as f64) < min => f64::NEG_INFINITY,
                Some(t) => (t as f64 + self.noise.gaussian(self.p.range_noise)).clamp(min, max),
            };
            self.channels[0].data[i] = depth;
        }
        write_pose(&mut self.channels, sim, &f);
    }

    fn channels(&self) -> &[Channel] {
        &self.channels
    }

    fn axes(&self) -> Vec<Channel> {
        vec![Channel::vector("focal_length", "px", &[focal_px(&self.p)])]
    }
}
