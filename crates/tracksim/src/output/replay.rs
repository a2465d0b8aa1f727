//! What the 3-D view needs beyond `trajectory.csv`: the scene (`scene.json`: terrain of every
//! kind and the vehicle's geometry, in world and body frames, m) and the belts' unwrapped
//! positions (`belts.csv`), written by every run so that `tracksim view DIR` can replay it.
//!
//! Everything is REP 103 (x forward, y left, z up), SI units. Convex shapes are sent as their
//! hull's triangles so the page needs no geometry code of its own.

use crate::error::{Error, Result};
use crate::geometry::TrackPath;
use crate::model::{
    CollisionShape, GrouserShape, Mount, Parent, Scenario, SensorKind, VehicleModel,
};
use crate::run::RunResult;
use crate::terrain::TerrainModel;
use glam::DVec3;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Format tag of `scene.json`.
pub const SCENE_FORMAT: &str = "tracksim-scene-1";
/// Arc-length spacing of the sampled track paths in `scene.json`, m (arcs are drawn as chords
/// this long at most).
pub const PATH_SAMPLE_M: f64 = 0.004;

/// A triangle mesh: flat vertex coordinates (x y z, m) and flat triangle indices.
#[derive(Clone, Debug, Default, Serialize)]
pub struct MeshData {
    /// x0 y0 z0 x1 ..., m.
    pub vertices_m: Vec<f32>,
    /// Three indices per triangle.
    pub triangles: Vec<u32>,
}

impl MeshData {
    fn from_points(points: &[DVec3], tris: &[[u32; 3]]) -> Self {
        MeshData {
            vertices_m: points
                .iter()
                .flat_map(|p| [p.x as f32, p.y as f32, p.z as f32])
                .collect(),
            triangles: tris.iter().flatten().copied().collect(),
        }
    }

    /// The convex hull of `points` (empty if they span no volume).
    fn hull(points: &[DVec3]) -> Self {
        let pts: Vec<_> = points
            .iter()
            .map(|p| rapier3d::prelude::Vector::new(p.x as f32, p.y as f32, p.z as f32))
            .collect();
        match rapier3d::parry::transformation::try_convex_hull(&pts) {
            Ok((v, t)) => MeshData {
                vertices_m: v.iter().flat_map(|p| [p.x, p.y, p.z]).collect(),
                triangles: t.iter().flatten().copied().collect(),
            },
            Err(_) => MeshData::default(),
        }
    }

    /// A box of half extents `half` centred at `centre`.
    fn cuboid(half: DVec3, centre: DVec3) -> Self {
        let corners: Vec<DVec3> = (0..8)
            .map(|i| {
                let s = |b: usize| if i & b != 0 { 1.0 } else { -1.0 };
                centre + DVec3::new(s(1) * half.x, s(2) * half.y, s(4) * half.z)
            })
            .collect();
        MeshData::hull(&corners)
    }
}

fn collision_mesh(s: &CollisionShape) -> MeshData {
    match s {
        CollisionShape::Box { half, centre } => MeshData::cuboid(*half, *centre),
        CollisionShape::Compound(parts) => {
            let mut out = MeshData {
                vertices_m: Vec::new(),
                triangles: Vec::new(),
            };
            for p in parts {
                let m = collision_mesh(p);
                let base = (out.vertices_m.len() / 3) as u32;
                out.vertices_m.extend(m.vertices_m);
                out.triangles.extend(m.triangles.iter().map(|i| i + base));
            }
            out
        }
        other => MeshData::hull(&other.hull_points()),
    }
}

fn grouser_mesh(s: &GrouserShape) -> MeshData {
    match s {
        GrouserShape::Box { half, centre } => MeshData::cuboid(*half, *centre),
        GrouserShape::Convex(p) => MeshData::hull(p),
    }
}

/// A box of the terrain (boxes, stairs, inclines, the ASTM obstacles).
#[derive(Clone, Debug, Serialize)]
pub struct SceneBox {
    /// Centre, m (world).
    pub centre_m: [f64; 3],
    /// Half extents, m.
    pub half_m: [f64; 3],
    /// Orientation as a quaternion x y z w.
    pub quat_xyzw: [f64; 4],
    /// Colour in camera images, `"#rrggbb"`.
    pub color: String,
}

