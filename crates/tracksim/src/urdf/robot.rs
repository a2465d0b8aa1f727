//! A URDF robot read, walked and checked ([`UrdfRobot`]).

use super::link::{ImportedArm, ImportedLink, JointRoles, MassPart, Owner};
use super::mesh::MeshCache;
use super::source::{self, UrdfSource};
use super::{TrackedVehiclePlugin, inertial, numbers, tree};
use crate::error::SpecIssue;
use std::path::Path;

/// Most problems listed for one robot file (200 collisions with one bad scale are one
/// mistake, not 200 lines).
pub const MAX_REPORTED_ISSUES: usize = 10;

/// A URDF robot, imported and checked.
#[derive(Clone, Debug)]
pub struct UrdfRobot {
    /// The file.
    pub file: std::path::PathBuf,
    /// `<robot name>` (an SDF file's `<model name>`).
    pub name: String,
    /// The file's format: `"URDF"` or `"SDF"`.
    pub format: &'static str,
    /// Every link, the root first, then in joint-tree order.
    pub links: Vec<ImportedLink>,
    /// The arms (flippers), in joint-tree order.
    pub arms: Vec<ImportedArm>,
    /// The tracked-vehicle plugin block, if any.
    pub plugin: Option<TrackedVehiclePlugin>,
    /// Gazebo `<mu1>` of the root link (SDF: its collisions' `<surface><friction><ode><mu>`).
    pub root_friction: Option<f64>,
    /// What was read but is probably a mistake (printed by `tracksim check`).
    pub warnings: Vec<String>,
    /// An SDF model's `<pose>` in its world: where the robot starts (m, rad; the vehicle
    /// itself is built in the model frame). `None` for a URDF, or a model without a pose.
    pub start_pose: Option<glam::DAffine3>,
    /// How many mesh files were read (each once, however many `<collision>`s name it).
    pub meshes_read: usize,
    /// Line-numbered names of links and joints, for messages.
    source: std::sync::Arc<UrdfSource>,
}

impl UrdfRobot {
    /// The colour of the root link's first `<visual>` with a `<material>` whose colour is
    /// given there or in the robot's named `<material>`s.
    pub fn root_color(&self) -> Option<crate::render::Rgb> {
        let robot = &self.source.robot;
        let root = robot
            .links
            .iter()
            .find(|l| Some(&l.name) == self.links.first().map(|r| &r.name))?;
        root.visual.iter().find_map(|v| {
            let m = v.material.as_ref()?;
            let rgba = m.color.as_ref().or_else(|| {
                robot
                    .materials
                    .iter()
                    .find(|n| n.name == m.name)?
                    .color
                    .as_ref()
            })?;
            let [r, g, b, _] = rgba.rgba.0;
            [r, g, b]
                .iter()
                .all(|v| v.is_finite())
                .then(|| crate::render::Rgb::from_unit(r, g, b))
        })
    }

    /// Every joint of the file as a transform parent -> child; `moving` for the flipper arms'
    /// joints only (a locked joint at its angle, a rigid one at 0, a wheel's not turned).
    pub fn joint_frames(&self) -> Vec<super::JointFrame> {
        self.source
            .robot
            .joints
            .iter()
            .map(|j| {
                let p = super::pose::pose(&j.origin);
                let (_, rotation, origin) = p.to_scale_rotation_translation();
                let axis = glam::DVec3::from_array(j.axis.xyz.0).normalize_or_zero();
                let locked = matches!(j.joint_type, urdf_rs::JointType::Revolute)
                    && j.limit.lower == j.limit.upper;
                super::JointFrame {
                    name: j.name.clone(),
                    parent: j.parent.link.clone(),
                    child: j.child.link.clone(),
                    origin,
                    rotation,
                    axis,
                    moving: self.arms.iter().any(|a| a.joint == j.name),
                    locked_angle: if locked { j.limit.lower } else { 0.0 },
                }
            })
            .collect()
    }

