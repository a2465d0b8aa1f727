//! What can be wrong with a track path ([`PathError`]), each naming the segment or pulley at
//! fault.

use super::{JOIN_TOLERANCE_M, TANGENT_TOLERANCE_RAD};
use std::fmt;

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