/// A horizontal cylinder of the terrain (a stair nosing): axis along y rotated by `yaw_rad`.
#[derive(Clone, Debug, Serialize)]
pub struct SceneCylinder {
    /// Centre, m (world).
    pub centre_m: [f64; 3],
    /// Yaw of the axis, rad.
    pub yaw_rad: f64,
    /// Half length, m.
    pub half_length_m: f64,
    /// Radius, m.
    pub radius_m: f64,
    /// Colour in camera images, `"#rrggbb"`.
    pub color: String,
}

/// The terrain as the page draws it.
#[derive(Clone, Debug, Serialize)]
pub struct SceneTerrain {
    /// Height of the flat ground, m, if there is one (it is infinite).
    pub ground_z_m: Option<f64>,
    /// Boxes.
    pub boxes: Vec<SceneBox>,
    /// Cylinders.
    pub cylinders: Vec<SceneCylinder>,
    /// Height fields (PNG and rough fields) and meshes (STL, OBJ) as world-frame triangles.
    pub meshes: Vec<MeshData>,
    /// Colour of the flat ground in camera images, `"#rrggbb"`.
    pub ground_color: String,
    /// Colour of each of `meshes` in camera images, `"#rrggbb"`, in the same order.
    pub mesh_colors: Vec<String>,
}

/// A flipper arm: it turns by its angle about `axis` through `pivot_m` (body frame).
#[derive(Clone, Debug, Serialize)]
pub struct SceneFlipper {
    /// Name.
    pub name: String,
    /// Pivot, m (body frame).
    pub pivot_m: [f64; 3],
    /// Unit axis (body frame).
    pub axis: [f64; 3],
    /// Initial angle, rad.
    pub initial_angle_rad: f64,
    /// Arm shape at angle 0 (body frame), if it has one.
    pub mesh: Option<MeshData>,
}

/// The grousers of a track: grouser k sits at arc length `offset_m + k * pitch_m + s` where s
/// is the belt's unwrapped position; shapes repeat in turn, in the footprint frame (x along the
/// belt, y along the loop axis, z outwards).
#[derive(Clone, Debug, Serialize)]
pub struct SceneGrousers {
    /// Number of grousers.
    pub count: usize,
    /// Arc length of grouser 0 at rest, m.
    pub offset_m: f64,
    /// Pitch L/N, m.
    pub pitch_m: f64,
    /// Shapes used in turn.
    pub shapes: Vec<MeshData>,
}

/// A track: its loop sampled by arc length, in the parent frame (for a flipper's track: the
/// body frame at flipper angle 0).
#[derive(Clone, Debug, Serialize)]
pub struct SceneTrack {
    /// Name.
    pub name: String,
    /// Index of the flipper it hangs on, or -1 for the chassis.
    pub parent: i64,
    /// Belt width, m.
    pub width_m: f64,
    /// Belt thickness, m.
    pub thickness_m: f64,
    /// Loop length L, m.
    pub length_m: f64,
    /// Unit loop axis (the footprint frame's y).
    pub lateral: [f64; 3],
    /// Arc lengths of the samples, m (0 first, L not repeated).
    pub s_m: Vec<f64>,
    /// Points on the path at `s_m`, flat x y z, m.
    pub points_m: Vec<f64>,
    /// Unit outward normals at `s_m`, flat.
    pub normals: Vec<f64>,
    /// Grousers, if any.
    pub grousers: Option<SceneGrousers>,
    /// Unit lateral axes at `s_m`, flat, for a loop that leaves its plane (a spatial conveyor
    /// loop); absent for a planar loop, whose lateral is `lateral` everywhere.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub laterals: Option<Vec<f64>>,
}

/// A conveyor: its belt in its own frame, placed in the world.
#[derive(Clone, Debug, Serialize)]
pub struct SceneConveyor {
    /// Origin of the conveyor's frame, m.
    pub centre_m: [f64; 3],
    /// Yaw of the conveyor's frame, rad.
    pub yaw_rad: f64,
    /// The belt (`parent` -1: the conveyor's frame).
    pub track: SceneTrack,
}

