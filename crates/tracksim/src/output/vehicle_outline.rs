//! The vehicle's outline in the side view (issue 14.4): chassis, track paths and flippers at a
//! few instants of a run, drawn over the terrain so one sees where the vehicle met a step.

use super::side_line::SideLine;
use crate::model::{CollisionShape, Parent, VehicleModel};
use crate::run::RunResult;
use crate::world::Sample;
use glam::{DQuat, DVec3, EulerRot};

/// The vehicle's outline at one instant: side-view polylines (x, z), m, closed.
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    /// Time, s.
    pub t: f64,
    /// Outlines of the chassis, each track path and each flipper arm.
    pub lines: Vec<SideLine>,
}

/// Points per track path in an outline.
const PATH_POINTS: usize = 96;

/// The outline of vehicle `v` in the state of sample `s`.
pub fn snapshot(v: &VehicleModel, s: &Sample) -> Snapshot {
    let p = &s.pose;
    let rot = DQuat::from_euler(EulerRot::ZYX, p.yaw, p.pitch, p.roll);
    let pos = DVec3::new(p.x, p.y, p.z);
    let to_side = |b: DVec3| {
        let w = pos + rot * b;
        (w.x, w.z)
    };
    // A point of flipper i's frame in the chassis frame.
    let flipper = |i: usize, q: DVec3| {
        let fl = &v.flippers[i];
        let a = s.flipper_angle.get(i).copied().unwrap_or(fl.initial_angle);
        fl.pivot + DQuat::from_axis_angle(fl.axis, a) * (q - fl.pivot)
    };
    let mut lines = vec![
        shape_outline(&v.body.shape)
            .into_iter()
            .map(to_side)
            .collect(),
    ];
    for t in &v.tracks {
        let len = t.path.length();
        let line = (0..=PATH_POINTS)
            .map(|k| {
                let q = t.path.frame_at(len * k as f64 / PATH_POINTS as f64).origin;
                let q = match t.parent {
                    Parent::Body => q,
                    Parent::Flipper(i) => flipper(i, q),
                };
                to_side(q)
            })
            .collect();
        lines.push(line);
    }
    for (i, fl) in v.flippers.iter().enumerate() {
        if let Some(shape) = &fl.shape {
            let line = shape_outline(shape)
                .into_iter()
                .map(|q| to_side(flipper(i, q)))
                .collect();
            lines.push(line);
        }
    }
    Snapshot { t: s.t, lines }
}

/// The side (x-z) rectangle of a shape's bounds at its mid-plane, closed, in its owner's frame.
fn shape_outline(shape: &CollisionShape) -> Vec<DVec3> {
    let (lo, hi) = shape.bounds();
    let y = 0.5 * (lo.y + hi.y);
    vec![
        DVec3::new(lo.x, y, lo.z),
        DVec3::new(hi.x, y, lo.z),
        DVec3::new(hi.x, y, hi.z),
        DVec3::new(lo.x, y, hi.z),
        DVec3::new(lo.x, y, lo.z),
    ]
}

/// Outlines of `v` at `count` instants spread evenly over the run (first and last included).
pub fn snapshots(v: &VehicleModel, run: &RunResult, count: usize) -> Vec<Snapshot> {
    let n = run.samples.len();
    if n == 0 || count == 0 {
        return Vec::new();
    }
    let mut picks: Vec<usize> = (0..count)
        .map(|k| {
            if count == 1 {
                n - 1
            } else {
                k * (n - 1) / (count - 1)
            }
        })
        .collect();
    picks.dedup();
    picks
        .into_iter()
        .filter_map(|i| run.samples.get(i))
        .map(|s| snapshot(v, &s))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::PoseRpy;

    #[test]
    fn a_pitched_body_is_drawn_pitched_at_its_position() {
        let spec = toml::from_str(include_str!("../../../../vehicles/packbot510.toml")).unwrap();
        let v = crate::model::compile_vehicle(&spec).unwrap();
        let s = Sample {
            t: 1.0,
            pose: PoseRpy {
                x: 2.0,
                z: 0.5,
                // REP 103: negative pitch is nose up.
                pitch: -std::f64::consts::FRAC_PI_2,
                ..Default::default()
            },
            ..Default::default()
        };
        let snap = snapshot(&v, &s);
        assert_eq!(snap.lines.len(), 1 + v.tracks.len());
        // Nose up by 90 deg: the 0.5 m long, 0.1 m tall box stands 0.1 m wide and 0.5 m tall.
        let body = &snap.lines[0];
        let (xs, zs): (Vec<f64>, Vec<f64>) = body.iter().copied().unzip();
        let span = |v: &[f64]| {
            v.iter().cloned().fold(f64::MIN, f64::max) - v.iter().cloned().fold(f64::MAX, f64::min)
        };
        assert!((span(&xs) - 0.1).abs() < 1e-9 && (span(&zs) - 0.5).abs() < 1e-9);
        assert!(
            zs.iter().cloned().fold(f64::MIN, f64::max) > 0.74,
            "the nose is up: {zs:?}"
        );
        // The track loop (pulleys 0.51 m apart, radius 0.082 m) spans 0.674 m vertically.
        let (_, tz): (Vec<f64>, Vec<f64>) = snap.lines[1].iter().copied().unzip();
        assert!((span(&tz) - 0.674).abs() < 0.002, "{}", span(&tz));
    }
}
