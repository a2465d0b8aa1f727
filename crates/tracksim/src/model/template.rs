//! A scenario file kept to be compiled again for any seed ([`ScenarioTemplate`]): a fixed file
//! is compiled once; a file with `[randomize]` is sampled and compiled per seed, reading no
//! file again except the terrain's own data files (and, in a file of several robots, each
//! robot's vehicle file, whose keys may be drawn).

use super::compile_file::{compile_file, scenario_vehicle};
use super::overrides::OverrideCommands;
use super::read::read_scenario_table;
use super::{Overrides, Randomizer, Scenario, VehicleModel};
use crate::error::{Error, Result, SpecIssue};
use crate::spec::ScenarioSpec;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A loaded scenario file, ready to give a [`Scenario`] for any seed.
#[derive(Clone, Debug)]
pub struct ScenarioTemplate {
    path: PathBuf,
    /// The file's table without `[randomize]`, the overrides written in.
    doc: toml::Table,
    randomizer: Randomizer,
    /// The vehicle of `vehicle.file` (loaded once) or the caller's, or `None` for an inline
    /// one.
    vehicle: Option<VehicleModel>,
    /// The compiled scenario of a file without `[randomize]`.
    fixed: Option<Scenario>,
    /// What the caller changed in the file before compiling it.
    overrides: Overrides,
    /// The commands of the overrides' commands file, read once.
    commands: Option<OverrideCommands>,
    /// The file's `simulation.seed`.
    file_seed: u64,
}

impl ScenarioTemplate {
    /// Reads a scenario file. Every problem is reported as by [`super::load_scenario`], and a
    /// `[randomize]` table is checked too: its keys, and the scenario compiled with every
    /// parameter at its low end and at its high end.
    pub fn load(path: &Path) -> Result<Self> {
        Self::load_with(path, &Overrides::default())
    }

    /// [`ScenarioTemplate::load`] with `overrides` written into the file's keys before every
    /// compilation (a `[randomize]` parameter naming an overridden key still draws it).
    pub fn load_with(path: &Path, overrides: &Overrides) -> Result<Self> {
        Self::load_inner(path, overrides, None)
    }

    /// [`ScenarioTemplate::load_with`] with `vehicle` in place of the file's `vehicle.file`
    /// (a vehicle compiled and varied by the caller, e.g. with another sensor set), the
    /// scenario's keys checked against it.
    pub fn load_for_vehicle(
        path: &Path,
        overrides: &Overrides,
        vehicle: VehicleModel,
    ) -> Result<Self> {
        Self::load_inner(path, overrides, Some(vehicle))
    }

    fn load_inner(path: &Path, overrides: &Overrides, given: Option<VehicleModel>) -> Result<Self> {
        let (spec, mut doc) = read_scenario(path, overrides)?;
        let invalid = |issues| Error::Invalid {
            path: path.to_path_buf(),
            issues,
        };
        let commands = overrides.read_commands()?;
        let fixed = |sc: Scenario, doc, vehicle, commands| ScenarioTemplate {
            path: path.to_path_buf(),
            doc,
            randomizer: Randomizer::default(),
            vehicle,
            fixed: Some(sc),
            overrides: overrides.clone(),
            commands,
            file_seed: spec.simulation.seed,
        };
        let team = !spec.vehicles.is_empty();
        if team && spec.randomize.is_empty() {
            // Several robots (issue 40): compiled robot by robot.
            let sc = super::compile_team::compile_team(path, &spec, overrides, commands.as_ref())?;
            return Ok(fixed(sc, doc, None, commands));
        }
        if spec.randomize.is_empty() {
            let vehicle = match given {
                Some(v) => v,
                None => scenario_vehicle(path, &spec)?,
            };
            let sc = compile_file(path, &spec, vehicle.clone(), overrides, commands.as_ref())?;
            return Ok(fixed(sc, doc, Some(vehicle), commands));
        }
        doc.remove("randomize");
        let randomizer = Randomizer::compile(&spec.randomize, &doc).map_err(invalid)?;
        // A file of several robots compiles each robot's own vehicle at every seed (its
        // `[vehicles.vehicle]` keys may be drawn).
        let vehicle = match (given, &spec.vehicle.inline) {
            (_, _) if team => None,
            (Some(v), _) => Some(v),
            (None, None) => Some(scenario_vehicle(path, &spec)?),
            (None, Some(_)) => None,
        };
        let t = ScenarioTemplate {
            path: path.to_path_buf(),
            doc,
            randomizer,
            vehicle,
            fixed: None,
            overrides: overrides.clone(),
            commands,
            file_seed: spec.simulation.seed,
        };
        // Checked at both ends of every range.
        let mut issues = Vec::new();
        for (end, values) in ["low", "high"].iter().zip(t.randomizer.extremes()) {
            if let Err(e) = t.with_values(&values, 0) {
                let at = super::sampled_text(&t.randomizer.apply(&t.doc, &values).1);
                let list = match e {
                    Error::Invalid { issues, .. } => issues,
                    other => vec![SpecIssue::new("", other.to_string())],
                };
                for i in list {
                    issues.push(SpecIssue::new(
                        i.key,
                        format!(
                            "{} (with every [randomize] value at its {end} end: {at}; narrow the range)",
                            i.message
                        ),
                    ));
                }
            }
        }
        if issues.is_empty() {
            Ok(t)
        } else {
            Err(invalid(issues))
        }
    }

