//! Golden trajectories: the physics must not change when the code is rearranged.
//!
//! Every bundled scenario of `scenarios/`, `tasks/`, `soil/` and `team/` is run under every track
//! method for a short time and the SHA-256 of its `trajectory.csv` is compared with
//! `tests/golden/trajectories.txt`. On a mismatch the test prints the new hashes; a deliberate physics change regenerates the file on purpose with
//! `scripts/update-golden.sh` (which sets `TRACKSIM_UPDATE_GOLDEN=1`) and says why in its commit.

use crate::common;
use common::root;
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use tracksim::Method;

/// Simulated time of every golden run, s (1000 steps at the default 1 ms).
const GOLDEN_DURATION_S: f64 = 1.0;

/// The methods every scenario is run with (`tracksim compare`'s list).
fn methods() -> Vec<String> {
    Method::COMPARED.iter().map(|m| m.name()).collect()
}

/// Runs one scenario with one method and hashes what `tracksim run` would write as
/// `trajectory.csv` (or the error, if the method cannot build that vehicle).
fn hash_run(file: &std::path::Path, method: &str) -> String {
    let o = tracksim::Overrides {
        duration_s: Some(GOLDEN_DURATION_S),
        method: Some(tracksim::Method::from_name(method).expect("a method name")),
        ..Default::default()
    };
    let sc = tracksim::load_scenario_with(file, &o).unwrap_or_else(|e| panic!("{e}"));
    let run = if sc.robot_count() > 1 {
        // A world with several robots (issue 40): every robot's trajectory, in file order.
        tracksim::run::run_team(&sc, Default::default()).map(|r| {
            r.robots
                .iter()
                .map(|(n, run)| format!("{n}\n{}", tracksim::output::trajectory_csv(run)))
                .collect::<String>()
        })
    } else {
        tracksim::run_scenario(&sc, |_, _| {}).map(|r| tracksim::output::trajectory_csv(&r))
    };
    let text = match run {
        Ok(text) => text,
        // The message names the file by its path: keep only the part inside the checkout, so
        // the hash does not depend on where the repository was cloned.
        Err(e) => format!("error: {e}").replace(&format!("{}/", root().display()), ""),
    };
    format!("{:x}", Sha256::digest(text.as_bytes()))
}

#[test]
fn bundled_trajectories_are_unchanged() {
    // The top folder's files by file name, the task suite's as `tasks/NAME.toml`.
    let files = common::bundled_scenarios()
        .into_iter()
        .chain(common::task_scenarios())
        .chain(common::soil_scenarios())
        .chain(common::team_scenarios());
    let mut got = BTreeMap::new();
    for f in files {
        let name = f
            .strip_prefix(root().join("scenarios"))
            .unwrap()
            .to_string_lossy()
            .to_string();
        for m in methods() {
            got.insert(format!("{name} {m}"), hash_run(&f, &m));
        }
    }
    let text: String = got.iter().map(|(k, h)| format!("{k} {h}\n")).collect();
    let path = root().join("crates/tracksim/tests/golden/trajectories.txt");
    if std::env::var_os("TRACKSIM_UPDATE_GOLDEN").is_some() {
        std::fs::write(&path, &text).unwrap();
        return;
    }
    let stored = std::fs::read_to_string(&path).unwrap_or_default();
    let want: BTreeMap<String, String> = stored
        .lines()
        .filter_map(|l| l.rsplit_once(' '))
        .map(|(k, h)| (k.to_string(), h.to_string()))
        .collect();
    let changed: Vec<String> = got
        .iter()
        .filter(|(k, h)| want.get(*k) != Some(h))
        .map(|(k, h)| format!("{k}: stored {:?}, now {h}", want.get(k)))
        .collect();
    assert!(
        changed.is_empty() && want.len() == got.len(),
        "trajectories changed ({} of {}; {} stored). If the physics change is deliberate, run \
         scripts/update-golden.sh and say why in the commit.\n{}",
        changed.len(),
        got.len(),
        want.len(),
        changed.join("\n")
    );
}
