//! Which links of a robot are tracks: the paper's ContinuousTrack plugins when the file has
//! any; else the links the Gazebo `TrackedVehicle` plugin names (tracks and flippers); else
//! the links whose name contains "track" and that have collision shapes. Then the left/right
//! separation and the track height found, against the `TrackedVehicle` plugin's.

use super::continuous_track;
use super::pattern::from_plugin;
use super::propose::{ProposedTrack, from_shapes};
use super::report::{Geometry, TrackSource};
use crate::urdf::{ImportedLink, LinkJoint, Owner, UrdfRobot};

/// The tracks proposed, with what could not be made into a track.
pub(super) struct Selected {
    pub source: TrackSource,
    pub tracks: Vec<ProposedTrack>,
    pub skipped: Vec<String>,
}

/// `base` for the first link the plugin names for a side; the link's own name for the others
/// (gz-sim lists a side's flippers under `<left_track>` too).
fn numbered(base: &str, k: usize, link: &str) -> String {
    if k == 0 {
        base.to_string()
    } else {
        link.to_string()
    }
}

/// The tracks of `robot`, whose file's text is `xml` (`Err`: no track found, with why).
/// The links turning on continuous joints whose parent is link `name` (its wheels).
fn wheels_of<'a>(robot: &'a UrdfRobot, name: &str) -> Vec<&'a ImportedLink> {
    robot
        .joint_frames()
        .iter()
        .filter(|j| j.parent == name)
        .filter_map(|j| robot.link(&j.child))
        .filter(|l| l.kind == LinkJoint::Continuous)
        .collect()
}

pub(super) fn select(robot: &UrdfRobot, xml: &str) -> Result<Selected, String> {
    let mut skipped = Vec::new();
    let plugins = continuous_track::read(xml)?;
    if !plugins.is_empty() {
        let mut tracks = Vec::new();
        for p in &plugins {
            match from_plugin(p, robot) {
                Ok(t) => tracks.push(t),
                Err(m) => skipped.push(m),
            }
        }
        return done(TrackSource::ContinuousTrack, tracks, skipped);
    }
    if let Some(p) = &robot.plugin {
        let sides = [
            ("left", "left_track", &p.left_tracks),
            ("right", "right_track", &p.right_tracks),
            ("left_flipper", "left_flipper", &p.left_flippers),
            ("right_flipper", "right_flipper", &p.right_flippers),
        ];
        let mut tracks = Vec::new();
        for (base, tag, links) in sides {
            for (k, l) in links.iter().enumerate() {
                let Some(link) = robot.link(l) else {
                    skipped.push(format!(
                        "link {l} (plugin <{tag}>) is not in the robot's tree"
                    ));
                    continue;
                };
                let why = format!(
                    "named by the Gazebo TrackedVehicle plugin's <{tag}><link> (line {})",
                    p.line
                );
                match from_shapes(&numbered(base, k, l), link, &wheels_of(robot, l), why) {
                    Ok(t) => tracks.push(t),
                    Err(m) => skipped.push(m),
                }
            }
        }
        return done(TrackSource::TrackedVehicle, tracks, skipped);
    }
    let mut tracks = Vec::new();
    let mut track_links = Vec::new();
    for l in &robot.links {
        // A wheel turning inside a track (continuous joint) is part of its track, not one.
        let wheels = wheels_of(robot, &l.name);
        if !l.name.to_ascii_lowercase().contains("track")
            || l.kind == LinkJoint::Continuous
            || l.shapes.is_empty() && wheels.is_empty()
        {
            continue;
        }
        let why = "its name contains \"track\" and it has collision shapes (no track plugin in \
                   the file)"
            .to_string();
        match from_shapes(&l.name, l, &wheels, why) {
            Ok(t) => {
                track_links.push(l.name.clone());
                tracks.push(t);
            }
            Err(m) => skipped.push(m),
        }
    }
    // A flipper arm hung on a track link (its joint's parent), turning about y, carries a
    // track of its own round its pulley cylinders (issue 60: Absolem's four flippers).
    for a in robot.arms.iter().filter(|a| a.axis.y.abs() > Y_AXIS_COS) {
        let on_track = robot
            .joint_frames()
            .iter()
            .any(|j| j.child == a.link && track_links.contains(&j.parent));
        let Some(link) = robot.link(&a.link).filter(|_| on_track) else {
            continue;
        };
        let why = format!(
            "a flipper arm (revolute joint {}) hung on a track link, with collision shapes",
            a.joint
        );
        match from_shapes(&a.link, link, &wheels_of(robot, &a.link), why) {
            Ok(t) => tracks.push(t),
            Err(m) => skipped.push(m),
        }
    }
    done(TrackSource::LinkNames, tracks, skipped)
}

