//! A vehicle's `[[sensors]]` table: one entry per sensor, its kind, where it is mounted and at
//! what rate it updates, and the keys of its kind. Every key but `name` and `kind` is optional;
//! which keys a kind takes, their defaults and their units are checked in
//! `crate::model::compile_sensor` (a key of another kind is refused, naming the kind's keys).
//! `docs/SENSORS.md` lists every key.

use serde::{Deserialize, Serialize};

/// One `[[sensors]]` entry.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SensorSpec {
    /// Name: 1 to 64 ASCII letters, digits, `_` or `-` (it names the sensor's output file).
    pub name: String,
    /// `imu`, `encoders`, `lidar`, `depth_camera` or `elevation_map`.
    pub kind: String,
    /// The link it is fixed to: `"body"` (default) or a flipper's name.
    #[serde(default)]
    pub mount: Option<String>,
    /// Position of the sensor frame's origin in the mount's frame, m (default 0).
    #[serde(default)]
    pub xyz_m: Option<[f64; 3]>,
    /// Orientation of the sensor frame in the mount's frame: roll, pitch, yaw about the fixed
    /// x, y, z axes (REP 103), degrees (default 0: x forward, y left, z up).
    #[serde(default)]
    pub rpy_deg: Option<[f64; 3]>,
    /// Update rate, Hz (at most one update per physics step).
    #[serde(default)]
    pub rate_hz: Option<f64>,

    /// IMU: accelerometer white noise density, m/s^2/sqrt(Hz) (default 0).
    #[serde(default)]
    pub accel_noise_density: Option<f64>,
    /// IMU: accelerometer bias random walk, m/s^3/sqrt(Hz) (default 0).
    #[serde(default)]
    pub accel_bias_random_walk: Option<f64>,
    /// IMU: gyroscope white noise density, rad/s/sqrt(Hz) (default 0).
    #[serde(default)]
    pub gyro_noise_density: Option<f64>,
    /// IMU: gyroscope bias random walk, rad/s^2/sqrt(Hz) (default 0).
    #[serde(default)]
    pub gyro_bias_random_walk: Option<f64>,

    /// Encoders: belt position resolution, m (default 0: exact).
    #[serde(default)]
    pub belt_resolution_m: Option<f64>,
    /// Encoders: flipper angle resolution, degrees (default 0: exact).
    #[serde(default)]
    pub angle_resolution_deg: Option<f64>,

    /// Lidar: rays over azimuth per scan line.
    #[serde(default)]
    pub azimuth_rays: Option<usize>,
    /// Lidar: azimuth field of view, degrees, centred on the sensor's x axis (default 360).
    #[serde(default)]
    pub azimuth_fov_deg: Option<f64>,
    /// Lidar: scan lines over elevation (default 1: a 2-D scanner).
    #[serde(default)]
    pub elevation_rays: Option<usize>,
    /// Lidar: elevation field of view, degrees, centred on the sensor's x-y plane (default 0).
    #[serde(default)]
    pub elevation_fov_deg: Option<f64>,
    /// Lidar, depth camera: nearest range reported, m (lidar default 0.05, camera 0.05).
    #[serde(default)]
    pub min_range_m: Option<f64>,
    /// Lidar, depth camera: farthest range reported, m (lidar default 10, camera 5).
    #[serde(default)]
    pub max_range_m: Option<f64>,
    /// Lidar, depth camera: standard deviation of the range (depth) noise, m (default 0).
    #[serde(default)]
    pub range_noise_m: Option<f64>,

    /// Depth and colour cameras: image width, pixels.
    #[serde(default)]
    pub width_px: Option<usize>,
    /// Depth and colour cameras: image height, pixels.
    #[serde(default)]
    pub height_px: Option<usize>,
    /// Depth and colour cameras: horizontal field of view, degrees (default 90; the vertical one follows
    /// from the image's aspect with square pixels).
    #[serde(default)]
    pub horizontal_fov_deg: Option<f64>,

    /// Elevation map: size along the body's heading and across it, m (default [2, 2]).
    #[serde(default)]
    pub size_m: Option<[f64; 2]>,
    /// Elevation map: cell size, m (default 2/64).
    #[serde(default)]
    pub resolution_m: Option<f64>,
    /// Elevation map: how far above the sensor the terrain is looked for, m (default 1).
    #[serde(default)]
    pub height_above_m: Option<f64>,
    /// Elevation map: how far below the sensor, m (default 2).
    #[serde(default)]
    pub depth_below_m: Option<f64>,
    /// Elevation map: cells the sensor cannot see (the line from the sensor to the cell's
    /// surface is blocked) are NaN (default false: every cell is known).
    #[serde(default)]
    pub occlusion: Option<bool>,

    /// Colour camera: standard deviation of the Gaussian noise added to each channel of each
    /// pixel, 8-bit levels (default 0).
    #[serde(default)]
    pub pixel_noise: Option<f64>,
    /// Colour camera: shadow rays towards the sun (default true).
    #[serde(default)]
    pub shadows: Option<bool>,
    /// Colour camera: threads its rows are rendered on (default 1; 0: every core). The image
    /// is the same whatever the count.
    #[serde(default)]
    pub threads: Option<usize>,

    /// Any kind but encoders: the frame its ROS messages are in (`header.frame_id`; for a
    /// camera its optical frame), as a ROS driver's `frame_id` parameter sets it (default
    /// `<name>_link`, a camera's `<name>_optical_frame`). A ROS name: letters, digits and `_`,
    /// not starting with a digit, `/` between tokens (not leading).
    #[serde(default)]
    pub frame_id: Option<String>,
}
