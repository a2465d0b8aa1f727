//! The colour camera (`kind = "rgb_camera"`): a pinhole camera looking along the sensor's x
//! axis, each pixel a ray traced through the world (`crate::render`: the hit's colour, Lambert
//! shading from one sun with a shadow ray, sky and far ground where nothing is hit), with the
//! depth of every pixel on the same rays as the depth camera (so colour and depth agree on
//! edges). Channels: `rgb` `[H, W, 3]` (8-bit levels 0..255), `depth` `[H, W]` (m, REP 117:
//! `+inf` beyond `max_range_m`, `-inf` nearer than `min_range_m`), the sensor's position and
//! orientation. Optional Gaussian noise per channel and pixel (`pixel_noise`, seeded: the same
//! run gives the same bytes). The robot's own colliders are not seen, as for every ray sensor.

use super::lidar::write_pose;
use super::mount::sensor_frame;
use super::noise::Noise;
use super::sensor::{Channel, Sensor, StreamFormat};
use super::sim_scene::{WorldScene, WorldShapes};
use crate::model::{RgbCameraModel, SensorModel};
use crate::render::{self, CameraPose, Frame, Light};
use crate::world::Simulation;

/// A colour camera at run time.
pub struct RgbCamera {
    model: SensorModel,
    p: RgbCameraModel,
    noise: Noise,
    /// The pixel rays, camera frame.
    rays: Vec<glam::Vec3>,
    /// The farthest pixel ray's length per unit of depth.
    corner: f64,
    shapes: WorldShapes,
    frame: Frame,
    pool: Option<rayon::ThreadPool>,
    channels: Vec<Channel>,
}

impl RgbCamera {
    /// The camera of `model`, sensor `index` of a run with `seed`.
    pub fn new(model: SensorModel, p: RgbCameraModel, seed: u64, index: usize) -> Self {
        let i = p.intrinsics;
        let pool = (p.threads != 1)
            .then(|| {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(p.threads)
                    .build()
                    .ok()
            })
            .flatten();
        RgbCamera {
            model,
            p,
            noise: Noise::new(seed, index),
            rays: i.pixel_rays_f32(),
            corner: i.corner_factor(),
            shapes: WorldShapes::default(),
            frame: Frame::new(i.width, i.height),
            pool,
            channels: vec![
                Channel::zeros("rgb", "", &[i.height, i.width, 3]),
                Channel::zeros("depth", "m", &[i.height, i.width]),
                Channel::zeros("position", "m", &[3]),
                Channel::zeros("orientation", "", &[4]),
            ],
        }
    }
}

impl Sensor for RgbCamera {
    fn model(&self) -> &SensorModel {
        &self.model
    }

    fn format(&self) -> StreamFormat {
        StreamFormat::Png
    }

    fn update(&mut self, sim: &Simulation, _dt: f64) {
        let f = sensor_frame(sim, &self.model);
        let (min, max) = (self.p.min_range as f32, self.p.max_range as f32);
        let light = Light::default();
        let shadow_range = if self.p.shadows {
            light.shadow_range as f64
        } else {
            0.0
        };
        self.shapes.gather(
            sim,
            f.position,
            self.p.max_range * self.corner,
            sim.sensor_filter(),
            shadow_range,
        );
        let scene = WorldScene {
            sim,
            shapes: &self.shapes,
        };
        let pose = CameraPose {
            position: f.position,
            rotation: f.rotation,
        };
        render::render(
            &scene,
            &self.p.intrinsics,
            &self.rays,
            &pose,
            &light,
            min,
            max,
            self.pool.as_ref(),
            &mut self.frame,
        );
        if self.p.pixel_noise > 0.0 {
            for b in &mut self.frame.rgb {
                let x = *b as f64 + self.noise.gaussian(self.p.pixel_noise);
                *b = x.round().clamp(0.0, 255.0) as u8;
            }
        }
        for (o, b) in self.channels[0].data.iter_mut().zip(&self.frame.rgb) {
            *o = *b as f64;
        }
        for (o, d) in self.channels[1].data.iter_mut().zip(&self.frame.depth) {
            *o = *d as f64;
        }
        write_pose(&mut self.channels, sim, &f);
    }

    fn channels(&self) -> &[Channel] {
        &self.channels
    }

    fn axes(&self) -> Vec<Channel> {
        vec![Channel::vector(
            "focal_length",
            "px",
            &[self.p.intrinsics.focal_px()],
        )]
    }

    fn frame(&self) -> Option<&Frame> {
        Some(&self.frame)
    }
}
