//! A validated closed track path ([`TrackPath`]): its segments by arc length, the frame at
//! any arc length, moved and mirrored copies.

use super::{Frame, JOIN_TOLERANCE_M, PathError, Segment, TANGENT_TOLERANCE_RAD};
use glam::{DQuat, DVec3};
use std::f64::consts::TAU;

/// A validated closed track path. Construct with [`TrackPath::new`] or
/// [`TrackPath::from_pulleys`].
#[derive(Clone, Debug, PartialEq)]
pub struct TrackPath {
    segments: Vec<Segment>,
    /// Arc length at which each segment starts, m.
    starts: Vec<f64>,
    length: f64,
    /// Unit axis about which the loop turns positively (for a track: +y, lateral); for a
    /// spatial loop, the first frame's lateral axis.
    axis: DVec3,
    /// A spatial loop's frame at the start of every segment (`None`: planar, the lateral axis
    /// is `axis` everywhere).
    frames: Option<Vec<DQuat>>,
    /// A spatial loop's twist: the angle about the tangent by which the transported frame
    /// comes back rotated after one lap, rad; taken out evenly along the loop.
    twist: f64,
}

impl TrackPath {
    /// The checks every loop gets: each segment on its own, then position and tangent
    /// continuity at every join, the closing one included. Returns the normalised segments and
    /// the join problems (per-segment problems end the check).
    fn checked_loop(
        segments: &[Segment],
    ) -> Result<(Vec<Segment>, Vec<PathError>), Vec<PathError>> {
        let mut errors = Vec::new();
        let n = segments.len();
        // One segment closes only as a full circle (a wheel, paper Fig. 8).
        let single_circle = n == 1 && !segments[0].is_straight();
        if n < 2 && !single_circle {
            return Err(vec![PathError::TooFewSegments(n)]);
        }
        // Per-segment checks.
        let mut segs = Vec::with_capacity(n);
        for (i, seg) in segments.iter().enumerate() {
            match *seg {
                Segment::Straight {
                    start,
                    direction,
                    length,
                } => {
                    if !start.is_finite() || !direction.is_finite() || !length.is_finite() {
                        errors.push(PathError::NotFinite { segment: i });
                        continue;
                    }
                    if length <= 0.0 {
                        errors.push(PathError::NonPositiveLength { segment: i, length });
                    }
                    if direction.length() < 1e-12 {
                        errors.push(PathError::ZeroVector {
                            segment: i,
                            what: "straight direction",
                        });
                        continue;
                    }
                    segs.push(Segment::Straight {
                        start,
                        direction: direction.normalize(),
                        length,
                    });
                }
                Segment::Arc {
                    start,
                    centre,
                    axis,
                    angle,
                } => {
                    if !start.is_finite()
                        || !centre.is_finite()
                        || !axis.is_finite()
                        || !angle.is_finite()
                    {
                        errors.push(PathError::NotFinite { segment: i });
                        continue;
                    }
                    if axis.length() < 1e-12 {
                        errors.push(PathError::ZeroVector {
                            segment: i,
                            what: "arc axis",
                        });
                        continue;
                    }
                    let s = Segment::Arc {
                        start,
                        centre,
                        axis: axis.normalize(),
                        angle,
                    };
                    let r = s.radius().unwrap_or(0.0);
                    if r <= 1e-9 {
                        errors.push(PathError::NonPositiveRadius {
                            segment: i,
                            radius: r,
                        });
                    }
                    let bad_angle = if single_circle {
                        (angle.abs() - TAU).abs() > TANGENT_TOLERANCE_RAD
                    } else {
                        angle == 0.0 || angle.abs() >= TAU - TANGENT_TOLERANCE_RAD
                    };
                    if bad_angle {
                        errors.push(PathError::BadArcAngle { segment: i, angle });
                    }
                    segs.push(s);
                }
            }
        }
        if !errors.is_empty() {
            return Err(errors);
        }
        // Joins: position and tangent continuity, including the closing join.
        for i in 0..n {
            let j = (i + 1) % n;
            let (end, t_end) = segs[i].end();
            let (start, t_start) = segs[j].point_tangent(0.0);
            let gap = (end - start).length();
            if gap > JOIN_TOLERANCE_M {
                errors.push(PathError::Gap {
                    segment: i,
                    next: j,
                    gap,
                });
            }
            let angle = t_end.angle_between(t_start);
            if angle > TANGENT_TOLERANCE_RAD {
                errors.push(PathError::Kink {
                    segment: i,
                    next: j,
                    angle,
                });
            }
        }
        Ok((segs, errors))
    }

