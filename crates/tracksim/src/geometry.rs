//! Track paths: closed loops of straight and circular segments (paper Sec. III-A), planar or
//! spatial (Fig. 8), and the grouser pattern distributed along them by arc length (Sec. III-B).
//!
//! All quantities are SI (m, rad) in `f64`, in the frame of the link the track hangs on (the
//! *track frame*). Every length and pose is computed in closed form; nothing is sampled.

use glam::{DQuat, DVec3};
use std::f64::consts::TAU;
use std::fmt;

/// Largest gap allowed between the end of one segment and the start of the next, m.
pub const JOIN_TOLERANCE_M: f64 = 1e-5;
/// Largest angle allowed between the end tangent of one segment and the start tangent of the
/// next, and between the loop's total turning and one full turn, rad.
pub const TANGENT_TOLERANCE_RAD: f64 = 1e-4;

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

/// A pulley around which the belt wraps, in the track frame's x-z plane, m.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pulley {
    /// Centre, x (forward), m.
    pub x: f64,
    /// Centre, z (up), m.
    pub z: f64,
    /// Radius of the belt's outer surface around this pulley (where grouser footprints lie), m.
    pub radius: f64,
}

/// Everything that can be wrong with a track path. Each names the segment (or pulley) at fault.
#[derive(Clone, Debug, PartialEq)]
pub enum PathError {
    /// Fewer than two segments.
    TooFewSegments(usize),
    /// A segment has a non-finite number.
    NotFinite { segment: usize },
    /// A straight has length <= 0.
    NonPositiveLength { segment: usize, length: f64 },
    /// A straight's direction or an arc's axis is the zero vector.
    ZeroVector { segment: usize, what: &'static str },
    /// An arc's start point lies on its axis.
    NonPositiveRadius { segment: usize, radius: f64 },
    /// An arc's angle is zero or a full turn or more.
    BadArcAngle { segment: usize, angle: f64 },
    /// Consecutive segments do not meet.
    Gap {
        segment: usize,
        next: usize,
        gap: f64,
    },
    /// Consecutive segments meet at an angle.
    Kink {
        segment: usize,
        next: usize,
        angle: f64,
    },
    /// The loop has no arc.
    NoArc,
    /// An arc's axis is not parallel to the loop's axis, or a straight leaves the loop's plane.
    NotPlanar { segment: usize },
    /// The loop does not turn exactly once.
    Turning { total: f64 },
    /// Fewer than two pulleys.
    TooFewPulleys(usize),
    /// A pulley's radius is not positive or a coordinate is not finite.
    BadPulley { pulley: usize, radius: f64 },
    /// Two pulleys overlap so that no outer tangent exists (one inside the other, or the same
    /// centre).
    PulleysOverlap {
        pulley: usize,
        next: usize,
        distance: f64,
    },
    /// The belt does not wrap a pulley: it runs straight past it (touching it) or would bend
    /// backwards around it, its centre on the line between its neighbours' in the loop
    /// (`collinear`) or inside the loop.
    PulleyNotWrapped {
        pulley: usize,
        before: usize,
        after: usize,
        collinear: bool,
    },
}

impl fmt::Display for PathError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use PathError::*;
        match *self {
            TooFewSegments(n) => write!(
                f,
                "a track loop needs at least 2 segments (or one full-circle arc), got {n}"
            ),
            NotFinite { segment } => write!(f, "segment {segment}: a value is not finite"),
            NonPositiveLength { segment, length } => {
                write!(
                    f,
                    "segment {segment}: straight length must be > 0 m, got {length}"
                )
            }
            ZeroVector { segment, what } => {
                write!(f, "segment {segment}: {what} must not be the zero vector")
            }
            NonPositiveRadius { segment, radius } => write!(
                f,
                "segment {segment}: arc radius must be > 0 m (start point off the axis), got {radius}"
            ),
            BadArcAngle { segment, angle } => write!(
                f,
                "segment {segment}: arc angle must be non-zero and less than a full turn (360 deg; exactly 360 deg only as the one segment of a wheel), got {:.4} deg",
                angle.to_degrees()
            ),
            Gap { segment, next, gap } => write!(
                f,
                "segment {segment} ends {:.6} m away from the start of segment {next} (tolerance {JOIN_TOLERANCE_M} m): the loop is broken",
                gap
            ),
            Kink {
                segment,
                next,
                angle,
            } => write!(
                f,
                "segment {segment} meets segment {next} at an angle of {:.4} deg (tolerance {:.4} deg): tangents must be continuous",
                angle.to_degrees(),
                TANGENT_TOLERANCE_RAD.to_degrees()
            ),
            NoArc => write!(f, "a track loop needs at least one arc segment"),
            NotPlanar { segment } => write!(
                f,
                "segment {segment}: not in the plane of the loop (arc axes must be parallel, straights perpendicular to them)"
            ),
            Turning { total } => write!(
                f,
                "the arcs turn {:.4} deg in total; a closed track loop turns exactly 360 deg (an arc set to a full circle, or pulleys out of order?)",
                total.to_degrees()
            ),
            TooFewPulleys(n) => write!(f, "a belt needs at least 2 pulleys, got {n}"),
            BadPulley { pulley, radius } => write!(
                f,
                "pulley {pulley}: radius must be > 0 m and coordinates finite, got radius {radius}"
            ),
            PulleysOverlap {
                pulley,
                next,
                distance,
            } if distance < 1e-9 => write!(
                f,
                "pulleys {pulley} and {next} have the same centre: a belt cannot run between them; remove one of them (`pulleys[{next}]`) or move it"
            ),
            PulleysOverlap {
                pulley,
                next,
                distance,
            } => write!(
                f,
                "pulleys {pulley} and {next} are {distance:.6} m apart: too close for a belt to run between them (one inside the other)"
            ),
            PulleyNotWrapped {
                pulley,
                before,
                after,
                collinear: true,
            } => write!(
                f,
                "pulley {pulley} has its centre on the line between pulleys {before} and {after}: the belt runs straight past it (touching it, or bending backwards around it if it is smaller), so it does not turn the belt; remove it, or move it outwards off that line (a belt wraps the outside of its pulleys, listed in order around the loop)"
            ),
            PulleyNotWrapped {
                pulley,
                before,
                after,
                collinear: false,
            } => write!(
                f,
                "pulley {pulley} lies inside the belt's loop, between pulleys {before} and {after}: the belt would bend backwards around it; move it outwards or remove it (a belt wraps the outside of its pulleys, listed in order around the loop)"
            ),
        }
    }
}

