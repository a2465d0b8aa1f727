//! A command's `fault` table (issue 43): what an instructor injects into a session, recorded in
//! its `commands.toml` so that `tracksim run FILE --commands DIR/commands.toml` reproduces it.
//!
//! ```toml
//! [[commands]]
//! t_s = 12.5
//! fault = { track = { left = "stopped" }, flipper = { front = "jammed" } }
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
}

impl FaultSpec {
    /// Whether the table sets nothing.
    pub fn is_empty(&self) -> bool {
        self.track.is_empty()
            && self.flipper.is_empty()
            && self.latency_s.is_none()
            && self.video.is_none()
    }
}
