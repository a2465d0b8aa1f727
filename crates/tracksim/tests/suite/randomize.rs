//! `[randomize]`, the learning environments and sweeps on the library side: a fixed file is
//! compiled as before, values come from the seed, the vector env does not depend on threads.

use crate::common;
use common::root;
use std::sync::Arc;
use tracksim::env::{EnvConfig, VecEnv};

fn step_random() -> std::path::PathBuf {
    root().join("scenarios/random/packbot_step_random.toml")
}

#[test]
fn a_fixed_file_compiles_to_the_same_trajectory_through_a_template() {
    let path = root().join("scenarios/packbot_step.toml");
    let short = tracksim::Overrides {
        duration_s: Some(0.3),
        ..Default::default()
    };
    let a = tracksim::load_scenario_with(&path, &short).unwrap();
    let t = tracksim::ScenarioTemplate::load_with(&path, &short).unwrap();
    let b = t.instantiate(t.file_seed()).unwrap();
    assert!(b.randomized.is_empty());
    let ra = tracksim::run_scenario(&a, |_, _| {}).unwrap();
    let rb = tracksim::run_scenario(&b, |_, _| {}).unwrap();
    assert_eq!(
        tracksim::output::trajectory_csv(&ra),
        tracksim::output::trajectory_csv(&rb)
    );
}

#[test]
fn values_come_from_the_seed_and_reach_the_compiled_scenario() {
    let t = tracksim::load_template(&step_random()).unwrap();
    let a = t.instantiate(4).unwrap();
    let b = t.instantiate(4).unwrap();
    let c = t.instantiate(5).unwrap();
    assert_eq!(a.randomized, b.randomized);
    assert_ne!(a.randomized, c.randomized);
    let yaw = a.randomized["start_yaw_deg"];
    assert!((a.start_yaw - yaw.to_radians()).abs() < 1e-12);
    assert_eq!(a.seed, 4);
    // `tracksim run` samples with the file's own seed, and reports the values.
    let run = tracksim::load_scenario(&step_random()).unwrap();
    assert_eq!(
        run.randomized,
        t.instantiate(t.file_seed()).unwrap().randomized
    );
}

#[test]
fn the_vector_env_gives_the_same_results_on_one_and_two_threads() {
    let t = Arc::new(tracksim::load_template(&step_random()).unwrap());
    let run = |threads| {
        let mut v = VecEnv::new(t.clone(), EnvConfig::default(), 3, 9, threads).unwrap();
        let no = v.envs()[0].obs_dim();
        let mut obs = vec![0f32; 3 * no];
        let mut all = Vec::new();
        for k in 0..8 {
            let a: Vec<f32> = (0..6).map(|i| ((i + k) % 3) as f32 * 0.5 - 0.2).collect();
            let s = v.step(&a, &mut obs).unwrap();
            all.extend(obs.iter().map(|x| x.to_bits() as u64));
            all.extend(s.iter().map(|s| s.info.progress_delta_m.to_bits()));
        }
        all
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn shards_parse_from_flags_and_job_array_variables() {
    use tracksim::sweep::Shard;
    assert_eq!(Shard::parse("1/3"), Ok(Shard { index: 1, count: 3 }));
    assert!(Shard::parse("3/3").is_err() && Shard::parse("x").is_err());
    let env = |pairs: &'static [(&'static str, &'static str)]| {
        move |k: &str| {
            pairs
                .iter()
                .find(|(n, _)| *n == k)
                .map(|(_, v)| v.to_string())
        }
    };
    let slurm = env(&[
        ("SLURM_ARRAY_TASK_ID", "3"),
        ("SLURM_ARRAY_TASK_MIN", "1"),
        ("SLURM_ARRAY_TASK_COUNT", "4"),
    ]);
    assert_eq!(Shard::from_env(slurm, None), Ok(Shard::new(2, 4).ok()));
    let k8s = env(&[("JOB_COMPLETION_INDEX", "2")]);
    assert!(
        Shard::from_env(k8s, None)
            .unwrap_err()
            .contains("--shard-count")
    );
    assert_eq!(Shard::from_env(k8s, Some(5)), Ok(Shard::new(2, 5).ok()));
    assert_eq!(Shard::from_env(env(&[]), None), Ok(None));
}
