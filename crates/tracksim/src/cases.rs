//! Named cases shared by `tracksim bench` and `tracksim validate` (Fig. 2) (Box2D's
//! `shared/benchmarks`): each is a bundled scenario file, by name, so that what the benchmark
//! times, what the validation runs and what a user opens are the same file.

use crate::error::{Error, Result};
use crate::model::{Overrides, Scenario, ScenarioTemplate};
use std::path::{Path, PathBuf};

/// A named case: a bundled scenario file and what it is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Case {
    /// Name, e.g. `packbot_flat`.
    pub name: &'static str,
    /// Scenario file relative to the repository root.
    pub file: &'static str,
    /// What it measures.
    pub about: &'static str,
}

/// Every named case.
pub const CASES: &[Case] = &[
    Case {
        name: "packbot_flat",
        file: "scenarios/packbot_flat.toml",
        about: "the paper's Table II case: PackBot 510 at 0.3 m/s on flat ground",
    },
    Case {
        name: "packbot_open_top",
        file: "scenarios/packbot_flat_open_top.toml",
        about: "the Table II case with the top runs as links without colliders (issue 16.5)",
    },
    Case {
        name: "quince_flat",
        file: "scenarios/quince_flat.toml",
        about: "Quince (6 tracks, 4 flippers) on flat ground",
    },
    Case {
        name: "packbot_rough",
        file: "scenarios/packbot_rough.toml",
        about: "PackBot on a seeded rough field and a height map",
    },
    Case {
        name: "packbot_step",
        file: "scenarios/packbot_step.toml",
        about: "a 0.10 m step climbed thanks to the grousers",
    },
    Case {
        name: "fig2_bump",
        file: "scenarios/bump_wheels_vs_track.toml",
        about: "paper Fig. 2: a bump the track climbs and 4 wheels do not",
    },
    Case {
        name: "fig3_wall",
        file: "scenarios/wall_low_friction.toml",
        about: "paper Fig. 3: a low-friction wall nothing should climb",
    },
    Case {
        name: "packbot_dry_sand",
        file: "scenarios/soil/packbot_dry_sand.toml",
        about: "the Table II drive on dry sand: deformable soil, ruts (issue 30)",
    },
    Case {
        name: "quince_step_240",
        file: "scenarios/quince_step_240.toml",
        about: "paper Fig. 7: Quince, front flippers at 45 deg, a 0.24 m step",
    },
];

/// The cases `tracksim bench` times, in table order: (short name given to `--cases`, case).
pub const BENCH: &[(&str, &str)] = &[
    ("packbot", "packbot_flat"),
    ("packbot_open_top", "packbot_open_top"),
    ("quince", "quince_flat"),
    ("rough", "packbot_rough"),
    ("sand", "packbot_dry_sand"),
];

/// The case called `name`.
pub fn case(name: &str) -> Option<&'static Case> {
    CASES.iter().find(|c| c.name == name)
}

/// The names of every case, for messages.
pub fn names() -> String {
    CASES
        .iter()
        .map(|c| format!("\"{}\"", c.name))
        .collect::<Vec<_>>()
        .join(", ")
}

impl Case {
    /// The case's scenario file under the repository root `root`.
    pub fn path(&self, root: &Path) -> PathBuf {
        root.join(self.file)
    }

    /// Loads the case's scenario from the repository root `root`.
    pub fn load(&self, root: &Path) -> Result<Scenario> {
        crate::model::load_scenario(&self.path(root))
    }
}

/// The case called `name`; an unknown name is an error that lists the known ones.
fn named(name: &str) -> Result<&'static Case> {
    case(name).ok_or_else(|| {
        Error::Build(format!(
            "unknown case \"{name}\"; the cases are {}",
            names()
        ))
    })
}

/// Loads the case called `name` from the repository root `root`; an unknown name is an error
/// that lists the known ones.
pub fn load(root: &Path, name: &str) -> Result<Scenario> {
    named(name)?.load(root)
}

/// The case called `name` from the repository root `root` as a template with `overrides`
/// (e.g. another method), to compile its scenario and its ensemble members.
pub fn template(root: &Path, name: &str, overrides: &Overrides) -> Result<ScenarioTemplate> {
    ScenarioTemplate::load_with(&named(name)?.path(root), overrides)
}
