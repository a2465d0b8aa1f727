//! Issue 24, items 4 and 5: the checks that only the Python bindings made are the library's
//! (environment settings, array lengths, sweep plans and shards), refused with key names for
//! Rust, CLI and Python users alike; and the messages a new user meets first (a typo in a key,
//! a vehicle file run as a scenario, pulleys on one line, a sweep of a fixed file).

use crate::common;
use common::root;
use std::path::PathBuf;
use std::sync::Arc;
use tracksim::Error;
use tracksim::env::{ActionMode, Env, EnvConfig, EnvValue, VecEnv};
use tracksim::geometry::{PathError, Pulley, TrackPath};
use tracksim::sweep::{MAX_RUNS, Shard, SweepOptions, SweepPlan};

/// The keys of an error's problems.
fn keys(e: &Error) -> Vec<String> {
    e.issues().iter().map(|i| i.key.clone()).collect()
}

/// The message of the problem at `key`.
fn message(e: &Error, key: &str) -> String {
    e.issues()
        .iter()
        .find(|i| i.key == key)
        .unwrap_or_else(|| panic!("no problem at {key}: {e}"))
        .message
        .clone()
}

fn flat() -> Arc<tracksim::ScenarioTemplate> {
    Arc::new(tracksim::load_template(&root().join("scenarios/packbot_flat.toml")).unwrap())
}

/// A fresh temporary folder for one test.
fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tracksim-issue24-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn env_settings_are_built_from_keys_and_unknown_ones_get_a_suggestion_and_every_key() {
    let c = EnvConfig::from_settings([
        ("control_period_s", EnvValue::from(0.1)),
        ("action", EnvValue::from("belts")),
        ("grid_shape", EnvValue::from((4i64, 3i64))),
        ("grid_spacing_m", EnvValue::from((1i64, 2i64))),
        ("flipper_range_rad", EnvValue::from((-0.5, 0.5))),
    ])
    .unwrap();
    assert_eq!(c.control_period_s, 0.1);
    assert_eq!(c.action, ActionMode::Belts);
    assert_eq!(c.grid_shape, (4, 3));
    assert_eq!(c.grid_spacing_m, (1.0, 2.0));

    let e = EnvConfig::from_settings([("period", EnvValue::from(0.1))]).unwrap_err();
    assert!(matches!(e, Error::Settings { .. }), "{e:?}");
    let m = message(&e, "period");
    assert!(m.contains("unknown environment setting `period`"), "{m}");
    assert!(m.contains("did you mean `control_period_s`?"), "{m}");
    for k in EnvConfig::KEYS {
        assert!(m.contains(&format!("`{k}`")), "{k} missing from {m}");
    }
    let e = EnvConfig::from_settings([("grid_shap", EnvValue::from((4i64, 3i64)))]).unwrap_err();
    assert!(
        message(&e, "grid_shap").contains("did you mean `grid_shape`?"),
        "{e}"
    );
    // Nothing close: no suggestion, the list still whole.
    let e = EnvConfig::from_settings([("zzzz", EnvValue::from(1.0))]).unwrap_err();
    let m = message(&e, "zzzz");
    assert!(
        !m.contains("did you mean") && m.contains("`no_terrain_m`"),
        "{m}"
    );
}

#[test]
fn env_values_of_the_wrong_kind_and_out_of_range_are_refused_with_their_keys() {
    let e = EnvConfig::from_settings([
        ("action", EnvValue::from("tank")),
        ("grid_shape", EnvValue::from((4.5, 3.0))),
        ("max_forward_mps", EnvValue::from("fast")),
        ("control_period_s", EnvValue::from(-1.0)),
        ("max_yaw_rate_rad_s", EnvValue::from(f64::NAN)),
        ("grid_spacing_m", EnvValue::from((0.0, 0.1))),
        ("flipper_range_rad", EnvValue::from((f64::INFINITY, 0.0))),
        ("no_terrain_m", EnvValue::from(f64::NAN)),
    ])
    .unwrap_err();
    let k = keys(&e);
    for key in [
        "action",
        "grid_shape",
        "max_forward_mps",
        "control_period_s",
        "max_yaw_rate_rad_s",
        "grid_spacing_m[0]",
        "flipper_range_rad",
        "no_terrain_m",
    ] {
        assert!(k.contains(&key.to_string()), "{key} not in {k:?}: {e}");
    }
    assert!(message(&e, "action").contains("\"twist\""), "{e}");
    assert!(
        message(&e, "grid_shape").contains("two whole numbers"),
        "{e}"
    );
    assert!(message(&e, "max_forward_mps").contains("a number"), "{e}");
    assert!(message(&e, "control_period_s").contains("> 0 s"), "{e}");
    let shown = e.to_string();
    assert!(
        shown.starts_with("environment settings: 8 problem(s):"),
        "{shown}"
    );

    let e = EnvConfig::from_settings([("grid_shape", EnvValue::from((-1i64, 3i64)))]).unwrap_err();
    assert!(
        message(&e, "grid_shape").contains("two whole numbers"),
        "{e}"
    );
    let c = EnvConfig {
        grid_shape: (1000, 1000),
        ..Default::default()
    };
    let e = c.check().unwrap_err();
    assert!(
        message(&e, "grid_shape").contains("at most 10000 cells"),
        "{e}"
    );
}

