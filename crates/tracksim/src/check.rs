//! Collecting input problems with their key paths, and the limits of what the engine (f32)
//! can represent: every checked number is also held to the range of its unit
//! ([`unit_range`]), so a value finite in f64 but beyond f32 (a mass of 1e-300 kg, a belt
//! speed of 1e39 m/s) is refused with the limit instead of running into NaN.

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

/// Largest magnitude of a position or length, m: 100 km (Rapier is f32; the floating origin
/// keeps the vehicle near the origin, but terrain and starts must stay within this range).
pub const MAX_LENGTH_M: f64 = 1e5;
/// Smallest positive length, m (1 um).
pub const MIN_LENGTH_M: f64 = 1e-6;
/// Largest speed (belt, forward), m/s, and yaw rate, rad/s: far beyond any tracked vehicle
/// (a run that fast goes unstable and exits 3), well within f32.
pub const MAX_SPEED_MPS: f64 = 1000.0;
/// Largest simulated duration, s (one day).
pub const MAX_DURATION_S: f64 = 86_400.0;
/// Largest number of physics steps in one run (`duration_s / dt_s`).
pub const MAX_STEPS: f64 = 1e8;
/// Smallest physics step, s.
pub const MIN_DT_S: f64 = 1e-5;
/// Largest magnitude of any other checked number (angles in degrees, gains, ...).
pub const MAX_PLAIN: f64 = 1e9;

/// The range `(smallest positive value, largest magnitude)` allowed for a quantity in `unit`.
pub fn unit_range(unit: &str) -> (f64, f64) {
    match unit {
        "m" => (MIN_LENGTH_M, MAX_LENGTH_M),
        "kg" => (1e-6, 1e6),
        "kg m^2" => (1e-12, 1e6),
        "s" => (1e-6, MAX_DURATION_S),
        "N m" => (1e-6, 1e7),
        "N s/m" => (1e-9, 1e9),
        "" => (1e-6, 1e4),
        _ => (1e-12, MAX_PLAIN),
    }
}

/// A number for a message: plain when moderate, in exponent form when huge or tiny (a value
/// of 1e300 is not printed as 301 digits).
pub fn num(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-4..1e7).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
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
        let (lo, hi) = unit_range(unit);
        if !(v.is_finite() && v > 0.0) {
            self.push(
                key,
                format!("must be a finite number > 0 {unit}, got {}", num(v)),
            );
        } else if !(lo..=hi).contains(&v) {
            self.push(
                key,
                format!(
                    "must be between {lo:e} and {hi:e} {unit} (the engine is f32), got {}",
                    num(v)
                ),
            );
        }
    }
    pub(crate) fn non_negative(&mut self, key: &str, v: f64, unit: &str) {
        let (lo, hi) = unit_range(unit);
        if !(v.is_finite() && v >= 0.0) {
            self.push(
                key,
                format!("must be a finite number >= 0 {unit}, got {}", num(v)),
            );
        } else if v > 0.0 && v < lo {
            self.push(
                key,
                format!(
                    "must be 0 or at least {lo:e} {unit} (smaller is 0 to the f32 engine), got {}",
                    num(v)
                ),
            );
        } else if v > hi {
            self.push(
                key,
                format!(
                    "must be at most {hi:e} {unit} (the engine is f32), got {}",
                    num(v)
                ),
            );
        }
    }
    /// Finite numbers of magnitude at most [`MAX_LENGTH_M`] (keys ending in `_m`) or
    /// [`MAX_PLAIN`].
    pub(crate) fn finite(&mut self, key: &str, v: &[f64]) {
        let max = if key.ends_with("_m") || key.contains("_m[") {
            MAX_LENGTH_M
        } else {
            MAX_PLAIN
        };
        if v.iter().any(|x| !x.is_finite()) {
            self.push(key, format!("must be finite numbers, got {v:?}"));
        } else if v.iter().any(|x| x.abs() > max) {
            self.push(
                key,
                format!(
                    "must be at most {max:e} in magnitude (the engine is f32), got [{}]",
                    v.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", ")
                ),
            );
        }
    }
    /// A track or flipper name, which becomes part of `trajectory.csv` column names: 1 to 64
    /// ASCII letters, digits, `_` or `-` (no comma, quote, space or newline to break the CSV).
    pub(crate) fn column_name(&mut self, key: &str, name: &str) {
        let ok = (1..=64).contains(&name.len())
            && name
                .chars()
                .all(|ch| ch.is_ascii_alphanumeric() || ch == '_' || ch == '-');
        if !ok {
            let shown: String = name.chars().take(64).collect();
            self.push(
                key,
                format!(
                    "must be 1 to 64 ASCII letters, digits, `_` or `-` (it names columns of \
                     trajectory.csv), got {shown:?}"
                ),
            );
        }
    }
    /// A finite number of magnitude at most `max` `unit`.
    pub(crate) fn bounded(&mut self, key: &str, v: f64, max: f64, unit: &str) {
        if !(v.is_finite() && v.abs() <= max) {
            self.push(
                key,
                format!(
                    "must be a finite number between -{max} and {max} {unit}, got {}",
                    num(v)
                ),
            );
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
        if points.len() > MAX_HULL_POINTS {
            self.push(
                key,
                format!(
                    "at most {MAX_HULL_POINTS} points, got {}: simplify the shape",
                    points.len()
                ),
            );
        }
        let pts: Vec<DVec3> = points.iter().map(|p| v3(*p)).collect();
        let usable = pts.len() >= 4 && pts.len() <= MAX_HULL_POINTS;
        if usable && pts.iter().all(|p| p.is_finite()) && hull_volume(&pts) < 1e-15 {
            self.push(key, "points are coplanar: the hull has no volume");
        }
        pts
    }
}

