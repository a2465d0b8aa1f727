//! A finished run read back from its folder: `scene.json` (what to draw: the subset of
//! [`crate::output::replay::Scene`] a video needs, every colour optional so that folders written
//! before colours were recorded still read, with the palette's defaults), `trajectory.csv` (the
//! pose, speed and flipper angles at every output sample), `belts.csv` (belt and conveyor
//! positions, loose boxes' poses) and `summary.json` (outcome, course score and events).
//!
//! [`Recording::state_at`] gives the state at any time by linear interpolation between the two
//! samples around it (orientation by spherical interpolation).

use crate::error::{Error, Result};
use crate::render::{Rgb, palette};
use glam::{DQuat, DVec3, EulerRot};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// A triangle mesh of `scene.json`: flat x y z (m) and flat triangle indices.
#[derive(Clone, Debug, Default, Deserialize)]
pub struct MeshIn {
    /// x0 y0 z0 x1 ..., m.
    #[serde(default)]
    pub vertices_m: Vec<f32>,
    /// Three indices per triangle.
    #[serde(default)]
    pub triangles: Vec<u32>,
}

/// A terrain box.
#[derive(Clone, Debug, Deserialize)]
pub struct BoxIn {
    /// Centre, m.
    pub centre_m: [f64; 3],
    /// Half extents, m.
    pub half_m: [f64; 3],
    /// Orientation, x y z w.
    pub quat_xyzw: [f64; 4],
    /// `"#rrggbb"` (absent in older folders).
    pub color: Option<String>,
}

/// A terrain cylinder, its axis along y turned by `yaw_rad` about z.
#[derive(Clone, Debug, Deserialize)]
pub struct CylinderIn {
    /// Centre, m.
    pub centre_m: [f64; 3],
    /// Yaw of the axis, rad.
    pub yaw_rad: f64,
    /// Half length, m.
    pub half_length_m: f64,
    /// Radius, m.
    pub radius_m: f64,
    /// `"#rrggbb"` (absent in older folders).
    pub color: Option<String>,
}

/// The terrain.
#[derive(Clone, Debug, Default, Deserialize)]
pub struct TerrainIn {
    /// Height of the flat ground, m.
    pub ground_z_m: Option<f64>,
    /// Boxes.
    #[serde(default)]
    pub boxes: Vec<BoxIn>,
    /// Cylinders.
    #[serde(default)]
    pub cylinders: Vec<CylinderIn>,
    /// Meshes and height fields, world frame.
    #[serde(default)]
    pub meshes: Vec<MeshIn>,
    /// The ground's colour.
    pub ground_color: Option<String>,
    /// The meshes' colours, in order.
    #[serde(default)]
    pub mesh_colors: Vec<String>,
}

/// A flipper arm.
#[derive(Clone, Debug, Deserialize)]
pub struct FlipperIn {
    /// Name (its column `flipper_NAME_rad`).
    pub name: String,
    /// Pivot, m (body frame).
    pub pivot_m: [f64; 3],
    /// Unit axis (body frame).
    pub axis: [f64; 3],
    /// Initial angle, rad.
    #[serde(default)]
    pub initial_angle_rad: f64,
    /// Arm shape at angle 0 (body frame).
    pub mesh: Option<MeshIn>,
}

/// Grousers of a track.
#[derive(Clone, Debug, Deserialize)]
pub struct GrousersIn {
    /// Number of grousers.
    pub count: usize,
    /// Arc length of grouser 0 at rest, m.
    pub offset_m: f64,
    /// Pitch, m.
    pub pitch_m: f64,
    /// Shapes used in turn (footprint frame: x along the belt, y lateral, z outwards).
    pub shapes: Vec<MeshIn>,
}

