//! Vehicle files (`vehicles/*.toml`): the chassis, flipper arms, tracks, their paths and
//! grousers, with their serde defaults. Unknown keys are rejected; units are SI unless the key
//! name says otherwise (`angle_deg`).

use serde::{Deserialize, Serialize};

/// A vehicle file (`vehicles/*.toml`).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct VehicleSpec {
    /// Display name.
    pub name: String,
    /// One-line description.
    #[serde(default)]
    pub description: String,
    /// The robot's URDF or SDF file (path relative to this file; told by its root element,
    /// `<robot>` or `<sdf>`, not by its extension): the chassis and the flipper arms
    /// (masses, inertias, collision shapes, revolute joints with limits and effort) come from
    /// it instead of `[body]` and `[[flippers]]`, and each track names the URDF link that
    /// carries it (`link`). `docs/URDF.md`.
    #[serde(default)]
    pub urdf: Option<String>,
    /// Friction coefficient of the chassis and arm surfaces of a URDF robot (default: the
    /// root link's Gazebo `<mu1>`, else 0.6).
    #[serde(default)]
    pub body_friction: Option<f64>,
    /// Control of a URDF robot's revolute joints (the flippers), by joint name: what URDF does
    /// not say (position gains, start angle) or overrides (`effort`).
    #[serde(default)]
    pub joints: std::collections::BTreeMap<String, JointSpec>,
    /// The chassis (not with `urdf`).
    #[serde(default)]
    pub body: Option<BodySpec>,
    /// Flipper arms carrying sub-tracks.
    #[serde(default)]
    pub flippers: Vec<FlipperSpec>,
    /// Tracks, on the body or on flippers.
    pub tracks: Vec<TrackSpec>,
    /// What the robot's encoders report (`odom_*` columns).
    #[serde(default)]
    pub odometry: Option<OdometrySpec>,
    /// Sensors on the chassis or a flipper (`[[sensors]]`, `docs/SENSORS.md`).
    #[serde(default)]
    pub sensors: Vec<super::SensorSpec>,
    /// Colours of the parts in camera images (`[colors]`).
    #[serde(default)]
    pub colors: Option<ColorsSpec>,
    /// How twist commands become belt speeds (`[steering]`).
    #[serde(default)]
    pub steering: Option<SteeringSpec>,
    /// URDF/SDF joints kept rigid (fixed at angle 0), e.g. a lidar gimbal's revolute joint.
    #[serde(default)]
    pub rigid_joints: Vec<String>,
    /// URDF/SDF joints that are the flipper arms (revolute or continuous); every other
    /// revolute joint is kept rigid (default: every revolute joint on the chassis, and every
    /// continuous joint whose link carries a track).
    #[serde(default)]
    pub flipper_joints: Option<Vec<String>>,
    /// The `<model name>` to read when `urdf` names an SDF file (default: the one model with
    /// a tracked-vehicle plugin, else the only non-static model). Not with a URDF file.
    /// `docs/URDF.md`, "SDF". (New keys go last: a table written as an array keeps its old
    /// fields' order.)
    #[serde(default)]
    pub sdf_model: Option<String>,
}

/// How a twist command (forward speed, yaw rate) becomes belt speeds (`[steering]`).
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SteeringSpec {
    /// One speed per side for every track on it, `v -+ w B / 2`, as Gazebo's `TrackedVehicle`
    /// (default: true when the URDF/SDF tracked-vehicle plugin names the sides, else false:
    /// each belt at `v - w y` for its own mid-plane).
    #[serde(default)]
    pub one_speed_per_side: Option<bool>,
    /// B of the per-side rule, m (default: the plugin's `tracks_separation`, else the
    /// distance between the mean left and mean right track mid-planes).
    #[serde(default)]
    pub track_separation_m: Option<f64>,
}

/// Colours of a vehicle's parts in camera images, each `"#rrggbb"` (`[colors]`).
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ColorsSpec {
    /// The chassis (default: the URDF root link's `<material><color>`, else olive drab).
    #[serde(default)]
    pub body: Option<String>,
    /// Belts and grousers (default black).
    #[serde(default)]
    pub tracks: Option<String>,
    /// Flipper arms (default dark olive).
    #[serde(default)]
    pub flippers: Option<String>,
}