/// A loose box: its size (its poses are in `belts.csv`).
#[derive(Clone, Debug, Serialize)]
pub struct SceneLooseBox {
    /// Half extents, m.
    pub half_m: [f64; 3],
    /// Centre at the start, m.
    pub centre_m: [f64; 3],
    /// Yaw at the start, rad.
    pub yaw_rad: f64,
    /// Colour in camera images, `"#rrggbb"`.
    pub color: String,
}

/// The colours of a vehicle's parts in camera images, `"#rrggbb"` each.
#[derive(Clone, Debug, Serialize)]
pub struct SceneVehicleColors {
    /// The chassis.
    pub body: String,
    /// Belts and grousers.
    pub tracks: String,
    /// Flipper arms.
    pub flippers: String,
}

/// The vehicle as the page draws it (body frame).
#[derive(Clone, Debug, Serialize)]
pub struct SceneVehicle {
    /// Name.
    pub name: String,
    /// Chassis shape.
    pub body: MeshData,
    /// Flippers in output order.
    pub flippers: Vec<SceneFlipper>,
    /// Tracks in output order.
    pub tracks: Vec<SceneTrack>,
    /// Colours of its parts.
    pub colors: SceneVehicleColors,
}

/// A lidar's scan pattern (`lidar` of a [`SceneSensor`]).
#[derive(Clone, Debug, Serialize)]
pub struct SceneLidar {
    /// Rays per scan line.
    pub azimuth_rays: usize,
    /// Azimuth field of view, rad.
    pub azimuth_fov_rad: f64,
    /// Scan lines.
    pub elevation_rays: usize,
    /// Elevation field of view, rad.
    pub elevation_fov_rad: f64,
    /// Nearest range reported, m.
    pub min_range_m: f64,
    /// Farthest range reported, m.
    pub max_range_m: f64,
}

/// A depth camera's image (`depth_camera` of a [`SceneSensor`]).
#[derive(Clone, Debug, Serialize)]
pub struct SceneDepthCamera {
    /// Image width, pixels.
    pub width_px: usize,
    /// Image height, pixels.
    pub height_px: usize,
    /// Horizontal field of view, rad.
    pub horizontal_fov_rad: f64,
    /// Nearest depth reported, m.
    pub min_range_m: f64,
    /// Farthest depth reported, m.
    pub max_range_m: f64,
}

/// A sensor of the vehicle (`[[sensors]]`), where it sits: its frame (REP 103, a camera looks
/// along its x axis) in its mount's frame (the body frame, or a flipper's: the body frame at
/// flipper angle 0, turning with the flipper).
#[derive(Clone, Debug, Serialize)]
pub struct SceneSensor {
    /// Name (its stream: `sensors/NAME.csv` or `.npz`).
    pub name: String,
    /// Kind (`imu`, `encoders`, `lidar`, `depth_camera`, `elevation_map`).
    pub kind: &'static str,
    /// `"body"` or the flipper's name.
    pub mount: String,
    /// Index of the flipper it is mounted on, or -1 for the body.
    pub mount_index: i64,
    /// Origin of the sensor frame in the mount frame, m.
    pub xyz_m: [f64; 3],
    /// Orientation of the sensor frame in the mount frame, quaternion x y z w.
    pub quat_xyzw: [f64; 4],
    /// Update rate, Hz.
    pub rate_hz: f64,
    /// The scan pattern of a lidar.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lidar: Option<SceneLidar>,
    /// The image of a depth camera.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub depth_camera: Option<SceneDepthCamera>,
    /// The image of a colour camera (`rgb_camera`): the same fields as a depth camera's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rgb_camera: Option<SceneDepthCamera>,
}

/// A gate of a course as the page draws it: a waypoint's circle or a gate line.
#[derive(Clone, Debug, Serialize)]
pub struct SceneGate {
    /// `waypoint` or `line`.
    pub kind: &'static str,
    /// Centre, m (world x, y).
    pub centre_m: [f64; 2],
    /// A waypoint's radius, m (`null` for a line).
    pub radius_m: Option<f64>,
    /// A line's width, m (`null` for a waypoint).
    pub width_m: Option<f64>,
    /// The direction a line is crossed in, rad about z from +x (`null` for a waypoint).
    pub yaw_rad: Option<f64>,
}

