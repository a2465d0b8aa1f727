//! A scenario's compiled `[course]` ([`CourseModel`]): gates, repetitions, time limit,
//! penalties and marked obstacles in SI units and radians, every bad value reported with its
//! key path. The run layer scores a run on it (`run::course`); docs/COURSES.md has the rules.

use crate::check::Checker;
use crate::spec::{CourseObstacleSpec, CourseSpec, GateSpec};
use glam::DVec3;

/// Most gates of one course.
pub const MAX_GATES: usize = 1000;
/// Most marked obstacles of one course.
pub const MAX_COURSE_OBSTACLES: usize = 1000;
/// Most repetitions of one course.
pub const MAX_REPETITIONS: u32 = 10_000;
/// Most characters of a course or obstacle name.
pub const MAX_COURSE_NAME_CHARS: usize = 200;

/// What passes a gate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GateKind {
    /// A waypoint: the body's origin comes within `radius` m of the centre (horizontally).
    Waypoint {
        /// Radius, m.
        radius: f64,
    },
    /// A gate line `width` m long through the centre, across the direction `yaw` (rad about z
    /// from +x): passed when the body's origin crosses it in that direction.
    Line {
        /// Width, m.
        width: f64,
        /// Direction of crossing, rad.
        yaw: f64,
    },
}

/// A gate of a course.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gate {
    /// Centre x (world), m.
    pub x: f64,
    /// Centre y (world), m.
    pub y: f64,
    /// Waypoint or line.
    pub kind: GateKind,
}

/// A marked obstacle: a box not to be touched (a marked volume, not a solid).
#[derive(Clone, Debug, PartialEq)]
pub struct CourseObstacle {
    /// Name in fault events.
    pub name: String,
    /// Centre (world), m.
    pub centre: DVec3,
    /// Half extents, m.
    pub half: DVec3,
    /// Yaw about z, rad.
    pub yaw: f64,
}

/// Penalty time per fault, s.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Penalties {
    /// Per reset, s.
    pub reset: f64,
    /// Per tip-over, s.
    pub tip_over: f64,
    /// Per touch of a marked obstacle, s.
    pub touch: f64,
}

/// A compiled course (`[course]`).
#[derive(Clone, Debug, PartialEq)]
pub struct CourseModel {
    /// Name.
    pub name: String,
    /// Gates in the order they are passed; a repetition ends at the last.
    pub gates: Vec<Gate>,
    /// Repetitions to complete (>= 1).
    pub repetitions: u32,
    /// Time limit of the trial, s.
    pub time_limit: Option<f64>,
    /// Penalties, s per fault.
    pub penalties: Penalties,
    /// Marked obstacles.
    pub obstacles: Vec<CourseObstacle>,
}

fn check_name(c: &mut Checker, key: &str, name: &str) {
    let n = name.chars().count();
    // A blank name (only spaces) is no name: the leaderboard groups by it (issue 65).
    if name.trim().is_empty() && n > 0 {
        c.push(
            key,
            "is blank: give the course a name (it groups attempts on the leaderboard), or leave \
             the key out for \"course\"",
        );
    } else if n == 0 || n > MAX_COURSE_NAME_CHARS || name.chars().any(char::is_control) {
        c.push(
            key,
            format!(
                "must be 1 to {MAX_COURSE_NAME_CHARS} characters without control characters, got \
                 {} characters",
                n
            ),
        );
    }
}