/// The position controller of a URDF revolute joint (`[joints.NAME]`).
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct JointSpec {
    /// Position gain, N m / rad (default 2000).
    #[serde(default)]
    pub stiffness_nm_per_rad: Option<f64>,
    /// Velocity gain, N m s / rad (default 50).
    #[serde(default)]
    pub damping_nms_per_rad: Option<f64>,
    /// Angle at the start, degrees (default 0; within the joint's limits).
    #[serde(default)]
    pub initial_angle_deg: Option<f64>,
    /// Torque limit of the joint motor, N m (default: the URDF `<limit effort>`).
    #[serde(default)]
    pub max_torque_nm: Option<f64>,
}

/// A track's DC drive motor (`[tracks.motor]`).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MotorSpec {
    /// Stall torque at the motor shaft, N m (with `no_load_speed_rad_s`: the DC motor's
    /// linear torque-speed line).
    #[serde(default)]
    pub stall_torque_nm: Option<f64>,
    /// No-load speed of the motor shaft, rad/s.
    #[serde(default)]
    pub no_load_speed_rad_s: Option<f64>,
    /// Instead of the line: the torque-speed curve as `[speed rad/s, torque N m]` points from
    /// speed 0 up to the no-load speed (torque 0), interpolated linearly.
    #[serde(default)]
    pub torque_speed: Option<Vec<[f64; 2]>>,
    /// Gear ratio (motor turns per sprocket turn).
    pub gear_ratio: f64,
    /// Gearbox efficiency, in (0, 1].
    pub efficiency: f64,
    /// The driver's torque (current) limit at the motor shaft, N m (default: the stall torque).
    #[serde(default)]
    pub torque_limit_nm: Option<f64>,
    /// Supply voltage, V (with `stall_current_a`: the electrical model, current and power).
    #[serde(default)]
    pub voltage_v: Option<f64>,
    /// Current at stall at `voltage_v`, A.
    #[serde(default)]
    pub stall_current_a: Option<f64>,
    /// Current at no load at `voltage_v`, A (default 0).
    #[serde(default)]
    pub no_load_current_a: Option<f64>,
}

/// Skid-steer odometry settings.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct OdometrySpec {
    /// Effective track separation of the skid-steer model, m (default: the distance between
    /// the left and right chassis tracks' mid-planes; skid turns need more, see README).
    pub track_separation_m: Option<f64>,
}

/// A collision shape.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum ShapeSpec {
    /// A box of full sizes `size_m` = [x, y, z] centred at `centre_m`.
    Box {
        /// Full sizes along x, y, z, m.
        size_m: [f64; 3],
        /// Centre, m.
        #[serde(default)]
        centre_m: [f64; 3],
    },
    /// The convex hull of points, m.
    Convex {
        /// Points, m.
        points_m: Vec<[f64; 3]>,
    },
}

/// The vehicle body (chassis).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Mass, kg.
    pub mass_kg: f64,
    /// Centre of mass in the body frame, m.
    #[serde(default)]
    pub centre_of_mass_m: [f64; 3],
    /// Principal moments of inertia about the centre of mass along the body axes, kg m^2.
    /// Default: those of a solid box filling the shape's bounding box.
    #[serde(default)]
    pub inertia_kgm2: Option<[f64; 3]>,
    /// Collision shape.
    pub shape: ShapeSpec,
    /// Friction coefficient of the body's own surface.
    #[serde(default = "default_friction")]
    pub friction: f64,
}

/// A flipper arm on a position-controlled revolute joint.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FlipperSpec {
    /// Name, used by tracks (`parent`) and commands.
    pub name: String,
    /// Joint position in the body frame, m.
    pub pivot_m: [f64; 3],
    /// Joint axis in the body frame; a positive angle turns the arm about it (right-hand rule).
    #[serde(default = "default_axis")]
    pub axis: [f64; 3],
    /// Mass of the arm (without its track belt), kg.
    pub mass_kg: f64,
    /// Centre of mass in the body frame at angle 0, m. Default: the pivot.
    #[serde(default)]
    pub centre_of_mass_m: Option<[f64; 3]>,
    /// Principal moments of inertia, kg m^2. Default: a slender arm's.
    #[serde(default)]
    pub inertia_kgm2: Option<[f64; 3]>,
    /// Optional collision shape of the arm itself, in the body frame at angle 0.
    #[serde(default)]
    pub shape: Option<ShapeSpec>,
    /// Angle at the start, degrees.
    #[serde(default)]
    pub initial_angle_deg: f64,
    /// Torque limit of the joint motor, N m.
    pub max_torque_nm: f64,
    /// Position gain, N m / rad.
    #[serde(default = "default_flipper_stiffness")]
    pub stiffness_nm_per_rad: f64,
    /// Velocity gain, N m s / rad.
    #[serde(default = "default_flipper_damping")]
    pub damping_nms_per_rad: f64,
}