/// A marked obstacle of a course (a box not to be touched).
#[derive(Clone, Debug, Serialize)]
pub struct SceneCourseObstacle {
    /// Name.
    pub name: String,
    /// Centre, m (world).
    pub centre_m: [f64; 3],
    /// Half extents, m.
    pub half_m: [f64; 3],
    /// Yaw about z, rad.
    pub yaw_rad: f64,
}

/// A course (`[course]`) as the page draws it; its score is in the live state and
/// `summary.json`.
#[derive(Clone, Debug, Serialize)]
pub struct SceneCourse {
    /// Name.
    pub name: String,
    /// Gates in the order they are passed.
    pub gates: Vec<SceneGate>,
    /// Marked obstacles.
    pub obstacles: Vec<SceneCourseObstacle>,
    /// Repetitions to complete.
    pub repetitions: u32,
    /// Time limit, s (`null`: none).
    pub time_limit_s: Option<f64>,
}

impl SceneCourse {
    /// The scene form of a compiled course.
    pub fn new(c: &crate::model::CourseModel) -> Self {
        use crate::model::GateKind;
        SceneCourse {
            name: c.name.clone(),
            gates: c
                .gates
                .iter()
                .map(|g| {
                    let (kind, radius_m, width_m, yaw_rad) = match g.kind {
                        GateKind::Waypoint { radius } => ("waypoint", Some(radius), None, None),
                        GateKind::Line { width, yaw } => ("line", None, Some(width), Some(yaw)),
                    };
                    SceneGate {
                        kind,
                        centre_m: [g.x, g.y],
                        radius_m,
                        width_m,
                        yaw_rad,
                    }
                })
                .collect(),
            obstacles: c
                .obstacles
                .iter()
                .map(|o| SceneCourseObstacle {
                    name: o.name.clone(),
                    centre_m: arr(o.centre),
                    half_m: arr(o.half),
                    yaw_rad: o.yaw,
                })
                .collect(),
            repetitions: c.repetitions,
            time_limit_s: c.time_limit,
        }
    }
}

/// A low-friction patch as the page draws it (`fault.patch`, issue 43): world x, y.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct ScenePatchArea {
    /// The rectangle's centre, world x and y, m.
    pub centre_m: [f64; 2],
    /// Its side lengths along world x and y, m.
    pub size_m: [f64; 2],
    /// The friction coefficient inside it, dimensionless.
    pub friction: f64,
}

/// A change of the low-friction patch in a recorded run: from simulated time `t_s` on, the
/// patch `patch` is on the ground (`null`: none).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct ScenePatch {
    /// Simulated time of the change, s.
    pub t_s: f64,
    /// The patch from then on (`null`: removed).
    pub patch: Option<ScenePatchArea>,
}

impl ScenePatch {
    /// The scene form of a run's patch change.
    pub fn new(c: &crate::world::PatchChange) -> Self {
        ScenePatch {
            t_s: c.t,
            patch: c.patch.map(|p| ScenePatchArea {
                centre_m: p.centre,
                size_m: p.size,
                friction: p.friction,
            }),
        }
    }
}

/// `scene.json`: what a replay or a live view draws, with the sampling of the recorded data.
#[derive(Clone, Debug, Serialize)]
pub struct Scene {
    /// [`SCENE_FORMAT`].
    pub format: &'static str,
    /// The scenario's description.
    pub description: String,
    /// Track method.
    pub method: String,
    /// Time step, s.
    pub dt_s: f64,
    /// Output interval of `trajectory.csv`, s.
    pub output_interval_s: f64,
    /// Success line along x, m, if the scenario has one.
    pub success_x_m: Option<f64>,
    /// Terrain.
    pub terrain: SceneTerrain,
    /// Vehicle.
    pub vehicle: SceneVehicle,
    /// Conveyors (`[[terrain.conveyors]]`), their belt positions in `belts.csv`.
    pub conveyors: Vec<SceneConveyor>,
    /// Loose boxes (`[[terrain.loose_boxes]]`), their poses in `belts.csv`.
    pub loose_boxes: Vec<SceneLooseBox>,
    /// The vehicle's sensors (`[[sensors]]`), in file order.
    pub sensors: Vec<SceneSensor>,
    /// The course (`[course]`), `null` when there is none.
    pub course: Option<SceneCourse>,
    /// The scenario's tip-over limit on |roll| and |pitch| (`outcome.max_tilt_deg`), degrees.
    pub max_tilt_deg: f64,
    /// The terrain has deformable soil: a live view receives new ruts in its state (`ruts`).
    pub soil: bool,
    /// The file of the ruts at the end of a run (`ruts.csv`), `null` without.
    pub ruts_csv: Option<String>,
    /// A recorded run's low-friction patch timeline (`fault.patch`): every change in order,
    /// the patch in force at time t being that of the last change at or before t (empty: no
    /// patch in the run, and always empty in a live view, whose states carry the patch).
    pub patches: Vec<ScenePatch>,
}

