//! Every bundled scenario (`scenarios/`, `classic/`, `random/`, `tasks/` at its file's seed) run to its
//! end, as `tracksim run` runs it, against the `[expect]` table in the file itself (issue 23):
//! the outcome and a few key figures its description promises. Until this test, bundled files
//! were only run for 2 s, and two of them had silently stopped doing what they said
//! (`packbot_mesh` was launched off the plateau by the floating origin at x = 2 m,
//! `packbot_stairs` stalled on the second stair). A file without `[expect]` fails here, so a
//! new bundled file must say what it does.
//!
//! The runs share the machine's cores (each run is one thread; the whole set is about 320 s
//! of simulated time).

use crate::common;

use std::path::Path;
use std::sync::Mutex;

/// Runs one file to its end; `Err` lists what it missed.
fn run_to_end(file: &Path) -> Result<String, String> {
    let sc = tracksim::load_scenario(file).map_err(|e| e.to_string())?;
    if sc.robot_count() > 1 {
        return run_team_to_end(file, &sc);
    }
    if sc.expect.is_empty() {
        return Err(format!(
            "{}: has no [expect] table: say what the scenario must show",
            file.display()
        ));
    }
    let r = tracksim::run_scenario(&sc, |_, _| {}).map_err(|e| e.to_string())?;
    let misses = tracksim::run::check_expectations(&sc.expect, &r);
    let p = &r.summary.final_pose;
    let line = format!(
        "{}: {} ({}) at {:.2} s, final x {:.3} y {:.3} z {:.3} m yaw {:.1} deg, mean speed {:.3} m/s",
        file.display(),
        r.summary.outcome,
        r.summary.outcome_reason,
        r.summary.outcome_time_s,
        p.x,
        p.y,
        p.z,
        p.yaw.to_degrees(),
        r.summary.mean_speed_mps
    );
    if misses.is_empty() {
        Ok(line)
    } else {
        Err(format!("{line}\n    {}", misses.join("\n    ")))
    }
}

/// Runs a file with several robots to its end against its `[expect]` tables (the world's and
/// each robot's); every robot must have one.
fn run_team_to_end(file: &Path, sc: &tracksim::Scenario) -> Result<String, String> {
    let team = sc.team.as_ref().expect("a team");
    if let Some(r) = team.robots.iter().find(|r| r.expect.is_empty()) {
        return Err(format!(
            "{}: robot `{}` has no [vehicles.expect] table: say what it must show",
            file.display(),
            r.name
        ));
    }
    let opts = tracksim::RunOptions::default();
    let r = tracksim::run::run_team(sc, opts).map_err(|e| e.to_string())?;
    let misses = tracksim::run::team::team_misses(sc, &r);
    let mut line = format!(
        "{}: {} ({}) at {:.2} s",
        file.display(),
        r.outcome.name(),
        r.outcome.reason(),
        r.outcome_time
    );
    for (name, run) in &r.robots {
        let p = &run.summary.final_pose;
        line += &format!(
            "\n    {name}: {} at {:.2} s, final x {:.3} y {:.3} z {:.3} m yaw {:.1} deg",
            run.summary.outcome,
            run.summary.outcome_time_s,
            p.x,
            p.y,
            p.z,
            p.yaw.to_degrees()
        );
    }
    if misses.is_empty() {
        Ok(line)
    } else {
        Err(format!("{line}\n    {}", misses.join("\n    ")))
    }
}

#[test]
fn every_bundled_scenario_does_what_its_file_says() {
    let files = common::all_bundled_scenarios();
    assert!(files.len() >= 20, "{files:?}");
    let queue = Mutex::new(files.clone());
    let results = Mutex::new(Vec::new());
    let workers = std::thread::available_parallelism().map_or(2, |n| n.get());
    std::thread::scope(|s| {
        for _ in 0..workers {
            s.spawn(|| {
                loop {
                    let Some(f) = queue.lock().unwrap().pop() else {
                        break;
                    };
                    let r = run_to_end(&f);
                    results.lock().unwrap().push((f, r));
                }
            });
        }
    });
    let results = results.into_inner().unwrap();
    assert_eq!(results.len(), files.len());
    let mut failed = Vec::new();
    for (_, r) in &results {
        match r {
            Ok(line) => println!("{line}"),
            Err(e) => failed.push(e.clone()),
        }
    }
    assert!(failed.is_empty(), "\n{}", failed.join("\n"));
}

/// A bad `[expect]` table is refused with its keys named, every problem at once.
#[test]
fn bad_expect_keys_are_named() {
    let dir = common::root().join("scenarios");
    let mut spec: tracksim::spec::ScenarioSpec =
        tracksim::model::read_toml(&dir.join("packbot_flat.toml")).unwrap();
    spec.expect.outcome = Some("win".into());
    spec.expect.final_z_m = Some([0.2, 0.1]);
    spec.expect.mean_speed_mps = Some([f64::NAN, 0.3]);
    let v = tracksim::model::load_vehicle(&dir.join(spec.vehicle.file.as_ref().unwrap())).unwrap();
    let issues = tracksim::compile_scenario(&spec, v, &dir).unwrap_err();
    let text = issues
        .iter()
        .map(|i| i.to_string())
        .collect::<Vec<_>>()
        .join("\n");
    for key in [
        "expect.outcome",
        "expect.final_z_m",
        "expect.mean_speed_mps",
    ] {
        assert!(text.contains(key), "{key} missing from {text}");
    }
}
