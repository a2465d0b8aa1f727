//! Sensors (`[[sensors]]` of a vehicle file): what the robot senses, computed after a physics
//! step at each sensor's own rate, from the state the step left (its broad phase for the rays).
//! Sensing never changes the physics: a run with sensors has the trajectory of one without.
//!
//! Every kind is a file behind one interface, [`Sensor`]: it fills named [`Channel`]s (arrays of
//! numbers with a shape and a unit) at each update, into buffers allocated once.
//! [`SensorSet`] schedules them (update `k` at the first step at or after `k / rate_hz`), keeps
//! the latest reading, measures each update's cost and, when recording, logs every reading as a
//! [`SensorStream`] for `crate::output` (`sensors/NAME.csv` or `.npz`).
//!
//! - `mount.rs`: the sensor's frame and motion, the filter that keeps the robot out of its rays;
//! - `noise.rs`: seeded Gaussian noise;
//! - `scene.rs`: what a sensor's rays can hit at an update, gathered once through the broad phase;
//! - `imu.rs`, `encoders.rs`, `lidar.rs`, `depth_camera.rs`, `rgb_camera.rs`,
//!   `elevation_map.rs`: the kinds;
//! - `sim_scene.rs`: the world as a scene for the colour tracer (`crate::render`), and the
//!   chase camera;
//! - `sensor.rs`: the [`Sensor`] trait, [`Channel`] and [`StreamFormat`];
//! - `set.rs`: [`SensorSet`], which builds every kind and runs them;
//! - `stream.rs`: the log of a run's readings.
//!
//! Frames: a sensor frame is REP 103 (x forward, y left, z up) placed by `xyz_m` and `rpy_deg`
//! in its mount's frame. Units SI.

mod depth_camera;
mod elevation_map;
mod encoders;
mod imu;
mod lidar;
pub mod mount;
mod noise;
mod rgb_camera;
pub mod scene;
mod sensor;
mod set;
pub mod sim_scene;
mod stream;

pub use elevation_map::ElevationMap;
pub use mount::SensorFrame;
pub use sensor::{Channel, Sensor, StreamFormat};
pub use set::{SensorSet, build};
pub use stream::{LogData, Reading, SensorStream, Values};