#[test]
fn env_and_vec_env_refuse_a_bad_config_built_in_rust() {
    let bad = EnvConfig {
        control_period_s: 0.0,
        max_belt_speed_mps: f64::INFINITY,
        ..EnvConfig::default()
    };
    let e = Env::new(flat(), bad.clone(), 0).err().expect("refused");
    assert_eq!(keys(&e), ["control_period_s", "max_belt_speed_mps"], "{e}");
    let e = VecEnv::new(flat(), bad, 2, 0, 1).err().expect("refused");
    assert_eq!(keys(&e), ["control_period_s", "max_belt_speed_mps"], "{e}");
    let e = VecEnv::new(flat(), EnvConfig::default(), 0, 0, 1)
        .err()
        .expect("refused");
    assert_eq!(keys(&e), ["num_envs"], "{e}");
}

#[test]
fn vec_env_arrays_of_the_wrong_length_are_refused() {
    let mut v = VecEnv::new(flat(), EnvConfig::default(), 2, 0, 1).unwrap();
    let e = v.reset_seeds(&[1, 2, 3]).unwrap_err();
    assert!(matches!(e, Error::Settings { .. }), "{e:?}");
    assert_eq!(
        message(&e, "seeds"),
        "expected 2 seeds (one per environment), got 3"
    );
    let (na, no) = (v.action_dim(), v.obs_dim());
    assert_eq!(na, 2); // forward speed and yaw rate; PackBot 510 has no flippers
    let mut obs = vec![0f32; 2 * no];
    let e = v.step(&[0.0; 3], &mut obs).unwrap_err();
    assert_eq!(
        message(&e, "actions"),
        "expected 4 values (2 environments times 2), got 3"
    );
    let e = v.step(&[0.0; 4], &mut obs[..no]).unwrap_err();
    assert!(message(&e, "obs").contains("got"), "{e}");
    assert!(v.step(&[0.0; 4], &mut obs).is_ok());
    assert!(v.check_actions_shape(&[2, 2]).is_ok() && v.check_actions_shape(&[4]).is_ok());
    let e = v.check_actions_shape(&[1, 4]).unwrap_err();
    assert!(
        message(&e, "actions").starts_with("expected shape (2, 2)"),
        "{e}"
    );
}

#[test]
fn controls_from_arrays_need_one_finite_value_per_track_or_flipper() {
    let flat = tracksim::load_scenario(&root().join("scenarios/packbot_flat.toml")).unwrap();
    let v = &flat.vehicle;
    let c = tracksim::Controls::belt_speeds(v, &[0.1, 0.3]).unwrap();
    assert_eq!(c.belt_speed, [Some(0.1), Some(0.3)]);
    let e = tracksim::Controls::belt_speeds(v, &[0.1]).unwrap_err();
    assert_eq!(
        message(&e, "belt_speeds"),
        "expected 2 belt speeds (one per track: left, right), got 1"
    );
    let e = tracksim::Controls::belt_speeds(v, &[0.1, f64::NAN]).unwrap_err();
    assert!(message(&e, "belt_speeds[1]").contains("finite"), "{e}");
    let e = tracksim::Controls::flipper_angles(v, &[0.5]).unwrap_err();
    assert!(
        message(&e, "flipper_angles").starts_with("expected 0 flipper angles"),
        "{e}"
    );
    let stairs = tracksim::load_scenario(&root().join("scenarios/packbot_stairs.toml")).unwrap();
    let c = tracksim::Controls::flipper_angles(&stairs.vehicle, &[0.5, 0.4]).unwrap();
    assert_eq!(c.flipper_angle, [Some(0.5), Some(0.4)]);
}

