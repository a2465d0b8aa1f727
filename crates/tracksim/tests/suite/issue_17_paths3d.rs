//! Issue 17.3: spatial loops (`TrackPath::spatial`): straights in any direction and arcs about
//! any axis. Property tests on a random family of truly three-dimensional loops (a stadium
//! whose two runs climb and descend through bends, placed at a random pose, so that its arcs
//! have arbitrary axes): they close with the exact length, their frame is orthonormal and
//! continuous (across the closing join too), grousers are equally spaced by arc length, and a
//! loop broken at any segment is rejected with that segment named.

use glam::{DQuat, DVec3};
use proptest::prelude::*;
use std::f64::consts::PI;
use tracksim::geometry::{GrouserLayout, PathError, Segment, TrackPath};

/// Builds a loop segment by segment from a moving pose (position and frame).
struct Turtle {
    p: DVec3,
    /// Tangent, left, up.
    t: DVec3,
    l: DVec3,
    segs: Vec<Segment>,
}

impl Turtle {
    fn new() -> Self {
        Turtle {
            p: DVec3::ZERO,
            t: DVec3::X,
            l: DVec3::Y,
            segs: Vec::new(),
        }
    }
    fn straight(&mut self, length: f64) {
        self.segs.push(Segment::Straight {
            start: self.p,
            direction: self.t,
            length,
        });
        self.p += self.t * length;
    }
    /// An arc of `radius` turning by `angle` > 0 about the unit axis `a` (square to the
    /// tangent).
    fn arc(&mut self, a: DVec3, radius: f64, angle: f64) {
        let centre = self.p - self.t.cross(a) * radius;
        self.segs.push(Segment::Arc {
            start: self.p,
            centre,
            axis: a,
            angle,
        });
        let r = DQuat::from_axis_angle(a, angle);
        self.p = centre + r * (self.p - centre);
        self.t = r * self.t;
        self.l = r * self.l;
    }
    fn up(&self) -> DVec3 {
        self.t.cross(self.l)
    }
}

/// The random loop's parameters: bend radius, climb angle and length of the first run,
/// descent angle (as a fraction of the climb's) of the second, turn radius, margin of the
/// flats, and the pose it is placed at.
#[derive(Clone, Debug)]
struct Params {
    rho: f64,
    alpha: f64,
    climb: f64,
    beta_frac: f64,
    turn: f64,
    margin: f64,
    axis: DVec3,
    angle: f64,
    shift: DVec3,
}

/// The loop's segments and its exact length.
fn climbing_stadium(p: &Params) -> (Vec<Segment>, f64) {
    let (rho, a, la) = (p.rho, p.alpha, p.climb);
    let b = a * p.beta_frac;
    let h = 2.0 * rho * (1.0 - a.cos()) + la * a.sin();
    let lb = (h - 2.0 * rho * (1.0 - b.cos())) / b.sin();
    let core_a = 2.0 * rho * a.sin() + la * a.cos();
    let core_b = 2.0 * rho * b.sin() + lb * b.cos();
    let d = core_a.max(core_b) + p.margin;
    let (fa, fb) = ((d - core_a) / 2.0, (d - core_b) / 2.0);
    let mut k = Turtle::new();
    let run = |k: &mut Turtle, flat: f64, angle: f64, len: f64, climb: bool| {
        k.straight(flat);
        let s = if climb { -1.0 } else { 1.0 };
        k.arc(k.l * s, rho, angle);
        k.straight(len);
        k.arc(k.l * -s, rho, angle);
        k.straight(flat);
    };
    run(&mut k, fa, a, la, true);
    k.arc(k.up(), p.turn, PI);
    run(&mut k, fb, b, lb, false);
    k.arc(k.up(), p.turn, PI);
    let length = 2.0 * fa + 2.0 * rho * a + la + 2.0 * fb + 2.0 * rho * b + lb + 2.0 * PI * p.turn;
    // Place it at a random pose: the arcs' axes become arbitrary.
    let q = DQuat::from_axis_angle(p.axis, p.angle);
    let segs = k.segs.iter().map(|s| s.moved(q, p.shift)).collect();
    (segs, length)
}

