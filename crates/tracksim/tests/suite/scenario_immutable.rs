//! The compiled `Scenario` is immutable after compile (issue 39), by its type: a `Scenario`
//! seals a `ScenarioData` that it derefs to (every read, `sc.vehicle`, `sc.solver.dt`, works)
//! without `DerefMut`, and only `model/` builds or changes one (`model/scenario.rs`, whose
//! `compile_fail` doc tests show that `sc.duration = 1.0`, `sc.commands.clear()` and a
//! `Scenario` rebuilt from a changed copy of its data do not compile). A variation of a file
//! (another method, duration, solver order, a moved start, a run that does not stop at its
//! outcome) is written into the file's keys through `model::Overrides` before compiling, or, in
//! a test, into the file's `ScenarioSpec`, so it is checked like the file's own values. The
//! syntactic check that stood here before the type did is gone: the compiler now refuses what
//! it looked for, in the tests and examples too.
//!
//! What stays here: the override keys are checked like the file's.

use std::path::Path;

/// The override keys added for the benchmark and the ensembles are written into the file's
/// keys and checked like them, their problems naming the key and what overrode it.
#[test]
fn the_new_overrides_are_checked_like_the_files_keys() {
    let f = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/packbot_flat.toml");
    let load = |o: tracksim::Overrides| tracksim::load_scenario_with(&f, &o);
    let plain = load(tracksim::Overrides::default()).unwrap();
    let o = tracksim::Overrides {
        stop_at_outcome: Some(false),
        order_salt: Some(3),
        start_offset: Some(tracksim::model::StartOffset {
            x_m: 0.25,
            y_m: -0.5,
            yaw_deg: 90.0,
        }),
        ..Default::default()
    };
    let sc = load(o).unwrap();
    assert!(plain.outcome.stop && !sc.outcome.stop);
    assert_eq!(sc.solver.order_salt, 3);
    assert_eq!(
        sc.start_xy,
        (plain.start_xy.0 + 0.25, plain.start_xy.1 - 0.5)
    );
    assert_eq!(sc.start_yaw, 90f64.to_radians());
    assert_eq!(
        sc.overridden,
        [
            "outcome.stop",
            "simulation.order_salt",
            "vehicle.x_m",
            "vehicle.y_m",
            "vehicle.yaw_deg"
        ]
    );
    let e = load(tracksim::Overrides {
        order_salt: Some(100_000),
        ..Default::default()
    })
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("simulation.order_salt (overridden: an ensemble member's solver order)")
            && e.contains("must be between 0 and 1024"),
        "{e}"
    );
}