fn arr(v: DVec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

fn terrain(t: &TerrainModel) -> SceneTerrain {
    let mut meshes: Vec<MeshData> = t
        .meshes
        .iter()
        .map(|m| MeshData::from_points(&m.vertices, &m.triangles))
        .collect();
    let mut mesh_colors: Vec<String> = t.meshes.iter().map(|m| m.color.to_string()).collect();
    for h in &t.heightfields {
        let mut pts = Vec::with_capacity(h.rows * h.cols);
        for r in 0..h.rows {
            for c in 0..h.cols {
                pts.push(h.vertex(r, c));
            }
        }
        let mut tris = Vec::new();
        let id = |r: usize, c: usize| (r * h.cols + c) as u32;
        for r in 0..h.rows - 1 {
            for c in 0..h.cols - 1 {
                // Row r is at larger y than row r + 1: counter-clockwise seen from above.
                tris.push([id(r, c), id(r + 1, c), id(r + 1, c + 1)]);
                tris.push([id(r, c), id(r + 1, c + 1), id(r, c + 1)]);
            }
        }
        meshes.push(MeshData::from_points(&pts, &tris));
        mesh_colors.push(h.color.to_string());
    }
    SceneTerrain {
        ground_z_m: t.ground.map(|(z, _)| z),
        boxes: t
            .boxes
            .iter()
            .map(|b| {
                let q = b.rotation();
                SceneBox {
                    centre_m: arr(b.centre),
                    half_m: arr(b.half),
                    quat_xyzw: [q.x, q.y, q.z, q.w],
                    color: b.color.to_string(),
                }
            })
            .collect(),
        cylinders: t
            .cylinders
            .iter()
            .map(|c| SceneCylinder {
                centre_m: arr(c.centre),
                yaw_rad: c.yaw,
                half_length_m: c.half_length,
                radius_m: c.radius,
                color: c.color.to_string(),
            })
            .collect(),
        meshes,
        ground_color: t.ground_color.to_string(),
        mesh_colors,
    }
}

/// A loop sampled by arc length.
struct PathSamples {
    s: Vec<f64>,
    points: Vec<f64>,
    normals: Vec<f64>,
    /// Lateral axes, if any differs from the loop's axis (a spatial loop).
    laterals: Option<Vec<f64>>,
}

/// Samples a loop every [`PATH_SAMPLE_M`] at most.
fn sample_path(path: &TrackPath) -> PathSamples {
    let l = path.length();
    let n = ((l / PATH_SAMPLE_M).ceil() as usize).max(16);
    let (mut s, mut p, mut nr, mut lat) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut planar = true;
    for i in 0..n {
        let si = l * i as f64 / n as f64;
        let f = path.frame_at(si);
        s.push(si);
        p.extend(arr(f.origin));
        nr.extend(arr(f.normal));
        lat.extend(arr(f.lateral));
        planar &= (f.lateral - path.axis()).length() < 1e-9;
    }
    PathSamples {
        s,
        points: p,
        normals: nr,
        laterals: (!planar).then_some(lat),
    }
}

/// The scene form of track `t`, hanging on `parent` (-1: the chassis or a conveyor's frame).
fn scene_track(t: &crate::model::TrackModel, parent: i64) -> SceneTrack {
    let ps = sample_path(&t.path);
    SceneTrack {
        name: t.name.clone(),
        parent,
        width_m: t.width,
        thickness_m: t.belt_thickness,
        length_m: t.path.length(),
        lateral: arr(t.path.axis()),
        s_m: ps.s,
        points_m: ps.points,
        normals: ps.normals,
        grousers: t.grousers.as_ref().map(|g| SceneGrousers {
            count: g.layout.count,
            offset_m: g.layout.offset,
            pitch_m: g.layout.pitch(&t.path),
            shapes: g.shapes.iter().map(grouser_mesh).collect(),
        }),
        laterals: ps.laterals,
    }
}

fn vehicle(v: &VehicleModel) -> SceneVehicle {
    SceneVehicle {
        name: v.name.clone(),
        body: collision_mesh(&v.body.shape),
        flippers: v
            .flippers
            .iter()
            .map(|f| SceneFlipper {
                name: f.name.clone(),
                pivot_m: arr(f.pivot),
                axis: arr(f.axis),
                initial_angle_rad: f.initial_angle,
                mesh: f.shape.as_ref().map(collision_mesh),
            })
            .collect(),
        tracks: v
            .tracks
            .iter()
            .map(|t| {
                let parent = match t.parent {
                    Parent::Body => -1,
                    Parent::Flipper(i) => i as i64,
                };
                scene_track(t, parent)
            })
            .collect(),
        colors: SceneVehicleColors {
            body: v.colors.body.to_string(),
            tracks: v.colors.tracks.to_string(),
            flippers: v.colors.flippers.to_string(),
        },
    }
}

fn sensors(v: &VehicleModel) -> Vec<SceneSensor> {
    v.sensors
        .iter()
        .map(|m| {
            let (mount, mount_index) = match m.mount {
                Mount::Body => ("body".to_string(), -1),
                Mount::Flipper(i) => (v.flippers[i].name.clone(), i as i64),
            };
            let q = m.rotation;
            SceneSensor {
                name: m.name.clone(),
                kind: m.kind.name(),
                mount,
                mount_index,
                xyz_m: arr(m.position),
                quat_xyzw: [q.x, q.y, q.z, q.w],
                rate_hz: m.rate_hz,
                lidar: match m.kind {
                    SensorKind::Lidar(p) => Some(SceneLidar {
                        azimuth_rays: p.azimuth_rays,
                        azimuth_fov_rad: p.azimuth_fov,
                        elevation_rays: p.elevation_rays,
                        elevation_fov_rad: p.elevation_fov,
                        min_range_m: p.min_range,
                        max_range_m: p.max_range,
                    }),
                    _ => None,
                },
                depth_camera: match m.kind {
                    SensorKind::DepthCamera(p) => Some(SceneDepthCamera {
                        width_px: p.width,
                        height_px: p.height,
                        horizontal_fov_rad: p.horizontal_fov,
                        min_range_m: p.min_range,
                        max_range_m: p.max_range,
                    }),
                    _ => None,
                },
                rgb_camera: match m.kind {
                    SensorKind::RgbCamera(p) => Some(SceneDepthCamera {
                        width_px: p.intrinsics.width,
                        height_px: p.intrinsics.height,
                        horizontal_fov_rad: p.intrinsics.horizontal_fov,
                        min_range_m: p.min_range,
                        max_range_m: p.max_range,
                    }),
                    _ => None,
                },
            }
        })
        .collect()
}

impl Scene {
    /// The scene of a compiled scenario.
    pub fn new(sc: &Scenario) -> Self {
        Scene {
            format: SCENE_FORMAT,
            description: sc.description.clone(),
            method: sc.method.name(),
            dt_s: sc.solver.dt,
            output_interval_s: sc.output_interval,
            success_x_m: sc.outcome.success_x,
            terrain: terrain(&sc.terrain),
            vehicle: vehicle(&sc.vehicle),
            conveyors: sc
                .conveyors
                .iter()
                .map(|c| SceneConveyor {
                    centre_m: arr(c.centre),
                    yaw_rad: c.yaw,
                    track: scene_track(&c.belt, -1),
                })
                .collect(),
            loose_boxes: sc
                .loose_boxes
                .iter()
                .map(|b| SceneLooseBox {
                    half_m: arr(b.solid.half),
                    centre_m: arr(b.solid.centre),
                    yaw_rad: b.solid.yaw,
                    color: b.solid.color.to_string(),
                })
                .collect(),
            sensors: sensors(&sc.vehicle),
            course: sc.course.as_ref().map(SceneCourse::new),
            max_tilt_deg: sc.outcome.max_tilt.to_degrees(),
            soil: !sc.terrain.soils.is_empty(),
            ruts_csv: None,
            patches: Vec::new(),
        }
    }

    /// As JSON text.
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).expect("scene serialises")
    }
}