    /// The scenario with the file's own `simulation.seed` (what `tracksim run` runs).
    pub fn file_scenario(&self) -> Result<Scenario> {
        self.instantiate(self.file_seed)
    }

    /// The file's `simulation.seed`.
    pub fn file_seed(&self) -> u64 {
        self.file_seed
    }

    /// The file it was read from.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The `[randomize]` parameters (empty for a fixed scenario).
    pub fn randomizer(&self) -> &Randomizer {
        &self.randomizer
    }

    /// The scenario for `seed`: the `[randomize]` values drawn from it (reported in
    /// [`super::ScenarioData::randomized`]) and `seed` as the scenario's seed. A file without
    /// `[randomize]` gives the same scenario for every seed, only the recorded seed differs.
    pub fn instantiate(&self, seed: u64) -> Result<Scenario> {
        if let Some(sc) = &self.fixed {
            let mut sc = sc.clone();
            sc.0.seed = seed;
            return Ok(sc);
        }
        self.drawn(&self.randomizer.sample(seed), seed)
    }

    /// The scenario of the drawn `values` with `seed`; a problem is reported with the seed and
    /// the values that gave it (the load checked only the ends of the ranges).
    fn drawn(&self, values: &[toml::Value], seed: u64) -> Result<Scenario> {
        self.with_values(values, seed).map_err(|e| match e {
            Error::Invalid { path, issues } => {
                let at = super::sampled_text(&self.randomizer.apply(&self.doc, values).1);
                let issues = issues
                    .into_iter()
                    .map(|i| {
                        let message = format!(
                            "{} (with the [randomize] values of seed {seed}: {at}; narrow the \
                             ranges so that no draw gives this)",
                            i.message
                        );
                        SpecIssue::new(i.key, message)
                    })
                    .collect();
                Error::Invalid { path, issues }
            }
            other => other,
        })
    }