fn gate(c: &mut Checker, k: &str, g: &GateSpec) -> Gate {
    c.finite(&format!("{k}.x_m"), &[g.x_m]);
    c.finite(&format!("{k}.y_m"), &[g.y_m]);
    let kind = match (g.radius_m, g.width_m) {
        (Some(r), None) => {
            c.positive(&format!("{k}.radius_m"), r, "m");
            if g.yaw_deg.is_some() {
                c.push(
                    format!("{k}.yaw_deg"),
                    "a waypoint (radius_m) has no direction: yaw_deg is for a gate line (width_m)",
                );
            }
            GateKind::Waypoint { radius: r }
        }
        (None, Some(w)) => {
            c.positive(&format!("{k}.width_m"), w, "m");
            let yaw = g.yaw_deg.unwrap_or(0.0);
            c.finite(&format!("{k}.yaw_deg"), &[yaw]);
            GateKind::Line {
                width: w,
                yaw: yaw.to_radians(),
            }
        }
        (Some(_), Some(_)) => {
            c.push(
                format!("{k}.width_m"),
                "give either radius_m (a waypoint) or width_m (a gate line), not both",
            );
            GateKind::Waypoint { radius: 1.0 }
        }
        (None, None) => {
            c.push(
                format!("{k}.radius_m"),
                "give radius_m (a waypoint) or width_m with yaw_deg (a gate line)",
            );
            GateKind::Waypoint { radius: 1.0 }
        }
    };
    Gate {
        x: g.x_m,
        y: g.y_m,
        kind,
    }
}

fn obstacle(c: &mut Checker, k: &str, i: usize, o: &CourseObstacleSpec) -> CourseObstacle {
    c.finite(&format!("{k}.x_m"), &[o.x_m]);
    c.finite(&format!("{k}.y_m"), &[o.y_m]);
    c.finite(&format!("{k}.z_m"), &[o.z_m]);
    for (j, h) in o.half_m.iter().enumerate() {
        c.positive(&format!("{k}.half_m[{j}]"), *h, "m");
    }
    c.finite(&format!("{k}.yaw_deg"), &[o.yaw_deg]);
    let name = o.name.clone().unwrap_or_else(|| format!("obstacle {i}"));
    check_name(c, &format!("{k}.name"), &name);
    CourseObstacle {
        name,
        centre: DVec3::new(o.x_m, o.y_m, o.z_m),
        half: DVec3::from_array(o.half_m),
        yaw: o.yaw_deg.to_radians(),
    }
}

/// Checks `[course]` and compiles it (degrees to radians).
pub(crate) fn compile_course(c: &mut Checker, s: &CourseSpec) -> CourseModel {
    let name = s.name.clone().unwrap_or_else(|| "course".into());
    check_name(c, "course.name", &name);
    if s.gates.is_empty() || s.gates.len() > MAX_GATES {
        c.push(
            "course.gates",
            format!(
                "a course needs 1 to {MAX_GATES} gates ([[course.gates]]), got {}",
                s.gates.len()
            ),
        );
    }
    let gates = s
        .gates
        .iter()
        .take(MAX_GATES)
        .enumerate()
        .map(|(i, g)| gate(c, &format!("course.gates[{i}]"), g))
        .collect();
    if s.repetitions == 0 || s.repetitions > MAX_REPETITIONS {
        c.push(
            "course.repetitions",
            format!(
                "must be a whole number from 1 to {MAX_REPETITIONS}, got {}",
                s.repetitions
            ),
        );
    }
    if let Some(t) = s.time_limit_s {
        c.positive("course.time_limit_s", t, "s");
    }
    let p = &s.penalty_s;
    c.non_negative("course.penalty_s.reset", p.reset, "s");
    c.non_negative("course.penalty_s.tip_over", p.tip_over, "s");
    c.non_negative("course.penalty_s.touch", p.touch, "s");
    if s.obstacles.len() > MAX_COURSE_OBSTACLES {
        c.push(
            "course.obstacles",
            format!(
                "at most {MAX_COURSE_OBSTACLES} marked obstacles, got {}",
                s.obstacles.len()
            ),
        );
    }
    let obstacles = s
        .obstacles
        .iter()
        .take(MAX_COURSE_OBSTACLES)
        .enumerate()
        .map(|(i, o)| obstacle(c, &format!("course.obstacles[{i}]"), i, o))
        .collect();
    CourseModel {
        name,
        gates,
        repetitions: s.repetitions,
        time_limit: s.time_limit_s,
        penalties: Penalties {
            reset: p.reset,
            tip_over: p.tip_over,
            touch: p.touch,
        },
        obstacles,
    }
}