#[test]
fn terrain_heights_need_one_y_per_x() {
    let sc = tracksim::load_scenario(&root().join("scenarios/packbot_step.toml")).unwrap();
    let sim = tracksim::Simulation::new(&sc).unwrap();
    let h = sim.terrain_heights(&[0.0, 1e4], &[0.0, 0.0]).unwrap();
    assert!(h[0].is_finite() && h[1].is_nan(), "{h:?}");
    let e = sim.terrain_heights(&[0.0, 1.0], &[0.0]).unwrap_err();
    assert_eq!(
        message(&e, "ys"),
        "expected one y per x: xs has 2 entries, ys 1"
    );
}

#[test]
fn sweep_plans_and_shards_are_refused_with_their_keys() {
    let e = Shard::new(4, 4).unwrap_err();
    assert!(matches!(e, Error::Settings { .. }), "{e:?}");
    assert!(
        message(&e, "shard").contains("need 0 <= index < count (the index runs from 0 to 3)"),
        "{e}"
    );
    assert!(message(&Shard::new(0, 0).unwrap_err(), "shard").contains("at least one shard"));
    assert_eq!(Shard::new(1, 4).unwrap(), Shard { index: 1, count: 4 });

    let e = SweepPlan::random(0, 0).unwrap_err();
    assert_eq!(
        message(&e, "runs"),
        format!("must be from 1 to {MAX_RUNS}, got 0")
    );
    assert_eq!(SweepPlan::random(3, 7).unwrap().runs[2].seed, 9);

    let axes = vec![
        ("friction".to_string(), vec![0.5, f64::NAN]),
        ("height".to_string(), vec![]),
        ("friction".to_string(), vec![0.4]),
        (" ".to_string(), vec![1.0]),
    ];
    let e = SweepPlan::grid(&axes, 1, 0).unwrap_err();
    assert!(message(&e, "grid.friction").contains("finite"), "{e}");
    assert!(message(&e, "grid.height").contains("no values"), "{e}");
    assert!(e.to_string().contains("given twice"), "{e}");
    assert!(message(&e, "grid").contains("empty name"), "{e}");
    let e = SweepPlan::grid(&[], 1, 0).unwrap_err();
    assert!(message(&e, "grid").contains("at least one axis"), "{e}");
    let big = vec![("a".to_string(), vec![1.0; 10_000]); 2];
    let e = SweepPlan::grid(&big, 1_000, 0).unwrap_err();
    assert!(message(&e, "grid").contains("at most"), "{e}");
    let e = SweepPlan::grid(&[("a".to_string(), vec![1.0])], 0, 0).unwrap_err();
    assert_eq!(keys(&e), ["runs"], "{e}");
    let g = SweepPlan::grid(&[("a".to_string(), vec![1.0, 2.0])], 2, 5).unwrap();
    assert_eq!(g.runs.len(), 4);

    let out = tmp("jobs");
    let opts = SweepOptions {
        out: out.clone(),
        jobs: 0,
        shard: None,
        resume: false,
        stop: None,
    };
    let plan = SweepPlan::random(1, 0).unwrap();
    let e = tracksim::sweep::run_sweep(&flat(), &plan, &opts, |_, _| {}).unwrap_err();
    assert!(
        message(&e, "jobs").starts_with("must be from 1 to 1024"),
        "{e}"
    );
    assert!(
        !out.join("runs").exists(),
        "nothing written before the refusal"
    );
}

#[test]
fn a_sweep_of_a_file_without_randomize_warns_that_its_runs_are_identical() {
    let fixed = flat();
    let w = SweepPlan::random(3, 0).unwrap().warnings(&fixed);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("packbot_flat.toml has no [randomize] table: its 3 runs will be identical"),
        "{}",
        w[0]
    );
    assert!(SweepPlan::random(1, 0).unwrap().warnings(&fixed).is_empty());
    let random =
        tracksim::load_template(&root().join("scenarios/random/packbot_step_random.toml")).unwrap();
    assert!(
        SweepPlan::random(3, 0)
            .unwrap()
            .warnings(&random)
            .is_empty()
    );
}