    /// Reads and checks `path`, a URDF or an SDF file told by its root element (relative
    /// paths inside it, meshes, are relative to its folder); an SDF file's model is chosen as
    /// [`UrdfRobot::load_model`] does without a name.
    pub fn load(path: &Path) -> Result<UrdfRobot, Vec<SpecIssue>> {
        Self::load_model(path, None)
    }

    /// Reads and checks `path` (URDF or SDF); `sdf_model` names the SDF `<model>` to read
    /// (the vehicle file's `sdf_model`). Without it: the one model with a tracked-vehicle
    /// plugin, else the only non-static model (docs/URDF.md, "SDF"). A name given for a URDF
    /// file is refused.
    pub fn load_model(path: &Path, sdf_model: Option<&str>) -> Result<UrdfRobot, Vec<SpecIssue>> {
        Self::load_with(path, sdf_model, &JointRoles::default())
    }

    /// [`UrdfRobot::load_model`] with the vehicle file's joint roles (rigid joints, named
    /// flippers, the links carrying tracks).
    /// At most [`MAX_REPORTED_ISSUES`] problems are returned (the rest counted in a last one).
    pub fn load_with(
        path: &Path,
        sdf_model: Option<&str>,
        roles: &JointRoles,
    ) -> Result<UrdfRobot, Vec<SpecIssue>> {
        let file = path
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default();
        Self::load_unbounded(path, sdf_model, roles).map_err(|mut issues| {
            // Every problem names the file (the key names the element where there is one).
            for i in &mut issues {
                if !i.key.contains(&file) && !i.message.contains(&file) {
                    i.message = format!("{file}: {}", i.message);
                }
            }
            if issues.len() > MAX_REPORTED_ISSUES {
                let more = issues.len() - MAX_REPORTED_ISSUES;
                issues.truncate(MAX_REPORTED_ISSUES);
                issues.push(SpecIssue::new(
                    "urdf",
                    format!(
                        "{file}: and {more} more problem(s) (the first {MAX_REPORTED_ISSUES} \
                         are listed)"
                    ),
                ));
            }
            issues
        })
    }

    fn load_unbounded(
        path: &Path,
        sdf_model: Option<&str>,
        roles: &JointRoles,
    ) -> Result<UrdfRobot, Vec<SpecIssue>> {
        let text = UrdfSource::read_text(path)?;
        let mut format = "URDF";
        let src = match roxmltree::Document::parse(&text) {
            Ok(doc) if doc.root_element().has_tag_name("sdf") => {
                format = "SDF";
                super::sdf::read_model(path, &doc, sdf_model)?
            }
            _ if sdf_model.is_some() => {
                return Err(vec![SpecIssue::new(
                    "sdf_model",
                    format!(
                        "{} is not an SDF file: `sdf_model` chooses a model of an SDF file; \
                         remove it",
                        path.display()
                    ),
                )]);
            }
            _ => UrdfSource::parse(path, &text)?,
        };
        let mut issues = Vec::new();
        for (element, text) in &src.gazebo.unreadable {
            issues.push(SpecIssue::new(
                source::key(&format!("{element} ({})", src.file_name())),
                format!("`{}` is not a number", crate::check::echoed(text)),
            ));
        }
        // Every number within the engine's bounds before anything is built from them.
        numbers::check(&src, &mut issues);
        if !issues.is_empty() {
            return Err(issues);
        }
        let mut warnings = Vec::new();
        let mut meshes = MeshCache::default();
        let (links, arms) = tree::walk(&src, roles, &mut meshes, &mut issues, &mut warnings);
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
            format,
            links,
            arms,
            plugin: src.gazebo.plugin.clone(),
            root_friction,
            warnings,
            start_pose: src.start_pose,
            meshes_read: meshes.reads,
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
    pub fn mass_part(&self, owner: Owner, issues: &mut Vec<SpecIssue>) -> MassPart {
        inertial::merged(&self.source, &self.links, owner, issues)
    }
}
