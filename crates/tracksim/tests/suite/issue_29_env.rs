//! Issue 29 (items 2 and 3, the library's part): the learner's observation
//! (`observation = "learner"`), velocity-controlled flippers (`flipper_action = "velocity"`)
//! and episodes recorded as run folders that replay (`record_dir`).

use crate::common::root;
use std::path::PathBuf;
use std::sync::Arc;
use tracksim::env::{Env, EnvConfig, EnvValue, LearnerObs, VecEnv};

/// Allocations of the current thread so far: the suite's counting allocator (defined in
/// `issue_25_sensors`; tests run on their own threads).
fn allocations() -> usize {
    crate::issue_25_sensors::ALLOCATIONS.with(|c| c.get())
}

fn template(name: &str) -> Arc<tracksim::ScenarioTemplate> {
    Arc::new(tracksim::load_template(&root().join("scenarios").join(name)).unwrap())
}

fn cfg(settings: &[(&str, EnvValue)]) -> EnvConfig {
    EnvConfig::from_settings(settings.iter().cloned()).unwrap()
}

fn learner() -> EnvConfig {
    cfg(&[("observation", "learner".into())])
}

/// The learner entry `name` of `env`'s observation.
fn entry(env: &Env, name: &str) -> Vec<f32> {
    let l = env.learner().expect("learner observation");
    let mut at = 0;
    for e in l.entries() {
        if e.name == name {
            return l.values()[at..at + e.len()].to_vec();
        }
        at += e.len();
    }
    panic!("no entry {name}");
}

#[test]
fn new_settings_are_refused_with_their_keys() {
    let bad: Vec<(&str, EnvValue)> = vec![
        ("observation", "image".into()),
        ("flipper_action", "torque".into()),
        ("flipper_action", 1.0.into()),
        ("max_flipper_rate_rad_s", 0.0.into()),
        ("max_flipper_rate_rad_s", f64::NAN.into()),
        ("map_shape", (0i64, 64i64).into()),
        ("map_shape", (200i64, 200i64).into()),
        ("map_resolution_m", (-0.1).into()),
        ("map_reach_m", 0.0.into()),
        ("goal_xy_m", (f64::INFINITY, 0.0).into()),
        ("record_dir", "".into()),
        ("record_dir", 3.0.into()),
    ];
    for (key, v) in bad {
        let e = EnvConfig::from_settings([(key, v.clone())]).unwrap_err();
        assert_eq!(e.issues()[0].key, key, "{key} = {v:?}: {e}");
    }
    let e = EnvConfig::from_settings([("observation", EnvValue::from("image"))]).unwrap_err();
    assert!(e.to_string().contains("\"learner\""), "{e}");
    assert!(
        e.to_string()
            .contains("observation: \"image\" is not an observation mode: use \"vector\""),
        "{e}"
    );
}

