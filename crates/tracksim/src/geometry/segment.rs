//! One piece of a track path ([`Segment`]): a straight run or a circular arc, planar or
//! spatial, with its length, point, tangent and the maps that move or mirror it.

use glam::{DQuat, DVec3};

/// One piece of a track path, as the paper parameterises it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Segment {
    /// A straight run from `start` along the unit vector `direction` for `length` m.
    Straight {
        /// Start point, m.
        start: DVec3,
        /// Direction of belt motion (normalised on validation).
        direction: DVec3,
        /// Length, m (> 0).
        length: f64,
    },
    /// A circular run: `start` rotated about the line through `centre` along `axis` by `angle`
    /// rad (right-hand rule; the sign gives the sense of travel).
    Arc {
        /// Start point, m.
        start: DVec3,
        /// A point on the rotation axis, m.
        centre: DVec3,
        /// Rotation axis (normalised on validation).
        axis: DVec3,
        /// Signed rotation angle, rad, with 0 < |angle| < 2 pi.
        angle: f64,
    },
}

impl Segment {
    /// Start point of the segment, m.
    pub fn start(&self) -> DVec3 {
        match *self {
            Segment::Straight { start, .. } | Segment::Arc { start, .. } => start,
        }
    }

    /// Radius of an arc (distance from the start point to the axis line), m; `None` for straights.
    pub fn radius(&self) -> Option<f64> {
        match *self {
            Segment::Straight { .. } => None,
            Segment::Arc {
                start,
                centre,
                axis,
                ..
            } => {
                let a = axis.normalize_or_zero();
                let d = start - centre;
                Some((d - a * a.dot(d)).length())
            }
        }
    }

    /// The foot of the perpendicular from the start point onto the arc's axis (the arc's true
    /// centre), m; `None` for straights.
    pub fn arc_centre(&self) -> Option<DVec3> {
        match *self {
            Segment::Straight { .. } => None,
            Segment::Arc {
                start,
                centre,
                axis,
                ..
            } => {
                let a = axis.normalize_or_zero();
                Some(centre + a * a.dot(start - centre))
            }
        }
    }

    /// Arc length of the segment, m.
    pub fn length(&self) -> f64 {
        match *self {
            Segment::Straight { length, .. } => length,
            Segment::Arc { angle, .. } => self.radius().unwrap_or(0.0) * angle.abs(),
        }
    }

    /// Point and unit tangent at arc length `s` from the segment's start (0 <= s <= length; values
    /// outside extrapolate along the same line or circle), m.
    pub fn point_tangent(&self, s: f64) -> (DVec3, DVec3) {
        match *self {
            Segment::Straight {
                start, direction, ..
            } => {
                let d = direction.normalize();
                (start + d * s, d)
            }
            Segment::Arc {
                start,
                centre,
                axis,
                angle,
            } => {
                let a = axis.normalize();
                let r = self.radius().unwrap_or(0.0);
                let theta = angle.signum() * s / r;
                let p = centre + DQuat::from_axis_angle(a, theta) * (start - centre);
                let c = centre + a * a.dot(p - centre);
                let t = (a.cross(p - c) / r) * angle.signum();
                (p, t)
            }
        }
    }

    /// End point and end tangent.
    pub fn end(&self) -> (DVec3, DVec3) {
        self.point_tangent(self.length())
    }

    /// True for a straight segment.
    pub fn is_straight(&self) -> bool {
        matches!(self, Segment::Straight { .. })
    }

    /// The same segment with its points mapped by `point`, its straight direction by
    /// `direction` and its arc axis by `axis`.
    fn mapped(
        &self,
        point: impl Fn(DVec3) -> DVec3,
        direction: impl Fn(DVec3) -> DVec3,
        axis: impl Fn(DVec3) -> DVec3,
    ) -> Segment {
        match *self {
            Segment::Straight {
                start,
                direction: d,
                length,
            } => Segment::Straight {
                start: point(start),
                direction: direction(d),
                length,
            },
            Segment::Arc {
                start,
                centre,
                axis: a,
                angle,
            } => Segment::Arc {
                start: point(start),
                centre: point(centre),
                axis: axis(a),
                angle,
            },
        }
    }

    /// The same segment moved rigidly: rotated by `rotation` about the origin, then shifted by
    /// `shift` m (e.g. a loop placed at a pose).
    pub fn moved(&self, rotation: DQuat, shift: DVec3) -> Segment {
        self.mapped(|v| rotation * v + shift, |v| rotation * v, |v| rotation * v)
    }

    /// The same segment reflected through the track frame's x-z plane (y -> -y), for the
    /// opposite side of a symmetric vehicle. Arc axes are pseudovectors, so the sense of travel
    /// is kept.
    pub fn mirrored_y(&self) -> Segment {
        let m = |v: DVec3| DVec3::new(v.x, -v.y, v.z);
        self.mapped(m, m, |v| -m(v))
    }
}
