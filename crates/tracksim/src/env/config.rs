//! [`EnvConfig`]: how an [`Env`](super::Env) turns actions into controls and what it observes,
//! built from named settings ([`EnvConfig::set`], [`EnvConfig::from_settings`]: what the Python
//! package's `config` dict holds) and checked ([`EnvConfig::check`], which
//! [`Env::new`](super::Env::new) calls) with every problem named by its key.

use crate::check::{Checker, MAX_SPEED_MPS, unknown_name};
use crate::error::{Error, Result, SpecIssue};

/// What the actions command besides the flippers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ActionMode {
    /// Two actions: forward speed and yaw rate (skid steering, [`Controls::twist`]).
    ///
    /// [`Controls::twist`]: crate::model::Controls::twist
    Twist,
    /// One action per track: its belt speed.
    Belts,
}

impl ActionMode {
    /// The names of the modes, as [`EnvConfig::set`] takes them for `action`.
    pub const NAMES: &'static [&'static str] = &["twist", "belts"];

    /// The mode called `name` (`"twist"` or `"belts"`).
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "twist" => Some(ActionMode::Twist),
            "belts" => Some(ActionMode::Belts),
            _ => None,
        }
    }

    /// The mode's name.
    pub fn name(&self) -> &'static str {
        match self {
            ActionMode::Twist => "twist",
            ActionMode::Belts => "belts",
        }
    }
}

/// What an [`Env`](super::Env)'s observation is made of.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ObservationMode {
    /// The state vector alone ([`Env::observe`](super::Env::observe)).
    #[default]
    Vector,
    /// The state vector and one array per sensor of the vehicle
    /// ([`Env::observe_sensors`](super::Env::observe_sensors)).
    Dict,
}

impl ObservationMode {
    /// The names of the modes, as [`EnvConfig::set`] takes them for `observation`.
    pub const NAMES: &'static [&'static str] = &["vector", "dict"];

    /// The mode called `name` (`"vector"` or `"dict"`).
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "vector" => Some(ObservationMode::Vector),
            "dict" => Some(ObservationMode::Dict),
            _ => None,
        }
    }

    /// The mode's name.
    pub fn name(&self) -> &'static str {
        match self {
            ObservationMode::Vector => "vector",
            ObservationMode::Dict => "dict",
        }
    }
}

/// How an [`Env`](super::Env) turns actions into controls and what it observes. Actions are
/// normalised to `[-1, 1]` (clipped) and scaled by the maxima here.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvConfig {
    /// Simulated time per action, s (a whole number of physics steps, at least one).
    pub control_period_s: f64,
    /// Twist or per-track belt speeds.
    pub action: ActionMode,
    /// Forward speed at action +1, m/s.
    pub max_forward_mps: f64,
    /// Yaw rate at action +1, rad/s (positive turns left).
    pub max_yaw_rate_rad_s: f64,
    /// Belt speed at action +1, m/s.
    pub max_belt_speed_mps: f64,
    /// Flipper target at action -1 and +1, rad.
    pub flipper_range_rad: (f64, f64),
    /// Terrain grid: rows ahead (along the heading) and columns across.
    pub grid_shape: (usize, usize),
    /// Spacing of the grid along and across the heading, m.
    pub grid_spacing_m: (f64, f64),
    /// Distance of the first grid row ahead of the body origin, m.
    pub grid_ahead_m: f64,
    /// Height reported where a ray finds no terrain, m relative to the body (also in the
    /// cells of an elevation map that found none, with `observation = "dict"`).
    pub no_terrain_m: f64,
    /// The state vector alone, or with the sensors' arrays.
    pub observation: ObservationMode,
}

impl Default for EnvConfig {
    fn default() -> Self {
        EnvConfig {
            control_period_s: 0.05,
            action: ActionMode::Twist,
            max_forward_mps: 0.5,
            max_yaw_rate_rad_s: 1.0,
            max_belt_speed_mps: 0.5,
            flipper_range_rad: (-60f64.to_radians(), 60f64.to_radians()),
            grid_shape: (5, 3),
            grid_spacing_m: (0.1, 0.15),
            grid_ahead_m: 0.3,
            no_terrain_m: -1.0,
            observation: ObservationMode::Vector,
        }
    }
}

