//! Collecting input problems with their key paths.

use crate::error::SpecIssue;
use glam::DVec3;

/// f64 geometry to Rapier's f32 vector.
pub(crate) fn f(v: DVec3) -> rapier3d::prelude::Vector {
    rapier3d::prelude::Vector::new(v.x as f32, v.y as f32, v.z as f32)
}

/// f64 rotation to Rapier's f32 rotation.
pub(crate) fn q(r: glam::DQuat) -> rapier3d::prelude::Rotation {
    rapier3d::prelude::Rotation::from_xyzw(r.x as f32, r.y as f32, r.z as f32, r.w as f32)
        .normalize()
}

pub(crate) fn v3(a: [f64; 3]) -> DVec3 {
    DVec3::from_array(a)
}

/// Collects issues with key paths.
#[derive(Default)]
pub(crate) struct Checker {
    pub(crate) issues: Vec<SpecIssue>,
}

impl Checker {
    pub(crate) fn push(&mut self, key: impl Into<String>, msg: impl Into<String>) {
        self.issues.push(SpecIssue::new(key, msg));
    }
    pub(crate) fn positive(&mut self, key: &str, v: f64, unit: &str) {
        if !(v.is_finite() && v > 0.0) {
            self.push(key, format!("must be a finite number > 0 {unit}, got {v}"));
        }
    }
    pub(crate) fn non_negative(&mut self, key: &str, v: f64, unit: &str) {
        if !(v.is_finite() && v >= 0.0) {
            self.push(key, format!("must be a finite number >= 0 {unit}, got {v}"));
        }
    }
    pub(crate) fn finite(&mut self, key: &str, v: &[f64]) {
        if v.iter().any(|x| !x.is_finite()) {
            self.push(key, format!("must be finite numbers, got {v:?}"));
        }
    }
    pub(crate) fn unit_vector(&mut self, key: &str, v: [f64; 3]) -> DVec3 {
        self.finite(key, &v);
        let d = v3(v);
        if d.length() < 1e-9 || !d.is_finite() {
            self.push(key, "must be a non-zero direction, e.g. [0, 1, 0]");
            DVec3::Y
        } else {
            d.normalize()
        }
    }
    pub(crate) fn points(&mut self, key: &str, points: &[[f64; 3]]) -> Vec<DVec3> {
        if points.len() < 4 {
            self.push(
                key,
                format!(
                    "a convex hull needs at least 4 points that are not coplanar, got {}",
                    points.len()
                ),
            );
        }
        for (i, p) in points.iter().enumerate() {
            self.finite(&format!("{key}[{i}]"), p);
        }
        let pts: Vec<DVec3> = points.iter().map(|p| v3(*p)).collect();
        if pts.len() >= 4 && pts.iter().all(|p| p.is_finite()) {
            let p0 = pts[0];
            let mut max_vol: f64 = 0.0;
            for a in &pts[1..] {
                for b in &pts[1..] {
                    for c in &pts[1..] {
                        max_vol = max_vol.max((*a - p0).dot((*b - p0).cross(*c - p0)).abs());
                    }
                }
            }
            if max_vol < 1e-15 {
                self.push(key, "points are coplanar: the hull has no volume");
            }
        }
        pts
    }
}