    /// [`ScenarioTemplate::instantiate`] with some parameters fixed instead of drawn (a grid
    /// point of a sweep): `fixed` maps parameter names to values in their keys' units. Names
    /// that are not `[randomize]` parameters are an error.
    pub fn instantiate_with(&self, seed: u64, fixed: &BTreeMap<String, f64>) -> Result<Scenario> {
        if fixed.is_empty() {
            return self.instantiate(seed);
        }
        let names: Vec<&str> = self
            .randomizer
            .params
            .iter()
            .map(|p| p.name.as_str())
            .collect();
        let unknown: Vec<SpecIssue> = fixed
            .keys()
            .filter(|k| !names.contains(&k.as_str()))
            .map(|k| {
                let hint = crate::check::did_you_mean(k, &names)
                    .map_or(String::new(), |n| format!(" (did you mean `{n}`?)"));
                SpecIssue::whole(
                    format!("randomize.{}", crate::check::echoed(k)),
                    format!(
                        "no such [randomize] parameter{hint}; the file has: {}",
                        names.join(", ")
                    ),
                )
            })
            .collect();
        if !unknown.is_empty() {
            return Err(Error::Invalid {
                path: self.path.clone(),
                issues: unknown,
            });
        }
        let mut values = self.randomizer.sample(seed);
        for (p, v) in self.randomizer.params.iter().zip(values.iter_mut()) {
            if let Some(x) = fixed.get(&p.name) {
                *v = match p.dist {
                    super::Distribution::Integers(..) if x.fract() == 0.0 => {
                        toml::Value::Integer(*x as i64)
                    }
                    _ => toml::Value::Float(*x),
                };
            }
        }
        self.drawn(&values, seed)
    }

    /// [`ScenarioTemplate::instantiate`] with `extra` overrides written into the file's keys
    /// after the `[randomize]` values drawn from `seed` (so an offset moves the drawn start),
    /// each checked like the file's own: an ensemble member's scenario. No `extra` override
    /// gives the scenario of `instantiate(seed)`.
    pub fn instantiate_overridden(&self, seed: u64, extra: &Overrides) -> Result<Scenario> {
        if extra.is_empty() {
            return self.instantiate(seed);
        }
        if extra.commands.is_some() {
            return Err(Error::Build(
                "a template's commands file is given when it is loaded (Overrides::commands)"
                    .into(),
            ));
        }
        self.compile_values(&self.randomizer.sample(seed), seed, extra)
    }

    fn with_values(&self, values: &[toml::Value], seed: u64) -> Result<Scenario> {
        self.compile_values(values, seed, &Overrides::default())
    }

    fn compile_values(
        &self,
        values: &[toml::Value],
        seed: u64,
        extra: &Overrides,
    ) -> Result<Scenario> {
        let (mut doc, sampled) = self.randomizer.apply(&self.doc, values);
        extra.apply(&mut doc);
        let doc = toml::Value::Table(doc);
        let spec: ScenarioSpec = crate::spec::strict::from_value(&doc).map_err(|e| {
            let with = match (sampled.is_empty(), extra.is_empty()) {
                (_, true) => format!("with the [randomize] values {sampled:?}"),
                (true, false) => format!("with the overrides of {}", extra.keys().join(", ")),
                _ => format!(
                    "with the [randomize] values {sampled:?} and the overrides of {}",
                    extra.keys().join(", ")
                ),
            };
            Error::Parse {
                path: self.path.clone(),
                message: format!("{with}: {e}"),
            }
        })?;
        let overrides = self.overrides.merged(extra);
        let mut sc = if spec.vehicles.is_empty() {
            let vehicle = match &self.vehicle {
                Some(v) => v.clone(),
                None => scenario_vehicle(&self.path, &spec)?,
            };
            compile_file(
                &self.path,
                &spec,
                vehicle,
                &overrides,
                self.commands.as_ref(),
            )?
        } else {
            super::compile_team::compile_team(
                &self.path,
                &spec,
                &overrides,
                self.commands.as_ref(),
            )?
        };
        sc.0.seed = seed;
        sc.0.randomized = sampled;
        Ok(sc)
    }
}

/// Reads a scenario file into its spec and its table, with `overrides` written into both (the
/// file read once, [`read_scenario_table`]).
fn read_scenario(path: &Path, overrides: &Overrides) -> Result<(ScenarioSpec, toml::Table)> {
    let (spec, mut doc) = read_scenario_table(path)?;
    if overrides.is_empty() {
        return Ok((spec, doc));
    }
    overrides.apply(&mut doc);
    let spec = crate::spec::strict::from_value(&toml::Value::Table(doc.clone())).map_err(|e| {
        crate::error::Error::Parse {
            path: path.to_path_buf(),
            message: format!("with the overrides of {}: {e}", overrides.keys().join(", ")),
        }
    })?;
    Ok((spec, doc))
}