/// One setting's value for [`EnvConfig::set`]: a number, a name, a pair of numbers or a pair
/// of whole numbers (a pair of whole numbers is also accepted where a pair of numbers is).
#[derive(Clone, Debug, PartialEq)]
pub enum EnvValue {
    /// A number (`control_period_s`, the maxima, `grid_ahead_m`, `no_terrain_m`).
    Number(f64),
    /// A name (`action`, `observation`).
    Text(String),
    /// Two numbers (`flipper_range_rad`, `grid_spacing_m`).
    Pair(f64, f64),
    /// Two whole numbers (`grid_shape`).
    IntPair(i64, i64),
}

impl EnvValue {
    fn what(&self) -> String {
        match self {
            EnvValue::Number(x) => format!("the number {x}"),
            EnvValue::Text(s) => format!("the name {:?}", crate::check::echoed(s)),
            EnvValue::Pair(a, b) => format!("the pair ({a}, {b})"),
            EnvValue::IntPair(a, b) => format!("the pair ({a}, {b})"),
        }
    }
}

impl From<f64> for EnvValue {
    fn from(x: f64) -> Self {
        EnvValue::Number(x)
    }
}

impl From<&str> for EnvValue {
    fn from(s: &str) -> Self {
        EnvValue::Text(s.to_string())
    }
}

impl From<(f64, f64)> for EnvValue {
    fn from((a, b): (f64, f64)) -> Self {
        EnvValue::Pair(a, b)
    }
}

impl From<(i64, i64)> for EnvValue {
    fn from((a, b): (i64, i64)) -> Self {
        EnvValue::IntPair(a, b)
    }
}

/// What [`Error::Settings`] calls an environment's configuration.
const WHAT: &str = "environment settings";

/// Most cells of the terrain grid (`grid_shape` rows times columns): each is a ray cast per
/// control period and an entry of the observation.
pub const MAX_GRID_CELLS: usize = 10_000;

