//! What `tracksim check` prints of an imported URDF robot: every link with its joint, the body
//! it became part of, its mass, whether its collision shapes are used, and the tracks it
//! carries; then the arms with their limits and torque, and the Gazebo plugin's links.

use super::LinkJoint;

/// One link in the report.
#[derive(Clone, Debug, PartialEq)]
pub struct LinkLine {
    /// Link name.
    pub name: String,
    /// Joint that carries it and its type (`None` for the root).
    pub joint: Option<String>,
    /// How it joins its parent.
    pub kind: LinkJoint,
    /// The simulated body it is part of: `chassis` or the arm's joint name.
    pub body: String,
    /// Mass, kg.
    pub mass: f64,
    /// Collision shapes in the URDF.
    pub shapes: usize,
    /// Why its shapes are not used, if they are not.
    pub shapes_dropped: Option<&'static str>,
    /// Tracks it carries.
    pub tracks: Vec<String>,
}

/// What was imported from a URDF file.
#[derive(Clone, Debug, PartialEq)]
pub struct UrdfReport {
    /// The URDF (or SDF) file.
    pub file: std::path::PathBuf,
    /// Its format: `"URDF"` or `"SDF"`.
    pub format: &'static str,
    /// `<robot name>`.
    pub robot: String,
    /// Every link.
    pub links: Vec<LinkLine>,
    /// One line per arm (flipper joint).
    pub arms: Vec<String>,
    /// Notes (plugin, friction, what is not used).
    pub notes: Vec<String>,
    /// The root link's name.
    pub root: String,
    /// Every joint of the file as a transform parent -> child (for `/tf` and `/tf_static`).
    pub joints: Vec<JointFrame>,
}

/// A URDF joint as the transform from its parent link to its child link.
#[derive(Clone, Debug, PartialEq)]
pub struct JointFrame {
    /// Joint name.
    pub name: String,
    /// Parent link.
    pub parent: String,
    /// Child link.
    pub child: String,
    /// The joint's `<origin>`: position of the child's frame in the parent's, m.
    pub origin: glam::DVec3,
    /// The joint's `<origin>` rotation.
    pub rotation: glam::DQuat,
    /// Unit axis (joint frame).
    pub axis: glam::DVec3,
    /// Whether it turns (revolute or continuous, not locked by equal limits).
    pub moving: bool,
    /// The angle it is held at when it does not move (a locked revolute joint's), rad.
    pub locked_angle: f64,
}

impl UrdfReport {
    /// The report as lines of text.
    pub fn lines(&self) -> Vec<String> {
        let mut out = vec![format!(
            "{} {} (robot \"{}\"): {} links",
            self.format,
            self.file.display(),
            self.robot,
            self.links.len()
        )];
        for l in &self.links {
            let joint = match (&l.joint, l.kind) {
                (None, _) => "root".to_string(),
                (Some(j), k) => format!("{} joint {j}", format!("{k:?}").to_ascii_lowercase()),
            };
            let shapes = match (l.shapes, l.shapes_dropped) {
                (0, _) => "no collision".to_string(),
                (n, None) => format!("{n} collision shape(s)"),
                (n, Some(why)) => format!("{n} collision shape(s) not used: {why}"),
            };
            let tracks = if l.tracks.is_empty() {
                String::new()
            } else {
                format!(", carries track {}", l.tracks.join(", "))
            };
            out.push(format!(
                "  link {}: {joint}, part of {}, {:.3} kg, {shapes}{tracks}",
                l.name, l.body, l.mass
            ));
        }
        out.extend(self.arms.iter().map(|a| format!("  arm {a}")));
        out.extend(self.notes.iter().map(|n| format!("  note: {n}")));
        out
    }
}
