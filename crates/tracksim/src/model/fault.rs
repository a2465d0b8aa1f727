//! A command's `fault` table compiled ([`Faults`]): track and flipper faults by index, the
//! latency and the video state, each checked with its key path (issue 43).

use super::{Method, VehicleModel};
use crate::check::Checker;
use crate::spec::{FaultSpec, PatchSpec};

/// Longest added command latency, s.
pub const MAX_LATENCY_S: f64 = 10.0;

/// Largest friction coefficient of a low-friction patch (dimensionless): rubber on dry
/// concrete is about 1; a patch is meant to be slippery.
pub const MAX_PATCH_FRICTION: f64 = 2.0;

/// A low-friction patch on the ground (`fault.patch`; a wet or icy patch): contacts of a
/// robot with the fixed ground whose contact point lies inside the rectangle have its friction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionPatch {
    /// The rectangle's centre, world x and y, m.
    pub centre: [f64; 2],
    /// The rectangle's side lengths along world x and y, m.
    pub size: [f64; 2],
    /// The friction coefficient inside it, dimensionless.
    pub friction: f64,
}

impl FrictionPatch {
    /// Whether the world point (`x`, `y`) m lies inside the rectangle (its edges included).
    pub fn contains(&self, x: f64, y: f64) -> bool {
        (x - self.centre[0]).abs() <= 0.5 * self.size[0]
            && (y - self.centre[1]).abs() <= 0.5 * self.size[1]
    }
}

/// A track's fault.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TrackFault {
    /// No fault: the track follows its commands.
    #[default]
    Ok,
    /// The belt is held at 0 m/s whatever is commanded (a seized drive, a thrown track's
    /// brake): the other tracks drive, so the robot turns about the stopped one.
    Stopped,
    /// The drive gives no force (a lost motor or controller): the belt free-wheels, its speed
    /// set by the ground and the vehicle.
    Unpowered,
}

impl TrackFault {
    /// The name a file gives it.
    pub fn name(self) -> &'static str {
        match self {
            TrackFault::Ok => "ok",
            TrackFault::Stopped => "stopped",
            TrackFault::Unpowered => "unpowered",
        }
    }

    /// Parses a file's name for it.
    pub fn from_name(s: &str) -> Option<TrackFault> {
        Some(match s {
            "ok" => TrackFault::Ok,
            "stopped" => TrackFault::Stopped,
            "unpowered" => TrackFault::Unpowered,
            _ => return None,
        })
    }
}

/// The faults one command entry sets or clears (`None`: unchanged).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Faults {
    /// Per track index (empty: none named).
    pub track: Vec<Option<TrackFault>>,
    /// Per flipper index: jammed (true) or cleared (false) (empty: none named).
    pub flipper_jammed: Vec<Option<bool>>,
    /// Added command latency, s (0: none). Informational: no effect on the physics.
    pub latency_s: Option<f64>,
    /// The trainee's onboard video dropped (true) or back (false). No effect on the physics.
    pub video_dropped: Option<bool>,
    /// A low-friction patch put on the ground (`Some(Some(..))`) or removed (`Some(None)`).
    pub patch: Option<Option<FrictionPatch>>,
}

impl Faults {
    /// Whether it changes nothing.
    pub fn is_empty(&self) -> bool {
        self.track.iter().all(Option::is_none)
            && self.flipper_jammed.iter().all(Option::is_none)
            && self.latency_s.is_none()
            && self.video_dropped.is_none()
            && self.patch.is_none()
    }

    /// Whether it makes some track unpowered.
    pub fn unpowers(&self) -> bool {
        self.track.contains(&Some(TrackFault::Unpowered))
    }
}