impl EnvConfig {
    /// The keys [`EnvConfig::set`] accepts, in the order of the fields.
    pub const KEYS: &'static [&'static str] = &[
        "control_period_s",
        "action",
        "max_forward_mps",
        "max_yaw_rate_rad_s",
        "max_belt_speed_mps",
        "flipper_range_rad",
        "grid_shape",
        "grid_spacing_m",
        "grid_ahead_m",
        "no_terrain_m",
        "observation",
    ];

    /// The default configuration with `settings` applied in order, then checked: every
    /// problem (unknown keys, values of the wrong kind, values out of range) in one
    /// [`Error::Settings`].
    pub fn from_settings<K: AsRef<str>>(
        settings: impl IntoIterator<Item = (K, EnvValue)>,
    ) -> Result<Self> {
        let mut c = EnvConfig::default();
        let mut issues = Vec::new();
        for (k, v) in settings {
            if let Err(e) = c.set(k.as_ref(), v) {
                issues.extend(e.issues().iter().cloned());
            }
        }
        if issues.is_empty() {
            c.check()?;
            return Ok(c);
        }
        // Limits of the settings that were taken, with the unknown keys and wrong kinds.
        if let Err(e) = c.check() {
            issues.extend(e.issues().iter().cloned());
        }
        Err(Error::Settings {
            what: WHAT.into(),
            issues,
        })
    }

    /// Sets `key` to `value` (the field of that name; `action` takes `"twist"` or `"belts"`,
    /// `observation` `"vector"` or `"dict"`, `grid_shape` two whole numbers). An unknown key or a value of the wrong kind is refused
    /// with the key named; ranges are checked by [`EnvConfig::check`].
    pub fn set(&mut self, key: &str, value: EnvValue) -> Result<()> {
        let wrong = |expected: &str| Error::Settings {
            what: WHAT.into(),
            issues: vec![SpecIssue::new(
                key,
                format!("expected {expected}, got {}", value.what()),
            )],
        };
        let pair = |v: &EnvValue| match *v {
            EnvValue::Pair(a, b) => Some((a, b)),
            EnvValue::IntPair(a, b) => Some((a as f64, b as f64)),
            _ => None,
        };
        match key {
            "action" => {
                let EnvValue::Text(s) = &value else {
                    return Err(wrong("a name: \"twist\" or \"belts\""));
                };
                self.action = ActionMode::from_name(s).ok_or_else(|| {
                    Error::setting(
                        WHAT,
                        key,
                        format!(
                            "{:?} is not an action mode: use \"twist\" (forward speed, yaw rate) \
                             or \"belts\" (one speed per track)",
                            crate::check::echoed(s)
                        ),
                    )
                })?;
            }
            "observation" => {
                let EnvValue::Text(s) = &value else {
                    return Err(wrong("a name: \"vector\" or \"dict\""));
                };
                self.observation = ObservationMode::from_name(s).ok_or_else(|| {
                    Error::setting(
                        WHAT,
                        key,
                        format!(
                            "{:?} is not an observation mode: use \"vector\" (the state \
                             vector) or \"dict\" (the state vector and one array per sensor)",
                            crate::check::echoed(s)
                        ),
                    )
                })?;
            }
            "flipper_range_rad" => {
                self.flipper_range_rad =
                    pair(&value).ok_or_else(|| wrong("two numbers (low, high), rad"))?;
            }
            "grid_spacing_m" => {
                self.grid_spacing_m =
                    pair(&value).ok_or_else(|| wrong("two numbers (along, across), m"))?;
            }
            "grid_shape" => {
                let EnvValue::IntPair(r, c) = value else {
                    return Err(wrong("two whole numbers (rows, columns), e.g. (5, 3)"));
                };
                let (Ok(r), Ok(c)) = (usize::try_from(r), usize::try_from(c)) else {
                    return Err(Error::setting(
                        WHAT,
                        key,
                        format!("rows and columns must be 0 or more, got ({r}, {c})"),
                    ));
                };
                self.grid_shape = (r, c);
            }
            _ => {
                let field = match key {
                    "control_period_s" => &mut self.control_period_s,
                    "max_forward_mps" => &mut self.max_forward_mps,
                    "max_yaw_rate_rad_s" => &mut self.max_yaw_rate_rad_s,
                    "max_belt_speed_mps" => &mut self.max_belt_speed_mps,
                    "grid_ahead_m" => &mut self.grid_ahead_m,
                    "no_terrain_m" => &mut self.no_terrain_m,
                    _ => {
                        return Err(Error::Settings {
                            what: WHAT.into(),
                            issues: vec![SpecIssue::whole(
                                crate::check::echoed(key),
                                unknown_name("environment setting", key, Self::KEYS),
                            )],
                        });
                    }
                };
                let EnvValue::Number(x) = value else {
                    return Err(wrong("a number"));
                };
                *field = x;
            }
        }
        Ok(())
    }

    /// Checks every limit, each problem named by its key: `control_period_s` from 1e-6 to
    /// 86400 s; the maxima finite, > 0 and at most 1000 (m/s, rad/s); `grid_spacing_m` finite
    /// and > 0; `flipper_range_rad`, `grid_ahead_m` and `no_terrain_m` finite; at most
    /// [`MAX_GRID_CELLS`] grid cells.
    pub fn check(&self) -> Result<()> {
        let mut c = Checker::default();
        c.positive("control_period_s", self.control_period_s, "s");
        for (key, v, unit) in [
            ("max_forward_mps", self.max_forward_mps, "m/s"),
            ("max_yaw_rate_rad_s", self.max_yaw_rate_rad_s, "rad/s"),
            ("max_belt_speed_mps", self.max_belt_speed_mps, "m/s"),
        ] {
            if !(v.is_finite() && v > 0.0 && v <= MAX_SPEED_MPS) {
                c.push(
                    key,
                    format!(
                        "must be a finite number > 0 and at most {MAX_SPEED_MPS} {unit}, got {}",
                        crate::check::num(v)
                    ),
                );
            }
        }
        let (lo, hi) = self.flipper_range_rad;
        c.finite("flipper_range_rad", &[lo, hi]);
        let (along, across) = self.grid_spacing_m;
        c.positive("grid_spacing_m[0]", along, "m");
        c.positive("grid_spacing_m[1]", across, "m");
        c.finite("grid_ahead_m", &[self.grid_ahead_m]);
        c.finite("no_terrain_m", &[self.no_terrain_m]);
        let (rows, cols) = self.grid_shape;
        if rows.checked_mul(cols).is_none_or(|n| n > MAX_GRID_CELLS) {
            c.push(
                "grid_shape",
                format!(
                    "at most {MAX_GRID_CELLS} cells (rows times columns: a ray cast each per \
                     control period), got ({rows}, {cols})"
                ),
            );
        }
        if c.issues.is_empty() {
            Ok(())
        } else {
            Err(Error::Settings {
                what: WHAT.into(),
                issues: c.issues,
            })
        }
    }
}
