//! The compiled vehicle: chassis, flippers and tracks with their collision and grouser shapes,
//! in SI units and radians, as [`compile_vehicle`](super::compile_vehicle) produces them.

pub use crate::geometry::CollisionShape;
use crate::geometry::{GrouserLayout, TrackPath};
use glam::DVec3;
use rapier3d::prelude::CoefficientCombineRule;

/// The chassis.
#[derive(Clone, Debug)]
pub struct BodyModel {
    /// Mass, kg.
    pub mass: f64,
    /// Centre of mass in the body frame, m.
    pub com: DVec3,
    /// Principal inertia along the body axes, kg m^2.
    pub inertia: DVec3,
    /// Products of inertia [Ixy, Ixz, Iyz] about the centre of mass in the body axes, kg m^2
    /// (0 for a file's `[body]`; a URDF robot's merged links may have them).
    pub inertia_products: DVec3,
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
    /// Products of inertia [Ixy, Ixz, Iyz] in the body axes at angle 0, kg m^2.
    pub inertia_products: DVec3,
    /// Joint limits [lower, upper], rad (URDF `<limit>`; `None`: free).
    pub limits: Option<[f64; 2]>,
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
    /// A lugged wheel's rim depth below its path (the rolling circle), m: the rim collider's
    /// radius is the path's less this; 0 for a belt.
    pub rim_inset: f64,
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
    /// Which included segments carry colliders (false: a link for the belt's momentum only).
    pub touching: Vec<bool>,
    /// Grousers, if any.
    pub grousers: Option<GrouserModel>,
    /// Contact compliance of the grousers and the belt (default: rigid).
    pub compliance: super::Compliance,
    /// Drive motor (None: the belt runs at the commanded speed whatever the load).
    pub motor: Option<super::DriveMotor>,
}

/// A compiled vehicle.
#[derive(Clone, Debug)]
pub struct VehicleModel {
    /// Colours of the parts in camera images.
    pub colors: VehicleColors,
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
    /// Effective track separation of the skid-steer odometry, m (`None`: geometric).
    pub odometry_separation: Option<f64>,
    /// How twist commands become belt speeds.
    pub steering: super::Steering,
    /// Sensors (`[[sensors]]`), in file order.
    pub sensors: Vec<super::SensorModel>,
    /// What was imported from a URDF file (`urdf`), for `tracksim check`.
    pub urdf: Option<super::UrdfReport>,
}

impl TrackModel {
    /// Lateral position (y) of the track's mid-plane in its parent frame, m (a flipper's frame
    /// is the chassis frame at angle 0, so this is the chassis-frame offset).
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

    /// Each track's mid-plane offset y in the chassis frame, m (a flipper track's at angle 0;
    /// turning an arm about its y axis does not move it sideways).
    pub fn track_offsets(&self) -> Vec<f64> {
        self.tracks.iter().map(TrackModel::lateral_offset).collect()
    }

    /// Belt speed of track `i`, m/s, for forward speed `forward` m/s and yaw rate `yaw_rate`
    /// rad/s by the vehicle's [`super::Steering`] rule.
    pub fn twist_belt_speed(&self, i: usize, forward: f64, yaw_rate: f64) -> f64 {
        self.steering
            .belt_speed(self.tracks[i].lateral_offset(), forward, yaw_rate)
    }
}

/// Colours of a vehicle's parts in camera images (`[colors]` of the vehicle file).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VehicleColors {
    /// The chassis.
    pub body: crate::render::Rgb,
    /// Belts and grousers.
    pub tracks: crate::render::Rgb,
    /// Flipper arms.
    pub flippers: crate::render::Rgb,
}

impl Default for VehicleColors {
    fn default() -> Self {
        use crate::render::palette;
        VehicleColors {
            body: palette::BODY,
            tracks: palette::TRACK,
            flippers: palette::FLIPPER,
        }
    }
}