    /// Validates a loop of segments in one plane. Returns every problem found, each naming
    /// its segment.
    pub fn new(segments: Vec<Segment>) -> Result<Self, Vec<PathError>> {
        let (segs, mut errors) = Self::checked_loop(&segments)?;
        let n = segs.len();
        // Planarity and total turning: the first arc defines the loop's positive axis.
        let first_arc = segs.iter().find_map(|s| match *s {
            Segment::Arc { axis, angle, .. } => Some(axis * angle.signum()),
            _ => None,
        });
        let Some(loop_axis) = first_arc else {
            errors.push(PathError::NoArc);
            return Err(errors);
        };
        let mut turning = 0.0;
        for (i, s) in segs.iter().enumerate() {
            match *s {
                Segment::Arc { axis, angle, .. } => {
                    if axis.cross(loop_axis).length() > TANGENT_TOLERANCE_RAD {
                        errors.push(PathError::NotPlanar { segment: i });
                    }
                    turning += angle * axis.dot(loop_axis).signum();
                }
                Segment::Straight { direction, .. } => {
                    if direction.dot(loop_axis).abs() > TANGENT_TOLERANCE_RAD {
                        errors.push(PathError::NotPlanar { segment: i });
                    }
                }
            }
        }
        if (turning - TAU).abs() > TANGENT_TOLERANCE_RAD * n as f64 {
            errors.push(PathError::Turning { total: turning });
        }
        if !errors.is_empty() {
            return Err(errors);
        }
        let mut starts = Vec::with_capacity(n);
        let mut acc = 0.0;
        for s in &segs {
            starts.push(acc);
            acc += s.length();
        }
        Ok(TrackPath {
            segments: segs,
            starts,
            length: acc,
            axis: loop_axis,
            frames: None,
            twist: 0.0,
        })
    }

    /// Validates a loop whose segments need not share a plane (paper Fig. 8: a belt that turns
    /// a corner, objects on a three-dimensional trajectory): straights in any direction and
    /// arcs about any axis, with the joins, tangents and closure of every loop checked. Its
    /// frame ([`TrackPath::frame_at`]) is carried along the loop by each arc's rotation, with
    /// the twist it has after one lap taken out evenly, so it is continuous everywhere,
    /// across the closing join too. Its [`TrackPath::axis`] is the lateral axis at s = 0: the
    /// signed axis of the first arc made square to the start tangent.
    pub fn spatial(segments: Vec<Segment>) -> Result<Self, Vec<PathError>> {
        let (segs, errors) = Self::checked_loop(&segments)?;
        if !errors.is_empty() {
            return Err(errors);
        }
        let mut starts = Vec::with_capacity(segs.len());
        let mut acc = 0.0;
        for s in &segs {
            starts.push(acc);
            acc += s.length();
        }
        let t0 = segs[0].point_tangent(0.0).1;
        let reference = segs
            .iter()
            .find_map(|s| match *s {
                Segment::Arc { axis, angle, .. } => Some(axis * angle.signum()),
                _ => None,
            })
            .unwrap_or(DVec3::Z);
        let mut lateral = reference - t0 * t0.dot(reference);
        if lateral.length() < 1e-6 {
            lateral = t0.any_orthonormal_vector();
        }
        let lateral = lateral.normalize();
        let mut q = DQuat::from_mat3(&glam::DMat3::from_cols(t0, lateral, t0.cross(lateral)));
        let mut frames = Vec::with_capacity(segs.len());
        for (i, seg) in segs.iter().enumerate() {
            frames.push(q);
            q = Self::transported(seg, q, seg.length());
            let next = segs[(i + 1) % segs.len()].point_tangent(0.0).1;
            q = (DQuat::from_rotation_arc(q * DVec3::X, next) * q).normalize();
        }
        let l_end = q * DVec3::Y;
        let twist = t0.dot(lateral.cross(l_end)).atan2(lateral.dot(l_end));
        Ok(TrackPath {
            segments: segs,
            starts,
            length: acc,
            axis: lateral,
            frames: Some(frames),
            twist,
        })
    }

