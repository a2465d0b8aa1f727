//! The compiled, immutable model (MuJoCo's `mjModel` idea): vehicle and scenario checked and
//! converted to SI units and radians, ready to be instantiated any number of times.

use crate::error::{Error, Result, SpecIssue};
use crate::geometry::{GrouserLayout, PathError, Pulley, Segment, TrackPath};
use crate::spec::*;
use crate::terrain::TerrainModel;
use glam::DVec3;
use rapier3d::prelude::CoefficientCombineRule;
use std::path::{Path, PathBuf};

/// A compiled collision shape in its owner's frame.
#[derive(Clone, Debug, PartialEq)]
pub enum CollisionShape {
    /// Box with half extents, centred at `centre`, m.
    Box {
        /// Half extents, m.
        half: DVec3,
        /// Centre, m.
        centre: DVec3,
    },
    /// Convex hull of points, m.
    Convex(Vec<DVec3>),
}

impl CollisionShape {
    /// Axis-aligned bounds (min, max), m.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        match self {
            CollisionShape::Box { half, centre } => (*centre - *half, *centre + *half),
            CollisionShape::Convex(p) => p.iter().fold(
                (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN)),
                |(lo, hi), q| (lo.min(*q), hi.max(*q)),
            ),
        }
    }
}

/// The chassis.
#[derive(Clone, Debug)]
pub struct BodyModel {
    /// Mass, kg.
    pub mass: f64,
    /// Centre of mass in the body frame, m.
    pub com: DVec3,
    /// Principal inertia along the body axes, kg m^2.
    pub inertia: DVec3,
    /// Collision shape.
    pub shape: CollisionShape,
    /// Friction coefficient.
    pub friction: f64,
}

/// A flipper arm.
#[derive(Clone, Debug)]
pub struct FlipperModel {
    /// Name.
    pub name: String,
    /// Pivot in the body frame, m.
    pub pivot: DVec3,
    /// Unit joint axis in the body frame.
    pub axis: DVec3,
    /// Mass, kg.
    pub mass: f64,
    /// Centre of mass (body frame at angle 0), m.
    pub com: DVec3,
    /// Principal inertia, kg m^2.
    pub inertia: DVec3,
    /// Optional arm shape (body frame at angle 0).
    pub shape: Option<CollisionShape>,
    /// Initial angle, rad.
    pub initial_angle: f64,
    /// Torque limit, N m.
    pub max_torque: f64,
    /// Position gain, N m / rad.
    pub stiffness: f64,
    /// Velocity gain, N m s / rad.
    pub damping: f64,
}

/// A grouser shape in its footprint frame (x along, y across, z out), m.
#[derive(Clone, Debug, PartialEq)]
pub enum GrouserShape {
    /// Cuboid: half extents and centre.
    Box {
        /// Half extents, m.
        half: DVec3,
        /// Centre, m.
        centre: DVec3,
    },
    /// Convex hull of points, m.
    Convex(Vec<DVec3>),
}

/// The grousers of one track.
#[derive(Clone, Debug)]
pub struct GrouserModel {
    /// Layout along the loop.
    pub layout: GrouserLayout,
    /// Shapes used in turn.
    pub shapes: Vec<GrouserShape>,
    /// Largest outward extent of any shape, m.
    pub height: f64,
}

/// What a track hangs on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Parent {
    /// The chassis.
    Body,
    /// The flipper with this index.
    Flipper(usize),
}

/// One track.
#[derive(Clone, Debug)]
pub struct TrackModel {
    /// Name.
    pub name: String,
    /// What it hangs on.
    pub parent: Parent,
    /// The loop, in the parent frame (for flippers: the body frame at angle 0).
    pub path: TrackPath,
    /// Belt width, m.
    pub width: f64,
    /// Belt thickness, m.
    pub belt_thickness: f64,
    /// Belt mass, kg.
    pub belt_mass: f64,
    /// Friction coefficient.
    pub friction: f64,
    /// Friction combine rule.
    pub combine: CoefficientCombineRule,
    /// Sprocket pitch radius, m.
    pub sprocket_radius: Option<f64>,
    /// Which segments get a link (false: omitted).
    pub included: Vec<bool>,
    /// Grousers, if any.
    pub grousers: Option<GrouserModel>,
}

/// A compiled vehicle.
#[derive(Clone, Debug)]
pub struct VehicleModel {
    /// Name.
    pub name: String,
    /// Description.
    pub description: String,
    /// Chassis.
    pub body: BodyModel,
    /// Flippers.
    pub flippers: Vec<FlipperModel>,
    /// Tracks.
    pub tracks: Vec<TrackModel>,
}

