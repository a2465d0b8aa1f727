//! Changes a caller makes to a scenario file before it is compiled ([`Overrides`]: the track
//! method, the duration, the solver iterations, the commands of another file, whether the run
//! stops at its outcome, the solver's order, a moved start), so that an overridden value is
//! checked like the file's own, with its key, and the compiled scenario records what was
//! overridden ([`super::ScenarioData::overridden`]). A compiled [`super::Scenario`] is not changed
//! afterwards: every variation of a file is written into its keys here.

use super::{Method, VehicleModel, compile_commands};
use crate::error::{Error, Result, SpecIssue};
use crate::spec::CommandSpec;
use std::path::{Path, PathBuf};

/// What to change in a scenario file before compiling it (`None`: the file's value).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overrides {
    /// Track method (`simulation.method`).
    pub method: Option<Method>,
    /// Simulated duration, s (`simulation.duration_s`).
    pub duration_s: Option<f64>,
    /// Solver iterations (`simulation.solver_iterations`).
    pub solver_iterations: Option<usize>,
    /// Time step, s (`simulation.dt_s`).
    pub dt_s: Option<f64>,
    /// Position-correction passes per solver iteration
    /// (`simulation.stabilization_iterations`).
    pub stabilization_iterations: Option<usize>,
    /// Share of the last step's impulses the solver starts from
    /// (`simulation.warmstart_coefficient`).
    pub warmstart_coefficient: Option<f64>,
    /// A file of `[[commands]]` replacing the scenario's (e.g. the `commands.toml` of a
    /// `tracksim drive` session).
    pub commands: Option<PathBuf>,
    /// Whether the run stops as soon as its outcome is decided (`outcome.stop`; a benchmark
    /// runs its whole duration).
    pub stop_at_outcome: Option<bool>,
    /// Inert colliders that change the solver's order (`simulation.order_salt`).
    pub order_salt: Option<usize>,
    /// The start moved and turned from the file's (`vehicle.x_m`, `vehicle.y_m`,
    /// `vehicle.yaw_deg`): an ensemble member's perturbation.
    pub start_offset: Option<StartOffset>,
    /// Each robot's start moved and turned from the file's, by its index in the file's
    /// `[[vehicles]]` (`vehicles[i].vehicle.x_m`, `y_m`, `yaw_deg`): a member's perturbation of
    /// an ensemble of several robots (empty: none).
    pub robot_offsets: Vec<StartOffset>,
}

/// A start moved and turned from the file's: added to its `vehicle.x_m`, `vehicle.y_m` and
/// `vehicle.yaw_deg` (0 where the file leaves them out).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StartOffset {
    /// Added to `vehicle.x_m`, m.
    pub x_m: f64,
    /// Added to `vehicle.y_m`, m.
    pub y_m: f64,
    /// Added to `vehicle.yaw_deg`, degrees (0: the key is left as it is).
    pub yaw_deg: f64,
}

/// A file holding only `[[commands]]`, as `tracksim drive` records a session (`commands.toml`);
/// or, for a file with several robots, `[[vehicles]]` each with a `name` and its
/// `[[vehicles.commands]]` (a session of several robots).
#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct CommandsFile {
    #[serde(default)]
    commands: Vec<CommandSpec>,
    #[serde(default)]
    vehicles: Vec<RobotCommands>,
}

/// One robot's commands in a commands file.
#[derive(Clone, Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct RobotCommands {
    name: String,
    #[serde(default)]
    commands: Vec<CommandSpec>,
}

/// The commands of an override file, read once and checked against each vehicle.
#[derive(Clone, Debug)]
pub(crate) struct OverrideCommands {
    path: PathBuf,
    specs: Vec<CommandSpec>,
    robots: Vec<RobotCommands>,
}

impl OverrideCommands {
    /// The commands compiled for `vehicle`; problems name the commands file.
    pub(crate) fn compile(&self, vehicle: &VehicleModel) -> Result<Vec<super::Command>> {
        if !self.robots.is_empty() {
            return Err(self.invalid(vec![SpecIssue::new(
                "vehicles",
                "this commands file drives several robots ([[vehicles]]); the scenario has one: \
                 give its controls as top-level [[commands]]",
            )]));
        }
        compile_commands(&self.specs, vehicle).map_err(|issues| self.invalid(issues))
    }

    /// Problems of the commands file, naming it.
    fn invalid(&self, issues: Vec<SpecIssue>) -> Error {
        Error::Invalid {
            path: self.path.clone(),
            issues,
        }
    }