/// A track's loop sampled by arc length (parent frame).
#[derive(Clone, Debug, Deserialize)]
pub struct TrackIn {
    /// Name (its column `belt_position_NAME_m`).
    pub name: String,
    /// Flipper it hangs on, -1 for the chassis.
    pub parent: i64,
    /// Belt width, m.
    pub width_m: f64,
    /// Loop length, m.
    pub length_m: f64,
    /// Unit loop axis.
    pub lateral: [f64; 3],
    /// Points on the path, flat x y z, m.
    pub points_m: Vec<f64>,
    /// Unit outward normals, flat.
    pub normals: Vec<f64>,
    /// Per-sample lateral axes of a loop that leaves its plane.
    pub laterals: Option<Vec<f64>>,
    /// Grousers.
    pub grousers: Option<GrousersIn>,
}

/// Colours of a vehicle's parts.
#[derive(Clone, Debug, Default, Deserialize)]
pub struct VehicleColorsIn {
    /// Chassis.
    pub body: Option<String>,
    /// Belts and grousers.
    pub tracks: Option<String>,
    /// Flipper arms.
    pub flippers: Option<String>,
}

/// The vehicle (body frame).
#[derive(Clone, Debug, Deserialize)]
pub struct VehicleIn {
    /// Name.
    #[serde(default)]
    pub name: String,
    /// Chassis shape.
    pub body: MeshIn,
    /// Flippers.
    #[serde(default)]
    pub flippers: Vec<FlipperIn>,
    /// Tracks.
    #[serde(default)]
    pub tracks: Vec<TrackIn>,
    /// Colours (absent in older folders).
    #[serde(default)]
    pub colors: VehicleColorsIn,
}

/// A conveyor: its belt in its own frame.
#[derive(Clone, Debug, Deserialize)]
pub struct ConveyorIn {
    /// Origin of its frame, m.
    pub centre_m: [f64; 3],
    /// Yaw of its frame, rad.
    pub yaw_rad: f64,
    /// The belt.
    pub track: TrackIn,
}

/// A loose box.
#[derive(Clone, Debug, Deserialize)]
pub struct LooseBoxIn {
    /// Half extents, m.
    pub half_m: [f64; 3],
    /// Centre at the start, m.
    pub centre_m: [f64; 3],
    /// Yaw at the start, rad.
    pub yaw_rad: f64,
    /// `"#rrggbb"` (absent in older folders).
    pub color: Option<String>,
}

/// A camera's image as `scene.json` gives it.
#[derive(Clone, Debug, Deserialize)]
pub struct CameraImageIn {
    /// Horizontal field of view, rad.
    pub horizontal_fov_rad: f64,
    /// Farthest depth, m.
    pub max_range_m: f64,
}

/// A sensor of the vehicle: where it sits.
#[derive(Clone, Debug, Deserialize)]
pub struct SensorIn {
    /// Name.
    pub name: String,
    /// Kind.
    pub kind: String,
    /// Flipper index it is mounted on, -1 for the body.
    #[serde(default = "minus_one")]
    pub mount_index: i64,
    /// Origin in the mount frame, m.
    pub xyz_m: [f64; 3],
    /// Orientation in the mount frame, x y z w.
    pub quat_xyzw: [f64; 4],
    /// A depth camera's image.
    pub depth_camera: Option<CameraImageIn>,
    /// A colour camera's image.
    pub rgb_camera: Option<CameraImageIn>,
}

fn minus_one() -> i64 {
    -1
}

/// `scene.json`, what a video draws.
#[derive(Clone, Debug, Deserialize)]
pub struct SceneIn {
    /// Terrain.
    #[serde(default)]
    pub terrain: TerrainIn,
    /// Vehicle.
    pub vehicle: VehicleIn,
    /// Conveyors.
    #[serde(default)]
    pub conveyors: Vec<ConveyorIn>,
    /// Loose boxes.
    #[serde(default)]
    pub loose_boxes: Vec<LooseBoxIn>,
    /// Sensors.
    #[serde(default)]
    pub sensors: Vec<SensorIn>,
    /// The course, if any (its name).
    pub course: Option<serde_json::Value>,
}

