//! [`EnvConfig`]: how an [`Env`](super::Env) turns actions into controls and what it observes,
//! built from named settings ([`EnvConfig::from_settings`] through the serde spec [`EnvSpec`]:
//! what the Python package's `config` dict holds) and checked ([`EnvConfig::check`], which
//! [`Env::new`](super::Env::new) calls) with every problem named by its key.

use crate::check::{Checker, MAX_SPEED_MPS, unknown_name};
use crate::error::{Error, Result, SpecIssue};

/// What the actions command besides the flippers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize)]
#[serde(try_from = "String")]
pub enum ActionMode {
    /// Two actions: forward speed and yaw rate (skid steering, [`Controls::twist`]).
    ///
    /// [`Controls::twist`]: crate::model::Controls::twist
    Twist,
    /// One action per track: its belt speed.
    Belts,
}

impl ActionMode {
    /// The names of the modes, as the settings ([`EnvSpec`]) take them for `action`.
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

/// What the flipper actions command.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize)]
#[serde(try_from = "String")]
pub enum FlipperAction {
    /// A target angle: action -1 .. +1 mapped linearly onto `flipper_range_rad`.
    #[default]
    Position,
    /// A rate: action -1 .. +1 times `max_flipper_rate_rad_s`, integrated into the target
    /// angle over each control period (clamped to `flipper_range_rad` and the joint limits);
    /// the joint's position servo follows the moving target.
    Velocity,
}

impl FlipperAction {
    /// The names of the modes, as the settings ([`EnvSpec`]) take them for `flipper_action`.
    pub const NAMES: &'static [&'static str] = &["position", "velocity"];

    /// The mode called `name` (`"position"` or `"velocity"`).
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "position" => Some(FlipperAction::Position),
            "velocity" => Some(FlipperAction::Velocity),
            _ => None,
        }
    }

    /// The mode's name.
    pub fn name(&self) -> &'static str {
        match self {
            FlipperAction::Position => "position",
            FlipperAction::Velocity => "velocity",
        }
    }
}

/// What an [`Env`](super::Env)'s observation is made of.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize)]
#[serde(try_from = "String")]
pub enum ObservationMode {
    /// The state vector alone ([`Env::observe`](super::Env::observe)).
    #[default]
    Vector,
    /// The state vector and one array per sensor of the vehicle
    /// ([`Env::observe_sensors`](super::Env::observe_sensors)).
    Dict,
    /// What a learner needs, entry by entry (body-frame elevation map, goal, velocities,
    /// orientation, flippers, per-track slip, traction and contacts): see
    /// [`LearnerObs`](super::LearnerObs).
    Learner,
}

impl ObservationMode {
    /// The names of the modes, as the settings ([`EnvSpec`]) take them for `observation`.
    pub const NAMES: &'static [&'static str] = &["vector", "dict", "learner"];

    /// The mode called `name` (`"vector"`, `"dict"` or `"learner"`).
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "vector" => Some(ObservationMode::Vector),
            "dict" => Some(ObservationMode::Dict),
            "learner" => Some(ObservationMode::Learner),
            _ => None,
        }
    }

    /// The mode's name.
    pub fn name(&self) -> &'static str {
        match self {
            ObservationMode::Vector => "vector",
            ObservationMode::Dict => "dict",
            ObservationMode::Learner => "learner",
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
    /// The state vector alone, or with the sensors' arrays, or the learner's entries.
    pub observation: ObservationMode,
    /// Flipper actions as target angles or as rates.
    pub flipper_action: FlipperAction,
    /// Flipper rate at action +1 with `flipper_action = "velocity"`, rad/s.
    pub max_flipper_rate_rad_s: f64,
    /// Cells of the learner's elevation map along and across the heading (a vehicle's own
    /// `elevation_map` sensor replaces it).
    pub map_shape: (usize, usize),
    /// Cell size of the learner's elevation map, m.
    pub map_resolution_m: f64,
    /// The learner's elevation map looks for terrain from this far above the body origin down
    /// to this far below it, m.
    pub map_reach_m: f64,
    /// The goal (world x, y), m (`None`: what the scenario's `[outcome]` implies, see
    /// [`LearnerObs`](super::LearnerObs)).
    pub goal_xy_m: Option<(f64, f64)>,
    /// Write each episode as a run folder under this folder (`None`: record nothing); see
    /// the env's `record.rs`.
    pub record_dir: Option<std::path::PathBuf>,
    /// The camera of [`Env::render`](super::Env::render): [`CHASE_CAMERA`] (behind and above
    /// the robot, following its heading) or the name of an `rgb_camera` sensor of the vehicle
    /// (its latest frame, at its own rate and size; the sensors then run whatever the
    /// observation).
    pub render_camera: String,
    /// Size of the chase camera's frames, pixels (width, height).
    pub render_size_px: (usize, usize),
}