/// One continuous track.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TrackSpec {
    /// Name, used by commands and outputs.
    pub name: String,
    /// If set, a mirror image of this track (y -> -y) is added under this name.
    #[serde(default)]
    pub mirror: Option<String>,
    /// What the mirrored copy hangs on (default: the same as `parent`).
    #[serde(default)]
    pub mirror_parent: Option<String>,
    /// What the track hangs on: "body" (default) or a flipper's name (not with `urdf`).
    #[serde(default = "default_parent")]
    pub parent: String,
    /// With `urdf`: the URDF link that carries the track; its path and grousers are given in
    /// that link's frame.
    #[serde(default)]
    pub link: Option<String>,
    /// With `urdf` and `mirror`: the link that carries the mirror image (default: `link`). The
    /// image is taken in the chassis frame (y -> -y).
    #[serde(default)]
    pub mirror_link: Option<String>,
    /// Belt width across the track, m.
    pub width_m: f64,
    /// Belt thickness (inwards from the path), m.
    #[serde(default = "default_belt_thickness")]
    pub belt_thickness_m: f64,
    /// Mass of the whole belt with its grousers, split over the segment links by length, kg.
    pub belt_mass_kg: f64,
    /// Friction coefficient of the belt and grousers.
    #[serde(default = "default_friction")]
    pub friction: f64,
    /// How belt friction combines with the other surface's: "min" (default, as in Gazebo/ODE),
    /// "average", "multiply", "max".
    #[serde(default = "default_combine")]
    pub friction_combine: String,
    /// Sprocket pitch radius, m, for commands given as sprocket angular speed.
    #[serde(default)]
    pub sprocket_pitch_radius_m: Option<f64>,
    /// Indices of segments that never touch anything and need no link (e.g. the top run).
    #[serde(default)]
    pub omit_segments: Vec<usize>,
    /// Indices of segments that never touch anything but keep their link (its mass, joint and
    /// motor: the belt's momentum) without colliders, e.g. the top run (okada2020 family).
    #[serde(default)]
    pub no_contact_segments: Vec<usize>,
    /// The loop.
    pub path: PathSpec,
    /// Grousers; none if absent.
    #[serde(default)]
    pub grousers: Option<GrouserSpec>,
    /// Optional contact compliance of the grousers and the belt (rubber); rigid if absent.
    #[serde(default)]
    pub compliance: Option<ComplianceSpec>,
    /// Drive motor behind a speed controller with a torque limit (okada2020 only; without it
    /// the belt runs at the commanded speed whatever the load).
    #[serde(default)]
    pub motor: Option<MotorSpec>,
}

/// Contact compliance of a track's rubber (`[tracks.compliance]`): each part that has a table
/// deflects along the contact normal as a spring and damper in parallel (Kelvin-Voigt); a part
/// without one keeps the engine's own (rigid, regularised) contact.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ComplianceSpec {
    /// Spring of one grouser against the terrain (per grouser and terrain piece).
    #[serde(default)]
    pub grousers: Option<ContactSpringSpec>,
    /// Spring of one belt link (the belt collider of a segment) against the terrain.
    #[serde(default)]
    pub belt: Option<ContactSpringSpec>,
}

/// A contact spring and damper in parallel, along the contact normal.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ContactSpringSpec {
    /// Stiffness, N/m (normal force per metre of deflection).
    pub stiffness_n_per_m: f64,
    /// Damping, N s/m (normal force per m/s of deflection rate).
    pub damping_ns_per_m: f64,
}