/// A colour of the files, or `default` where absent or not `"#rrggbb"`.
pub fn color_or(c: Option<&str>, default: Rgb) -> Rgb {
    c.and_then(Rgb::parse).unwrap_or(default)
}

impl SceneIn {
    /// The vehicle's colours (body, tracks, flippers).
    pub fn vehicle_colors(&self) -> [Rgb; 3] {
        let c = &self.vehicle.colors;
        [
            color_or(c.body.as_deref(), palette::BODY),
            color_or(c.tracks.as_deref(), palette::TRACK),
            color_or(c.flippers.as_deref(), palette::FLIPPER),
        ]
    }
}

/// A CSV file of numbers with a header row.
#[derive(Clone, Debug, Default)]
pub struct Table {
    /// Column names.
    pub header: Vec<String>,
    /// Rows (empty cells: NaN).
    pub rows: Vec<Vec<f64>>,
}

impl Table {
    /// Reads `path`.
    pub fn read(path: &Path) -> Result<Table> {
        let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let mut lines = text.lines();
        let header: Vec<String> = lines
            .next()
            .unwrap_or("")
            .split(',')
            .map(str::to_string)
            .collect();
        let mut rows = Vec::new();
        for (i, l) in lines.enumerate() {
            if l.trim().is_empty() {
                continue;
            }
            let row: Vec<f64> = l
                .split(',')
                .map(|c| c.trim().parse().unwrap_or(f64::NAN))
                .collect();
            if row.len() != header.len() {
                return Err(invalid(
                    path,
                    &format!("line {}", i + 2),
                    format!(
                        "has {} cells, the header {}: the file is cut or not a tracksim output; run again",
                        row.len(),
                        header.len()
                    ),
                ));
            }
            rows.push(row);
        }
        Ok(Table { header, rows })
    }

    /// The index of column `name`.
    pub fn col(&self, name: &str) -> Option<usize> {
        self.header.iter().position(|h| h == name)
    }
}

fn invalid(path: &Path, key: &str, message: String) -> Error {
    Error::Invalid {
        path: path.to_path_buf(),
        issues: vec![crate::error::SpecIssue::new(key, message)],
    }
}

/// What `summary.json` tells a video: the outcome and the course's events.
#[derive(Clone, Debug, Default)]
pub struct SummaryIn {
    /// `success`, `failure`, ...
    pub outcome: Option<String>,
    /// Why.
    pub outcome_reason: Option<String>,
    /// When it was decided, s.
    pub outcome_time_s: Option<f64>,
    /// The course's gates per repetition and repetitions required.
    pub course_gates: Option<(u64, u64)>,
    /// The course's events: (time s, kind).
    pub course_events: Vec<(f64, String)>,
    /// The course's final score (`score_s`), s.
    pub course_score_s: Option<f64>,
}

impl SummaryIn {
    fn read(path: &Path) -> SummaryIn {
        let Ok(text) = std::fs::read_to_string(path) else {
            return SummaryIn::default();
        };
        let Ok(v) = serde_json::from_str::<serde_json::Value>(&text) else {
            return SummaryIn::default();
        };
        let s = |k: &str| v.get(k).and_then(|x| x.as_str()).map(str::to_string);
        let c = v.get("course").filter(|c| c.is_object());
        SummaryIn {
            outcome: s("outcome"),
            outcome_reason: s("outcome_reason"),
            outcome_time_s: v.get("outcome_time_s").and_then(|x| x.as_f64()),
            course_gates: c.and_then(|c| {
                Some((
                    c.get("gates_total")?.as_u64()?,
                    c.get("repetitions_required")?.as_u64()?,
                ))
            }),
            course_events: c
                .and_then(|c| c.get("events")?.as_array().cloned())
                .unwrap_or_default()
                .iter()
                .filter_map(|e| Some((e.get("t_s")?.as_f64()?, e.get("kind")?.as_str()?.into())))
                .collect(),
            course_score_s: c.and_then(|c| c.get("score")?.get("score_s")?.as_f64()),
        }
    }
}