#[test]
fn learner_observation_layout_bounds_and_values() {
    let t = template("packbot_stairs.toml");
    let mut env = Env::new(t, learner(), 0).unwrap();
    let l = env.learner().unwrap();
    let names: Vec<(&str, Vec<usize>)> = l
        .entries()
        .iter()
        .map(|e| (e.name, e.shape.clone()))
        .collect();
    let v = |n: usize| vec![n];
    assert_eq!(
        names,
        [
            ("roll_pitch_rad", v(2)),
            ("orientation_xyzw", v(4)),
            ("linear_velocity_mps", v(3)),
            ("angular_velocity_rad_s", v(3)),
            ("goal_m", v(3)),
            ("flipper_angle_rad", v(2)),
            ("flipper_velocity_rad_s", v(2)),
            ("track_slip", v(4)),
            ("track_traction_n", v(4)),
            ("track_contacts", v(4)),
            ("elevation_map_m", vec![64, 64]),
        ]
    );
    assert_eq!(env.obs_dim(), 2 + 4 + 3 + 3 + 3 + 2 + 2 + 4 * 3 + 64 * 64);
    assert_eq!(env.obs_names().len(), env.obs_dim());
    assert_eq!(env.obs_names()[0], "roll_pitch_rad[0]");
    // Drive up to the stairs' foot, flippers raised.
    let mut speeds = Vec::new();
    for k in 0..40 {
        let before = env.simulation().body_pose();
        env.step(&[0.6, 0.0, 0.5, 0.5]);
        let after = env.simulation().body_pose();
        let l = env.learner().unwrap();
        let mut at = 0;
        for e in l.entries() {
            for x in &l.values()[at..at + e.len()] {
                assert!(
                    x.is_finite() && (e.low as f32..=e.high as f32).contains(x),
                    "{} = {x} outside [{}, {}]",
                    e.name,
                    e.low,
                    e.high
                );
            }
            at += e.len();
        }
        if k >= 20 {
            // The mean forward speed over the period, against the entry at its end.
            let dx = (after.x - before.x) / 0.05;
            speeds.push((dx, entry(&env, "linear_velocity_mps")[0] as f64));
        }
    }
    let mean = |f: fn(&(f64, f64)) -> f64| speeds.iter().map(f).sum::<f64>() / 20.0;
    let (moved, said) = (mean(|s| s.0), mean(|s| s.1));
    // Commanded 0.3 m/s; the entry and the pose's motion agree within 1 cm/s over 1 s.
    assert!((moved - said).abs() < 0.01 && moved > 0.2, "{moved} {said}");
    // Orientation and roll/pitch agree: level robot, yaw from the pose.
    let p = env.simulation().body_pose();
    let q = entry(&env, "orientation_xyzw");
    let rp = entry(&env, "roll_pitch_rad");
    assert!((rp[0] as f64 - p.roll).abs() < 1e-6 && (rp[1] as f64 - p.pitch).abs() < 1e-6);
    let yaw = 2.0 * (q[2] as f64).atan2(q[3] as f64);
    assert!((yaw - p.yaw).abs() < 1e-3, "{yaw} {}", p.yaw);
    // Goal: success_z_m = 1.0 only, so 10 m ahead of the start along its heading (+x from
    // the origin), at z = 1 m; in the body frame (the robot pitches on the first step).
    let g = entry(&env, "goal_m");
    let rot = glam::DQuat::from_euler(glam::EulerRot::ZYX, p.yaw, p.pitch, p.roll);
    let want = rot.inverse() * glam::DVec3::new(10.0 - p.x, -p.y, 1.0 - p.z);
    for k in 0..3 {
        assert!((g[k] as f64 - want[k]).abs() < 1e-3, "{g:?} vs {want:?}");
    }
    // Slip, traction and contacts are the CLI's figures (trajectory.csv).
    let s = env.simulation().sample();
    let slip = entry(&env, "track_slip");
    let traction = entry(&env, "track_traction_n");
    let contacts = entry(&env, "track_contacts");
    for i in 0..4 {
        assert_eq!(slip[i], s.slip[i] as f32);
        assert_eq!(traction[i], s.loads[i].traction_n as f32);
        assert_eq!(contacts[i], s.loads[i].contacts as f32);
    }
    assert!(contacts[0] > 0.0 && traction[0].abs() < 200.0);
    // The map: each cell's height is the terrain's (an independent downward ray through the
    // query pipeline) minus the body origin's height, at the cell's centre on the heading.
    let map = entry(&env, "elevation_map_m");
    let (c, sn) = (p.yaw.cos(), p.yaw.sin());
    let res = 2.0 / 64.0;
    let mut stairs = 0;
    for i in (0..64).step_by(5) {
        for j in (0..64).step_by(7) {
            let (ax, ay) = ((i as f64 + 0.5 - 32.0) * res, (j as f64 + 0.5 - 32.0) * res);
            let (x, y) = (p.x + c * ax - sn * ay, p.y + sn * ax + c * ay);
            let z = env.simulation().terrain_below(x, y).unwrap();
            if z > 0.1 {
                stairs += 1;
            }
            let h = map[i * 64 + j] as f64;
            // A cell edge of a riser can fall either side by f32 rounding: skip near risers.
            let near_riser = ((x - 0.9) / 0.3).fract().abs() < 0.02;
            if !near_riser {
                assert!(
                    (h - (z - p.z)).abs() < 1e-3,
                    "cell {i},{j}: {h} vs {}",
                    z - p.z
                );
            }
        }
    }
    assert!(stairs > 5, "the map ahead sees the first steps");
}

#[test]
fn learner_observation_does_not_allocate() {
    let t = template("packbot_stairs.toml");
    let mut env = Env::new(t, learner(), 0).unwrap();
    for _ in 0..5 {
        env.step(&[0.6, 0.0, 0.0, 0.0]);
    }
    let c = learner();
    let start = env.simulation().body_pose();
    let mut l = LearnerObs::new(env.simulation(), env.scenario(), &c, &start);
    let mut out = vec![0f32; env.obs_dim()];
    l.update(env.simulation());
    let before = allocations();
    for _ in 0..10 {
        l.update(env.simulation());
        env.observe(&mut out);
    }
    assert_eq!(allocations() - before, 0, "allocations in 10 observations");
    // The same values as the env's but the goal (10 m ahead of another start).
    let (a, b) = (l.values(), &out[..]);
    assert_eq!(a[..12], b[..12]);
    assert_eq!(a[15..], b[15..]);
    let (n, us) = l.cost();
    eprintln!("learner observation: {us:.0} us per update over {n} updates (dev profile)");
}

