//! A command's `fault` table (issue 43): what an instructor injects into a session, recorded in
//! its `commands.toml` so that `tracksim run FILE --commands DIR/commands.toml` reproduces it.
//!
//! ```toml
//! [[commands]]
//! t_s = 12.5
//! fault = { track = { left = "stopped" }, flipper = { front = "jammed" } }
//!
//! [[commands]]
//! t_s = 20.0
//! fault.patch = { centre_m = [2.0, 0.0], size_m = [1.0, 1.5], friction = 0.1 }
//! ```
//!
//! Each key changes only what it names, from the entry's time on, until another entry says
//! `"ok"`. Units and meanings are in docs/TRAINING.md ("Faults").

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A command's `fault` table: faults set or cleared at the entry's time.
#[derive(Clone, Debug, Default, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FaultSpec {
    /// Track faults by track name: `"stopped"` (the belt held at 0 whatever is commanded),
    /// `"unpowered"` (the drive gives no force: the belt free-wheels) or `"ok"` (cleared: the
    /// latest command applies again).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub track: BTreeMap<String, String>,
    /// Flipper faults by flipper name: `"jammed"` (held at the angle it has, commands ignored)
    /// or `"ok"` (cleared: the latest target applies again).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub flipper: BTreeMap<String, String>,
    /// Added command latency, s (0 to 10; 0 clears it): the trainee's controls reached the
    /// robot this late. Informational in a file: the entries that follow are already the
    /// controls as applied (late), so a replay needs no delay of its own.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub latency_s: Option<f64>,
    /// The onboard video and sensor feed of the trainee's page: `"dropped"` (frozen, "no
    /// signal") or `"ok"`. No effect on the physics.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub video: Option<String>,
    /// A low-friction patch on the ground (a wet or icy patch): a table `{ centre_m, size_m,
    /// friction }` puts it there (replacing the one before), `"ok"` removes it. One patch per
    /// world, whichever robot's entry names it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub patch: Option<PatchSpec>,
}

/// A `fault.patch` value: the patch's rectangle and friction, or a word (`"ok"` removes it;
/// any other word is refused when compiled, naming the key).
#[derive(Clone, Debug, PartialEq)]
pub enum PatchSpec {
    /// The patch to put on the ground.
    Area(PatchArea),
    /// A word: `"ok"` removes the patch.
    Word(String),
}

/// A low-friction patch: an axis-aligned rectangle of the ground in world x, y.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PatchArea {
    /// The rectangle's centre, world x and y, m.
    pub centre_m: [f64; 2],
    /// The rectangle's side lengths along world x and y, m.
    pub size_m: [f64; 2],
    /// The friction coefficient of a contact with the ground inside it (0 to 2),
    /// dimensionless.
    pub friction: f64,
}

impl Serialize for PatchSpec {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            PatchSpec::Area(a) => a.serialize(s),
            PatchSpec::Word(w) => s.serialize_str(w),
        }
    }
}

impl<'de> Deserialize<'de> for PatchSpec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        /// A table is read as [`PatchArea`] (its own errors: an unknown key named), a string
        /// as a word.
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = PatchSpec;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str(
                    "a table { centre_m = [x, y], size_m = [a, b], friction = mu } or \"ok\"",
                )
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<PatchSpec, E> {
                Ok(PatchSpec::Word(v.to_string()))
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, m: A) -> Result<PatchSpec, A::Error> {
                PatchArea::deserialize(serde::de::value::MapAccessDeserializer::new(m))
                    .map(PatchSpec::Area)
            }
        }
        d.deserialize_any(V)
    }
}

impl FaultSpec {
    /// Whether the table sets nothing.
    pub fn is_empty(&self) -> bool {
        self.track.is_empty()
            && self.flipper.is_empty()
            && self.latency_s.is_none()
            && self.video.is_none()
            && self.patch.is_none()
    }
}