impl TrackModel {
    /// Lateral position (y) of the track's mid-plane in its parent frame, m.
    pub fn lateral_offset(&self) -> f64 {
        let segs = self.path.segments();
        segs.iter().map(|s| s.start().y).sum::<f64>() / segs.len() as f64
    }
}

impl VehicleModel {
    /// Index of the track called `name`.
    pub fn track_index(&self, name: &str) -> Option<usize> {
        self.tracks.iter().position(|t| t.name == name)
    }
    /// Index of the flipper called `name`.
    pub fn flipper_index(&self, name: &str) -> Option<usize> {
        self.flippers.iter().position(|f| f.name == name)
    }
}

use crate::check::{Checker, v3};

/// Checks a collision shape and compiles it.
fn shape(c: &mut Checker, key: &str, s: &ShapeSpec) -> CollisionShape {
    match s {
        ShapeSpec::Box { size_m, centre_m } => {
            for (i, v) in size_m.iter().enumerate() {
                c.positive(&format!("{key}.size_m[{i}]"), *v, "m");
            }
            c.finite(&format!("{key}.centre_m"), centre_m);
            CollisionShape::Box {
                half: v3(*size_m) * 0.5,
                centre: v3(*centre_m),
            }
        }
        ShapeSpec::Convex { points_m } => {
            let pts = c.points(&format!("{key}.points_m"), points_m);
            CollisionShape::Convex(pts)
        }
    }
}

fn box_inertia(mass: f64, size: DVec3) -> DVec3 {
    DVec3::new(
        size.y * size.y + size.z * size.z,
        size.x * size.x + size.z * size.z,
        size.x * size.x + size.y * size.y,
    ) * (mass / 12.0)
}

fn path_issue(key: &str, e: &PathError) -> SpecIssue {
    let key = match e {
        PathError::NotFinite { segment }
        | PathError::NonPositiveLength { segment, .. }
        | PathError::ZeroVector { segment, .. }
        | PathError::NonPositiveRadius { segment, .. }
        | PathError::BadArcAngle { segment, .. }
        | PathError::Gap { segment, .. }
        | PathError::Kink { segment, .. }
        | PathError::NotPlanar { segment } => format!("{key}.segments[{segment}]"),
        PathError::BadPulley { pulley, .. } | PathError::PulleysOverlap { pulley, .. } => {
            format!("{key}.pulleys[{pulley}]")
        }
        _ => key.to_string(),
    };
    SpecIssue::new(key, e.to_string())
}

fn combine_rule(s: &str) -> Option<CoefficientCombineRule> {
    Some(match s {
        "min" => CoefficientCombineRule::Min,
        "average" => CoefficientCombineRule::Average,
        "multiply" => CoefficientCombineRule::Multiply,
        "max" => CoefficientCombineRule::Max,
        _ => return None,
    })
}