/// The bundled flat scenario with `edit` applied to its text, written next to a copy of its
/// vehicle file (also edited by `vehicle_edit`).
fn edited_files(
    name: &str,
    edit: impl Fn(&str) -> String,
    vehicle_edit: impl Fn(&str) -> String,
) -> PathBuf {
    let d = tmp(name);
    let text = std::fs::read_to_string(root().join("scenarios/packbot_flat.toml")).unwrap();
    let text = text.replace("../vehicles/packbot510.toml", "packbot510.toml");
    std::fs::write(d.join("s.toml"), edit(&text)).unwrap();
    let v = std::fs::read_to_string(root().join("vehicles/packbot510.toml")).unwrap();
    std::fs::write(d.join("packbot510.toml"), vehicle_edit(&v)).unwrap();
    d.join("s.toml")
}

#[test]
fn a_typo_in_a_key_gets_a_suggestion_and_the_whole_list_of_keys() {
    let same = |s: &str| s.to_string();
    let p = edited_files(
        "typo_outcome",
        |s| format!("{s}\n[outcome]\nsucess_x_m = 1.0\n"),
        same,
    );
    let e = tracksim::load_scenario(&p).unwrap_err().to_string();
    assert!(
        e.contains("unknown key `sucess_x_m`: did you mean `success_x_m`?"),
        "{e}"
    );
    assert!(e.contains("`fail_off_terrain`, `stop`"), "{e}");
    // [simulation] has more keys than a message line held (cut at 200 characters before):
    // every one is listed.
    let p = edited_files(
        "typo_simulation",
        |s| s.replace("[simulation]", "[simulation]\ndtt = 0.001"),
        same,
    );
    let e = tracksim::load_template(&p).unwrap_err().to_string();
    assert!(!e.contains("cut"), "{e}");
    for k in [
        "`dt_s`",
        "`held_friction_in_bias_pass`",
        "`method`",
        "`seed`",
    ] {
        assert!(e.contains(k), "{k} missing: {e}");
    }
    assert!(e.contains("did you mean `dt_s`?"), "{e}");
    // A vehicle key, and a kind name (a serde variant).
    let p = edited_files("typo_vehicle", same, |v| {
        v.replacen("[[tracks]]", "[[tracks]]\nbelt_thicknes_m = 0.01", 1)
    });
    let e = tracksim::load_scenario(&p).unwrap_err().to_string();
    assert!(e.contains("did you mean `belt_thickness_m`?"), "{e}");
    assert!(e.contains("`sprocket_pitch_radius_m`"), "{e}");
    let p = edited_files("typo_variant", same, |v| {
        v.replace("type = \"box\"", "type = \"boxx\"")
    });
    let e = tracksim::load_scenario(&p).unwrap_err().to_string();
    assert!(
        e.contains("unknown value `boxx`: did you mean `box`?"),
        "{e}"
    );
    // A key 10 kB long is not echoed whole.
    let long = "k".repeat(10_000);
    let p = edited_files(
        "typo_long",
        |s| format!("{s}\n[outcome]\n{long} = 1.0\n"),
        same,
    );
    let e = tracksim::load_scenario(&p).unwrap_err().to_string();
    assert!(
        e.len() < 2_000 && e.contains("`stop`"),
        "{} characters",
        e.len()
    );
}

#[test]
fn a_randomize_grid_name_typo_gets_a_suggestion() {
    let t =
        tracksim::load_template(&root().join("scenarios/random/packbot_step_random.toml")).unwrap();
    let name = t.randomizer().params[0].name.clone();
    let typo = format!("{name}x");
    let fixed = [(typo.clone(), 0.0)].into_iter().collect();
    let e = t.instantiate_with(0, &fixed).unwrap_err();
    let m = message(&e, &format!("randomize.{typo}"));
    assert!(m.contains(&format!("(did you mean `{name}`?)")), "{m}");
}

#[test]
fn a_vehicle_file_loaded_as_a_scenario_says_what_it_is_and_how_to_use_it() {
    let path = root().join("vehicles/packbot510.toml");
    for e in [
        tracksim::load_scenario(&path).unwrap_err(),
        tracksim::load_template(&path).unwrap_err(),
    ] {
        let m = e.to_string();
        assert!(m.contains("this is a vehicle file"), "{m}");
        assert!(m.contains("`file = \"packbot510.toml\"`"), "{m}");
        assert!(m.contains("scenarios/packbot_flat.toml"), "{m}");
        assert!(m.contains("tracksim check"), "{m}");
        assert!(!m.contains("unknown"), "{m}");
    }
}