/// The state of a robot at one time.
#[derive(Clone, Debug, PartialEq)]
pub struct RobotState {
    /// Time, s.
    pub t: f64,
    /// Body origin, m (world).
    pub position: DVec3,
    /// Body orientation.
    pub rotation: DQuat,
    /// Speed of the body origin, m/s.
    pub speed: f64,
    /// Flipper angles, rad, in scene order.
    pub flippers: Vec<f64>,
    /// Unwrapped belt positions, m, in track order.
    pub belts: Vec<f64>,
    /// Conveyor belt positions, m.
    pub conveyors: Vec<f64>,
    /// Loose boxes' poses (centre m, orientation).
    pub boxes: Vec<(DVec3, DQuat)>,
}

/// One robot's run folder, read.
#[derive(Clone, Debug)]
pub struct Recording {
    /// The folder.
    pub dir: PathBuf,
    /// Its robot's name (the folder's name in a team run).
    pub name: String,
    /// `scene.json`.
    pub scene: SceneIn,
    /// `summary.json` (empty if absent).
    pub summary: SummaryIn,
    /// A robot reset during a team run, read over the whole session
    /// ([`Recording::read_session`]): each earlier attempt's first sample time, s, and its
    /// `summary.json`, in order (empty otherwise; [`Recording::summary`] is the last
    /// attempt's).
    pub earlier: Vec<(f64, SummaryIn)>,
    /// The last attempt's first sample time, s.
    pub last_from_s: f64,
    traj: Table,
    belts: Table,
    cols: Cols,
}

#[derive(Clone, Debug, Default)]
struct Cols {
    pose: [usize; 6],
    vel: [usize; 3],
    flippers: Vec<Option<usize>>,
    belts: Vec<Option<usize>>,
    conveyors: Vec<Option<usize>>,
    boxes: Vec<Option<[usize; 6]>>,
}

/// Why `dir` is not a run folder, with the fix.
pub fn missing(dir: &Path, file: &str) -> Error {
    invalid(
        &dir.join(file),
        "",
        format!(
            "not found: {} is not the output folder of a finished run (`tracksim run FILE --out DIR`, `tracksim drive`, an environment's episode folder, a team run's folder); give such a folder (of a `tracksim compare` folder, one method's subfolder)",
            dir.display()
        ),
    )
}

