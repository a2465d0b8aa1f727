//! A scenario's `[randomize]` table: named parameters, each a distribution (`uniform`,
//! `integers` or `choice`) and the file keys it writes (`key`, or `keys` with a scale and offset
//! per key). Sampled from a seed by [`crate::model::Randomizer`].

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// One randomised parameter (`[randomize.NAME]`): exactly one distribution, and `key` or `keys`.
#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RandomParamSpec {
    /// Uniform real value in `[low, high]` (units of the target keys).
    #[serde(default)]
    pub uniform: Option<Vec<f64>>,
    /// Uniform integer in `[low, high]`, both included (seeds, counts).
    #[serde(default)]
    pub integers: Option<Vec<i64>>,
    /// One of these numbers, each equally likely.
    #[serde(default)]
    pub choice: Option<Vec<toml::Value>>,
    /// The one key the value is written to, as an error message names keys:
    /// `terrain.boxes[0].size_m[2]`, `vehicle.body_mass_kg`.
    #[serde(default)]
    pub key: Option<String>,
    /// Several keys, each written `value * scale + offset` (a number is the scale).
    #[serde(default)]
    pub keys: Option<BTreeMap<String, RandomTargetSpec>>,
}

/// How a sampled value is written to one key: `value * scale + offset`.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(
    untagged,
    expecting = "a number (the scale) or a table { scale = .., offset = .. }"
)]
pub enum RandomTargetSpec {
    /// Scale only.
    Scale(f64),
    /// Scale and offset (offset in the key's unit).
    Affine(AffineSpec),
}

/// `{ scale, offset }` of a randomised key.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct AffineSpec {
    /// Factor, default 1.
    #[serde(default = "one")]
    pub scale: f64,
    /// Added after scaling, in the key's unit; default 0.
    #[serde(default)]
    pub offset: f64,
}

fn one() -> f64 {
    1.0
}