fn pulley(x: f64, z: f64, radius: f64) -> Pulley {
    Pulley { x, z, radius }
}

#[test]
fn pulleys_on_one_line_are_named_instead_of_a_720_deg_turn() {
    // The middle pulley on the line between the others, as large or smaller: the belt runs
    // past it or would bend backwards around it.
    for r in [0.05, 0.03] {
        let e = TrackPath::from_pulleys(
            &[
                pulley(-0.3, 0.0, 0.05),
                pulley(0.0, 0.0, r),
                pulley(0.3, 0.0, 0.05),
            ],
            0.0,
        )
        .unwrap_err();
        assert_eq!(
            e,
            [PathError::PulleyNotWrapped {
                pulley: 1,
                before: 0,
                after: 2,
                collinear: true
            }],
            "radius {r}"
        );
        assert!(
            e[0].to_string()
                .contains("on the line between pulleys 0 and 2")
        );
    }
    // In any order in the list.
    let e = TrackPath::from_pulleys(
        &[
            pulley(0.3, 0.0, 0.05),
            pulley(-0.3, 0.0, 0.05),
            pulley(0.0, 0.0, 0.05),
        ],
        0.0,
    )
    .unwrap_err();
    assert!(
        matches!(
            e[..],
            [PathError::PulleyNotWrapped {
                pulley: 2,
                collinear: true,
                ..
            }]
        ),
        "{e:?}"
    );
    // A larger middle pulley lifts the belt: a loop.
    assert!(
        TrackPath::from_pulleys(
            &[
                pulley(-0.3, 0.0, 0.05),
                pulley(0.0, 0.0, 0.06),
                pulley(0.3, 0.0, 0.05)
            ],
            0.0,
        )
        .is_ok()
    );
    // Two pulleys at one place, next to each other in the list or not.
    for list in [
        [
            pulley(0.0, 0.0, 0.05),
            pulley(0.0, 0.0, 0.05),
            pulley(0.3, 0.1, 0.05),
        ],
        [
            pulley(0.0, 0.0, 0.05),
            pulley(0.3, 0.1, 0.05),
            pulley(0.0, 0.0, 0.05),
        ],
    ] {
        let e = TrackPath::from_pulleys(&list, 0.0).unwrap_err();
        assert!(e[0].to_string().contains("have the same centre"), "{e:?}");
    }
    let four = [
        pulley(0.0, 0.0, 0.05),
        pulley(0.3, 0.1, 0.05),
        pulley(0.0, 0.0, 0.05),
        pulley(0.3, -0.1, 0.05),
    ];
    let e = TrackPath::from_pulleys(&four, 0.0).unwrap_err();
    assert!(
        matches!(
            e[..],
            [PathError::PulleysOverlap {
                pulley: 0,
                next: 2,
                ..
            }]
        ),
        "{e:?}"
    );
}

#[test]
fn a_vehicle_file_with_collinear_pulleys_names_the_pulley_key() {
    let p = edited_files(
        "collinear",
        |s| s.to_string(),
        |v| {
            v.replace(
                "  { x_m = 0.255, z_m = 0.0, radius_m = 0.082 },\n]",
                "  { x_m = 0.255, z_m = 0.0, radius_m = 0.082 },\n  { x_m = 0.0, z_m = 0.0, radius_m = 0.082 },\n]",
            )
        },
    );
    let e = tracksim::load_scenario(&p).unwrap_err();
    let m = e.to_string();
    assert!(
        m.contains(
            "tracks[0].path.pulleys[2]: pulley 2 has its centre on the line between pulleys 1 and 0"
        ),
        "{m}"
    );
    assert!(!m.contains("720"), "{m}");
}

#[test]
fn an_env_action_of_the_wrong_length_is_refused() {
    let env = Env::new(flat(), EnvConfig::default(), 0).unwrap();
    assert_eq!(env.action_dim(), 2);
    assert!(env.check_action(&[0.5, 0.0]).is_ok());
    for bad in [&[0.5][..], &[0.5, 0.0, 1.0][..]] {
        let e = env.check_action(bad).unwrap_err();
        assert_eq!(keys(&e), ["action"], "{e}");
        assert!(message(&e, "action").contains("expected 2 actions"), "{e}");
    }
}