impl Recording {
    /// Reads the run folder `dir`.
    pub fn read(dir: &Path) -> Result<Recording> {
        for f in ["scene.json", "trajectory.csv"] {
            if !dir.join(f).is_file() {
                return Err(missing(dir, f));
            }
        }
        let sp = dir.join("scene.json");
        let text = std::fs::read_to_string(&sp).map_err(|source| Error::Io {
            path: sp.clone(),
            source,
        })?;
        let scene: SceneIn = serde_json::from_str(&text).map_err(|e| Error::Parse {
            path: sp.clone(),
            message: format!("{e} (not a tracksim scene.json: run again to write it)"),
        })?;
        let tp = dir.join("trajectory.csv");
        let traj = Table::read(&tp)?;
        if traj.rows.is_empty() {
            return Err(invalid(
                &tp,
                "",
                "has no samples: the run wrote nothing to show; run it for longer".into(),
            ));
        }
        let bp = dir.join("belts.csv");
        let belts = if bp.is_file() {
            Table::read(&bp)?
        } else {
            Table::default()
        };
        let need = |name: &str| {
            traj.col(name).ok_or_else(|| {
                invalid(
                    &tp,
                    name,
                    "column missing: not a tracksim trajectory.csv; run again to write it".into(),
                )
            })
        };
        let mut pose = [0; 6];
        for (k, n) in ["x_m", "y_m", "z_m", "roll_rad", "pitch_rad", "yaw_rad"]
            .iter()
            .enumerate()
        {
            pose[k] = need(n)?;
        }
        let mut vel = [0; 3];
        for (k, n) in ["vx_mps", "vy_mps", "vz_mps"].iter().enumerate() {
            vel[k] = need(n)?;
        }
        let cols = Cols {
            pose,
            vel,
            flippers: scene
                .vehicle
                .flippers
                .iter()
                .map(|f| traj.col(&format!("flipper_{}_rad", f.name)))
                .collect(),
            belts: scene
                .vehicle
                .tracks
                .iter()
                .map(|t| belts.col(&format!("belt_position_{}_m", t.name)))
                .collect(),
            conveyors: (0..scene.conveyors.len())
                .map(|i| belts.col(&format!("conveyor_position_{i}_m")))
                .collect(),
            boxes: (0..scene.loose_boxes.len())
                .map(|i| {
                    let mut c = [0; 6];
                    for (k, n) in ["x_m", "y_m", "z_m", "roll_rad", "pitch_rad", "yaw_rad"]
                        .iter()
                        .enumerate()
                    {
                        c[k] = belts.col(&format!("box_{i}_{n}"))?;
                    }
                    Some(c)
                })
                .collect(),
        };
        let name = dir
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "run".into());
        Ok(Recording {
            dir: dir.to_path_buf(),
            name,
            summary: SummaryIn::read(&dir.join("summary.json")),
            earlier: Vec::new(),
            last_from_s: traj.rows[0][0],
            scene,
            traj,
            belts,
            cols,
        })
    }

    /// Reads the folder `dir` of a robot of a team run; a robot reset during the session (its
    /// earlier attempts kept in `dir/attempts/N/`, issue 43) over the whole session: the
    /// attempts' samples in order, at the world's times, so that it goes back to its start at
    /// each reset as it did, and each attempt's summary for the times it was under way. The
    /// last attempt alone when an earlier one is not there whole (not written to its end, or
    /// its files of other columns), as `tracksim view` serves it.
    pub fn read_session(dir: &Path) -> Result<Recording> {
        let mut last = Recording::read(dir)?;
        let kept = crate::output::kept_attempts::kept_attempts(dir).unwrap_or_default();
        let mut traj = Vec::new();
        let mut belts = Vec::new();
        let mut earlier = Vec::new();
        for sub in &kept {
            let (Ok(t), Ok(b)) = (
                Table::read(&sub.join("trajectory.csv")),
                Table::read(&sub.join("belts.csv")),
            ) else {
                return Ok(last);
            };
            if t.header != last.traj.header || b.header != last.belts.header || t.rows.is_empty() {
                return Ok(last);
            }
            earlier.push((t.rows[0][0], SummaryIn::read(&sub.join("summary.json"))));
            traj.extend(t.rows);
            belts.extend(b.rows);
        }
        traj.append(&mut last.traj.rows);
        belts.append(&mut last.belts.rows);
        last.traj.rows = traj;
        last.belts.rows = belts;
        last.earlier = earlier;
        Ok(last)
    }

    /// The summary of the attempt under way at time `t` s (the last attempt's at and after its
    /// first sample, and without earlier attempts).
    pub fn summary_at(&self, t: f64) -> &SummaryIn {
        if self.earlier.is_empty() || t + 1e-9 >= self.last_from_s {
            return &self.summary;
        }
        self.earlier
            .iter()
            .rev()
            .find(|(from, _)| *from <= t + 1e-9)
            .or(self.earlier.first())
            .map_or(&self.summary, |(_, s)| s)
    }

    /// Time of the first sample, s.
    pub fn start_s(&self) -> f64 {
        self.traj.rows[0][0]
    }

    /// Time of the last sample, s.
    pub fn end_s(&self) -> f64 {
        self.traj.rows[self.traj.rows.len() - 1][0]
    }

    /// The state at time `t` (clamped to the recording).
    pub fn state_at(&self, t: f64) -> RobotState {
        let (r0, r1, w) = bracket(&self.traj.rows, t);
        let lerp = |c: usize| {
            let (a, b) = (r0[c], r1[c]);
            if a.is_finite() && b.is_finite() {
                a + (b - a) * w
            } else if a.is_finite() {
                a
            } else {
                0.0
            }
        };
        let p = &self.cols.pose;
        let q = |r: &[f64]| DQuat::from_euler(EulerRot::ZYX, r[p[5]], r[p[4]], r[p[3]]);
        let v = DVec3::new(
            lerp(self.cols.vel[0]),
            lerp(self.cols.vel[1]),
            lerp(self.cols.vel[2]),
        );
        let flippers = self
            .cols
            .flippers
            .iter()
            .zip(&self.scene.vehicle.flippers)
            .map(|(c, f)| c.map_or(f.initial_angle_rad, lerp))
            .collect();
        let (b0, b1, bw) = bracket(&self.belts.rows, t);
        let blerp = |c: usize| {
            let (a, b) = (b0.get(c).copied(), b1.get(c).copied());
            match (a, b) {
                (Some(a), Some(b)) if a.is_finite() && b.is_finite() => a + (b - a) * bw,
                _ => 0.0,
            }
        };
        let boxes = self
            .cols
            .boxes
            .iter()
            .zip(&self.scene.loose_boxes)
            .map(|(c, b)| match c {
                Some(c) if !self.belts.rows.is_empty() => {
                    let at = |r: &[f64]| {
                        (
                            DVec3::new(r[c[0]], r[c[1]], r[c[2]]),
                            DQuat::from_euler(EulerRot::ZYX, r[c[5]], r[c[4]], r[c[3]]),
                        )
                    };
                    let ((pa, qa), (pb, qb)) = (at(b0), at(b1));
                    (pa.lerp(pb, bw), qa.slerp(qb, bw))
                }
                _ => (
                    DVec3::from_array(b.centre_m),
                    DQuat::from_rotation_z(b.yaw_rad),
                ),
            })
            .collect();
        RobotState {
            t,
            position: DVec3::new(lerp(p[0]), lerp(p[1]), lerp(p[2])),
            rotation: q(r0).slerp(q(r1), w).normalize(),
            speed: v.length(),
            flippers,
            belts: self
                .cols
                .belts
                .iter()
                .map(|c| c.map_or(0.0, blerp))
                .collect(),
            conveyors: self
                .cols
                .conveyors
                .iter()
                .map(|c| c.map_or(0.0, blerp))
                .collect(),
            boxes,
        }
    }
}

