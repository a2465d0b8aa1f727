//! Track methods as plug-ins: one file per method behind the [`Track`] trait, one dispatch
//! point ([`build_track`], from the model's [`crate::model::Method`]), and the parts they share
//! ([`common`]). The world holds a list of `Box<dyn Track>` and never names a method.
//!
//! - [`okada2020`]: the paper's segment links with grousers and rollback (and its no-grouser
//!   variant);
//! - [`clustered`]: the segment links with each link's grousers as one compound, clustered;
//! - [`line_tips`]: the segment links with a 2-point tip collider per grouser on flat ground;
//! - [`wheels`]: multiple wheels along the lower run;
//! - [`constraint_to_ground`]: one rigid outline whose contacts get the belt's surface velocity;
//! - [`plates`]: a closed chain of plates on hinges around sprocket and idler.

#![warn(clippy::too_many_lines)]

pub mod clustered;
pub mod common;
pub mod constraint_to_ground;
pub mod line_tips;
mod method;
pub mod okada2020;
pub mod plates;
mod track;
pub mod wheels;

pub use common::*;
pub use method::{build_conveyor_belt, build_track, configure_world};
pub use track::{BuildContext, LinkError, Track, TrackContact};

/// Phase of a belt at unwrapped `position` m for grouser pitch `pitch` m: `position` minus the
/// nearest whole number of pitches, in `[-p/2, p/2)`, with that number (0 and 0 without pitch).
pub fn phase_and_wraps(position: f64, pitch: Option<f64>) -> (f64, i64) {
    match pitch {
        Some(p) => {
            let w = (position / p).round();
            (position - w * p, w as i64)
        }
        None => (0.0, 0),
    }
}

/// [`phase_and_wraps`] without the wraps, m.
pub fn phase(position: f64, pitch: Option<f64>) -> f64 {
    phase_and_wraps(position, pitch).0
}
