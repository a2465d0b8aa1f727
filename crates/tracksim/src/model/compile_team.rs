//! A file with several robots (`[[vehicles]]`) compiled: each robot as the one robot of the
//! file (its `[vehicles.vehicle]`, `[[vehicles.commands]]`, `[vehicles.outcome]` or the file's
//! `[outcome]`, `[vehicles.drawbar]`, `[vehicles.expect]` in place of the top-level keys), its
//! problems keyed under `vehicles[k].`, then the checks of the world: names, how many, how far
//! apart, the keys that belong to a robot left at the top. Every problem is reported at once.

use super::compile_file::{compile_file, scenario_vehicle};
use super::overrides::{OverrideCommands, Overrides};
use super::scenario::Scenario;
use super::team::{MAX_ROBOT_SPREAD_M, MAX_ROBOTS, RobotModel, Team, TeamRule};
use crate::check::Checker;
use crate::error::{Error, Result, SpecIssue};
use crate::spec::{ExpectSpec, RobotSpec, ScenarioSpec};
use std::path::Path;

/// Longest robot name, characters.
const MAX_NAME_CHARS: usize = 64;

/// Compiles a scenario file with `[[vehicles]]` (`spec.vehicles` not empty).
pub(crate) fn compile_team(
    path: &Path,
    spec: &ScenarioSpec,
    overrides: &Overrides,
    commands: Option<&OverrideCommands>,
) -> Result<Scenario> {
    let mut issues = world_issues(spec);
    let names: Vec<&str> = spec.vehicles.iter().map(|r| r.name.as_str()).collect();
    let replaced = commands.map(|c| c.per_robot(&names)).transpose()?;
    let mut robots = Vec::new();
    let mut first: Option<Scenario> = None;
    for (k, r) in spec.vehicles.iter().enumerate() {
        let own = replaced.as_ref().map(|c| c[k].clone());
        match compile_robot(path, spec, r, overrides, own) {
            Ok(sc) => {
                robots.push((k, RobotModel::of(&r.name, &sc)));
                first.get_or_insert(sc);
            }
            Err(list) => issues.extend(list.into_iter().map(|i| keyed(k, r, i))),
        }
    }
    issues.extend(spread_issues(&robots));
    let mut c = Checker::default();
    let expect = super::expect::compile_expect(&mut c, &team_expect(&spec.expect));
    issues.extend(c.issues);
    let rule = TeamRule::parse(spec.outcome.team.as_deref()).unwrap_or_else(|issue| {
        issues.push(issue);
        TeamRule::All
    });
    let mut seen = Vec::new();
    issues.retain(|i| {
        let new = !seen.contains(i);
        seen.push(i.clone());
        new
    });
    match first {
        Some(mut sc) if issues.is_empty() => {
            sc.0.team = Some(Box::new(Team {
                robots: robots.into_iter().map(|(_, r)| r).collect(),
                rule,
                stop: spec.outcome.stop,
                expect,
            }));
            Ok(sc)
        }
        _ => Err(Error::Invalid {
            path: path.to_path_buf(),
            issues: overrides.mark(issues),
        }),
    }
}

/// Robot `r` compiled as the one robot of the file (with `commands` in place of its own, when
/// a commands file replaces them).
fn compile_robot(
    path: &Path,
    spec: &ScenarioSpec,
    r: &RobotSpec,
    overrides: &Overrides,
    commands: Option<Vec<crate::spec::CommandSpec>>,
) -> std::result::Result<Scenario, Vec<SpecIssue>> {
    let one = ScenarioSpec {
        vehicle: r.vehicle.clone(),
        vehicles: Vec::new(),
        commands: commands.unwrap_or_else(|| r.commands.clone()),
        // The file's rule is the world's (checked once, by `compile_team`), not the robot's.
        outcome: r
            .outcome
            .clone()
            .unwrap_or_else(|| crate::spec::OutcomeSpec {
                team: None,
                ..spec.outcome.clone()
            }),
        drawbar: r.drawbar.clone(),
        expect: r.expect.clone(),
        ..spec.clone()
    };
    let as_issues = |e: Error| match e {
        Error::Invalid { path: p, issues } if p == path => issues,
        other => vec![SpecIssue::new("vehicle.file", other.to_string())],
    };
    let vehicle = scenario_vehicle(path, &one).map_err(as_issues)?;
    let mut sc =
        compile_file(path, &one, vehicle, &Overrides::default(), None).map_err(as_issues)?;
    sc.0.overridden = overrides.keys();
    Ok(sc)
}