fn params() -> impl Strategy<Value = Params> {
    (
        (0.02f64..0.2, 0.1f64..1.2, 0.05f64..1.0, 0.3f64..1.0),
        (0.05f64..0.5, 0.01f64..0.5),
        (
            prop::array::uniform3(-1.0f64..1.0),
            -PI..PI,
            prop::array::uniform3(-5.0f64..5.0),
        ),
    )
        .prop_filter("axis not zero", |(_, _, (a, _, _))| {
            DVec3::from_array(*a).length() > 0.1
        })
        .prop_map(
            |((rho, alpha, climb, beta_frac), (turn, margin), (a, angle, shift))| Params {
                rho,
                alpha,
                climb,
                beta_frac,
                turn,
                margin,
                axis: DVec3::from_array(a).normalize(),
                angle,
                shift: DVec3::from_array(shift),
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Random spatial loops are accepted with their exact length, are not planar (the planar
    /// constructor refuses them), and their frame is orthonormal, continuous along the loop
    /// (its axes turn no faster than the tightest bend and the spread-out twist allow) and
    /// across the closing join.
    #[test]
    fn random_spatial_loops_close_with_a_continuous_frame(p in params()) {
        let (segs, length) = climbing_stadium(&p);
        prop_assert!(TrackPath::new(segs.clone()).is_err());
        let path = TrackPath::spatial(segs).map_err(|e| TestCaseError::fail(format!("{e:?}")))?;
        prop_assert!(!path.is_planar());
        // Rounding of a dozen closed-form segment lengths: 1e-12 m.
        prop_assert!((path.length() - length).abs() < 1e-12, "{} vs {length}", path.length());
        let n = 4000;
        let ds = path.length() / n as f64;
        let rate = 1.0 / p.rho.min(p.turn) + 2.0 * PI / path.length();
        let mut prev = path.frame_at(0.0);
        for i in 1..=n {
            let f = path.frame_at(i as f64 * ds);
            for v in [f.tangent, f.lateral, f.normal] {
                prop_assert!((v.length() - 1.0).abs() < 1e-9);
            }
            prop_assert!(f.tangent.dot(f.lateral).abs() < 1e-9);
            prop_assert!((f.tangent.cross(f.lateral) - f.normal).length() < 1e-9);
            // Continuity: each axis moves by at most (curvature + twist rate) * ds, plus the
            // joins' tolerance (1e-4 rad) once.
            let step = rate * ds * 1.01 + 1e-4;
            prop_assert!((f.lateral - prev.lateral).length() < step, "lateral jumps at s = {}", i as f64 * ds);
            prop_assert!((f.tangent - prev.tangent).length() < step);
            prop_assert!((f.origin - prev.origin).length() <= ds * (1.0 + 1e-9));
            prev = f;
        }
        // i = n is s = L, wrapped to 0: the loop above compared the last frame with it.
    }

    /// Grousers on a random spatial loop are equally spaced by arc length: the path between
    /// consecutive footprints, measured as a fine polyline of frame origins, is one pitch
    /// (the polyline is short of the arc by at most pitch (ds / r)^2 / 24, below 1e-7 m here).
    #[test]
    fn grousers_on_spatial_loops_are_equally_spaced(p in params(), count in 3usize..60, offset in 0.0f64..1.0) {
        let (segs, _) = climbing_stadium(&p);
        let path = TrackPath::spatial(segs).unwrap();
        let g = GrouserLayout { count, offset };
        let pitch = g.pitch(&path);
        let m = 400;
        for k in 0..count {
            let s0 = g.footprint_s(&path, k);
            let mut len = 0.0;
            let mut last = path.frame_at(s0).origin;
            for j in 1..=m {
                let o = path.frame_at(s0 + pitch * j as f64 / m as f64).origin;
                len += (o - last).length();
                last = o;
            }
            // A chord of an arc of radius r spanning ds is short of it by ds (ds / r)^2 / 24.
            let ds = pitch / m as f64;
            let bound = pitch * (ds / p.rho.min(p.turn)).powi(2) / 24.0 + 1e-9;
            prop_assert!(len <= pitch + 1e-9 && pitch - len < bound, "grouser {k}: {len} vs {pitch} (bound {bound})");
            let next = path.frame_at(g.footprint_s(&path, (k + 1) % count)).origin;
            prop_assert!((last - next).length() < 1e-9);
        }
    }

    /// Moving one segment's start point breaks the loop at that segment's joins, and bending a
    /// straight makes a kink there: each rejected with the segment named in the message.
    #[test]
    fn broken_spatial_loops_name_the_segment(p in params(), pick in 0usize..100, d in prop::array::uniform3(-1.0f64..1.0)) {
        let (mut segs, _) = climbing_stadium(&p);
        let n = segs.len();
        let i = pick % n;
        let d = DVec3::from_array(d);
        prop_assume!(d.length() > 0.1);
        let shift = d.normalize() * 1e-3;
        match &mut segs[i] {
            Segment::Straight { start, .. } => *start += shift,
            Segment::Arc { start, centre, .. } => {
                *start += shift;
                *centre += shift;
            }
        }
        let errs = TrackPath::spatial(segs).unwrap_err();
        let prev = (i + n - 1) % n;
        let gap = errs.iter().find(|e| matches!(e, PathError::Gap { segment, next, .. } if *segment == prev && *next == i));
        prop_assert!(gap.is_some(), "{errs:?}");
        let msg = gap.unwrap().to_string();
        prop_assert!(msg.contains(&format!("segment {prev}")) && msg.contains(&format!("segment {i}")), "{msg}");
        // A straight turned by 1 mrad about its left axis: kinks at both its ends.
        let (mut segs, _) = climbing_stadium(&p);
        let j = segs.iter().position(|s| s.is_straight()).unwrap();
        if let Segment::Straight { direction, .. } = &mut segs[j] {
            *direction = DQuat::from_axis_angle(direction.any_orthonormal_vector(), 1e-3) * *direction;
        }
        let errs = TrackPath::spatial(segs).unwrap_err();
        let kink = errs.iter().find(|e| matches!(e, PathError::Kink { next, .. } if *next == j));
        prop_assert!(kink.is_some(), "{errs:?}");
        let want = format!("segment {j}");
        prop_assert!(kink.unwrap().to_string().contains(&want));
    }
}

/// A planar loop given to the spatial constructor has the planar frame (lateral = the loop's
/// axis everywhere), so the two constructors agree where both apply.
#[test]
fn the_spatial_frame_of_a_planar_loop_is_the_planar_frame() {
    let pulleys = [
        tracksim::geometry::Pulley {
            x: -0.25,
            z: 0.0,
            radius: 0.08,
        },
        tracksim::geometry::Pulley {
            x: 0.25,
            z: 0.05,
            radius: 0.05,
        },
    ];
    let planar = TrackPath::from_pulleys(&pulleys, 0.2).unwrap();
    let spatial = TrackPath::spatial(planar.segments().to_vec()).unwrap();
    assert!(planar.is_planar() && !spatial.is_planar());
    for i in 0..1000 {
        let s = planar.length() * i as f64 / 1000.0;
        let (a, b) = (planar.frame_at(s), spatial.frame_at(s));
        assert!((a.origin - b.origin).length() < 1e-12);
        assert!((a.lateral - b.lateral).length() < 1e-9, "s = {s}");
        assert!((a.normal - b.normal).length() < 1e-9, "s = {s}");
    }
}