/// The text of `belts.csv`: `t_s`, then the unwrapped belt position per track, m; then per
/// conveyor `i` its belt position `conveyor_position_i_m`, and per loose box `i` its pose
/// `box_i_x_m`, `_y_m`, `_z_m`, `_roll_rad`, `_pitch_rad`, `_yaw_rad` (world frame, REP 103).
pub fn belts_csv(result: &RunResult) -> String {
    let mut bytes = Vec::new();
    write_belts_csv(result, &mut bytes).expect("writing to memory");
    String::from_utf8(bytes).expect("belts.csv is UTF-8")
}

/// Writes [`belts_csv`] to `w` a row at a time (the samples may be on disk: issue 45).
fn write_belts_csv(result: &RunResult, w: &mut dyn std::io::Write) -> std::io::Result<()> {
    let mut text = String::from("t_s");
    for n in &result.track_names {
        text.push_str(&format!(",belt_position_{n}_m"));
    }
    let first = result.samples.first();
    for i in 0..first.map_or(0, |s| s.conveyor_position.len()) {
        text.push_str(&format!(",conveyor_position_{i}_m"));
    }
    for i in 0..first.map_or(0, |s| s.loose_poses.len()) {
        for c in ["x_m", "y_m", "z_m", "roll_rad", "pitch_rad", "yaw_rad"] {
            text.push_str(&format!(",box_{i}_{c}"));
        }
    }
    text.push('\n');
    w.write_all(text.as_bytes())?;
    for s in result.samples.iter() {
        text.clear();
        text.push_str(&format!("{:.6}", s.t));
        for p in s.belt_position.iter().chain(&s.conveyor_position) {
            text.push_str(&format!(",{p:.6}"));
        }
        for p in &s.loose_poses {
            for v in [p.x, p.y, p.z, p.roll, p.pitch, p.yaw] {
                text.push_str(&format!(",{v:.6}"));
            }
        }
        text.push('\n');
        w.write_all(text.as_bytes())?;
    }
    Ok(())
}