impl std::error::Error for PathError {}

/// The pulleys of a loop (`order`: clockwise, at least 3) that the belt does not wrap, given
/// the arc `wraps[k]` on pulley `order[k + 1]` (rad, in [0, 2 pi)): an arc within
/// [`TANGENT_TOLERANCE_RAD`] of none or of a full turn (the belt runs straight past the pulley,
/// or bends backwards by that little), then, when the arcs do not add up to one turn, the
/// pulleys with the largest arcs (each a backward bend wrapped to nearly a full turn), one
/// per extra turn.
fn unwrapped_pulleys(pulleys: &[Pulley], order: &[usize], wraps: &[f64]) -> Vec<PathError> {
    let n = order.len();
    if n < 3 {
        return Vec::new();
    }
    let error = |k: usize| {
        let (i, j, l) = (order[k], order[(k + 1) % n], order[(k + 2) % n]);
        let (a, b, c) = (pulleys[i], pulleys[j], pulleys[l]);
        let (ux, uz) = (c.x - a.x, c.z - a.z);
        let len = ux.hypot(uz);
        let off = ((b.x - a.x) * uz - (b.z - a.z) * ux).abs() / len.max(1e-300);
        let t = ((b.x - a.x) * ux + (b.z - a.z) * uz) / (len * len).max(1e-300);
        PathError::PulleyNotWrapped {
            pulley: j,
            before: i,
            after: l,
            collinear: off <= JOIN_TOLERANCE_M && (0.0..=1.0).contains(&t),
        }
    };
    let flat: Vec<PathError> = (0..n)
        .filter(|k| wraps[*k] < TANGENT_TOLERANCE_RAD || wraps[*k] > TAU - TANGENT_TOLERANCE_RAD)
        .map(error)
        .collect();
    if !flat.is_empty() {
        return flat;
    }
    let total: f64 = wraps.iter().sum();
    let extra = ((total - TAU) / TAU).round();
    if (total - TAU).abs() <= TANGENT_TOLERANCE_RAD * n as f64 || extra < 1.0 {
        return Vec::new();
    }
    let mut by_size: Vec<usize> = (0..n).collect();
    by_size.sort_by(|a, b| wraps[*b].total_cmp(&wraps[*a]));
    let mut worst: Vec<usize> = by_size.into_iter().take(extra as usize).collect();
    worst.sort_by_key(|k| order[(k + 1) % n]);
    worst.into_iter().map(error).collect()
}

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

    /// Builds the belt that wraps the given pulleys on their outside, in the plane y = `plane_y`
    /// of the track frame. Pulleys may be listed in either sense around the loop; the loop is
    /// always traversed so that a positive belt speed moves the lower run backwards (-x), i.e.
    /// drives the vehicle forwards, turning about +y. Segment 0 is the straight leaving the
    /// rearmost pulley (smallest x, then smallest z), followed by the arc on the next pulley in
    /// that sense, and so on: rotating or reversing the list gives the same path.
    pub fn from_pulleys(pulleys: &[Pulley], plane_y: f64) -> Result<Self, Vec<PathError>> {
        let n = pulleys.len();
        if n < 2 {
            return Err(vec![PathError::TooFewPulleys(n)]);
        }
        let mut errors: Vec<PathError> = pulleys
            .iter()
            .enumerate()
            .filter(|(_, p)| {
                !(p.radius > 0.0 && p.radius.is_finite() && p.x.is_finite() && p.z.is_finite())
            })
            .map(|(i, p)| PathError::BadPulley {
                pulley: i,
                radius: p.radius,
            })
            .collect();
        if !errors.is_empty() {
            return Err(errors);
        }
        // One pulley inside another (or the same centre), wherever they are in the list.
        for i in 0..n {
            for j in i + 1..n {
                let (a, b) = (pulleys[i], pulleys[j]);
                let dist = (b.x - a.x).hypot(b.z - a.z);
                if dist <= (a.radius - b.radius).abs() + 1e-9 {
                    errors.push(PathError::PulleysOverlap {
                        pulley: i,
                        next: j,
                        distance: dist,
                    });
                }
            }
        }
        if !errors.is_empty() {
            return Err(errors);
        }
        // Order the pulleys clockwise in the (x right, z up) picture, which is positive rotation
        // about +y. Keep the user's indices for messages.
        let mut order: Vec<usize> = (0..n).collect();
        let area2: f64 = (0..n)
            .map(|i| {
                let (a, b) = (pulleys[i], pulleys[(i + 1) % n]);
                a.x * b.z - b.x * a.z
            })
            .sum();
        if area2 > 0.0 {
            order.reverse();
        }
        // Start at the rearmost pulley (smallest x, then smallest z), whatever the list's first
        // entry: the loop, its segments' order and the grousers' places (grouser 0 at the loop
        // start) then depend on the pulleys only, never on the order they are listed in.
        let first = (0..n)
            .min_by(|&a, &b| {
                let (pa, pb) = (pulleys[order[a]], pulleys[order[b]]);
                pa.x.total_cmp(&pb.x).then(pa.z.total_cmp(&pb.z))
            })
            .unwrap_or(0);
        order.rotate_left(first);
        // Outer tangent between consecutive pulleys: normal n with n.(c2 - c1) = r1 - r2.
        let mut normals = Vec::with_capacity(n);
        let mut errors = Vec::new();
        for k in 0..n {
            let (i, j) = (order[k], order[(k + 1) % n]);
            let (p1, p2) = (pulleys[i], pulleys[j]);
            let d = (p2.x - p1.x, p2.z - p1.z);
            let dist = (d.0 * d.0 + d.1 * d.1).sqrt();
            let dr = p1.radius - p2.radius;
            if dist <= dr.abs() + 1e-9 {
                errors.push(PathError::PulleysOverlap {
                    pulley: i,
                    next: j,
                    distance: dist,
                });
                normals.push((0.0, 0.0));
                continue;
            }
            let u = (d.0 / dist, d.1 / dist);
            let left = (-u.1, u.0);
            let sa = dr / dist;
            let ca = (1.0 - sa * sa).sqrt();
            normals.push((ca * left.0 + sa * u.0, ca * left.1 + sa * u.1));
        }
        if !errors.is_empty() {
            return Err(errors);
        }
        // The arc on pulley order[k + 1], from normal k to the next straight's normal,
        // clockwise in (x, z) = positive about +y.
        let wraps: Vec<f64> = (0..n)
            .map(|k| {
                let (nk, nn) = (normals[k], normals[(k + 1) % n]);
                let cross = nk.0 * nn.1 - nk.1 * nn.0;
                let dot = nk.0 * nn.0 + nk.1 * nn.1;
                let theta = -cross.atan2(dot);
                if theta < 0.0 { theta + TAU } else { theta }
            })
            .collect();
        let errors = unwrapped_pulleys(pulleys, &order, &wraps);
        if !errors.is_empty() {
            return Err(errors);
        }
        let p3 = |x: f64, z: f64| DVec3::new(x, plane_y, z);
        let mut segments = Vec::with_capacity(2 * n);
        for k in 0..n {
            let (i, j) = (order[k], order[(k + 1) % n]);
            let (p1, p2) = (pulleys[i], pulleys[j]);
            let nk = normals[k];
            let a = p3(p1.x + p1.radius * nk.0, p1.z + p1.radius * nk.1);
            let b = p3(p2.x + p2.radius * nk.0, p2.z + p2.radius * nk.1);
            segments.push(Segment::Straight {
                start: a,
                direction: (b - a).normalize(),
                length: (b - a).length(),
            });
            let theta = wraps[k];
            if theta > 1e-9 {
                segments.push(Segment::Arc {
                    start: b,
                    centre: p3(p2.x, p2.z),
                    axis: DVec3::Y,
                    angle: theta,
                });
            }
        }
        TrackPath::new(segments)
    }

    /// A full circle of `radius` m about the axis +y through (`x`, `plane_y`, `z`) (a wheel's
    /// rolling circle), starting at its lowest point, traversed so that a positive belt speed
    /// moves the bottom backwards (-x), i.e. rolls forwards.
    pub fn circle(x: f64, z: f64, radius: f64, plane_y: f64) -> Result<Self, Vec<PathError>> {
        if !(radius > 0.0 && radius.is_finite() && x.is_finite() && z.is_finite()) {
            return Err(vec![PathError::BadPulley { pulley: 0, radius }]);
        }
        let centre = DVec3::new(x, plane_y, z);
        TrackPath::new(vec![Segment::Arc {
            start: centre - DVec3::Z * radius,
            centre,
            axis: DVec3::Y,
            angle: TAU,
        }])
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

/// An orthonormal frame on a track path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Origin, m.
    pub origin: DVec3,
    /// Unit tangent (direction of belt travel).
    pub tangent: DVec3,
    /// Unit lateral axis (the loop's axis).
    pub lateral: DVec3,
    /// Unit outward normal.
    pub normal: DVec3,
}