/// Compiles command `k`'s `fault` table (`k`: its key path, e.g. `commands[3]`) for `vehicle`.
pub(crate) fn compile_faults(
    c: &mut Checker,
    k: &str,
    f: &FaultSpec,
    vehicle: &VehicleModel,
) -> Faults {
    let mut out = Faults {
        track: vec![None; vehicle.tracks.len()],
        flipper_jammed: vec![None; vehicle.flippers.len()],
        ..Faults::default()
    };
    let tracks: Vec<&str> = vehicle.tracks.iter().map(|t| t.name.as_str()).collect();
    for (name, kind) in &f.track {
        let key = format!("{k}.fault.track.{name}");
        match (vehicle.track_index(name), TrackFault::from_name(kind)) {
            (None, _) => c.push(
                key,
                format!(
                    "no track called \"{name}\"; the vehicle has {}",
                    tracks.join(", ")
                ),
            ),
            (_, None) => c.push(
                key,
                format!(
                    "unknown track fault \"{}\"; use \"stopped\", \"unpowered\" or \"ok\"",
                    crate::check::echoed(kind)
                ),
            ),
            (Some(i), Some(t)) => out.track[i] = Some(t),
        }
    }
    let flippers: Vec<&str> = vehicle.flippers.iter().map(|f| f.name.as_str()).collect();
    for (name, kind) in &f.flipper {
        let key = format!("{k}.fault.flipper.{name}");
        let jammed = match kind.as_str() {
            "jammed" => Some(true),
            "ok" => Some(false),
            _ => None,
        };
        match (vehicle.flipper_index(name), jammed) {
            (None, _) => c.push(
                key,
                format!(
                    "no flipper called \"{name}\"; the vehicle has {}",
                    if flippers.is_empty() {
                        "none".to_string()
                    } else {
                        flippers.join(", ")
                    }
                ),
            ),
            (_, None) => c.push(
                key,
                format!(
                    "unknown flipper fault \"{}\"; use \"jammed\" or \"ok\"",
                    crate::check::echoed(kind)
                ),
            ),
            (Some(i), Some(j)) => out.flipper_jammed[i] = Some(j),
        }
    }
    if let Some(l) = f.latency_s {
        if l.is_finite() && (0.0..=MAX_LATENCY_S).contains(&l) {
            out.latency_s = Some(l);
        } else {
            c.push(
                format!("{k}.fault.latency_s"),
                format!(
                    "must be a number of seconds in [0, {MAX_LATENCY_S}] (0 clears it), got {}",
                    crate::check::num(l)
                ),
            );
        }
    }
    if let Some(v) = &f.video {
        match v.as_str() {
            "dropped" => out.video_dropped = Some(true),
            "ok" => out.video_dropped = Some(false),
            _ => c.push(
                format!("{k}.fault.video"),
                format!(
                    "unknown video state \"{}\"; use \"dropped\" or \"ok\"",
                    crate::check::echoed(v)
                ),
            ),
        }
    }
    if let Some(p) = &f.patch {
        out.patch = compile_patch(c, &format!("{k}.fault.patch"), p);
    }
    out
}

/// Compiles a `fault.patch` value at key `key`: a rectangle of positive finite sides, a finite
/// centre and a friction in [0, [`MAX_PATCH_FRICTION`]], or `"ok"` (removed).
fn compile_patch(c: &mut Checker, key: &str, p: &PatchSpec) -> Option<Option<FrictionPatch>> {
    let a = match p {
        PatchSpec::Word(w) if w == "ok" => return Some(None),
        PatchSpec::Word(w) => {
            c.push(
                key,
                format!(
                    "unknown patch state \"{}\"; use \"ok\" to remove the patch, or a table \
                     {{ centre_m = [x, y], size_m = [a, b], friction = 0.1 }} to put one",
                    crate::check::echoed(w)
                ),
            );
            return None;
        }
        PatchSpec::Area(a) => a,
    };
    let before = c.issues.len();
    c.finite(&format!("{key}.centre_m"), &a.centre_m);
    for (i, s) in a.size_m.iter().enumerate() {
        c.positive(&format!("{key}.size_m[{i}]"), *s, "m");
    }
    if !(a.friction.is_finite() && (0.0..=MAX_PATCH_FRICTION).contains(&a.friction)) {
        c.push(
            format!("{key}.friction"),
            format!(
                "must be a friction coefficient in [0, {MAX_PATCH_FRICTION}], got {}",
                crate::check::num(a.friction)
            ),
        );
    }
    (c.issues.len() == before).then_some(Some(FrictionPatch {
        centre: a.centre_m,
        size: a.size_m,
        friction: a.friction,
    }))
}

/// Whether `method` models an unpowered (free-wheeling) belt: the segment links, the wheels
/// and the plate chain's sprocket have joints whose drive can be let go. A belt of surface
/// velocity (`constraint_to_ground`) cannot: it has no belt body or drive joint, only a speed
/// imposed on its contacts, and Rapier's friction is one coefficient per contact manifold, the
/// same in every direction, so a belt free along its length but gripping sideways has no
/// expression there (a surface velocity equal to the ground's, renewed each step, would hold
/// the speed along the belt like a brake within each step, not let it roll).
pub fn models_unpowered(method: Method) -> bool {
    matches!(
        method,
        Method::Okada2020
            | Method::Okada2020NoGrousers
            | Method::Okada2020LineTips
            | Method::Okada2020Clustered
            | Method::Wheels(_)
            | Method::Plates
    )
}
