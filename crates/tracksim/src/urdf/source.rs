//! The URDF file as text: read with a size bound, refused when it is xacro, parsed by urdf-rs
//! into its robot, and parsed again with roxmltree for what urdf-rs does not keep: where each
//! element is (line numbers for messages), which links have an `<inertial>`, and the Gazebo
//! extensions (`gazebo.rs`).

use crate::error::SpecIssue;
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

/// A URDF file, read and parsed.
#[derive(Debug)]
pub(crate) struct UrdfSource {
    /// The file.
    pub path: PathBuf,
    /// The robot as urdf-rs reads it.
    pub robot: urdf_rs::Robot,
    /// Line of each `<link>`, by name.
    pub(super) link_lines: HashMap<String, u32>,
    /// Line of each `<joint>`, by name.
    pub(super) joint_lines: HashMap<String, u32>,
    /// Links that have an `<inertial>` element.
    pub with_inertial: HashSet<String>,
    /// The Gazebo extensions.
    pub gazebo: super::gazebo::GazeboExtensions,
    /// An SDF model's `<pose>` in its world (the robot's start pose), m and rad; `None` for a
    /// URDF or a model without a pose.
    pub start_pose: Option<glam::DAffine3>,
}

/// Largest URDF file read, bytes (a robot description is kilobytes; meshes are separate).
pub const MAX_URDF_BYTES: u64 = 16 << 20;

/// The key of a problem in the URDF file: the `urdf` key and the element.
pub(crate) fn key(element: &str) -> String {
    format!("urdf {element}")
}

impl UrdfSource {
    /// Reads the text of `path` (a URDF or SDF file), bounded; problems are keyed `urdf`.
    /// Its nesting and element counts are checked here, before any tree parser sees it
    /// (`limits.rs`).
    pub fn read_text(path: &Path) -> Result<String, Vec<SpecIssue>> {
        let text = crate::files::read_text_bounded(path, MAX_URDF_BYTES).map_err(|e| {
            vec![SpecIssue::new(
                "urdf",
                format!(
                    "cannot read the URDF file: {e}; the path is relative to the vehicle file's \
                     folder"
                ),
            )]
        })?;
        super::limits::prescan_xml(path, &text, true)
            .map_err(|m| vec![SpecIssue::new("urdf", m)])?;
        Ok(text)
    }

    /// Parses `text`, the URDF file `path`; problems are keyed `urdf` (the vehicle file's key).
    pub fn parse(path: &Path, text: &str) -> Result<UrdfSource, Vec<SpecIssue>> {
        let fail = |m: String| vec![SpecIssue::new("urdf", m)];
        let xacro = || {
            fail(format!(
                "{} is a xacro file; expand it first (`xacro robot.urdf.xacro > robot.urdf`) and \
                 name the result",
                path.display()
            ))
        };
        let doc = roxmltree::Document::parse(text).map_err(|e| {
            // An element with the xacro prefix and no namespace declared for it.
            if matches!(&e, roxmltree::Error::UnknownNamespace(p, _) if p == "xacro") {
                return xacro();
            }
            fail(format!("{} is not well-formed XML: {e}", path.display()))
        })?;
        // xacro by its elements and attributes (in the xacro namespace), not by its text: an
        // expanded file may keep the namespace declaration or commented-out xacro lines.
        let in_xacro = |ns: Option<&str>| ns.is_some_and(|n| n.contains("ros.org/wiki/xacro"));
        if doc.descendants().any(|n| {
            n.is_element()
                && (in_xacro(n.tag_name().namespace())
                    || n.attributes().any(|a| in_xacro(a.namespace())))
        }) {
            return Err(xacro());
        }
        let root = doc.root_element();
        if root.tag_name().name() != "robot" {
            return Err(fail(format!(
                "{}: the root element is <{}>, a URDF file's is <robot> (an SDF file's <sdf>)",
                path.display(),
                root.tag_name().name()
            )));
        }
        let line = |n: roxmltree::Node| doc.text_pos_at(n.range().start).row;
        let mut link_lines = HashMap::new();
        let mut joint_lines = HashMap::new();
        let mut with_inertial = HashSet::new();
        for n in root.children().filter(|n| n.is_element()) {
            let name = n.attribute("name").unwrap_or_default().to_string();
            match n.tag_name().name() {
                "link" => {
                    if n.children().any(|c| c.has_tag_name("inertial")) {
                        with_inertial.insert(name.clone());
                    }
                    link_lines.insert(name, line(n));
                }
                "joint" => {
                    joint_lines.insert(name, line(n));
                }
                _ => {}
            }
        }
        // URDF 1.1's `quat_xyzw`: urdf-rs turns a NaN or zero quaternion into no rotation
        // without a word (issue 65); refused here, with its line.
        for n in root.descendants().filter(|n| n.has_tag_name("origin")) {
            let Some(q) = n.attribute("quat_xyzw") else {
                continue;
            };
            let v: Vec<f64> = q
                .split_whitespace()
                .filter_map(|s| s.parse::<f64>().ok())
                .collect();
            let norm = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            let ok = v.len() == 4 && v.iter().all(|x| x.is_finite()) && norm > 1e-9;
            if !ok {
                return Err(vec![SpecIssue::new(
                    key(&format!(
                        "<origin quat_xyzw=\"{}\"> ({} line {})",
                        crate::check::echoed(q),
                        path.file_name()
                            .map(|f| f.to_string_lossy().into_owned())
                            .unwrap_or_default(),
                        line(n)
                    )),
                    "must be four finite numbers x y z w of a non-zero quaternion (0 0 0 1: no \
                     rotation)",
                )]);
            }
        }
        let mut gazebo = super::gazebo::GazeboExtensions::read(root, &line);
        if let Some(p) = &mut gazebo.plugin {
            p.file = path
                .file_name()
                .map(|f| f.to_string_lossy().into_owned())
                .unwrap_or_default();
        }
        let robot = urdf_rs::read_from_string(text).map_err(|e| {
            fail(format!(
                "{}: not a valid URDF robot: {}",
                path.display(),
                crate::check::shorten(&e.to_string())
            ))
        })?;
        Ok(UrdfSource {
            path: path.to_path_buf(),
            robot,
            link_lines,
            joint_lines,
            with_inertial,
            gazebo,
            start_pose: None,
        })
    }

    /// `<link name="NAME"> (FILE line N)`, for messages.
    pub fn link(&self, name: &str) -> String {
        self.at("link", name, self.link_lines.get(name))
    }

    /// `<joint name="NAME"> (FILE line N)`, for messages.
    pub fn joint(&self, name: &str) -> String {
        self.at("joint", name, self.joint_lines.get(name))
    }

    /// The file's name, for messages.
    pub fn file_name(&self) -> String {
        self.path
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default()
    }

    fn at(&self, tag: &str, name: &str, line: Option<&u32>) -> String {
        let file = self.file_name();
        match line {
            Some(l) => format!(
                "<{tag} name=\"{}\"> ({file} line {l})",
                crate::check::echoed(name)
            ),
            None => format!("<{tag} name=\"{}\"> ({file})", crate::check::echoed(name)),
        }
    }
}
