//! What the importer makes of a URDF file's links and joints: how each link joins its parent
//! ([`LinkJoint`]), the body it becomes part of ([`Owner`]), the links ([`ImportedLink`]), the
//! arms ([`ImportedArm`]) and merged mass properties ([`MassPart`]).

use crate::geometry::CollisionShape;
use glam::{DAffine3, DMat3, DVec3};

/// The simulated body a link becomes part of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Owner {
    /// The chassis (the root link and everything fixed or continuous on it).
    Chassis,
    /// The arm (flipper) with this index, in joint-tree order.
    Arm(usize),
}

/// How a link joins its parent.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LinkJoint {
    /// The root link: the chassis.
    Root,
    /// A fixed joint: merged into its parent.
    Fixed,
    /// A continuous joint (a wheel, sprocket or idler inside a track): its mass is merged into
    /// its parent, its collisions are dropped (the belt rolls, not the wheel).
    Continuous,
    /// A revolute joint on the chassis: a flipper arm.
    Revolute,
}

/// What the vehicle file says about the robot's joints before the tree is walked.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct JointRoles {
    /// Joints kept rigid (fixed at angle 0): a lidar gimbal, a pan-tilt head (`rigid_joints`).
    pub rigid: Vec<String>,
    /// If given, the only revolute or continuous joints that are flipper arms; every other
    /// revolute joint is kept rigid (`flipper_joints`).
    pub flippers: Option<Vec<String>>,
    /// Links that carry a track of the vehicle file: a continuous joint on the chassis whose
    /// child carries a track is a flipper arm without limits (not a wheel inside a track).
    pub track_links: Vec<String>,
}

impl JointRoles {
    /// Whether joint `name` is kept rigid.
    pub fn is_rigid(&self, name: &str) -> bool {
        self.rigid.iter().any(|j| j == name)
    }

    /// Whether joint `name` is named a flipper (`None`: no list given).
    pub fn named_flipper(&self, name: &str) -> Option<bool> {
        self.flippers.as_ref().map(|f| f.iter().any(|j| j == name))
    }
}

/// One imported link.
#[derive(Clone, Debug)]
pub struct ImportedLink {
    /// Link name.
    pub name: String,
    /// The joint that carries it (`None` for the root).
    pub joint: Option<String>,
    /// How it joins its parent.
    pub kind: LinkJoint,
    /// The body it is part of: the chassis or an arm.
    pub owner: Owner,
    /// Its frame in the chassis frame (arms at angle 0).
    pub pose: DAffine3,
    /// Its mass, kg (0 without `<inertial>`).
    pub mass: f64,
    /// Its collision shapes in the chassis frame.
    pub shapes: Vec<CollisionShape>,
}

/// Mass properties of a rigid part, in the chassis frame.
#[derive(Clone, Copy, Debug)]
pub struct MassPart {
    /// Mass, kg.
    pub mass: f64,
    /// Centre of mass, m.
    pub com: DVec3,
    /// Inertia tensor about the centre of mass, kg m^2.
    pub inertia: DMat3,
}

/// A revolute joint on the chassis: a flipper arm.
#[derive(Clone, Debug)]
pub struct ImportedArm {
    /// Joint name (the flipper's name in commands and outputs).
    pub joint: String,
    /// Child link name.
    pub link: String,
    /// Joint origin in the chassis frame, m.
    pub pivot: DVec3,
    /// Unit joint axis in the chassis frame.
    pub axis: DVec3,
    /// `<limit lower upper>`, rad (`None` when unbounded).
    pub limits: Option<[f64; 2]>,
    /// `<limit effort>`, N m.
    pub effort: f64,
}
