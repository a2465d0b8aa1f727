//! Checking and compiling a vehicle's `[[sensors]]` into [`SensorModel`]s, in named stages: the
//! common keys (name, mount, pose, rate), the keys of the kind (a key of another kind is refused
//! with the kind's keys listed), then the kind's parameters with their defaults and limits.

use super::sensor::{
    DepthCameraModel, ElevationMapModel, EncodersModel, ImuModel, LidarModel, Mount,
    RgbCameraModel, SensorKind, SensorModel,
};
use crate::check::{Checker, unknown_name, v3};
use crate::spec::SensorSpec;
use glam::{DQuat, EulerRot};

/// Most rays (lidar rays, camera pixels, elevation cells) one sensor casts per update: a
/// 1024 x 1024 image. More would take seconds per update.
pub const MAX_RAYS: usize = 1 << 20;
/// Longest range a ray sensor may have, m.
pub const MAX_SENSOR_RANGE_M: f64 = 1000.0;
/// Highest rate a sensor may have, Hz (the step limits it further: at most one update per
/// physics step, checked with the scenario's `dt_s`).
pub const MAX_RATE_HZ: f64 = 100_000.0;

/// The kinds, as written in files.
pub const SENSOR_KINDS: &[&str] = &[
    "imu",
    "encoders",
    "lidar",
    "depth_camera",
    "rgb_camera",
    "elevation_map",
];

/// Keys every kind takes.
const COMMON_KEYS: &[&str] = &[
    "name", "kind", "mount", "xyz_m", "rpy_deg", "rate_hz", "frame_id",
];

/// The keys of a kind beyond [`COMMON_KEYS`].
fn kind_keys(kind: &str) -> &'static [&'static str] {
    match kind {
        "imu" => &[
            "accel_noise_density",
            "accel_bias_random_walk",
            "gyro_noise_density",
            "gyro_bias_random_walk",
        ],
        "encoders" => &["belt_resolution_m", "angle_resolution_deg"],
        "lidar" => &[
            "azimuth_rays",
            "azimuth_fov_deg",
            "elevation_rays",
            "elevation_fov_deg",
            "min_range_m",
            "max_range_m",
            "range_noise_m",
        ],
        "depth_camera" => &[
            "width_px",
            "height_px",
            "horizontal_fov_deg",
            "min_range_m",
            "max_range_m",
            "range_noise_m",
        ],
        "rgb_camera" => &[
            "width_px",
            "height_px",
            "horizontal_fov_deg",
            "min_range_m",
            "max_range_m",
            "pixel_noise",
            "shadows",
            "threads",
        ],
        "elevation_map" => &[
            "size_m",
            "resolution_m",
            "height_above_m",
            "depth_below_m",
            "occlusion",
        ],
        _ => &[],
    }
}

/// The kind-specific keys a spec sets (`Some`).
fn keys_given(s: &SensorSpec) -> Vec<&'static str> {
    let given = [
        ("accel_noise_density", s.accel_noise_density.is_some()),
        ("accel_bias_random_walk", s.accel_bias_random_walk.is_some()),
        ("gyro_noise_density", s.gyro_noise_density.is_some()),
        ("gyro_bias_random_walk", s.gyro_bias_random_walk.is_some()),
        ("belt_resolution_m", s.belt_resolution_m.is_some()),
        ("angle_resolution_deg", s.angle_resolution_deg.is_some()),
        ("azimuth_rays", s.azimuth_rays.is_some()),
        ("azimuth_fov_deg", s.azimuth_fov_deg.is_some()),
        ("elevation_rays", s.elevation_rays.is_some()),
        ("elevation_fov_deg", s.elevation_fov_deg.is_some()),
        ("min_range_m", s.min_range_m.is_some()),
        ("max_range_m", s.max_range_m.is_some()),
        ("range_noise_m", s.range_noise_m.is_some()),
        ("width_px", s.width_px.is_some()),
        ("height_px", s.height_px.is_some()),
        ("horizontal_fov_deg", s.horizontal_fov_deg.is_some()),
        ("size_m", s.size_m.is_some()),
        ("resolution_m", s.resolution_m.is_some()),
        ("height_above_m", s.height_above_m.is_some()),
        ("depth_below_m", s.depth_below_m.is_some()),
        ("occlusion", s.occlusion.is_some()),
        ("pixel_noise", s.pixel_noise.is_some()),
        ("shadows", s.shadows.is_some()),
        ("threads", s.threads.is_some()),
    ];
    given.iter().filter(|(_, g)| *g).map(|(k, _)| *k).collect()
}