#[test]
fn learner_map_comes_from_the_vehicles_elevation_map_sensor() {
    let t = template("packbot_sensors.toml");
    let env = Env::new(t, learner(), 0).unwrap();
    let l = env.learner().unwrap();
    let map = l.entries().last().unwrap();
    assert_eq!(map.name, "elevation_map_m");
    // The sensor "elevation": 2 m x 2 m at 0.03125 m, 64 x 64.
    assert_eq!(map.shape, [64, 64]);
    // Goal from goal_xy_m, in the body frame (the robot starts level, heading +x), at the
    // outcome's success_z_m = 1 m.
    let c = cfg(&[
        ("observation", "learner".into()),
        ("goal_xy_m", (3.0, 1.0).into()),
    ]);
    let env = Env::new(template("packbot_sensors.toml"), c, 0).unwrap();
    let p = env.simulation().body_pose();
    let g = entry(&env, "goal_m");
    assert!((g[0] as f64 - (3.0 - p.x)).abs() < 0.01, "{g:?}");
    assert!((g[1] as f64 - (1.0 - p.y)).abs() < 0.01, "{g:?}");
    assert!((g[2] as f64 - (1.0 - p.z)).abs() < 0.02, "{g:?}");
}

#[test]
fn learner_observation_in_the_vector_env_is_the_single_envs() {
    let t = template("random/packbot_flippers_step_random.toml");
    let mut v = VecEnv::new(t.clone(), learner(), 2, 7, 2).unwrap();
    let mut one = Env::new(t, learner(), 8).unwrap();
    assert_eq!(v.obs_dim(), one.obs_dim());
    let n = v.obs_dim();
    let mut obs = vec![0f32; 2 * n];
    for _ in 0..3 {
        v.step(&[0.5, 0.1, 0.2, -0.2, 0.5, 0.1, 0.2, -0.2], &mut obs)
            .unwrap();
        one.step(&[0.5, 0.1, 0.2, -0.2]);
    }
    let mut o = vec![0f32; n];
    one.observe(&mut o);
    assert_eq!(&obs[n..], &o[..]);
}

/// Steps `env` with `action` for `seconds`, returning (time, flipper 0 angle) after each step.
fn run(env: &mut Env, action: &[f32], seconds: f64) -> Vec<(f64, f64)> {
    let n = (seconds / 0.05).round() as usize;
    (0..n)
        .map(|_| {
            env.step(action);
            let s = env.simulation();
            (s.time(), s.flipper_angle(0))
        })
        .collect()
}