/// An issue of robot `k`'s compilation keyed where it is in the file: the robot's own keys
/// under `vehicles[k].`, the world's (terrain, simulation) as they are.
fn keyed(k: usize, r: &RobotSpec, i: SpecIssue) -> SpecIssue {
    let own = ["vehicle", "commands", "drawbar", "expect"]
        .iter()
        .chain(r.outcome.as_ref().map(|_| &"outcome"))
        .any(|p| {
            i.key == *p
                || i.key.starts_with(&format!("{p}."))
                || i.key.starts_with(&format!("{p}["))
        });
    if own {
        SpecIssue::new(format!("vehicles[{k}].{}", i.key), i.message)
    } else {
        i
    }
}

/// The file's own problems: a robot's keys left at the top level, names, how many robots.
fn world_issues(spec: &ScenarioSpec) -> Vec<SpecIssue> {
    let mut c = Checker::default();
    let v = &spec.vehicle;
    if v.file.is_some() || v.inline.is_some() {
        c.push(
            "vehicle",
            "a file with [[vehicles]] gives each robot its vehicle as [vehicles.vehicle]; \
             remove the top-level [vehicle]",
        );
    }
    if !spec.commands.is_empty() {
        c.push(
            "commands",
            "a file with [[vehicles]] gives each robot its commands as [[vehicles.commands]]",
        );
    }
    if spec.drawbar.is_some() {
        c.push(
            "drawbar",
            "a file with [[vehicles]] gives a robot its drawbar as [vehicles.drawbar]",
        );
    }
    if format!("{:?}", team_expect(&spec.expect)) != format!("{:?}", spec.expect) {
        c.push(
            "expect",
            "a file with [[vehicles]] checks the world's outcome here (`outcome`, \
             `reason_contains`, `outcome_time_s`); give a robot's figures in its [vehicles.expect]",
        );
    }
    if spec.vehicles.len() > MAX_ROBOTS {
        c.push(
            "vehicles",
            format!(
                "{} robots; one world holds at most {MAX_ROBOTS} (a collision-group bit each)",
                spec.vehicles.len()
            ),
        );
    }
    for (k, r) in spec.vehicles.iter().enumerate() {
        if let Some(why) = name_problem(&r.name) {
            c.push(format!("vehicles[{k}].name"), why);
        } else if let Some(j) = spec.vehicles[..k].iter().position(|o| o.name == r.name) {
            c.push(
                format!("vehicles[{k}].name"),
                format!(
                    "`{}` is also the name of vehicles[{j}]: names must be unique",
                    r.name
                ),
            );
        }
    }
    c.issues
}

/// Why `name` is not a ROS-safe robot name (it becomes a topic namespace, a frame prefix and a
/// folder), if it is not.
pub fn robot_name_problem(name: &str) -> Option<String> {
    name_problem(name)
}

/// [`robot_name_problem`].
pub(crate) fn name_problem(name: &str) -> Option<String> {
    let ok_first = name.chars().next().is_some_and(|c| c.is_ascii_lowercase());
    let ok_rest = name
        .chars()
        .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
    if name.is_empty() {
        Some("a robot needs a name (e.g. name = \"alpha\")".into())
    } else if name.chars().count() > MAX_NAME_CHARS {
        Some(format!("longer than {MAX_NAME_CHARS} characters"))
    } else if !ok_first || !ok_rest || name.contains("__") {
        Some(format!(
            "`{}` is not ROS-safe: a lower-case letter, then lower-case letters, digits or single \
             `_` (e.g. \"packbot_1\"); it names the robot's topics, frames and output folder",
            crate::check::echoed(name)
        ))
    } else {
        None
    }
}

/// Robots that start further apart than one world holds ([`MAX_ROBOT_SPREAD_M`]).
/// `robots`: each compiled robot with its index in the file.
fn spread_issues(robots: &[(usize, RobotModel)]) -> Vec<SpecIssue> {
    let mut out = Vec::new();
    for (i, (k, r)) in robots.iter().enumerate() {
        for (j, o) in &robots[..i] {
            let d = (r.start_xy.0 - o.start_xy.0)
                .abs()
                .max((r.start_xy.1 - o.start_xy.1).abs());
            if d > MAX_ROBOT_SPREAD_M {
                out.push(SpecIssue::new(
                    format!("vehicles[{k}].vehicle.x_m"),
                    format!(
                        "`{}` starts {d:.2} m from `{}` (vehicles[{j}]) in x or y; one world holds \
                         robots within {MAX_ROBOT_SPREAD_M} m of each other (Rapier's f32 around \
                         one floating origin): put them closer, or in separate scenarios",
                        r.name, o.name
                    ),
                ));
            }
        }
    }
    out
}

/// The world's `[expect]`: its outcome and when; a robot's final pose and figures belong in
/// its `[vehicles.expect]` (the others are refused).
fn team_expect(e: &ExpectSpec) -> ExpectSpec {
    ExpectSpec {
        outcome: e.outcome.clone(),
        reason_contains: e.reason_contains.clone(),
        outcome_time_s: e.outcome_time_s,
        ..ExpectSpec::default()
    }
}