impl Frame {
    /// The frame's rotation (columns: tangent, lateral, normal).
    pub fn rotation(&self) -> DQuat {
        DQuat::from_mat3(&glam::DMat3::from_cols(
            self.tangent,
            self.lateral,
            self.normal,
        ))
    }

    /// Maps a point given in this frame's coordinates into the track frame, m.
    pub fn to_track(&self, local: DVec3) -> DVec3 {
        self.origin + self.tangent * local.x + self.lateral * local.y + self.normal * local.z
    }
}

/// N grousers spaced L/N apart along a path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GrouserLayout {
    /// Number of grousers on the loop (>= 1).
    pub count: usize,
    /// Arc length of grouser 0's footprint from the loop start, m.
    pub offset: f64,
}

impl GrouserLayout {
    /// Pitch L/N, m.
    pub fn pitch(&self, path: &TrackPath) -> f64 {
        path.length() / self.count as f64
    }

    /// Arc length of grouser k's footprint, wrapped into [0, L), m.
    pub fn footprint_s(&self, path: &TrackPath, k: usize) -> f64 {
        (self.offset + k as f64 * self.pitch(path)).rem_euclid(path.length())
    }

    /// Footprint frames of all grousers with the segment each belongs to at rest.
    pub fn footprints(&self, path: &TrackPath) -> Vec<(usize, Frame)> {
        (0..self.count)
            .map(|k| {
                let s = self.footprint_s(path, k);
                (path.segment_at(s), path.frame_at(s))
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn oval(a: f64, r: f64) -> TrackPath {
        TrackPath::from_pulleys(
            &[
                Pulley {
                    x: -a / 2.0,
                    z: 0.0,
                    radius: r,
                },
                Pulley {
                    x: a / 2.0,
                    z: 0.0,
                    radius: r,
                },
            ],
            0.0,
        )
        .unwrap()
    }

    #[test]
    fn oval_length_is_exact() {
        let p = oval(0.51, 0.082);
        let expected = 2.0 * 0.51 + 2.0 * PI * 0.082;
        assert!((p.length() - expected).abs() < 1e-12, "{}", p.length());
        assert_eq!(p.segments().len(), 4);
        // Lower run moves backwards so a positive belt speed drives forwards.
        let lower = p.frame_at(p.segment_start(2) + 0.1);
        assert!((lower.tangent - DVec3::NEG_X).length() < 1e-12);
        assert!((lower.normal - DVec3::NEG_Z).length() < 1e-12);
        assert!((lower.origin.z + 0.082).abs() < 1e-12);
        assert!((p.axis() - DVec3::Y).length() < 1e-12);
    }
}