/// A track path, as pulleys, as explicit segments, or as a lugged wheel (exactly one of the
/// three).
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PathSpec {
    /// y of the track's mid-plane in the parent frame (pulley and wheel forms), m.
    #[serde(default)]
    pub plane_y_m: Option<f64>,
    /// A lugged wheel (paper Fig. 8): its axle centre and rim radius (where the lugs stand,
    /// `radius_m`); the track's `[grousers]` are its lugs, `width_m` its width, `belt_mass_kg`
    /// the mass of the rim and lugs. It compiles to one full-circle segment link whose belt
    /// speed is the wheel's rolling speed on flat ground.
    #[serde(default)]
    pub wheel: Option<PulleySpec>,
    /// Pulleys the belt wraps, in order around the loop (either sense).
    #[serde(default)]
    pub pulleys: Option<Vec<PulleySpec>>,
    /// Explicit segments in order of belt travel (paper Sec. III-A).
    #[serde(default)]
    pub segments: Option<Vec<SegmentSpec>>,
    /// The `segments` need not share a plane (straights in any direction, arcs about any axis;
    /// conveyors only, paper Fig. 8): the loop then carries only its grousers (the objects it
    /// moves), no belt surface.
    #[serde(default)]
    pub spatial: bool,
}

/// A pulley in the track's x-z plane.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PulleySpec {
    /// Centre x, m.
    pub x_m: f64,
    /// Centre z, m.
    pub z_m: f64,
    /// Radius to the belt's outer surface (grouser footprints), m.
    pub radius_m: f64,
}

/// An explicit path segment.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum SegmentSpec {
    /// Straight: start point, direction, length.
    Straight {
        /// Start, m.
        start_m: [f64; 3],
        /// Direction of belt travel (any length).
        direction: [f64; 3],
        /// Length, m.
        length_m: f64,
    },
    /// Arc: start point rotated about the axis through `centre_m` by `angle_deg`.
    Arc {
        /// Start, m.
        start_m: [f64; 3],
        /// A point on the axis, m.
        centre_m: [f64; 3],
        /// Rotation axis (right-hand rule).
        axis: [f64; 3],
        /// Rotation angle, degrees.
        angle_deg: f64,
    },
}

/// The grouser pattern.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct GrouserSpec {
    /// Number of grousers on the loop.
    pub count: usize,
    /// Arc length from the loop start to grouser 0's footprint, m (a pulley loop starts where
    /// the belt leaves the rearmost pulley: smallest x, then smallest z).
    #[serde(default)]
    pub offset_m: f64,
    /// Shapes, used in turn around the belt (grouser k gets shape k mod len).
    pub shapes: Vec<GrouserShapeSpec>,
}

/// A grouser shape, in its footprint frame: x along the belt, y across, z outwards.
#[derive(Clone, Debug, Deserialize, Serialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum GrouserShapeSpec {
    /// A cuboid standing on the belt.
    Box {
        /// Along the belt, m.
        length_m: f64,
        /// Outwards from the belt, m.
        height_m: f64,
        /// Across the belt, m (default: the track width).
        #[serde(default)]
        width_m: Option<f64>,
        /// Shift of the footprint centre along the belt, m.
        #[serde(default)]
        shift_m: f64,
    },
    /// A trapezoidal prism (cross-section in the x-z plane) extruded across the belt.
    Trapezoid {
        /// Base on the belt, m.
        bottom_m: f64,
        /// Top (outer) base, m.
        top_m: f64,
        /// Height, m.
        height_m: f64,
        /// Across the belt, m (default: the track width).
        #[serde(default)]
        width_m: Option<f64>,
        /// Shift along the belt, m.
        #[serde(default)]
        shift_m: f64,
    },
    /// The convex hull of points given in the footprint frame, m.
    Convex {
        /// Points, m.
        points_m: Vec<[f64; 3]>,
    },
}

fn default_friction() -> f64 {
    0.6
}
fn default_axis() -> [f64; 3] {
    [0.0, 1.0, 0.0]
}
fn default_parent() -> String {
    "body".into()
}
fn default_combine() -> String {
    "min".into()
}
fn default_belt_thickness() -> f64 {
    0.01
}
fn default_flipper_stiffness() -> f64 {
    2000.0
}
fn default_flipper_damping() -> f64 {
    50.0
}
