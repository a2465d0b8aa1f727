//! URDF import (`urdf = "robot.urdf"` in a vehicle file): the robot's links and joints become
//! tracksim's chassis and flipper arms; the tracks stay in the vehicle file and name the link
//! that carries each. A parser of its own: it imports nothing of `model/`, which compiles what
//! it reads (`model/compile_urdf.rs`).
//!
//! - `source.rs`: reading the file (urdf-rs for the robot, roxmltree for line numbers,
//!   `<inertial>` presence and the Gazebo extensions), refusing xacro.
//! - `gazebo.rs`: the `TrackedVehicle` plugin block and `<mu1>` friction.
//! - `tree.rs`: the joint tree from the root link: fixed and continuous joints merged into
//!   their parent, revolute joints on the chassis as arms; loops, second parents, unknown
//!   links and unsupported joint types refused with the element named.
//! - `inertial.rs`: each link's mass and inertia checked (positive, positive definite,
//!   triangle inequality) and moved into the chassis frame; parts merged.
//! - `pose.rs`: a URDF `<origin>` as a transform;
//! - `shapes.rs`: collision geometry (box, cylinder, sphere, mesh as its convex hull).
//! - `hull.rs`: a mesh's convex hull, its volume checked before parry builds it.
//! - `mesh.rs`: mesh files (STL, OBJ, COLLADA with mesh-loader), bounded, each read and
//!   hulled once per load.
//! - `limits.rs`: the size bounds checked before a parser sees a file (XML nesting depth,
//!   element, link, joint and collision counts; COLLADA counts against their data).
//! - `numbers.rs`: every number of the robot within the f32 engine's bounds (the TOML
//!   checker's).
//! - `guard.rs`: a dependency's panic (mesh-loader, parry) caught at the call and turned into
//!   an error.
//! - `link.rs`: the imported links, arms and mass parts, and the body each link becomes part of;
//! - `robot.rs`: the robot read, walked and checked ([`UrdfRobot`]);
//! - `report.rs`: what `tracksim check` prints.
//! - `sdf/`: SDFormat files: a `<model>` converted into the same robot a URDF gives (so the
//!   tree walk, the checks and the compile are shared), and a `<world>`'s static models as
//!   terrain ([`sdf::world_terrain`]).
//!
//! Frames: every pose here is in the chassis (root link) frame with all arms at angle 0, the
//! frame tracksim's vehicle model uses.

mod gazebo;
mod guard;
mod hull;
mod inertial;
mod limits;
mod link;
mod mesh;
mod numbers;
mod pose;
mod report;
mod robot;
pub mod sdf;
mod shapes;
mod source;
mod tree;

pub use gazebo::TrackedVehiclePlugin;
pub use limits::{MAX_COLLISIONS, MAX_JOINTS, MAX_LINKS, MAX_XML_DEPTH, MAX_XML_ELEMENTS};
pub use link::{ImportedArm, ImportedLink, JointRoles, LinkJoint, MassPart, Owner};
pub use mesh::{MAX_MESH_TRIANGLES, MAX_ROBOT_MESH_BYTES};
pub use report::{JointFrame, LinkLine, UrdfReport};
pub use robot::{MAX_REPORTED_ISSUES, UrdfRobot};
pub use source::MAX_URDF_BYTES;