    /// Each robot's commands, replacing its own, for a file whose robots are `names` (in file
    /// order): every robot must be listed once under its name, and no other. A file of one
    /// robot's `[[commands]]` is refused.
    pub(crate) fn per_robot(&self, names: &[&str]) -> Result<Vec<Vec<CommandSpec>>> {
        let mut issues = Vec::new();
        if self.robots.is_empty() {
            issues.push(SpecIssue::new(
                "commands",
                "this commands file drives one robot; a scenario with [[vehicles]] is replayed \
                 from a file with [[vehicles]] (name, [[vehicles.commands]]) for each robot, as \
                 `tracksim drive` writes it",
            ));
        }
        for (i, r) in self.robots.iter().enumerate() {
            if !names.contains(&r.name.as_str()) {
                issues.push(SpecIssue::new(
                    format!("vehicles[{i}].name"),
                    format!(
                        "no robot `{}` in the scenario (its robots: {})",
                        r.name,
                        names.join(", ")
                    ),
                ));
            } else if self.robots[..i].iter().any(|o| o.name == r.name) {
                issues.push(SpecIssue::new(
                    format!("vehicles[{i}].name"),
                    format!("robot `{}` is listed twice", r.name),
                ));
            }
        }
        let mut out = Vec::new();
        for n in names {
            match self.robots.iter().find(|r| r.name == *n) {
                Some(r) => out.push(r.commands.clone()),
                None if !self.robots.is_empty() => {
                    issues.push(SpecIssue::new(
                        "vehicles",
                        format!("robot `{n}` is not listed: give every robot of the scenario its commands (an empty list for none)"),
                    ));
                }
                None => {}
            }
        }
        if issues.is_empty() {
            Ok(out)
        } else {
            Err(self.invalid(issues))
        }
    }
}

impl Overrides {
    /// No override: the file as it is.
    pub fn is_empty(&self) -> bool {
        *self == Overrides::default()
    }

    /// The keys of the file these overrides replace.
    pub fn keys(&self) -> Vec<String> {
        let mut keys: Vec<String> = self
            .keys_and_flags()
            .into_iter()
            .map(|(k, _)| k.to_string())
            .collect();
        for (i, o) in self.robot_offsets.iter().enumerate() {
            keys.push(format!("vehicles[{i}].vehicle.x_m"));
            keys.push(format!("vehicles[{i}].vehicle.y_m"));
            if o.yaw_deg != 0.0 {
                keys.push(format!("vehicles[{i}].vehicle.yaw_deg"));
            }
        }
        keys
    }

    /// Each overridden key with the command-line flag that sets it.
    fn keys_and_flags(&self) -> Vec<(&'static str, &'static str)> {
        [
            (self.method.is_some(), "simulation.method", "--method"),
            (
                self.duration_s.is_some(),
                "simulation.duration_s",
                "--duration",
            ),
            (
                self.solver_iterations.is_some(),
                "simulation.solver_iterations",
                "--solver-iterations",
            ),
            (self.dt_s.is_some(), "simulation.dt_s", "--dt"),
            (
                self.stabilization_iterations.is_some(),
                "simulation.stabilization_iterations",
                "--stabilization-iterations",
            ),
            (
                self.warmstart_coefficient.is_some(),
                "simulation.warmstart_coefficient",
                "--warmstart",
            ),
            (self.commands.is_some(), "commands", "--commands"),
            (
                self.stop_at_outcome.is_some(),
                "outcome.stop",
                "the benchmark's full duration",
            ),
            (
                self.order_salt.is_some(),
                "simulation.order_salt",
                "an ensemble member's solver order",
            ),
            (
                self.start_offset.is_some(),
                "vehicle.x_m",
                "an ensemble member's start",
            ),
            (
                self.start_offset.is_some(),
                "vehicle.y_m",
                "an ensemble member's start",
            ),
            (
                self.start_offset.is_some_and(|o| o.yaw_deg != 0.0),
                "vehicle.yaw_deg",
                "an ensemble member's start",
            ),
        ]
        .into_iter()
        .filter(|(set, ..)| *set)
        .map(|(_, k, f)| (k, f))
        .collect()
    }

    /// These overrides with those set in `extra` replacing them (what a template's member is
    /// compiled with: the template's overrides and the member's).
    pub(crate) fn merged(&self, extra: &Overrides) -> Overrides {
        Overrides {
            method: extra.method.or(self.method),
            duration_s: extra.duration_s.or(self.duration_s),
            solver_iterations: extra.solver_iterations.or(self.solver_iterations),
            dt_s: extra.dt_s.or(self.dt_s),
            stabilization_iterations: extra
                .stabilization_iterations
                .or(self.stabilization_iterations),
            warmstart_coefficient: extra.warmstart_coefficient.or(self.warmstart_coefficient),
            commands: extra.commands.clone().or_else(|| self.commands.clone()),
            stop_at_outcome: extra.stop_at_outcome.or(self.stop_at_outcome),
            order_salt: extra.order_salt.or(self.order_salt),
            start_offset: extra.start_offset.or(self.start_offset),
            robot_offsets: if extra.robot_offsets.is_empty() {
                self.robot_offsets.clone()
            } else {
                extra.robot_offsets.clone()
            },
        }
    }

