//! A compiled sensor (`[[sensors]]`): its kind with its parameters in SI units, where it is
//! mounted and its rate. `compile_sensor.rs` checks and builds them; `crate::sensors` runs them.

use glam::{DQuat, DVec3};

/// The link a sensor is fixed to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mount {
    /// The chassis (its frame: the vehicle file's body frame).
    Body,
    /// Flipper `i` (its frame: the body frame at flipper angle 0, turning with the flipper).
    Flipper(usize),
}

/// An IMU's noise (datasheet units; all 0: a perfect IMU).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImuModel {
    /// Accelerometer white noise density, m/s^2/sqrt(Hz).
    pub accel_noise_density: f64,
    /// Accelerometer bias random walk, m/s^3/sqrt(Hz).
    pub accel_bias_random_walk: f64,
    /// Gyroscope white noise density, rad/s/sqrt(Hz).
    pub gyro_noise_density: f64,
    /// Gyroscope bias random walk, rad/s^2/sqrt(Hz).
    pub gyro_bias_random_walk: f64,
}

/// Track and flipper encoders.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EncodersModel {
    /// Belt position resolution, m (0: exact).
    pub belt_resolution: f64,
    /// Flipper angle resolution, rad (0: exact).
    pub angle_resolution: f64,
}

/// A scanning lidar: rays over azimuth x elevation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LidarModel {
    /// Rays per scan line.
    pub azimuth_rays: usize,
    /// Azimuth field of view, rad (2 pi: a full turn, the last ray not repeating the first).
    pub azimuth_fov: f64,
    /// Scan lines.
    pub elevation_rays: usize,
    /// Elevation field of view, rad.
    pub elevation_fov: f64,
    /// Nearest range reported, m.
    pub min_range: f64,
    /// Farthest range reported, m.
    pub max_range: f64,
    /// Range noise standard deviation, m.
    pub range_noise: f64,
}

/// A pinhole depth camera looking along the sensor's x axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthCameraModel {
    /// Image width, pixels.
    pub width: usize,
    /// Image height, pixels.
    pub height: usize,
    /// Horizontal field of view, rad.
    pub horizontal_fov: f64,
    /// Nearest depth reported, m.
    pub min_range: f64,
    /// Farthest depth reported, m.
    pub max_range: f64,
    /// Depth noise standard deviation, m.
    pub range_noise: f64,
}

/// A colour camera: a pinhole camera looking along the sensor's x axis, ray traced
/// (`crate::render`), with the depth of each pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RgbCameraModel {
    /// The image: width, height (pixels) and horizontal field of view (rad).
    pub intrinsics: crate::render::Intrinsics,
    /// Nearest depth reported, m (nearer: `-inf`).
    pub min_range: f64,
    /// Farthest surface seen, m (beyond: the sky or the far ground; depth `+inf`).
    pub max_range: f64,
    /// Gaussian noise per channel and pixel, 8-bit levels (standard deviation).
    pub pixel_noise: f64,
    /// Shadow rays towards the sun.
    pub shadows: bool,
    /// Threads to render on (0: every core).
    pub threads: usize,
}

/// A body-yaw-aligned grid of terrain heights around the sensor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ElevationMapModel {
    /// Cells along the heading (x) and across it (y).
    pub cells: [usize; 2],
    /// Cell size, m.
    pub resolution: f64,
    /// Terrain looked for from this far above the sensor, m.
    pub height_above: f64,
    /// down to this far below it, m.
    pub depth_below: f64,
    /// Cells the sensor cannot see are NaN.
    pub occlusion: bool,
}

/// What a sensor measures, with its parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SensorKind {
    /// Specific force, angular rate and orientation.
    Imu(ImuModel),
    /// Belt positions and speeds, flipper angles.
    Encoders(EncodersModel),
    /// Ranges and hit points over azimuth x elevation.
    Lidar(LidarModel),
    /// A depth image.
    DepthCamera(DepthCameraModel),
    /// A colour image (rgb8) and its depth.
    RgbCamera(RgbCameraModel),
    /// Terrain heights relative to the sensor.
    ElevationMap(ElevationMapModel),
}

impl SensorKind {
    /// The kind's name in files (`kind = "..."`).
    pub fn name(&self) -> &'static str {
        match self {
            SensorKind::Imu(_) => "imu",
            SensorKind::Encoders(_) => "encoders",
            SensorKind::Lidar(_) => "lidar",
            SensorKind::DepthCamera(_) => "depth_camera",
            SensorKind::RgbCamera(_) => "rgb_camera",
            SensorKind::ElevationMap(_) => "elevation_map",
        }
    }
}

/// A compiled `[[sensors]]` entry.
#[derive(Clone, Debug, PartialEq)]
pub struct SensorModel {
    /// Name (unique on the vehicle).
    pub name: String,
    /// The link it is fixed to.
    pub mount: Mount,
    /// Position of the sensor frame in the mount's frame, m.
    pub position: DVec3,
    /// Orientation of the sensor frame in the mount's frame.
    pub rotation: DQuat,
    /// Update rate, Hz.
    pub rate_hz: f64,
    /// Kind and parameters.
    pub kind: SensorKind,
    /// The frame of its ROS messages if the file names one (`frame_id`; `None`: the default
    /// names, see `crate::output::ros_sensors::message_frame`).
    pub frame_id: Option<String>,
}
