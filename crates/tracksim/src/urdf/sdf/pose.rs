//! SDFormat poses and frames (1.6 to 1.9). A `<pose>` is `x y z roll pitch yaw` (m, rad;
//! `degrees="true"` for degrees; `rotation_format="quat_xyzw"` for `x y z qx qy qz qw`), the
//! rotation about the fixed x, y, z axes (as URDF's `rpy`). It is in the frame its
//! `relative_to` names, else in the element's default frame: a link's in the model frame
//! (`__model__`), a joint's in its child link's frame, an `<inertial>`'s or `<collision>`'s in
//! its link's frame, a `<frame>`'s in the frame it is `attached_to` (default the model's).
//! [`Frames`] resolves any of them into the model frame, refusing unknown names and loops.

use super::file::{Ctx, Node, child, children, numbers};
use crate::error::SpecIssue;
use glam::{DAffine3, DQuat, DVec3, EulerRot};
use std::collections::HashMap;

/// The model frame's name.
pub(super) const MODEL: &str = "__model__";

/// A `<pose>` as read: the transform and the frame it is in (`None`: the default frame).
#[derive(Clone, Debug)]
pub(super) struct RawPose {
    /// The pose, m and rad.
    pub x: DAffine3,
    /// `relative_to`.
    pub relative_to: Option<String>,
}

/// Roll, pitch, yaw (rad, about the fixed x, y, z axes) as a rotation.
pub(super) fn rpy(r: f64, p: f64, y: f64) -> DQuat {
    DQuat::from_euler(EulerRot::ZYX, y, p, r)
}

/// The `<pose>` child of `n` (identity in the default frame when there is none).
pub(super) fn pose_of(ctx: &Ctx, n: Node) -> Result<RawPose, SpecIssue> {
    let Some(p) = child(n, "pose") else {
        return Ok(RawPose {
            x: DAffine3::IDENTITY,
            relative_to: None,
        });
    };
    if p.attribute("frame").is_some_and(|f| !f.trim().is_empty()) {
        return Err(ctx.issue(
            p,
            "`frame` (SDFormat 1.5) is not read: write `relative_to` (SDFormat 1.7), e.g. with \
             `gz sdf -p`",
        ));
    }
    let quat = match p.attribute("rotation_format") {
        None | Some("euler_rpy") => false,
        Some("quat_xyzw") => true,
        Some(other) => {
            return Err(ctx.issue(
                p,
                format!(
                    "rotation_format=\"{}\" is not SDFormat's (euler_rpy or quat_xyzw)",
                    crate::check::echoed(other)
                ),
            ));
        }
    };
    let empty = super::file::text(p).is_empty();
    let v = if empty {
        vec![0.0; 6]
    } else {
        numbers(ctx, p, if quat { &[7] } else { &[6] })?
    };
    // The TOML checker's bounds (what the f32 engine represents): a position within
    // MAX_LENGTH_M, an angle or quaternion component within MAX_PLAIN (a quaternion of 1e308s
    // has an infinite length and normalises to NaN).
    let (max_m, max_plain) = (crate::check::MAX_LENGTH_M, crate::check::MAX_PLAIN);
    if v[..3].iter().any(|x| x.abs() > max_m) || v[3..].iter().any(|x| x.abs() > max_plain) {
        return Err(ctx.issue(
            p,
            format!(
                "\"{}\" is beyond the f32 engine's bounds ({max_m:e} m for x y z, {max_plain:e} \
                 for the angles or quaternion); check the units and the numbers",
                v.iter()
                    .map(|x| crate::check::num(*x))
                    .collect::<Vec<_>>()
                    .join(" ")
            ),
        ));
    }
    let t = DVec3::new(v[0], v[1], v[2]);
    let r = if quat && !empty {
        let q = DQuat::from_xyzw(v[3], v[4], v[5], v[6]);
        if q.length() < 1e-9 {
            return Err(ctx.issue(p, "its quaternion is zero: it is no rotation"));
        }
        q.normalize()
    } else {
        let k = match p.attribute("degrees") {
            Some("true" | "1") => std::f64::consts::PI / 180.0,
            _ => 1.0,
        };
        rpy(v[3] * k, v[4] * k, v[5] * k)
    };
    Ok(RawPose {
        x: DAffine3::from_rotation_translation(r, t),
        relative_to: p
            .attribute("relative_to")
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(String::from),
    })
}

/// One named frame of a model: its pose, the frame that pose is in, and its element's line.
#[derive(Clone, Debug)]
struct Entry {
    pose: DAffine3,
    relative_to: String,
    what: String,
}

/// The named frames of one `<model>`: links, joints and `<frame>`s, each resolvable into the
/// model frame.
pub(super) struct Frames {
    entries: HashMap<String, Entry>,
    /// The model, for messages.
    model: String,
}

impl Frames {
    /// Reads the frames of `model` (problems in `issues`).
    pub fn read(ctx: &Ctx, model: Node, issues: &mut Vec<SpecIssue>) -> Frames {
        let mut entries = HashMap::new();
        let mut add = |n: Node, default: String, issues: &mut Vec<SpecIssue>| {
            let Some(name) = n.attribute("name") else {
                return;
            };
            match pose_of(ctx, n) {
                Ok(p) => {
                    entries.entry(name.to_string()).or_insert(Entry {
                        pose: p.x,
                        relative_to: p.relative_to.unwrap_or(default),
                        what: ctx.at(n),
                    });
                }
                Err(e) => issues.push(e),
            }
        };
        for l in children(model, "link") {
            add(l, MODEL.into(), issues);
        }
        for j in children(model, "joint") {
            let child_link = child(j, "child")
                .map(|c| super::file::text(c).to_string())
                .unwrap_or_default();
            add(j, child_link, issues);
        }
        for f in children(model, "frame") {
            let attached = f
                .attribute("attached_to")
                .filter(|a| !a.trim().is_empty())
                .unwrap_or(MODEL)
                .to_string();
            add(f, attached, issues);
        }
        Frames {
            entries,
            model: model.attribute("name").unwrap_or_default().to_string(),
        }
    }

    /// The frame `name` in the model frame, or why it cannot be found.
    pub fn resolve(&self, name: &str) -> Result<DAffine3, String> {
        let mut x = DAffine3::IDENTITY;
        let mut at = name.to_string();
        let mut path: Vec<String> = Vec::new();
        while at != MODEL {
            let Some(e) = self.entries.get(&at) else {
                return Err(format!(
                    "frame \"{}\" is not a link, joint or <frame> of model \"{}\"{}",
                    crate::check::echoed(&at),
                    crate::check::echoed(&self.model),
                    path.last()
                        .map(|p| format!(" (named by {p})"))
                        .unwrap_or_default()
                ));
            };
            if path.contains(&e.what) {
                return Err(format!(
                    "the poses of {} are relative to each other in a loop",
                    path.join(", ")
                ));
            }
            path.push(e.what.clone());
            x = e.pose * x;
            at = e.relative_to.clone();
        }
        Ok(x)
    }

    /// A pose read from an element (`raw`) in the model frame, its default frame `default`.
    pub fn place(&self, raw: &RawPose, default: &str) -> Result<DAffine3, String> {
        let frame = raw.relative_to.as_deref().unwrap_or(default);
        Ok(self.resolve(frame)? * raw.x)
    }
}