/// Most points of one convex shape.
pub const MAX_HULL_POINTS: usize = 10_000;

/// Volume of the convex hull of `pts`, m^3 (parry's quickhull, O(n log n); 0 when the points
/// are coplanar or the hull cannot be built).
pub(crate) fn hull_volume(pts: &[DVec3]) -> f64 {
    use rapier3d::parry::transformation::try_convex_hull;
    let fp: Vec<_> = pts.iter().map(|p| f(*p)).collect();
    let Ok((verts, tris)) = try_convex_hull(&fp) else {
        return 0.0;
    };
    if tris.is_empty() {
        return 0.0;
    }
    // Volume of the closed triangle mesh by the divergence theorem, about its first vertex.
    let o = verts[0];
    let vol: f32 = tris
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| verts[i as usize] - o);
            a.dot(b.cross(c))
        })
        .sum();
    f64::from(vol.abs()) / 6.0
}

/// Most characters of a name from the input echoed in a message (a key may be 50 MB long).
pub(crate) const MAX_ECHOED_NAME_CHARS: usize = 100;

/// `name` as it is echoed in a message: cut to [`MAX_ECHOED_NAME_CHARS`] characters.
pub(crate) fn echoed(name: &str) -> String {
    if name.chars().count() <= MAX_ECHOED_NAME_CHARS {
        name.to_string()
    } else {
        let kept: String = name.chars().take(MAX_ECHOED_NAME_CHARS).collect();
        format!("{kept}...")
    }
}

/// The name of `known` that `given` is most likely a typo of: the most similar by
/// Jaro-Winkler similarity if at least 0.75 (`sucess_x_m` -> `success_x_m`, `dtt` -> `dt_s`),
/// else one that contains `given` (at least 3 characters: `period` -> `control_period_s`).
pub(crate) fn did_you_mean<'a>(given: &str, known: &[&'a str]) -> Option<&'a str> {
    let lower = given.to_ascii_lowercase();
    let best = known
        .iter()
        .map(|k| (strsim::jaro_winkler(&lower, &k.to_ascii_lowercase()), *k))
        .filter(|(s, _)| *s >= 0.75)
        .max_by(|a, b| a.0.total_cmp(&b.0));
    if let Some((_, k)) = best {
        return Some(k);
    }
    if lower.chars().count() < 3 {
        return None;
    }
    known
        .iter()
        .find(|k| k.to_ascii_lowercase().contains(&lower))
        .copied()
}

/// The message for an unknown name `given` among `known` (each a `what`, e.g. "key"): a
/// "did you mean" when one is close, and every accepted name (the list is never cut: it comes
/// from the code, not the file).
pub(crate) fn unknown_name(what: &str, given: &str, known: &[&str]) -> String {
    let list = known
        .iter()
        .map(|k| format!("`{k}`"))
        .collect::<Vec<_>>()
        .join(", ");
    let given = echoed(given);
    match did_you_mean(&given, known) {
        _ if known.is_empty() => format!("unknown {what} `{given}`: none is accepted here"),
        Some(k) => format!(
            "unknown {what} `{given}`: did you mean `{k}`? The accepted {what}s are: {list}"
        ),
        None => format!("unknown {what} `{given}`; the accepted {what}s are: {list}"),
    }
}

/// Longest line of a parser message kept whole, characters (a 50 MB line is not echoed).
pub const MAX_MESSAGE_LINE_CHARS: usize = 200;

/// Cuts every line of a parser message to [`MAX_MESSAGE_LINE_CHARS`] characters.
pub fn shorten(message: &str) -> String {
    message
        .lines()
        .map(|l| {
            if l.chars().count() > MAX_MESSAGE_LINE_CHARS {
                let cut: String = l.chars().take(MAX_MESSAGE_LINE_CHARS).collect();
                format!("{cut} ... (line cut)")
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}
