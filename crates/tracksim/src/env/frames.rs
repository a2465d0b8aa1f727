//! Frames of an environment's current state for watching and videos ([`super::Env::render`]):
//! the chase camera ([`ChaseCamera`], behind and above the robot, following its heading,
//! `render_size_px` pixels, 70 deg across) traced by the colour renderer
//! ([`crate::render`]) on demand, or the latest frame of one of the vehicle's `rgb_camera`
//! sensors (`render_camera` = its name). rgb8, rows from the top.

use super::config::{CHASE_CAMERA, EnvConfig};
use crate::error::{Error, Result};
use crate::model::{Scenario, SensorKind};
use crate::render::{ChaseCamera, Frame, Intrinsics};
use crate::sensors::sim_scene::{WorldShapes, render_chase};
use crate::world::Simulation;

/// Where an environment's frames come from.
pub(super) enum FrameSource {
    /// The chase camera, its buffers kept between frames.
    Chase(Box<ChaseFrames>),
    /// The rgb_camera sensor of this index (file order).
    Sensor(usize),
}

/// The chase camera and its buffers.
pub(super) struct ChaseFrames {
    camera: ChaseCamera,
    shapes: WorldShapes,
    frame: Frame,
}

impl FrameSource {
    /// The source `cfg.render_camera` names on `sc`'s vehicle: the chase camera, or an
    /// rgb_camera sensor (another name is refused, keyed `render_camera`, with the cameras).
    pub(super) fn of(cfg: &EnvConfig, sc: &Scenario) -> Result<FrameSource> {
        if cfg.render_camera == CHASE_CAMERA {
            let (width, height) = cfg.render_size_px;
            let camera = ChaseCamera {
                intrinsics: Intrinsics {
                    width,
                    height,
                    ..ChaseCamera::default().intrinsics
                },
                ..ChaseCamera::default()
            };
            return Ok(FrameSource::Chase(Box::new(ChaseFrames {
                camera,
                shapes: WorldShapes::default(),
                frame: Frame::new(width, height),
            })));
        }
        let sensors = &sc.vehicle.sensors;
        match sensors.iter().position(|m| m.name == cfg.render_camera) {
            Some(i) if matches!(sensors[i].kind, SensorKind::RgbCamera(_)) => {
                Ok(FrameSource::Sensor(i))
            }
            found => {
                let cameras: Vec<String> = sensors
                    .iter()
                    .filter(|m| matches!(m.kind, SensorKind::RgbCamera(_)))
                    .map(|m| format!("{:?}", m.name))
                    .collect();
                let what = if found.is_some() {
                    "is not an rgb_camera"
                } else {
                    "is no sensor of the vehicle"
                };
                Err(Error::setting(
                    "environment settings",
                    "render_camera",
                    format!(
                        "{:?} {what}: use {CHASE_CAMERA:?}{}",
                        crate::check::echoed(&cfg.render_camera),
                        if cameras.is_empty() {
                            " (the vehicle has no rgb_camera)".to_string()
                        } else {
                            format!(
                                " or one of the vehicle's rgb cameras: {}",
                                cameras.join(", ")
                            )
                        }
                    ),
                ))
            }
        }
    }

    /// The sensors must run for this source.
    pub(super) fn needs_sensors(&self) -> bool {
        matches!(self, FrameSource::Sensor(_))
    }

    /// Width and height of the frames, pixels.
    pub(super) fn size(&self, sc: &Scenario) -> (usize, usize) {
        match self {
            FrameSource::Chase(c) => (c.frame.width, c.frame.height),
            FrameSource::Sensor(i) => match sc.vehicle.sensors[*i].kind {
                SensorKind::RgbCamera(p) => (p.intrinsics.width, p.intrinsics.height),
                _ => (0, 0),
            },
        }
    }

    /// The frame of the current state: the chase camera traced now, or the sensor's latest
    /// reading (`None` if the sensor gives no frame).
    pub(super) fn render<'a>(
        &'a mut self,
        sim: &Simulation,
        sensors: &'a crate::sensors::SensorSet,
    ) -> Option<&'a Frame> {
        match self {
            FrameSource::Chase(c) => {
                render_chase(sim, &c.camera, &mut c.shapes, &mut c.frame);
                Some(&c.frame)
            }
            FrameSource::Sensor(i) => sensors.sensor(*i).frame(),
        }
    }
}