/// The rows around time `t` (column 0) and the weight of the second; an empty table gives
/// empty rows.
fn bracket(rows: &[Vec<f64>], t: f64) -> (&[f64], &[f64], f64) {
    if rows.is_empty() {
        return (&[], &[], 0.0);
    }
    let i = rows.partition_point(|r| r[0] <= t);
    if i == 0 {
        return (&rows[0], &rows[0], 0.0);
    }
    if i >= rows.len() {
        let last = &rows[rows.len() - 1];
        return (last, last, 0.0);
    }
    let (a, b) = (&rows[i - 1], &rows[i]);
    let span = b[0] - a[0];
    let w = if span > 0.0 {
        ((t - a[0]) / span).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a, b, w)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bracket_interpolates_and_clamps() {
        let rows = vec![vec![0.0, 1.0], vec![0.1, 3.0], vec![0.2, 5.0]];
        let (a, b, w) = bracket(&rows, 0.05);
        assert_eq!((a[1], b[1]), (1.0, 3.0));
        assert!((w - 0.5).abs() < 1e-12);
        assert_eq!(bracket(&rows, -1.0).0[1], 1.0);
        assert_eq!(bracket(&rows, 9.0).1[1], 5.0);
        assert_eq!(bracket(&rows, 0.2).0[1], 5.0);
    }

    #[test]
    fn absent_colours_take_the_default() {
        assert_eq!(color_or(None, palette::BOX), palette::BOX);
        assert_eq!(color_or(Some("red"), palette::BOX), palette::BOX);
        assert_eq!(color_or(Some("#010203"), palette::BOX), Rgb([1, 2, 3]));
    }
}