    /// Writes the overridden values into a scenario file's table `doc` (the commands are
    /// removed: they come from [`Overrides::read_commands`] once the vehicle is known). A key
    /// the file gives a value of the wrong kind keeps it (the file's own problem, reported by
    /// the parse).
    pub(crate) fn apply(&self, doc: &mut toml::Table) {
        if let Some(stop) = self.stop_at_outcome
            && let Some(t) = table(doc, "outcome")
        {
            t.insert("stop".into(), toml::Value::Boolean(stop));
        }
        if let Some(o) = self.start_offset
            && let Some(v) = table(doc, "vehicle")
        {
            add_to(v, "x_m", o.x_m);
            add_to(v, "y_m", o.y_m);
            if o.yaw_deg != 0.0 {
                add_to(v, "yaw_deg", o.yaw_deg);
            }
        }
        if let Some(toml::Value::Array(robots)) = doc.get_mut("vehicles") {
            for (o, r) in self.robot_offsets.iter().zip(robots.iter_mut()) {
                let Some(v) = r.as_table_mut().and_then(|r| table(r, "vehicle")) else {
                    continue;
                };
                add_to(v, "x_m", o.x_m);
                add_to(v, "y_m", o.y_m);
                if o.yaw_deg != 0.0 {
                    add_to(v, "yaw_deg", o.yaw_deg);
                }
            }
        }
        if let Some(sim) = table(doc, "simulation") {
            if let Some(n) = self.order_salt {
                let n = i64::try_from(n).unwrap_or(i64::MAX);
                sim.insert("order_salt".into(), toml::Value::Integer(n));
            }
            if let Some(m) = self.method {
                sim.insert("method".into(), toml::Value::String(m.name()));
            }
            if let Some(d) = self.duration_s {
                sim.insert("duration_s".into(), toml::Value::Float(d));
            }
            if let Some(n) = self.solver_iterations {
                let n = i64::try_from(n).unwrap_or(i64::MAX);
                sim.insert("solver_iterations".into(), toml::Value::Integer(n));
            }
            if let Some(dt) = self.dt_s {
                sim.insert("dt_s".into(), toml::Value::Float(dt));
            }
            if let Some(n) = self.stabilization_iterations {
                let n = i64::try_from(n).unwrap_or(i64::MAX);
                sim.insert("stabilization_iterations".into(), toml::Value::Integer(n));
            }
            if let Some(w) = self.warmstart_coefficient {
                sim.insert("warmstart_coefficient".into(), toml::Value::Float(w));
            }
        }
        if self.commands.is_some() {
            doc.remove("commands");
        }
    }

    /// Reads the commands file, if one is given (its problems name it).
    pub(crate) fn read_commands(&self) -> Result<Option<OverrideCommands>> {
        let Some(path) = &self.commands else {
            return Ok(None);
        };
        let f: CommandsFile = super::read::read_toml(path)?;
        if !f.vehicles.is_empty() && !f.commands.is_empty() {
            return Err(Error::Invalid {
                path: path.clone(),
                issues: vec![SpecIssue::new(
                    "commands",
                    "give either [[commands]] (one robot) or [[vehicles]] (several), not both",
                )],
            });
        }
        Ok(Some(OverrideCommands {
            path: path.clone(),
            specs: f.commands,
            robots: f.vehicles,
        }))
    }

    /// Marks the problems of overridden keys as such (the value is the caller's, not the
    /// file's), naming the command-line flag that sets each.
    pub(crate) fn mark(&self, issues: Vec<SpecIssue>) -> Vec<SpecIssue> {
        let keys = self.keys_and_flags();
        issues
            .into_iter()
            .map(|i| match keys.iter().find(|(k, _)| i.key == *k) {
                Some((k, flag)) => SpecIssue::new(format!("{k} (overridden: {flag})"), i.message),
                None => i,
            })
            .collect()
    }
}

/// The table `key` of `doc`, made if missing; `None` if the file gives it as something else
/// (the file's own problem, which the parse reports with its key).
fn table<'a>(doc: &'a mut toml::Table, key: &str) -> Option<&'a mut toml::Table> {
    doc.entry(key)
        .or_insert_with(|| toml::Value::Table(toml::Table::new()))
        .as_table_mut()
}

/// Adds `d` to the number at `key` of `t` (0 if missing); a value that is not a number is left
/// for the parse to report.
fn add_to(t: &mut toml::Table, key: &str, d: f64) {
    let base = match t.get(key) {
        None => 0.0,
        Some(toml::Value::Float(x)) => *x,
        Some(toml::Value::Integer(i)) => *i as f64,
        Some(_) => return,
    };
    t.insert(key.into(), toml::Value::Float(base + d));
}

/// Loads a file of `[[commands]]` (the format of a scenario's) for `vehicle`: the commands
/// that replace a scenario's (`tracksim run --commands FILE`).
pub fn load_commands(path: &Path, vehicle: &VehicleModel) -> Result<Vec<super::Command>> {
    let o = Overrides {
        commands: Some(path.to_path_buf()),
        ..Overrides::default()
    };
    match o.read_commands()? {
        Some(c) => c.compile(vehicle),
        None => Ok(Vec::new()),
    }
}
