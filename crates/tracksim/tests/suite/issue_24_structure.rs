//! Issue 24: one run loop, the method as data, overrides before compiling.

use std::path::{Path, PathBuf};
use tracksim::{Method, Overrides, Runner};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn scenario(name: &str) -> PathBuf {
    root().join("scenarios").join(name)
}

/// A caller stepping the runner itself (controls at sample boundaries, as `drive` and the env
/// do) gets exactly the trajectory `run_scenario` writes for the same commands.
#[test]
fn a_runner_stepped_by_hand_is_the_run() {
    let o = Overrides {
        duration_s: Some(1.5),
        ..Default::default()
    };
    let sc = tracksim::load_scenario_with(&scenario("packbot_turn.toml"), &o).unwrap();
    let by_run = tracksim::run_scenario(&sc, |_, _| {}).unwrap();
    // The same commands given by the caller instead of the timeline.
    let commands = sc.commands.clone();
    let mut r = Runner::new(&sc).unwrap().without_commands();
    let mut next = 0;
    while !r.finished() {
        while next < commands.len() && commands[next].t <= r.time() + 1e-9 {
            r.apply(&commands[next].controls);
            next += 1;
        }
        r.step().unwrap();
    }
    let by_hand = r.finish(tracksim::run::End::Reached);
    assert_eq!(
        tracksim::output::trajectory_csv(&by_hand),
        tracksim::output::trajectory_csv(&by_run)
    );
    assert_eq!(by_hand.outcome, by_run.outcome);
}

/// An interrupted run keeps what was simulated, with the time it stopped at.
#[test]
fn an_interrupted_run_keeps_its_samples() {
    let sc = tracksim::load_scenario(&scenario("packbot_flat.toml")).unwrap();
    let mut r = Runner::new(&sc).unwrap();
    for _ in 0..123 {
        r.step().unwrap();
    }
    let t = r.time();
    let result = r.finish(tracksim::run::End::Interrupted);
    assert_eq!(result.outcome.name(), "interrupted");
    assert!((result.samples.last().unwrap().t - t).abs() < 1e-12);
    assert!((result.summary.sim_time_s - t).abs() < 1e-12);
}

fn problems(e: tracksim::Error) -> Vec<tracksim::SpecIssue> {
    match e {
        tracksim::Error::Invalid { issues, .. } => issues,
        other => panic!("expected a list of problems, got {other}"),
    }
}

/// An unknown method is reported with every other problem of the file, at load.
#[test]
fn the_method_is_checked_with_the_other_keys() {
    let dir = std::env::temp_dir().join(format!("tracksim_issue24_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(scenario("packbot_flat.toml"))
        .unwrap()
        .replace(
            "\"../vehicles/",
            &format!("\"{}/vehicles/", root().display()),
        )
        .replace(
            "duration_s = 10.0",
            "duration_s = -10.0\nmethod = \"okada2021\"",
        );
    assert!(
        text.contains("okada2021"),
        "the bundled file names its method"
    );
    let f = dir.join("bad_method.toml");
    std::fs::write(&f, text).unwrap();
    let issues = problems(tracksim::load_scenario(&f).unwrap_err());
    let keys: Vec<&str> = issues.iter().map(|i| i.key.as_str()).collect();
    assert!(keys.contains(&"simulation.method"), "{issues:?}");
    assert!(keys.contains(&"simulation.duration_s"), "{issues:?}");
    let m = issues
        .iter()
        .find(|i| i.key == "simulation.method")
        .unwrap();
    assert!(m.message.contains("okada2021") && m.message.contains("wheelsK"));
}

/// A motor on a method that cannot model one is refused at load (not when the world is
/// built), keyed by the track; the override is named.
#[test]
fn a_method_override_is_checked_before_compiling() {
    let motor = root().join("scenarios/classic/packbot_motor_slope.toml");
    let o = Overrides {
        method: Some(Method::Wheels(4)),
        ..Default::default()
    };
    let issues = problems(tracksim::load_scenario_with(&motor, &o).unwrap_err());
    assert!(
        issues
            .iter()
            .any(|i| i.key.contains("motor") && i.message.contains("wheels4")),
        "{issues:?}"
    );
    let sc = tracksim::load_scenario_with(
        &scenario("packbot_flat.toml"),
        &Overrides {
            method: Some(Method::Plates),
            duration_s: Some(0.25),
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(sc.method, Method::Plates);
    assert_eq!(sc.duration, 0.25);
    assert_eq!(
        sc.overridden,
        ["simulation.method", "simulation.duration_s"]
    );
    let bad = tracksim::load_scenario_with(
        &scenario("packbot_flat.toml"),
        &Overrides {
            duration_s: Some(-1.0),
            ..Default::default()
        },
    )
    .unwrap_err();
    let issues = problems(bad);
    assert!(
        issues
            .iter()
            .all(|i| i.key == "simulation.duration_s (overridden: --duration)"),
        "{issues:?}"
    );
}

#[test]
fn a_misspelt_method_gets_a_suggestion() {
    let e = Method::parse("simulation.method", "okada2002").unwrap_err();
    assert!(e.message.contains("did you mean \"okada2020\""), "{e}");
    assert!(e.message.contains("wheelsK"), "every name is listed: {e}");
    assert!(Method::parse("simulation.method", "wheels4").is_ok());
}