/// The text of `ruts.csv`: every loaded soil cell at the end of a run, one row each: its centre
/// (`x_m`, `y_m`), the undisturbed surface's height there (`surface_z_m`), the rut's depth below
/// it (`depth_m`), the cell's side (`cell_m`), the time it was first loaded (`t_s`, for a
/// replay) and the soil's index.
pub fn ruts_csv(ruts: &[crate::world::RutCell]) -> String {
    let mut text = String::from("x_m,y_m,surface_z_m,depth_m,cell_m,t_s,soil\n");
    for r in ruts {
        text.push_str(&format!(
            "{:.4},{:.4},{:.5},{:.5},{},{:.3},{}\n",
            r.x_m, r.y_m, r.surface_z_m, r.depth_m, r.cell_m, r.t_s, r.soil
        ));
    }
    text
}

/// Writes `scene.json`, `belts.csv` and (on soil) `ruts.csv` into `dir` (created if needed); returns their paths.
pub fn write_replay(sc: &Scenario, result: &RunResult, dir: &Path) -> Result<Vec<PathBuf>> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| Error::Io { path, source }
    };
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    let scene = dir.join("scene.json");
    let mut s = Scene::new(sc);
    s.patches = result.patches.iter().map(ScenePatch::new).collect();
    let mut written = Vec::new();
    if !result.ruts.is_empty() {
        let ruts = dir.join("ruts.csv");
        crate::files::write_atomic(&ruts, ruts_csv(&result.ruts).as_bytes())?;
        s.ruts_csv = Some("ruts.csv".into());
        written.push(ruts);
    }
    crate::files::write_atomic(&scene, s.to_json().as_bytes())?;
    let belts = dir.join("belts.csv");
    crate::files::write_atomic_with(&belts, |w| write_belts_csv(result, w))?;
    written.splice(0..0, [scene, belts]);
    Ok(written)
}