/// The node's and the recording's own topics of one segment (`/odom`, `/course`, ... in
/// `crate::ros::topics` and `run.mcap`): a sensor's readings go on `/<name>`, so a sensor may
/// not be named after one of them.
pub const RESERVED_SENSOR_NAMES: &[&str] = &[
    "cmd_vel",
    "clock",
    "odom",
    "tf",
    "tf_static",
    "joint_states",
    "tracks",
    "robot_description",
    "course",
    "scene",
    "soil",
    "rosout",
    "parameter_events",
];

/// Compiles every `[[sensors]]` entry; problems go to `c` with their key paths.
pub(crate) fn compile_sensors(
    c: &mut Checker,
    specs: &[SensorSpec],
    mounts: &super::mounts::Mounts,
) -> Vec<SensorModel> {
    let mut out = Vec::new();
    for (i, s) in specs.iter().enumerate() {
        let k = format!("sensors[{i}]");
        c.column_name(&format!("{k}.name"), &s.name);
        if specs[..i].iter().any(|o| o.name == s.name) {
            c.push(
                format!("{k}.name"),
                format!(
                    "duplicate sensor name \"{}\": each names its output file",
                    s.name
                ),
            );
        }
        if RESERVED_SENSOR_NAMES.contains(&s.name.replace('-', "_").as_str()) {
            c.push(
                format!("{k}.name"),
                format!(
                    "sensor name \"{}\" is a topic of the robot's own (its readings go on \
                     /<name> under `tracksim ros` and in run.mcap): rename the sensor, e.g. \
                     \"{}_sensor\"",
                    s.name, s.name
                ),
            );
        }
        if !SENSOR_KINDS.contains(&s.kind.as_str()) {
            c.push(
                format!("{k}.kind"),
                unknown_name("kind", &s.kind, SENSOR_KINDS),
            );
            continue;
        }
        let allowed = kind_keys(&s.kind);
        for key in keys_given(s) {
            if !allowed.contains(&key) {
                let mut all: Vec<&str> = COMMON_KEYS.to_vec();
                all.extend_from_slice(allowed);
                c.push(
                    format!("{k}.{key}"),
                    format!(
                        "is not a key of a `{}` sensor; it takes: {}",
                        s.kind,
                        all.iter()
                            .map(|a| format!("`{a}`"))
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                );
            }
        }
        if let Some(m) = sensor(c, &k, s, mounts) {
            out.push(m);
        }
    }
    out
}

/// The common keys, then the kind's parameters.
fn sensor(
    c: &mut Checker,
    k: &str,
    s: &SensorSpec,
    mounts: &super::mounts::Mounts,
) -> Option<SensorModel> {
    let name = s.mount.as_deref().unwrap_or("body");
    let (parent, frame) = mounts.resolve(c, &format!("{k}.mount"), "mount", name);
    let mount = match parent {
        super::Parent::Body => Mount::Body,
        super::Parent::Flipper(j) => Mount::Flipper(j),
    };
    let xyz = s.xyz_m.unwrap_or([0.0; 3]);
    c.finite(&format!("{k}.xyz_m"), &xyz);
    let rpy = s.rpy_deg.unwrap_or([0.0; 3]);
    for (j, a) in rpy.iter().enumerate() {
        c.bounded(&format!("{k}.rpy_deg[{j}]"), *a, 360.0, "deg");
    }
    let (r, p, y) = (
        rpy[0].to_radians(),
        rpy[1].to_radians(),
        rpy[2].to_radians(),
    );
    let rotation = DQuat::from_euler(EulerRot::ZYX, y, p, r);
    let default_rate = match s.kind.as_str() {
        "imu" => 200.0,
        "encoders" => 100.0,
        "elevation_map" => 20.0,
        _ => 10.0,
    };
    let rate_hz = s.rate_hz.unwrap_or(default_rate);
    c.positive(&format!("{k}.rate_hz"), rate_hz, "Hz");
    if rate_hz > MAX_RATE_HZ {
        c.push(
            format!("{k}.rate_hz"),
            format!("must be at most {MAX_RATE_HZ} Hz, got {rate_hz}"),
        );
    }
    let kind = match s.kind.as_str() {
        "imu" => SensorKind::Imu(imu(c, k, s)),
        "encoders" => SensorKind::Encoders(encoders(c, k, s)),
        "lidar" => SensorKind::Lidar(lidar(c, k, s)),
        "depth_camera" => SensorKind::DepthCamera(depth_camera(c, k, s)),
        "rgb_camera" => SensorKind::RgbCamera(rgb_camera(c, k, s)),
        _ => SensorKind::ElevationMap(elevation_map(c, k, s)),
    };
    let frame_id = s.frame_id.clone();
    if let Some(f) = &frame_id {
        if let Some(why) = frame_id_problem(f) {
            c.push(format!("{k}.frame_id"), why);
        }
        if s.kind == "encoders" {
            c.push(
                format!("{k}.frame_id"),
                "encoders have no frame (their readings are joint states)".to_string(),
            );
        }
    }
    Some(SensorModel {
        frame_id,
        name: s.name.clone(),
        mount,
        position: frame.transform_point3(v3(xyz)),
        rotation: glam::DQuat::from_mat3(&frame.matrix3) * rotation,
        rate_hz,
        kind,
    })
}

/// Why `f` is not a valid ROS frame id (tf2: a ROS name without a leading `/`): tokens of
/// ASCII letters, digits and `_`, none starting with a digit, joined by single `/`.
pub fn frame_id_problem(f: &str) -> Option<String> {
    let ok = !f.is_empty()
        && f.len() <= 256
        && f.split('/').all(|t| {
            t.chars()
                .next()
                .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
                && t.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        });
    (!ok).then(|| {
        format!(
            "`{f}` is not a ROS frame id: letters, digits and `_` (not starting with a digit), \
             with single `/` between such names and none leading or trailing"
        )
    })
}

/// A non-negative value of key `key` with default 0.
fn noise(c: &mut Checker, k: &str, key: &str, v: Option<f64>, unit: &str) -> f64 {
    let v = v.unwrap_or(0.0);
    c.non_negative(&format!("{k}.{key}"), v, unit);
    v
}

fn imu(c: &mut Checker, k: &str, s: &SensorSpec) -> ImuModel {
    ImuModel {
        accel_noise_density: noise(
            c,
            k,
            "accel_noise_density",
            s.accel_noise_density,
            "m/s^2/sqrt(Hz)",
        ),
        accel_bias_random_walk: noise(
            c,
            k,
            "accel_bias_random_walk",
            s.accel_bias_random_walk,
            "m/s^3/sqrt(Hz)",
        ),
        gyro_noise_density: noise(
            c,
            k,
            "gyro_noise_density",
            s.gyro_noise_density,
            "rad/s/sqrt(Hz)",
        ),
        gyro_bias_random_walk: noise(
            c,
            k,
            "gyro_bias_random_walk",
            s.gyro_bias_random_walk,
            "rad/s^2/sqrt(Hz)",
        ),
    }
}

fn encoders(c: &mut Checker, k: &str, s: &SensorSpec) -> EncodersModel {
    EncodersModel {
        belt_resolution: noise(c, k, "belt_resolution_m", s.belt_resolution_m, "m"),
        angle_resolution: noise(c, k, "angle_resolution_deg", s.angle_resolution_deg, "deg")
            .to_radians(),
    }
}

/// A field of view in degrees, in (`lo`, `hi`] (or [0, `hi`] when `zero_ok`).
fn fov(c: &mut Checker, key: &str, v: f64, hi: f64, zero_ok: bool) -> f64 {
    let ok = v.is_finite() && v <= hi && (v > 0.0 || (zero_ok && v == 0.0));
    if !ok {
        let lo = if zero_ok { "0 <=" } else { "0 <" };
        c.push(
            key,
            format!("must be a field of view with {lo} angle <= {hi} deg, got {v}"),
        );
    }
    v.to_radians()
}

/// A count of rays in 1..=[`MAX_RAYS`] with key `key`.
fn count(c: &mut Checker, key: &str, v: Option<usize>, default: Option<usize>) -> usize {
    match v.or(default) {
        None => {
            c.push(key, "is required for this kind");
            1
        }
        Some(n) if n == 0 || n > MAX_RAYS => {
            c.push(key, format!("must be between 1 and {MAX_RAYS}, got {n}"));
            1
        }
        Some(n) => n,
    }
}

/// Nearest and farthest range with their checks.
fn ranges(c: &mut Checker, k: &str, s: &SensorSpec, max_default: f64) -> (f64, f64) {
    let min = s.min_range_m.unwrap_or(0.05);
    let max = s.max_range_m.unwrap_or(max_default);
    c.non_negative(&format!("{k}.min_range_m"), min, "m");
    c.positive(&format!("{k}.max_range_m"), max, "m");
    if max > MAX_SENSOR_RANGE_M {
        c.push(
            format!("{k}.max_range_m"),
            format!("must be at most {MAX_SENSOR_RANGE_M} m, got {max}"),
        );
    }
    if min.is_finite() && max.is_finite() && min >= max {
        c.push(
            format!("{k}.max_range_m"),
            format!("must be larger than min_range_m ({min} m), got {max}"),
        );
    }
    (min, max)
}

/// The product of ray counts stays within [`MAX_RAYS`].
fn total_rays(c: &mut Checker, key: &str, n: usize, what: &str) {
    if n > MAX_RAYS {
        c.push(
            key,
            format!("{n} {what} per update is more than the {MAX_RAYS} a sensor may cast"),
        );
    }
}

fn lidar(c: &mut Checker, k: &str, s: &SensorSpec) -> LidarModel {
    let az = count(c, &format!("{k}.azimuth_rays"), s.azimuth_rays, None);
    let el = count(c, &format!("{k}.elevation_rays"), s.elevation_rays, Some(1));
    total_rays(
        c,
        &format!("{k}.elevation_rays"),
        az.saturating_mul(el),
        "rays",
    );
    let azimuth_fov = fov(
        c,
        &format!("{k}.azimuth_fov_deg"),
        s.azimuth_fov_deg.unwrap_or(360.0),
        360.0,
        false,
    );
    let elevation_fov = fov(
        c,
        &format!("{k}.elevation_fov_deg"),
        s.elevation_fov_deg.unwrap_or(0.0),
        180.0,
        el == 1,
    );
    let (min_range, max_range) = ranges(c, k, s, 10.0);
    LidarModel {
        azimuth_rays: az,
        azimuth_fov,
        elevation_rays: el,
        elevation_fov,
        min_range,
        max_range,
        range_noise: noise(c, k, "range_noise_m", s.range_noise_m, "m"),
    }
}

/// A camera's image keys: width and height (pixels) and horizontal field of view (rad).
fn image(c: &mut Checker, k: &str, s: &SensorSpec) -> (usize, usize, f64) {
    let w = count(c, &format!("{k}.width_px"), s.width_px, None);
    let h = count(c, &format!("{k}.height_px"), s.height_px, None);
    total_rays(c, &format!("{k}.height_px"), w.saturating_mul(h), "pixels");
    let horizontal_fov = fov(
        c,
        &format!("{k}.horizontal_fov_deg"),
        s.horizontal_fov_deg.unwrap_or(90.0),
        170.0,
        false,
    );
    (w, h, horizontal_fov)
}

fn depth_camera(c: &mut Checker, k: &str, s: &SensorSpec) -> DepthCameraModel {
    let (width, height, horizontal_fov) = image(c, k, s);
    let (min_range, max_range) = ranges(c, k, s, 5.0);
    DepthCameraModel {
        width,
        height,
        horizontal_fov,
        min_range,
        max_range,
        range_noise: noise(c, k, "range_noise_m", s.range_noise_m, "m"),
    }
}

/// Most threads a colour camera may ask for.
const MAX_RENDER_THREADS: usize = 256;

fn rgb_camera(c: &mut Checker, k: &str, s: &SensorSpec) -> RgbCameraModel {
    let (width, height, horizontal_fov) = image(c, k, s);
    let (min_range, max_range) = ranges(c, k, s, 30.0);
    let pixel_noise = s.pixel_noise.unwrap_or(0.0);
    if !(pixel_noise.is_finite() && (0.0..=255.0).contains(&pixel_noise)) {
        c.push(
            format!("{k}.pixel_noise"),
            format!("must be 0 to 255 (8-bit levels), got {pixel_noise}"),
        );
    }
    let threads = s.threads.unwrap_or(1);
    if threads > MAX_RENDER_THREADS {
        c.push(
            format!("{k}.threads"),
            format!("must be 0 (every core) to {MAX_RENDER_THREADS}, got {threads}"),
        );
    }
    RgbCameraModel {
        intrinsics: crate::render::Intrinsics {
            width,
            height,
            horizontal_fov,
        },
        min_range,
        max_range,
        pixel_noise,
        shadows: s.shadows.unwrap_or(true),
        threads,
    }
}

fn elevation_map(c: &mut Checker, k: &str, s: &SensorSpec) -> ElevationMapModel {
    let size = s.size_m.unwrap_or([2.0, 2.0]);
    let resolution = s.resolution_m.unwrap_or(2.0 / 64.0);
    c.positive(&format!("{k}.resolution_m"), resolution, "m");
    let mut cells = [1usize; 2];
    for (j, v) in size.iter().enumerate() {
        let key = format!("{k}.size_m[{j}]");
        c.positive(&key, *v, "m");
        if v.is_finite() && *v > 0.0 && resolution.is_finite() && resolution > 0.0 {
            let n = (v / resolution).round();
            if n < 1.0 || n > MAX_RAYS as f64 {
                c.push(
                    key,
                    format!("gives {n} cells of {resolution} m; it must give 1 to {MAX_RAYS}"),
                );
            } else {
                cells[j] = n as usize;
            }
        }
    }
    total_rays(
        c,
        &format!("{k}.resolution_m"),
        cells[0].saturating_mul(cells[1]),
        "cells",
    );
    let height_above = s.height_above_m.unwrap_or(1.0);
    let depth_below = s.depth_below_m.unwrap_or(2.0);
    c.non_negative(&format!("{k}.height_above_m"), height_above, "m");
    c.positive(&format!("{k}.depth_below_m"), depth_below, "m");
    for (key, v) in [
        ("height_above_m", height_above),
        ("depth_below_m", depth_below),
    ] {
        if v > MAX_SENSOR_RANGE_M {
            c.push(
                format!("{k}.{key}"),
                format!("must be at most {MAX_SENSOR_RANGE_M} m, got {v}"),
            );
        }
    }
    ElevationMapModel {
        cells,
        resolution,
        height_above,
        depth_below,
        occlusion: s.occlusion.unwrap_or(false),
    }
}