/// [`EnvConfig::render_camera`]'s name of the chase camera.
pub const CHASE_CAMERA: &str = "chase";

/// Most pixels of a rendered frame (`render_size_px` width times height): a 1024 x 1024 image,
/// as for a camera sensor.
pub const MAX_RENDER_PIXELS: usize = crate::model::MAX_RAYS;

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
            flipper_action: FlipperAction::Position,
            max_flipper_rate_rad_s: 1.0,
            map_shape: (64, 64),
            map_resolution_m: 2.0 / 64.0,
            map_reach_m: 1.0,
            goal_xy_m: None,
            record_dir: None,
            render_camera: CHASE_CAMERA.to_string(),
            render_size_px: (160, 120),
        }
    }
}

/// One setting's value for [`EnvConfig::from_settings`]: a number, a name, a pair of numbers or a pair
/// of whole numbers (a pair of whole numbers is also accepted where a pair of numbers is).
#[derive(Clone, Debug, PartialEq)]
pub enum EnvValue {
    /// A number (`control_period_s`, the maxima, `grid_ahead_m`, `no_terrain_m`).
    Number(f64),
    /// A name (`action`, `observation`, `flipper_action`) or a folder (`record_dir`).
    Text(String),
    /// Two numbers (`flipper_range_rad`, `grid_spacing_m`, `goal_xy_m`).
    Pair(f64, f64),
    /// Two whole numbers (`grid_shape`, `map_shape`).
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
    /// The keys of the settings ([`EnvSpec`]'s fields), in the order of the fields.
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
        "flipper_action",
        "max_flipper_rate_rad_s",
        "map_shape",
        "map_resolution_m",
        "map_reach_m",
        "goal_xy_m",
        "record_dir",
        "render_camera",
        "render_size_px",
    ];

    /// The default configuration with `settings` applied in order, then checked: every
    /// problem (unknown keys with a suggestion, values of the wrong kind, values out of range)
    /// in one [`Error::Settings`], each named by its key. Each setting is read through
    /// [`EnvSpec`], the serde spec of the settings (`deny_unknown_fields`, like every file).
    pub fn from_settings<K: AsRef<str>>(
        settings: impl IntoIterator<Item = (K, EnvValue)>,
    ) -> Result<Self> {
        let mut c = EnvConfig::default();
        let mut issues = Vec::new();
        for (k, v) in settings {
            match EnvSpec::of_setting(k.as_ref(), &v) {
                Ok(spec) => spec.apply_to(&mut c),
                Err(i) => issues.push(i),
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

    /// Checks every limit, each problem named by its key: `control_period_s` from 1e-6 to
    /// 86400 s; the maxima finite, > 0 and at most 1000 (m/s, rad/s); `grid_spacing_m` finite
    /// and > 0; `flipper_range_rad`, `grid_ahead_m` and `no_terrain_m` finite; at most
    /// [`MAX_GRID_CELLS`] grid cells; `max_flipper_rate_rad_s` finite, > 0 and at most 1000
    /// rad/s; `map_shape` 1 to [`MAX_GRID_CELLS`] cells; `map_resolution_m` and `map_reach_m`
    /// finite and > 0; `goal_xy_m` finite; `render_size_px` 1 to [`MAX_RENDER_PIXELS`] pixels;
    /// `render_camera` not empty (the vehicle's sensors are checked by [`super::Env::new`]).
    pub fn check(&self) -> Result<()> {
        let mut c = Checker::default();
        c.positive("control_period_s", self.control_period_s, "s");
        for (key, v, unit) in [
            ("max_forward_mps", self.max_forward_mps, "m/s"),
            ("max_yaw_rate_rad_s", self.max_yaw_rate_rad_s, "rad/s"),
            ("max_belt_speed_mps", self.max_belt_speed_mps, "m/s"),
            (
                "max_flipper_rate_rad_s",
                self.max_flipper_rate_rad_s,
                "rad/s",
            ),
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
        let (rows, cols) = self.map_shape;
        if rows
            .checked_mul(cols)
            .is_none_or(|n| n == 0 || n > MAX_GRID_CELLS)
        {
            c.push(
                "map_shape",
                format!(
                    "from 1 to {MAX_GRID_CELLS} cells (rows times columns: a ray cast each per \
                     control period), got ({rows}, {cols})"
                ),
            );
        }
        c.positive("map_resolution_m", self.map_resolution_m, "m");
        c.positive("map_reach_m", self.map_reach_m, "m");
        if let Some((x, y)) = self.goal_xy_m {
            c.finite("goal_xy_m", &[x, y]);
        }
        let (w, h) = self.render_size_px;
        if w == 0 || h == 0 || w.checked_mul(h).is_none_or(|n| n > MAX_RENDER_PIXELS) {
            c.push(
                "render_size_px",
                format!(
                    "from 1 x 1 to {MAX_RENDER_PIXELS} pixels (width times height: a ray each \
                     per frame), got ({w}, {h})"
                ),
            );
        }
        if self.render_camera.trim().is_empty() {
            c.push(
                "render_camera",
                format!("an empty name: use {CHASE_CAMERA:?} or an rgb_camera sensor's name"),
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

/// The environment settings as a caller writes them: the serde spec of [`EnvConfig`]'s named
/// settings, unknown keys refused (`deny_unknown_fields`) like every file's spec; each field
/// given overrides the default.
#[derive(Clone, Debug, Default, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnvSpec {
    /// [`EnvConfig::control_period_s`], s.
    pub control_period_s: Option<f64>,
    /// [`EnvConfig::action`].
    pub action: Option<ActionMode>,
    /// [`EnvConfig::max_forward_mps`], m/s.
    pub max_forward_mps: Option<f64>,
    /// [`EnvConfig::max_yaw_rate_rad_s`], rad/s.
    pub max_yaw_rate_rad_s: Option<f64>,
    /// [`EnvConfig::max_belt_speed_mps`], m/s.
    pub max_belt_speed_mps: Option<f64>,
    /// [`EnvConfig::flipper_range_rad`]: two numbers (low, high), rad.
    pub flipper_range_rad: Option<(f64, f64)>,
    /// [`EnvConfig::grid_shape`]: two whole numbers (rows, columns).
    pub grid_shape: Option<(usize, usize)>,
    /// [`EnvConfig::grid_spacing_m`]: two numbers (along, across), m.
    pub grid_spacing_m: Option<(f64, f64)>,
    /// [`EnvConfig::grid_ahead_m`], m.
    pub grid_ahead_m: Option<f64>,
    /// [`EnvConfig::no_terrain_m`], m.
    pub no_terrain_m: Option<f64>,
    /// [`EnvConfig::observation`].
    pub observation: Option<ObservationMode>,
    /// [`EnvConfig::flipper_action`].
    pub flipper_action: Option<FlipperAction>,
    /// [`EnvConfig::max_flipper_rate_rad_s`], rad/s.
    pub max_flipper_rate_rad_s: Option<f64>,
    /// [`EnvConfig::map_shape`]: two whole numbers (rows, columns).
    pub map_shape: Option<(usize, usize)>,
    /// [`EnvConfig::map_resolution_m`], m.
    pub map_resolution_m: Option<f64>,
    /// [`EnvConfig::map_reach_m`], m.
    pub map_reach_m: Option<f64>,
    /// [`EnvConfig::goal_xy_m`]: two numbers (x, y), m.
    pub goal_xy_m: Option<(f64, f64)>,
    /// [`EnvConfig::record_dir`]: a folder.
    pub record_dir: Option<std::path::PathBuf>,
    /// [`EnvConfig::render_camera`]: `"chase"` or an rgb_camera sensor's name.
    pub render_camera: Option<String>,
    /// [`EnvConfig::render_size_px`]: two whole numbers (width, height), pixels.
    pub render_size_px: Option<(usize, usize)>,
}

impl EnvSpec {
    /// The spec of one setting `key` = `value`, or its problem keyed `key`: an unknown key with
    /// a suggestion and every key, a value serde cannot read as the field (the message says
    /// what was expected and what was given), an empty `record_dir`.
    pub fn of_setting(key: &str, value: &EnvValue) -> std::result::Result<EnvSpec, SpecIssue> {
        if !EnvConfig::KEYS.contains(&key) {
            return Err(SpecIssue::whole(
                crate::check::echoed(key),
                unknown_name("environment setting", key, EnvConfig::KEYS),
            ));
        }
        let v = match value {
            EnvValue::Number(x) => toml::Value::Float(*x),
            EnvValue::Text(s) => toml::Value::String(s.clone()),
            EnvValue::Pair(a, b) => toml::Value::Array(vec![(*a).into(), (*b).into()]),
            EnvValue::IntPair(a, b) => toml::Value::Array(vec![(*a).into(), (*b).into()]),
        };
        let mut t = toml::Table::new();
        t.insert(key.to_string(), v);
        let spec: EnvSpec = serde::Deserialize::deserialize(toml::Value::Table(t))
            .map_err(|e| SpecIssue::new(key, Self::refusal(key, value, e.message().trim_end())))?;
        if spec
            .record_dir
            .as_ref()
            .is_some_and(|d| d.as_os_str().is_empty())
        {
            return Err(SpecIssue::new(
                key,
                "an empty path: give the folder to write the episodes into",
            ));
        }
        Ok(spec)
    }

    /// What a value of setting `key` is, in words (for its messages).
    fn expected(key: &str) -> &'static str {
        match key {
            "action" => "a name: \"twist\" or \"belts\"",
            "observation" => "a name: \"vector\", \"dict\" or \"learner\"",
            "flipper_action" => "a name: \"position\" or \"velocity\"",
            "grid_shape" | "map_shape" => "two whole numbers (rows, columns), e.g. (5, 3)",
            "flipper_range_rad" => "two numbers (low, high), rad",
            "grid_spacing_m" => "two numbers (along, across), m",
            "goal_xy_m" => "two numbers (x, y), m",
            "record_dir" => "a folder (a path as a string)",
            "render_camera" => "a name: \"chase\" or an rgb_camera sensor of the vehicle",
            "render_size_px" => "two whole numbers (width, height), pixels, e.g. (160, 120)",
            _ => "a number",
        }
    }

    /// Why setting `key` refuses `value`, which serde could not read (`why`): a value of the
    /// wrong kind is told what the key takes; one of the right kind is told why too (a mode's
    /// own message names the modes).
    fn refusal(key: &str, value: &EnvValue, why: &str) -> String {
        let expected = Self::expected(key);
        if !Self::kind_fits(key, value) {
            format!("expected {expected}, got {}", value.what())
        } else if expected.starts_with("a name") {
            why.to_string()
        } else {
            format!("expected {expected}: {why}")
        }
    }

    /// Whether `value` is of the kind setting `key` takes (a name, a number, two numbers, two
    /// whole numbers).
    fn kind_fits(key: &str, value: &EnvValue) -> bool {
        match (Self::expected(key), value) {
            (e, EnvValue::Text(_)) => e.starts_with("a name") || e.starts_with("a folder"),
            (e, EnvValue::IntPair(..)) => e.starts_with("two"),
            (e, EnvValue::Pair(..)) => e.starts_with("two numbers"),
            (e, EnvValue::Number(_)) => e == "a number",
        }
    }

    /// Writes every field given into `c`.
    pub fn apply_to(self, c: &mut EnvConfig) {
        let EnvSpec {
            control_period_s,
            action,
            max_forward_mps,
            max_yaw_rate_rad_s,
            max_belt_speed_mps,
            flipper_range_rad,
            grid_shape,
            grid_spacing_m,
            grid_ahead_m,
            no_terrain_m,
            observation,
            flipper_action,
            max_flipper_rate_rad_s,
            map_shape,
            map_resolution_m,
            map_reach_m,
            goal_xy_m,
            record_dir,
            render_camera,
            render_size_px,
        } = self;
        let set = |slot: &mut f64, v: Option<f64>| {
            if let Some(v) = v {
                *slot = v;
            }
        };
        set(&mut c.control_period_s, control_period_s);
        set(&mut c.max_forward_mps, max_forward_mps);
        set(&mut c.max_yaw_rate_rad_s, max_yaw_rate_rad_s);
        set(&mut c.max_belt_speed_mps, max_belt_speed_mps);
        set(&mut c.grid_ahead_m, grid_ahead_m);
        set(&mut c.no_terrain_m, no_terrain_m);
        set(&mut c.max_flipper_rate_rad_s, max_flipper_rate_rad_s);
        set(&mut c.map_resolution_m, map_resolution_m);
        set(&mut c.map_reach_m, map_reach_m);
        c.action = action.unwrap_or(c.action);
        c.observation = observation.unwrap_or(c.observation);
        c.flipper_action = flipper_action.unwrap_or(c.flipper_action);
        c.flipper_range_rad = flipper_range_rad.unwrap_or(c.flipper_range_rad);
        c.grid_shape = grid_shape.unwrap_or(c.grid_shape);
        c.grid_spacing_m = grid_spacing_m.unwrap_or(c.grid_spacing_m);
        c.map_shape = map_shape.unwrap_or(c.map_shape);
        if goal_xy_m.is_some() {
            c.goal_xy_m = goal_xy_m;
        }
        if record_dir.is_some() {
            c.record_dir = record_dir;
        }
        if let Some(r) = render_camera {
            c.render_camera = r;
        }
        c.render_size_px = render_size_px.unwrap_or(c.render_size_px);
    }
}

/// A mode named in the settings, read by its name (the message lists the names).
macro_rules! from_name_str {
    ($t:ty, $what:literal, $use:literal) => {
        impl TryFrom<String> for $t {
            type Error = String;
            fn try_from(s: String) -> std::result::Result<Self, String> {
                <$t>::from_name(&s).ok_or_else(|| {
                    format!(
                        concat!("{:?} is not ", $what, ": use ", $use),
                        crate::check::echoed(&s)
                    )
                })
            }
        }
    };
}

from_name_str!(
    ActionMode,
    "an action mode",
    "\"twist\" (forward speed, yaw rate) or \"belts\" (one speed per track)"
);
from_name_str!(
    ObservationMode,
    "an observation mode",
    "\"vector\" (the state vector), \"dict\" (the state vector and one array per sensor) or \
     \"learner\" (elevation map, goal, velocities, orientation, flippers, per-track slip, \
     traction and contacts)"
);
from_name_str!(
    FlipperAction,
    "a flipper action",
    "\"position\" (target angles over flipper_range_rad) or \"velocity\" (rates up to \
     max_flipper_rate_rad_s)"
);
