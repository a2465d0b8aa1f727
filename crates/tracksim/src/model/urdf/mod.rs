//! URDF import (`urdf = "robot.urdf"` in a vehicle file): the robot's links and joints become
//! tracksim's chassis and flipper arms; the tracks stay in the vehicle file and name the link
//! that carries each.
//!
//! - `source.rs`: reading the file (urdf-rs for the robot, roxmltree for line numbers,
//!   `<inertial>` presence and the Gazebo extensions), refusing xacro.
//! - `gazebo.rs`: the `TrackedVehicle` plugin block and `<mu1>` friction.
//! - `tree.rs`: the joint tree from the root link: fixed and continuous joints merged into
//!   their parent, revolute joints on the chassis as arms; loops, second parents, unknown
//!   links and unsupported joint types refused with the element named.
//! - `inertial.rs`: each link's mass and inertia checked (positive, positive definite,
//!   triangle inequality) and moved into the chassis frame; parts merged.
//! - `shapes.rs`: collision geometry (box, cylinder, sphere, mesh as its convex hull).
//! - `mesh.rs`: mesh files (STL, OBJ, COLLADA with mesh-loader), bounded.
//! - `report.rs`: what `tracksim check` prints.
//!
//! Frames: every pose here is in the chassis (root link) frame with all arms at angle 0, the
//! frame tracksim's vehicle model uses.

mod gazebo;
mod inertial;
mod mesh;
mod report;
mod shapes;
mod source;
mod tree;

pub use gazebo::TrackedVehiclePlugin;
pub use report::{LinkLine, UrdfReport};
pub(crate) use source::UrdfSource;

use super::{CollisionShape, Parent};
use crate::error::SpecIssue;
use glam::{DAffine3, DMat3, DVec3};
use std::path::Path;

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
    pub owner: Parent,
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

/// A URDF robot, imported and checked.
#[derive(Clone, Debug)]
pub struct UrdfRobot {
    /// The file.
    pub file: std::path::PathBuf,
    /// `<robot name>`.
    pub name: String,
    /// Every link, the root first, then in joint-tree order.
    pub links: Vec<ImportedLink>,
    /// The arms (flippers), in joint-tree order.
    pub arms: Vec<ImportedArm>,
    /// The tracked-vehicle plugin block, if any.
    pub plugin: Option<TrackedVehiclePlugin>,
    /// Gazebo `<mu1>` of the root link.
    pub root_friction: Option<f64>,
    /// Line-numbered names of links and joints, for messages.
    source: std::sync::Arc<UrdfSource>,
}

impl UrdfRobot {
    /// Reads and checks `path` (relative paths inside it, meshes, are relative to its folder).
    pub fn load(path: &Path) -> Result<UrdfRobot, Vec<SpecIssue>> {
        let src = UrdfSource::read(path)?;
        let mut issues = Vec::new();
        for (element, text) in &src.gazebo.unreadable {
            issues.push(SpecIssue::new(
                source::key(element),
                format!("`{}` is not a number", crate::check::echoed(text)),
            ));
        }
        let (links, arms) = tree::walk(&src, &mut issues);
        if let Some(p) = &src.gazebo.plugin {
            for (tag, l) in p.track_links() {
                // Against the file's links, not the tree walked: a broken tree is its own
                // message, not one per plugin link it did not reach.
                if !src.robot.links.iter().any(|k| k.name == l) {
                    issues.push(SpecIssue::new(
                        source::key(&p.at(tag)),
                        format!(
                            "names link \"{}\", which the URDF does not have",
                            crate::check::echoed(l)
                        ),
                    ));
                }
            }
        }
        if !issues.is_empty() {
            return Err(issues);
        }
        let root_friction = links
            .first()
            .and_then(|r| src.gazebo.friction.get(&r.name).copied());
        Ok(UrdfRobot {
            file: path.to_path_buf(),
            name: src.robot.name.clone(),
            links,
            arms,
            plugin: src.gazebo.plugin.clone(),
            root_friction,
            source: std::sync::Arc::new(src),
        })
    }

    /// The link called `name`.
    pub fn link(&self, name: &str) -> Option<&ImportedLink> {
        self.links.iter().find(|l| l.name == name)
    }

    /// `<link name="NAME"> (FILE line N)`, for messages.
    pub fn describe_link(&self, name: &str) -> String {
        self.source.link(name)
    }

    /// `<joint name="NAME"> (FILE line N)`, for messages.
    pub fn describe_joint(&self, name: &str) -> String {
        self.source.joint(name)
    }

    /// The merged mass properties of `owner` (chassis or arm), with the per-link checks'
    /// problems in `issues`.
    pub fn mass_part(&self, owner: Parent, issues: &mut Vec<SpecIssue>) -> MassPart {
        inertial::merged(&self.source, &self.links, owner, issues)
    }
}