/// Compiles a vehicle description, reporting every problem with its key path.
pub fn compile_vehicle(spec: &VehicleSpec) -> Result<VehicleModel, Vec<SpecIssue>> {
    let mut c = Checker::default();
    if spec.name.trim().is_empty() {
        c.push("name", "must not be empty");
    }
    // Body.
    let b = &spec.body;
    c.positive("body.mass_kg", b.mass_kg, "kg");
    c.non_negative("body.friction", b.friction, "");
    c.finite("body.centre_of_mass_m", &b.centre_of_mass_m);
    let body_shape = shape(&mut c, "body.shape", &b.shape);
    let inertia = match b.inertia_kgm2 {
        Some(i) => {
            for (k, v) in i.iter().enumerate() {
                c.positive(&format!("body.inertia_kgm2[{k}]"), *v, "kg m^2");
            }
            v3(i)
        }
        None => {
            let (lo, hi) = body_shape.bounds();
            box_inertia(b.mass_kg, hi - lo)
        }
    };
    let body = BodyModel {
        mass: b.mass_kg,
        com: v3(b.centre_of_mass_m),
        inertia,
        shape: body_shape,
        friction: b.friction,
    };
    // Flippers.
    let mut flippers = Vec::new();
    for (i, f) in spec.flippers.iter().enumerate() {
        let k = format!("flippers[{i}]");
        if f.name.trim().is_empty() || f.name == "body" {
            c.push(
                format!("{k}.name"),
                "must be a non-empty name other than \"body\"",
            );
        }
        if spec.flippers[..i].iter().any(|g| g.name == f.name) {
            c.push(
                format!("{k}.name"),
                format!("duplicate flipper name \"{}\"", f.name),
            );
        }
        c.finite(&format!("{k}.pivot_m"), &f.pivot_m);
        let axis = c.unit_vector(&format!("{k}.axis"), f.axis);
        c.positive(&format!("{k}.mass_kg"), f.mass_kg, "kg");
        c.positive(&format!("{k}.max_torque_nm"), f.max_torque_nm, "N m");
        c.positive(
            &format!("{k}.stiffness_nm_per_rad"),
            f.stiffness_nm_per_rad,
            "N m/rad",
        );
        c.non_negative(
            &format!("{k}.damping_nms_per_rad"),
            f.damping_nms_per_rad,
            "N m s/rad",
        );
        c.finite(&format!("{k}.initial_angle_deg"), &[f.initial_angle_deg]);
        let shape = f
            .shape
            .as_ref()
            .map(|s| shape(&mut c, &format!("{k}.shape"), s));
        let com = f.centre_of_mass_m.map(v3).unwrap_or(v3(f.pivot_m));
        let inertia = match f.inertia_kgm2 {
            Some(i) => {
                for (j, v) in i.iter().enumerate() {
                    c.positive(&format!("{k}.inertia_kgm2[{j}]"), *v, "kg m^2");
                }
                v3(i)
            }
            None => match &shape {
                Some(s) => {
                    let (lo, hi) = s.bounds();
                    box_inertia(f.mass_kg, hi - lo)
                }
                None => DVec3::splat(f.mass_kg * 0.01),
            },
        };
        flippers.push(FlipperModel {
            name: f.name.clone(),
            pivot: v3(f.pivot_m),
            axis,
            mass: f.mass_kg,
            com,
            inertia,
            shape,
            initial_angle: f.initial_angle_deg.to_radians(),
            max_torque: f.max_torque_nm,
            stiffness: f.stiffness_nm_per_rad,
            damping: f.damping_nms_per_rad,
        });
    }
    // Tracks.
    let mut tracks: Vec<TrackModel> = Vec::new();
    if spec.tracks.is_empty() {
        c.push("tracks", "a vehicle needs at least one track");
    }
    for (i, t) in spec.tracks.iter().enumerate() {
        let k = format!("tracks[{i}]");
        let mut resolve = |key: String, name: &str| {
            if name == "body" {
                Parent::Body
            } else if let Some(j) = spec.flippers.iter().position(|f| f.name == name) {
                Parent::Flipper(j)
            } else {
                c.push(
                    key,
                    format!(
                        "no flipper called \"{name}\"; use \"body\" or one of the names under [[flippers]]"
                    ),
                );
                Parent::Body
            }
        };
        let parent = resolve(format!("{k}.parent"), &t.parent);
        let mirror_parent = match &t.mirror_parent {
            Some(p) => resolve(format!("{k}.mirror_parent"), p),
            None => parent,
        };
        if t.mirror_parent.is_some() && t.mirror.is_none() {
            c.push(
                format!("{k}.mirror_parent"),
                "only used together with `mirror`",
            );
        }
        c.positive(&format!("{k}.width_m"), t.width_m, "m");
        c.positive(&format!("{k}.belt_thickness_m"), t.belt_thickness_m, "m");
        c.positive(&format!("{k}.belt_mass_kg"), t.belt_mass_kg, "kg");
        c.non_negative(&format!("{k}.friction"), t.friction, "");
        let combine = combine_rule(&t.friction_combine).unwrap_or_else(|| {
            c.push(
                format!("{k}.friction_combine"),
                format!(
                    "unknown rule \"{}\"; use \"min\", \"average\", \"multiply\" or \"max\"",
                    t.friction_combine
                ),
            );
            CoefficientCombineRule::Min
        });
        if let Some(r) = t.sprocket_pitch_radius_m {
            c.positive(&format!("{k}.sprocket_pitch_radius_m"), r, "m");
        }
        // Grousers.
        let grousers = match &t.grousers {
            None => None,
            Some(g) => {
                let gk = format!("{k}.grousers");
                if g.count == 0 {
                    c.push(
                        format!("{gk}.count"),
                        "must be >= 1 (remove the [grousers] table for a track without grousers)",
                    );
                }
                c.finite(&format!("{gk}.offset_m"), &[g.offset_m]);
                if g.shapes.is_empty() {
                    c.push(format!("{gk}.shapes"), "needs at least one shape");
                }
                if g.count > 0 && !g.shapes.is_empty() && g.count % g.shapes.len() != 0 {
                    c.push(
                        format!("{gk}.count"),
                        format!(
                            "{} grousers cannot repeat {} shapes evenly; use a multiple of {}",
                            g.count,
                            g.shapes.len(),
                            g.shapes.len()
                        ),
                    );
                }
                let mut shapes = Vec::new();
                let mut height: f64 = 0.0;
                for (j, s) in g.shapes.iter().enumerate() {
                    let sk = format!("{gk}.shapes[{j}]");
                    let shape = match s {
                        GrouserShapeSpec::Box {
                            length_m,
                            height_m,
                            width_m,
                            shift_m,
                        } => {
                            let w = width_m.unwrap_or(t.width_m);
                            c.positive(&format!("{sk}.length_m"), *length_m, "m");
                            c.positive(&format!("{sk}.height_m"), *height_m, "m");
                            c.positive(&format!("{sk}.width_m"), w, "m");
                            c.finite(&format!("{sk}.shift_m"), &[*shift_m]);
                            height = height.max(*height_m);
                            GrouserShape::Box {
                                half: DVec3::new(*length_m, w, *height_m) * 0.5,
                                centre: DVec3::new(*shift_m, 0.0, height_m * 0.5),
                            }
                        }
                        GrouserShapeSpec::Trapezoid {
                            bottom_m,
                            top_m,
                            height_m,
                            width_m,
                            shift_m,
                        } => {
                            let w = width_m.unwrap_or(t.width_m);
                            c.positive(&format!("{sk}.bottom_m"), *bottom_m, "m");
                            c.positive(&format!("{sk}.top_m"), *top_m, "m");
                            c.positive(&format!("{sk}.height_m"), *height_m, "m");
                            c.positive(&format!("{sk}.width_m"), w, "m");
                            c.finite(&format!("{sk}.shift_m"), &[*shift_m]);
                            height = height.max(*height_m);
                            let mut pts = Vec::new();
                            for y in [-w / 2.0, w / 2.0] {
                                for (x, z) in [
                                    (-bottom_m / 2.0, 0.0),
                                    (bottom_m / 2.0, 0.0),
                                    (-top_m / 2.0, *height_m),
                                    (top_m / 2.0, *height_m),
                                ] {
                                    pts.push(DVec3::new(x + shift_m, y, z));
                                }
                            }
                            GrouserShape::Convex(pts)
                        }
                        GrouserShapeSpec::Convex { points_m } => {
                            let pts = c.points(&format!("{sk}.points_m"), points_m);
                            height = pts.iter().map(|p| p.z).fold(height, f64::max);
                            GrouserShape::Convex(pts)
                        }
                    };
                    shapes.push(shape);
                }
                (g.count > 0).then_some(GrouserModel {
                    layout: GrouserLayout {
                        count: g.count,
                        offset: g.offset_m,
                    },
                    shapes,
                    height,
                })
            }
        };
        // Path.
        let pk = format!("{k}.path");
        let path = match (&t.path.pulleys, &t.path.segments) {
            (Some(p), None) => {
                let y = t.path.plane_y_m.unwrap_or(0.0);
                c.finite(&format!("{pk}.plane_y_m"), &[y]);
                let pulleys: Vec<Pulley> = p
                    .iter()
                    .map(|q| Pulley {
                        x: q.x_m,
                        z: q.z_m,
                        radius: q.radius_m,
                    })
                    .collect();
                TrackPath::from_pulleys(&pulleys, y)
            }
            (None, Some(s)) => {
                if t.path.plane_y_m.is_some() {
                    c.push(
                        format!("{pk}.plane_y_m"),
                        "only used with pulleys; explicit segments carry their own y",
                    );
                }
                let segs = s
                    .iter()
                    .map(|s| match *s {
                        SegmentSpec::Straight {
                            start_m,
                            direction,
                            length_m,
                        } => Segment::Straight {
                            start: v3(start_m),
                            direction: v3(direction),
                            length: length_m,
                        },
                        SegmentSpec::Arc {
                            start_m,
                            centre_m,
                            axis,
                            angle_deg,
                        } => Segment::Arc {
                            start: v3(start_m),
                            centre: v3(centre_m),
                            axis: v3(axis),
                            angle: angle_deg.to_radians(),
                        },
                    })
                    .collect();
                TrackPath::new(segs)
            }
            _ => {
                c.push(
                    pk.clone(),
                    "give exactly one of `pulleys` (list of {x_m, z_m, radius_m}) or `segments`",
                );
                continue;
            }
        };
        let path = match path {
            Ok(p) => p,
            Err(errs) => {
                for e in &errs {
                    c.issues.push(path_issue(&pk, e));
                }
                continue;
            }
        };
        if path.axis().dot(DVec3::Y) < 1.0 - 1e-6 {
            c.push(
                pk.clone(),
                "the loop must lie in an x-z plane and turn about +y (lower run moving backwards for a positive belt speed); reverse the segment order",
            );
        }
        let n = path.segments().len();
        let mut included = vec![true; n];
        for (j, &o) in t.omit_segments.iter().enumerate() {
            if o >= n {
                c.push(
                    format!("{k}.omit_segments[{j}]"),
                    format!(
                        "segment {o} does not exist; the loop has segments 0..{}",
                        n - 1
                    ),
                );
            } else {
                included[o] = false;
            }
        }
        if included.iter().all(|x| !x) {
            c.push(format!("{k}.omit_segments"), "cannot omit every segment");
        }
        let model = TrackModel {
            name: t.name.clone(),
            parent,
            path,
            width: t.width_m,
            belt_thickness: t.belt_thickness_m,
            belt_mass: t.belt_mass_kg,
            friction: t.friction,
            combine,
            sprocket_radius: t.sprocket_pitch_radius_m,
            included,
            grousers,
        };
        if let Some(m) = &t.mirror {
            let mut mirrored = model.clone();
            mirrored.name = m.clone();
            mirrored.parent = mirror_parent;
            mirrored.path = model.path.mirrored_y();
            tracks.push(model);
            tracks.push(mirrored);
        } else {
            tracks.push(model);
        }
    }
    for (i, t) in tracks.iter().enumerate() {
        if t.name.trim().is_empty() {
            c.push("tracks", "every track needs a non-empty name");
        } else if tracks[..i].iter().any(|u| u.name == t.name) {
            c.push(
                "tracks",
                format!(
                    "duplicate track name \"{}\" (check `name` and `mirror`)",
                    t.name
                ),
            );
        }
    }
    if c.issues.is_empty() {
        Ok(VehicleModel {
            name: spec.name.clone(),
            description: spec.description.clone(),
            body,
            flippers,
            tracks,
        })
    } else {
        Err(c.issues)
    }
}

