//! What a track or a sensor can be fixed to, by name: the chassis (`"body"`) and the flippers
//! of a vehicle file, or, for a URDF robot, every link (its frame and the body it is part of:
//! the chassis or an arm). The frame is in the chassis frame with the arms at angle 0, the
//! frame of the compiled vehicle.

use super::Parent;
use crate::check::{Checker, unknown_name};
use crate::urdf::UrdfRobot;
use glam::DAffine3;

/// The names tracks (`parent`, `link`) and sensors (`mount`) may use.
pub(crate) struct Mounts {
    /// (name, body, frame in the chassis frame at angle 0).
    names: Vec<(String, Parent, DAffine3)>,
    /// True for a URDF robot (names are links).
    urdf: bool,
    /// The robot file's name, for messages (empty for a vehicle file's flippers).
    file: String,
}

impl Mounts {
    /// The chassis and the flippers of a vehicle file (frames: the chassis frame).
    pub fn of_flippers<'a>(flippers: impl Iterator<Item = &'a str>) -> Self {
        let mut names = vec![("body".to_string(), Parent::Body, DAffine3::IDENTITY)];
        names.extend(
            flippers
                .enumerate()
                .map(|(i, n)| (n.to_string(), Parent::Flipper(i), DAffine3::IDENTITY)),
        );
        Mounts {
            names,
            urdf: false,
            file: String::new(),
        }
    }

    /// `"body"` (the root link's frame) and every link of a URDF robot.
    pub fn of_urdf(robot: &UrdfRobot) -> Self {
        let mut names = vec![("body".to_string(), Parent::Body, DAffine3::IDENTITY)];
        names.extend(
            robot
                .links
                .iter()
                .map(|l| (l.name.clone(), l.owner.into(), l.pose)),
        );
        let file = robot
            .file
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default();
        Mounts {
            names,
            urdf: true,
            file,
        }
    }

    /// True for a URDF robot.
    pub fn is_urdf(&self) -> bool {
        self.urdf
    }

    /// The body and frame of `name`; an unknown name is reported under `key` (with the known
    /// names) and gives the chassis.
    pub fn resolve(
        &self,
        c: &mut Checker,
        key: &str,
        what: &str,
        name: &str,
    ) -> (Parent, DAffine3) {
        match self.names.iter().find(|(n, ..)| n == name) {
            Some((_, p, f)) => (*p, *f),
            None => {
                let known: Vec<&str> = self.names.iter().map(|(n, ..)| n.as_str()).collect();
                let mut m = unknown_name(what, name, &known);
                if self.urdf {
                    m = format!("{m} (the links of {})", self.file);
                }
                c.push(key, m);
                (Parent::Body, DAffine3::IDENTITY)
            }
        }
    }
}