/// |cos| of the angle between an arm's axis and y above which it turns about y (8 deg).
const Y_AXIS_COS: f64 = 0.99;

/// The robot's arms as the vehicle file's flippers, and those kept rigid with why: an arm
/// that turns about an axis other than y and carries none of `tracks` is a sensor's gimbal
/// or a steering joint, not a flipper (issue 60: Absolem's lidar gimbal about x became a
/// "flipper" with 2,000 N m/rad gains).
pub(super) fn flippers(
    robot: &UrdfRobot,
    tracks: &[ProposedTrack],
) -> (Vec<String>, Vec<(String, String)>) {
    let mut flippers = Vec::new();
    let mut rigid = Vec::new();
    for a in &robot.arms {
        let carries = tracks.iter().any(|t| t.link == a.link);
        if a.axis.y.abs() > Y_AXIS_COS || carries {
            flippers.push(a.joint.clone());
        } else {
            rigid.push((
                a.joint.clone(),
                format!(
                    "turns about ({:.2}, {:.2}, {:.2}), not y, and carries no track: kept rigid \
                     at angle 0 (`rigid_joints`), not a flipper; remove it from `rigid_joints` \
                     and give it a [joints.{}] table to make it an arm",
                    a.axis.x, a.axis.y, a.axis.z, a.joint
                ),
            ));
        }
    }
    (flippers, rigid)
}

fn done(
    source: TrackSource,
    tracks: Vec<ProposedTrack>,
    skipped: Vec<String>,
) -> Result<Selected, String> {
    if tracks.is_empty() {
        let why = match source {
            TrackSource::ContinuousTrack => "its ContinuousTrack plugin(s) gave no usable track",
            TrackSource::TrackedVehicle => "the TrackedVehicle plugin's links gave no usable track",
            TrackSource::LinkNames => {
                "it has no track plugin (the paper's ContinuousTrack or Gazebo's TrackedVehicle) \
                 and no link whose name contains \"track\" with collision shapes"
            }
        };
        let detail = if skipped.is_empty() {
            String::new()
        } else {
            format!(": {}", skipped.join("; "))
        };
        return Err(format!(
            "no tracks found: {why}{detail}. Write the tracks by hand (docs/URDF.md)"
        ));
    }
    Ok(Selected {
        source,
        tracks,
        skipped,
    })
}

/// The `<tracks_height>` of the `TrackedVehicle` plugin in `xml`, m (urdf/ does not keep it).
fn plugin_height(xml: &str) -> Option<f64> {
    let doc = roxmltree::Document::parse(xml).ok()?;
    doc.descendants()
        .filter(|n| n.has_tag_name("plugin"))
        .filter(|n| {
            let f = n
                .attribute("filename")
                .unwrap_or_default()
                .to_ascii_lowercase();
            let name = n.attribute("name").unwrap_or_default().to_ascii_lowercase();
            f.contains("tracked") || name.contains("trackedvehicle")
        })
        .find_map(|n| n.descendants().find(|d| d.has_tag_name("tracks_height")))
        .and_then(|h| h.text()?.trim().parse().ok())
}

/// Separation of the left and right chassis tracks and the main tracks' height, as found and
/// as the `TrackedVehicle` plugin says.
pub(super) fn geometry(robot: &UrdfRobot, tracks: &[ProposedTrack], xml: &str) -> Geometry {
    let on_chassis: Vec<&ProposedTrack> = tracks
        .iter()
        .filter(|t| {
            !robot.plugin.as_ref().is_some_and(|p| {
                p.left_flippers.contains(&t.link) || p.right_flippers.contains(&t.link)
            })
        })
        .filter(|t| {
            robot
                .link(&t.link)
                .is_some_and(|l| l.owner == Owner::Chassis)
        })
        .collect();
    let mean = |v: Vec<f64>| (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64);
    let left = mean(
        on_chassis
            .iter()
            .filter(|t| t.chassis_y > 1e-6)
            .map(|t| t.chassis_y)
            .collect(),
    );
    let right = mean(
        on_chassis
            .iter()
            .filter(|t| t.chassis_y < -1e-6)
            .map(|t| t.chassis_y)
            .collect(),
    );
    Geometry {
        separation: left.zip(right).map(|(l, r)| l - r),
        plugin_separation: robot.plugin.as_ref().and_then(|p| p.tracks_separation),
        height: on_chassis.first().map(|t| t.height()),
        plugin_height: plugin_height(xml),
    }
}