    /// Frame rotation `q` at the start of `seg` carried `s` m along it (arcs rotate it about
    /// their axis with the tangent; straights keep it).
    fn transported(seg: &Segment, q: DQuat, s: f64) -> DQuat {
        match *seg {
            Segment::Straight { .. } => q,
            Segment::Arc { axis, angle, .. } => {
                let r = seg.radius().unwrap_or(1.0);
                DQuat::from_axis_angle(axis, angle.signum() * s / r) * q
            }
        }
    }

    /// True for a loop in one plane ([`TrackPath::new`]), false for [`TrackPath::spatial`].
    pub fn is_planar(&self) -> bool {
        self.frames.is_none()
    }

    /// The segments, in order of belt travel.
    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }

    /// Arc length at which segment `i` starts, m.
    pub fn segment_start(&self, i: usize) -> f64 {
        self.starts[i]
    }

    /// Total loop length L, m.
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Unit axis about which the loop turns positively (+y for a track driving forwards).
    pub fn axis(&self) -> DVec3 {
        self.axis
    }

    /// Index of the segment containing arc length `s` (wrapped into [0, L)).
    pub fn segment_at(&self, s: f64) -> usize {
        let s = s.rem_euclid(self.length);
        match self.starts.binary_search_by(|x| x.total_cmp(&s)) {
            Ok(i) => i,
            Err(i) => i - 1,
        }
    }

    /// The footprint frame at arc length `s` (wrapped): origin on the path, x along the belt's
    /// motion, y along the loop axis, z outwards (away from the pulleys), m.
    pub fn frame_at(&self, s: f64) -> Frame {
        let s = s.rem_euclid(self.length);
        let i = self.segment_at(s);
        let (p, t) = self.segments[i].point_tangent(s - self.starts[i]);
        if let Some(frames) = &self.frames {
            let q = Self::transported(&self.segments[i], frames[i], s - self.starts[i]);
            let q = DQuat::from_axis_angle(t, -self.twist * s / self.length) * q;
            let lateral = (q * DVec3::Y - t * t.dot(q * DVec3::Y)).normalize();
            return Frame {
                origin: p,
                tangent: t,
                lateral,
                normal: t.cross(lateral),
            };
        }
        Frame {
            origin: p,
            tangent: t,
            lateral: self.axis,
            normal: t.cross(self.axis),
        }
    }

    /// The same loop moved rigidly: rotated by `rotation` about the origin, then shifted by
    /// `shift` m (a loop given in a link's frame, placed in its parent's).
    pub fn moved(&self, rotation: DQuat, shift: DVec3) -> Self {
        let segs = self
            .segments
            .iter()
            .map(|s| s.moved(rotation, shift))
            .collect();
        if self.is_planar() {
            TrackPath::new(segs)
        } else {
            TrackPath::spatial(segs)
        }
        .expect("a moved valid loop is valid")
    }

    /// The same loop reflected to the other side of the vehicle (y -> -y).
    pub fn mirrored_y(&self) -> Self {
        let segs = self.segments.iter().map(Segment::mirrored_y).collect();
        if self.is_planar() {
            TrackPath::new(segs)
        } else {
            TrackPath::spatial(segs)
        }
        .expect("a mirrored valid loop is valid")
    }
}