/// Reads and parses a TOML file into `T`, naming the file in every error.
pub fn read_toml<T: serde::de::DeserializeOwned>(path: &Path) -> Result<T> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    toml::from_str(&text).map_err(|e| Error::Parse {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// Loads and compiles a vehicle file.
pub fn load_vehicle(path: &Path) -> Result<VehicleModel> {
    let spec: VehicleSpec = read_toml(path)?;
    compile_vehicle(&spec).map_err(|issues| Error::Invalid {
        path: path.to_path_buf(),
        issues,
    })
}

/// Solver settings.
#[derive(Clone, Debug)]
pub struct SolverSettings {
    /// Time step, s.
    pub dt: f64,
    /// Solver iterations.
    pub iterations: usize,
    /// Contact clustering on or off.
    pub contact_clustering: bool,
    /// Smallest segment link mass, kg.
    pub min_link_mass: f64,
    /// Speculative contact distance, m.
    pub prediction_distance: f64,
    /// Uncorrected vehicle-terrain penetration (ODE's `min_depth`), m; 0 = rigid contact.
    pub contact_slop: f64,
}

impl Default for SolverSettings {
    fn default() -> Self {
        SolverSettings {
            dt: 0.001,
            iterations: 4,
            contact_clustering: false,
            min_link_mass: MIN_LINK_MASS_KG,
            prediction_distance: 0.02,
            contact_slop: 0.0,
        }
    }
}

/// Default smallest mass given to a segment link or wheel body, kg: on the PackBot climbing a
/// step the floor halves the per-step joint error of the segment links (docs/DESIGN.md).
pub const MIN_LINK_MASS_KG: f64 = 0.5;

/// The inputs of one step, by track and flipper index (a controller's output, or one entry of a
/// file's `[[commands]]`); `None` keeps the previous value.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Controls {
    /// Belt speed per track index, m/s (positive drives forwards).
    pub belt_speed: Vec<Option<f64>>,
    /// Flipper target angle per flipper index, rad.
    pub flipper_angle: Vec<Option<f64>>,
}

impl Controls {
    /// Controls that change nothing, sized for `v`.
    pub fn keep(v: &VehicleModel) -> Self {
        Controls {
            belt_speed: vec![None; v.tracks.len()],
            flipper_angle: vec![None; v.flippers.len()],
        }
    }

    /// Every belt at `speed` m/s.
    pub fn belts(v: &VehicleModel, speed: f64) -> Self {
        Controls {
            belt_speed: vec![Some(speed); v.tracks.len()],
            ..Controls::keep(v)
        }
    }

    /// Body-level skid steering without slip: forward speed `forward` m/s and yaw rate
    /// `yaw_rate` rad/s (REP 103, positive turns left) about the body origin; each belt runs at
    /// `forward - yaw_rate * y` for its track's mid-plane at lateral offset `y` m.
    pub fn twist(v: &VehicleModel, forward: f64, yaw_rate: f64) -> Self {
        Controls {
            belt_speed: v
                .tracks
                .iter()
                .map(|t| Some(forward - yaw_rate * t.lateral_offset()))
                .collect(),
            ..Controls::keep(v)
        }
    }

    /// Sets flipper `i`'s target angle, rad.
    pub fn with_flipper(mut self, i: usize, angle: f64) -> Self {
        if let Some(a) = self.flipper_angle.get_mut(i) {
            *a = Some(angle);
        }
        self
    }
}

/// One timed command of a scenario file, resolved to track and flipper indices.
#[derive(Clone, Debug, PartialEq)]
pub struct Command {
    /// Start time, s.
    pub t: f64,
    /// What it sets.
    pub controls: Controls,
}

/// Success and failure conditions, compiled.
#[derive(Clone, Debug)]
pub struct OutcomeModel {
    /// Success when body x passes this, m.
    pub success_x: Option<f64>,
    /// Success when body z reaches this, m.
    pub success_z: Option<f64>,
    /// Tip-over limit on |roll| and |pitch|, rad.
    pub max_tilt: f64,
    /// Fail when leaving a bounded terrain.
    pub fail_off_terrain: bool,
    /// Stop when decided.
    pub stop: bool,
}

/// A compiled scenario.
#[derive(Clone, Debug)]
pub struct Scenario {
    /// Where it was read from, if from a file.
    pub source: Option<PathBuf>,
    /// Description.
    pub description: String,
    /// The vehicle.
    pub vehicle: VehicleModel,
    /// Start position (x, y, optional z), m.
    pub start_xy: (f64, f64),
    /// Start height, m (None: rest on the ground).
    pub start_z: Option<f64>,
    /// Start yaw, rad.
    pub start_yaw: f64,
    /// Start pitch, rad.
    pub start_pitch: f64,
    /// The world.
    pub terrain: TerrainModel,
    /// Solver.
    pub solver: SolverSettings,
    /// Duration, s.
    pub duration: f64,
    /// Output interval, s.
    pub output_interval: f64,
    /// Commands, sorted by time.
    pub commands: Vec<Command>,
    /// Outcome conditions.
    pub outcome: OutcomeModel,
    /// Track method name (`simulation.method`), resolved by the track layer
    /// (`tracks::Method::from_name`).
    pub method: String,
    /// Seed.
    pub seed: u64,
}

/// Checks of keys the model layer does not interpret (e.g. `simulation.method`, resolved by the
/// track layer), reported with the model's own problems.
pub type ExtraChecks<'a> = &'a dyn Fn(&ScenarioSpec) -> Vec<SpecIssue>;

/// Compiles a scenario whose vehicle is already loaded (no check of the method name: see
/// [`compile_scenario_with`]).
pub fn compile_scenario(
    spec: &ScenarioSpec,
    vehicle: VehicleModel,
    base_dir: &Path,
) -> Result<Scenario, Vec<SpecIssue>> {
    compile_scenario_with(spec, vehicle, base_dir, &|_| Vec::new())
}

/// Compiles a scenario whose vehicle is already loaded; `extra` adds the problems of keys that
/// upper layers interpret, so that every problem is reported at once.
pub fn compile_scenario_with(
    spec: &ScenarioSpec,
    mut vehicle: VehicleModel,
    base_dir: &Path,
    extra: ExtraChecks,
) -> Result<Scenario, Vec<SpecIssue>> {
    let mut c = Checker::default();
    let v = &spec.vehicle;
    c.finite("vehicle.x_m", &[v.x_m, v.y_m, v.yaw_deg, v.pitch_deg]);
    if let Some(z) = v.z_m {
        c.finite("vehicle.z_m", &[z]);
    }
    if let Some(f) = v.track_friction {
        c.non_negative("vehicle.track_friction", f, "");
        for t in &mut vehicle.tracks {
            t.friction = f;
        }
    }
    if let Some(m) = v.body_mass_kg {
        c.positive("vehicle.body_mass_kg", m, "kg");
        vehicle.body.inertia *= m / vehicle.body.mass;
        vehicle.body.mass = m;
    }
    if let Some(m) = v.belt_mass_kg {
        c.positive("vehicle.belt_mass_kg", m, "kg");
        for t in &mut vehicle.tracks {
            t.belt_mass = m;
        }
    }
    if let Some(n) = v.grouser_count {
        if n > 0 && vehicle.tracks.iter().all(|t| t.grousers.is_none()) {
            c.push(
                "vehicle.grouser_count",
                "the vehicle's tracks have no grousers to count; add a [tracks.grousers] table to the vehicle file (0 is the only count that applies)",
            );
        }
        for t in &mut vehicle.tracks {
            if n == 0 {
                t.grousers = None;
            } else if let Some(g) = &mut t.grousers {
                if n % g.shapes.len() != 0 {
                    c.push(
                        "vehicle.grouser_count",
                        format!(
                            "must be a multiple of the {} grouser shapes",
                            g.shapes.len()
                        ),
                    );
                }
                g.layout.count = n;
            }
        }
    }
    // Terrain.
    let terrain = crate::terrain::compile_terrain(&spec.terrain, base_dir, &mut c.issues);
    // Simulation.
    let s = &spec.simulation;
    if !(s.dt_s.is_finite() && s.dt_s > 0.0 && s.dt_s <= 0.01) {
        c.push(
            "simulation.dt_s",
            format!(
                "must be > 0 and at most 0.01 s (tracks with grousers need 1-2 ms), got {}",
                s.dt_s
            ),
        );
    }
    c.positive("simulation.duration_s", s.duration_s, "s");
    c.positive("simulation.output_interval_s", s.output_interval_s, "s");
    c.non_negative("simulation.min_link_mass_kg", s.min_link_mass_kg, "kg");
    c.positive(
        "simulation.prediction_distance_m",
        s.prediction_distance_m,
        "m",
    );
    if !(s.contact_slop_m.is_finite() && (0.0..=0.02).contains(&s.contact_slop_m)) {
        c.push(
            "simulation.contact_slop_m",
            format!(
                "must be between 0 and 0.02 m (the paper's simulator used 0.01), got {}",
                s.contact_slop_m
            ),
        );
    }
    if s.solver_iterations == 0 || s.solver_iterations > 100 {
        c.push(
            "simulation.solver_iterations",
            format!("must be between 1 and 100, got {}", s.solver_iterations),
        );
    }
    // Commands.
    let mut commands = Vec::new();
    let nt = vehicle.tracks.len();
    let mut last_t = f64::NEG_INFINITY;
    for (i, cmd) in spec.commands.iter().enumerate() {
        let k = format!("commands[{i}]");
        if !(cmd.t_s.is_finite() && cmd.t_s >= 0.0) {
            c.push(
                format!("{k}.t_s"),
                format!("must be >= 0 s, got {}", cmd.t_s),
            );
        } else if cmd.t_s < last_t {
            c.push(
                format!("{k}.t_s"),
                "commands must be listed in order of time",
            );
        }
        last_t = cmd.t_s;
        let mut belt = vec![None; nt];
        if cmd.belt_speed_mps.is_some() && cmd.sprocket_rad_s.is_some() {
            c.push(k.clone(), "give belt_speed_mps or sprocket_rad_s, not both");
        }
        let given = [
            ("belt_speed_mps", &cmd.belt_speed_mps, false),
            ("sprocket_rad_s", &cmd.sprocket_rad_s, true),
        ];
        for (key, values, sprocket) in given {
            let Some(values) = values else { continue };
            let entries: Vec<(usize, f64, String)> = match values {
                PerTrack::All(x) => (0..nt).map(|j| (j, *x, format!("{k}.{key}"))).collect(),
                PerTrack::ByName(m) => {
                    let mut e = Vec::new();
                    for (name, x) in m {
                        match vehicle.track_index(name) {
                            Some(j) => e.push((j, *x, format!("{k}.{key}.{name}"))),
                            None => c.push(
                                format!("{k}.{key}.{name}"),
                                format!(
                                    "no track called \"{name}\"; the vehicle has {}",
                                    vehicle
                                        .tracks
                                        .iter()
                                        .map(|t| format!("\"{}\"", t.name))
                                        .collect::<Vec<_>>()
                                        .join(", ")
                                ),
                            ),
                        }
                    }
                    e
                }
            };
            for (j, x, kk) in entries {
                let scale = if sprocket {
                    vehicle.tracks[j].sprocket_radius
                } else {
                    Some(1.0)
                };
                if !x.is_finite() {
                    c.push(kk, format!("must be finite, got {x}"));
                } else if let Some(f) = scale {
                    belt[j] = Some(x * f);
                } else {
                    c.push(
                        kk,
                        format!(
                            "track \"{}\" has no sprocket_pitch_radius_m; give belt_speed_mps instead or add the radius to the vehicle file",
                            vehicle.tracks[j].name
                        ),
                    );
                }
            }
        }
        match (cmd.forward_mps, cmd.yaw_rate_rad_s) {
            (None, None) => {}
            (v_fwd, w) => {
                let (v_fwd, w) = (v_fwd.unwrap_or(0.0), w.unwrap_or(0.0));
                if cmd.belt_speed_mps.is_some() || cmd.sprocket_rad_s.is_some() {
                    c.push(
                        k.clone(),
                        "give forward_mps/yaw_rate_rad_s or per-track speeds, not both",
                    );
                }
                if !(v_fwd.is_finite() && w.is_finite()) {
                    c.push(k.clone(), "forward_mps and yaw_rate_rad_s must be finite");
                }
                belt = Controls::twist(&vehicle, v_fwd, w).belt_speed;
            }
        }
        let mut flip = vec![None; vehicle.flippers.len()];
        for (name, a) in &cmd.flipper_angle_deg {
            match vehicle.flipper_index(name) {
                Some(j) if a.is_finite() => flip[j] = Some(a.to_radians()),
                Some(_) => c.push(
                    format!("{k}.flipper_angle_deg.{name}"),
                    format!("must be finite, got {a}"),
                ),
                None => c.push(
                    format!("{k}.flipper_angle_deg.{name}"),
                    format!("no flipper called \"{name}\""),
                ),
            }
        }
        commands.push(Command {
            t: cmd.t_s,
            controls: Controls {
                belt_speed: belt,
                flipper_angle: flip,
            },
        });
    }
    for issue in extra(spec) {
        c.issues.push(issue);
    }
    let o = &spec.outcome;
    if let Some(x) = o.success_x_m {
        c.finite("outcome.success_x_m", &[x]);
    }
    if let Some(z) = o.success_z_m {
        c.finite("outcome.success_z_m", &[z]);
    }
    if !(o.max_tilt_deg.is_finite() && o.max_tilt_deg > 0.0 && o.max_tilt_deg <= 180.0) {
        c.push(
            "outcome.max_tilt_deg",
            format!("must be in (0, 180] degrees, got {}", o.max_tilt_deg),
        );
    }
    if !c.issues.is_empty() {
        // One line per problem even where a value applies to every track.
        let mut seen = Vec::new();
        c.issues.retain(|i| {
            let new = !seen.contains(i);
            seen.push(i.clone());
            new
        });
        return Err(c.issues);
    }
    Ok(Scenario {
        outcome: OutcomeModel {
            success_x: o.success_x_m,
            success_z: o.success_z_m,
            max_tilt: o.max_tilt_deg.to_radians(),
            fail_off_terrain: o.fail_off_terrain,
            stop: o.stop,
        },
        method: s.method.clone(),
        seed: s.seed,
        source: None,
        description: spec.description.clone(),
        vehicle,
        start_xy: (v.x_m, v.y_m),
        start_z: v.z_m,
        start_yaw: v.yaw_deg.to_radians(),
        start_pitch: v.pitch_deg.to_radians(),
        terrain,
        solver: SolverSettings {
            dt: s.dt_s,
            iterations: s.solver_iterations,
            contact_clustering: s.contact_clustering,
            min_link_mass: s.min_link_mass_kg,
            prediction_distance: s.prediction_distance_m,
            contact_slop: s.contact_slop_m,
        },
        duration: s.duration_s,
        output_interval: s.output_interval_s,
        commands,
    })
}

/// Loads a scenario file and the vehicle file it names (relative to the scenario's folder);
/// `extra` as in [`compile_scenario_with`].
pub fn load_scenario_with(path: &Path, extra: ExtraChecks) -> Result<Scenario> {
    let spec: ScenarioSpec = read_toml(path)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let invalid = |issues| Error::Invalid {
        path: path.to_path_buf(),
        issues,
    };
    let vehicle = match (&spec.vehicle.file, &spec.vehicle.inline) {
        (Some(file), None) => {
            let vpath = dir.join(file);
            if !vpath.is_file() {
                return Err(invalid(vec![SpecIssue::new(
                    "vehicle.file",
                    format!(
                        "vehicle file {} not found (paths are relative to the scenario file's folder)",
                        vpath.display()
                    ),
                )]));
            }
            load_vehicle(&vpath)?
        }
        (None, Some(inline)) => compile_vehicle(inline).map_err(|issues| {
            invalid(
                issues
                    .into_iter()
                    .map(|i| SpecIssue::new(format!("vehicle.inline.{}", i.key), i.message))
                    .collect(),
            )
        })?,
        _ => {
            return Err(invalid(vec![SpecIssue::new(
                "vehicle",
                "give exactly one of `file` (a vehicle file) or `[vehicle.inline]`",
            )]));
        }
    };
    let mut sc = compile_scenario_with(&spec, vehicle, dir, extra).map_err(invalid)?;
    sc.source = Some(path.to_path_buf());
    Ok(sc)
}