#[test]
fn velocity_flippers_follow_the_commanded_rate_and_hold_the_limits() {
    let c = cfg(&[
        ("flipper_action", "velocity".into()),
        ("max_flipper_rate_rad_s", 1.0.into()),
        ("observation", "learner".into()),
    ]);
    let mut env = Env::new(template("packbot_stairs.toml"), c, 0).unwrap();
    // 0.5 rad/s up for 0.8 s: the servo (2000 N m/rad, 50 N m s/rad) follows the target ramp
    // with a constant lag once settled (its time constant is 25 ms), so after 0.2 s the angle
    // climbs at the commanded rate; the target moves in 50 ms steps, so the rate is measured
    // between period ends over 0.5 s.
    let a = run(&mut env, &[0.0, 0.0, 0.5, 0.5], 0.8);
    let (t0, a0) = a[5];
    let (t1, a1) = a[15];
    let rate = (a1 - a0) / (t1 - t0);
    assert!((rate - 0.5).abs() < 0.5 * 0.02, "measured {rate} rad/s");
    // The entry is the arm's rate at the period's end: the target moves in one step per
    // period, so the arm moves fastest at the start of a period and slows towards its end.
    let seen = entry(&env, "flipper_velocity_rad_s");
    assert!(seen[0] > 0.0 && seen[0] < 1.0, "{seen:?}");
    // Full rate up for 1.5 s: the target stops at the range's top (60 deg), the arm with it.
    let top = 60f64.to_radians();
    let a = run(&mut env, &[0.0, 0.0, 1.0, 1.0], 1.5);
    assert!((env.simulation().flipper_target(0) - top).abs() < 1e-9);
    let highest = a.iter().map(|x| x.1).fold(f64::MIN, f64::max);
    // Within the servo's static deflection under the arm's weight (about 1.5 N m / 2000 N m
    // per rad = 0.001 rad) and its overshoot.
    assert!(highest < top + 0.01, "{highest} > {top}");
    assert!((a.last().unwrap().1 - top).abs() < 0.01);
    // No wind-up: one period down moves the target 0.05 rad below the top at once.
    env.step(&[0.0, 0.0, -1.0, -1.0]);
    assert!((env.simulation().flipper_target(0) - (top - 0.05)).abs() < 1e-9);
    // A range beyond the joint's limits is clamped to the limits.
    let c = cfg(&[
        ("flipper_action", "velocity".into()),
        ("flipper_range_rad", (-3.0, 3.0).into()),
    ]);
    let t = template("packbot_urdf_stairs.toml");
    let mut env = Env::new(t, c, 0).unwrap();
    let limits = env.scenario().vehicle.flippers[0].limits;
    if let Some([_, hi]) = limits {
        let na = env.action_dim();
        let mut action = vec![0f32; na];
        for x in action
            .iter_mut()
            .skip(na - env.scenario().vehicle.flippers.len())
        {
            *x = 1.0;
        }
        for _ in 0..100 {
            env.step(&action);
        }
        assert!((env.simulation().flipper_target(0) - hi).abs() < 1e-9);
    }
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tracksim-issue29-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// Records an episode of `packbot_stairs.toml` with `settings`, replays its commands.toml as
/// `tracksim run FILE --commands DIR/commands.toml --duration T` does, and compares.
fn record_and_replay(name: &str, settings: &[(&str, EnvValue)], actions: &[Vec<f32>]) {
    let dir = tmp(name);
    let mut s = settings.to_vec();
    s.push(("record_dir", EnvValue::Text(dir.display().to_string())));
    let file = root().join("scenarios/packbot_stairs.toml");
    let t = Arc::new(tracksim::load_template(&file).unwrap());
    let mut env = Env::new(t, cfg(&s), 5).unwrap();
    for a in actions {
        for _ in 0..6 {
            env.step(a);
        }
    }
    let duration = env.simulation().time();
    let folder = env.flush_record().unwrap().expect("a folder");
    assert_eq!(folder, dir.join("seed5-ep0"));
    for f in [
        "summary.json",
        "trajectory.csv",
        "scene.json",
        "belts.csv",
        "commands.toml",
    ] {
        assert!(folder.join(f).is_file(), "{f} missing");
    }
    let commands = std::fs::read_to_string(folder.join("commands.toml")).unwrap();
    assert!(commands.contains("--duration"), "{commands}");
    // Issue 64: the printed command carries the episode's seed (every episode's scenario is
    // instantiated with it).
    assert!(commands.contains("--keep-running --seed 5\n"), "{commands}");
    // The replay.
    let o = tracksim::Overrides {
        commands: Some(folder.join("commands.toml")),
        duration_s: Some(duration),
        ..Default::default()
    };
    let sc = tracksim::load_scenario_with(&file, &o).unwrap();
    let result = tracksim::run_scenario(&sc, |_, _| {}).unwrap();
    let out = dir.join("replay");
    tracksim::output::write_outputs(
        &sc,
        &result,
        &out,
        tracksim::output::Outputs {
            replay: true,
            plots: false,
            mcap: false,
            raw_images: false,
        },
    )
    .unwrap();
    let a = std::fs::read(folder.join("trajectory.csv")).unwrap();
    let b = std::fs::read(out.join("trajectory.csv")).unwrap();
    assert!(a.len() > 1000);
    assert!(a == b, "{name}: the replay's trajectory.csv differs");
    // Nothing is written for an episode without a step, and it takes no number.
    env.reset(6).unwrap();
    assert_eq!(env.flush_record().unwrap(), None);
    env.reset(7).unwrap();
    env.step(&actions[0]);
    assert_eq!(env.flush_record().unwrap(), Some(dir.join("seed7-ep1")));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn recorded_episodes_replay_byte_for_byte() {
    let twist = [
        vec![0.6, 0.0, 0.4, 0.4],
        vec![0.8, 0.3, -0.2, 0.1],
        vec![0.8, 0.3, -0.2, 0.1],
        vec![0.5, -0.5, 0.9, 0.9],
    ];
    record_and_replay("twist", &[], &twist);
    // Belts: one speed per track (left, right, flipper_left, flipper_right), then flipper
    // rates.
    let belts = [
        vec![0.6, 0.5, 0.6, 0.5, 0.4, 0.2],
        vec![0.6, 0.5, 0.6, 0.5, -0.7, 0.3],
    ];
    record_and_replay(
        "belts-velocity",
        &[
            ("action", "belts".into()),
            ("flipper_action", "velocity".into()),
        ],
        &belts,
    );
}
