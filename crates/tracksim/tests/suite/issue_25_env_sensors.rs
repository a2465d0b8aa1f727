//! Issue 25 (Python part, in the library): the environment setting `observation` ("vector",
//! the default, or "dict") and the sensors' arrays of a dict observation
//! (`Env::observe_sensors`), for one environment and a `VecEnv`.

use crate::common;
use common::root;
use std::sync::Arc;
use tracksim::env::{Env, EnvConfig, EnvValue, ObservationMode, VecEnv};

fn template(name: &str) -> Arc<tracksim::ScenarioTemplate> {
    Arc::new(tracksim::load_template(&root().join("scenarios").join(name)).unwrap())
}

fn dict() -> EnvConfig {
    EnvConfig::from_settings([("observation", EnvValue::from("dict"))]).unwrap()
}

#[test]
fn observation_is_a_setting_refused_with_its_key() {
    assert_eq!(EnvConfig::default().observation, ObservationMode::Vector);
    assert_eq!(dict().observation, ObservationMode::Dict);
    for bad in [EnvValue::from("image"), EnvValue::from(1.0)] {
        let e = EnvConfig::from_settings([("observation", bad)]).unwrap_err();
        let i = &e.issues()[0];
        assert_eq!(i.key, "observation", "{e}");
        assert!(i.message.contains("\"vector\""), "{e}");
    }
}

#[test]
fn dict_observation_has_one_entry_per_sensor_without_non_numbers() {
    let mut env = Env::new(template("packbot_sensors.toml"), dict(), 0).unwrap();
    let spec = env.sensor_obs_spec();
    let names: Vec<&str> = spec.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "imu",
            "encoders",
            "scan",
            "elevation",
            "front_camera",
            "flipper_imu"
        ]
    );
    let shapes: Vec<Vec<usize>> = spec.iter().map(|s| s.shape.clone()).collect();
    assert_eq!(
        shapes,
        [
            vec![10],
            vec![10],
            vec![1, 720],
            vec![64, 64],
            vec![48, 64],
            vec![10]
        ]
    );
    assert_eq!((spec[2].low, spec[2].high), (0.0, 10.0));
    let mut vector = Env::new(template("packbot_sensors.toml"), EnvConfig::default(), 0).unwrap();
    assert!(vector.sensor_obs_spec().is_empty() && vector.sensor_obs_dim() == 0);
    for _ in 0..10 {
        env.step(&[1.0, 0.0, 0.0, 0.0]);
        vector.step(&[1.0, 0.0, 0.0, 0.0]);
    }
    let mut o = vec![0f32; env.sensor_obs_dim()];
    env.observe_sensors(&mut o);
    assert!(o.iter().all(|x| x.is_finite()));
    // The IMU first: specific force, +9.81 m/s^2 up (the robot drives on the flat ground).
    assert!((o[2] - 9.81).abs() < 1.0, "{}", o[2]);
    // Ranges within [0, max range]; the raw scan has no returns where it sees open ground.
    let scan = &o[20..20 + 720];
    assert!(scan.iter().all(|r| (0.0..=10.0).contains(r)));
    // The state vector is the vector observation's.
    let (mut a, mut b) = (vec![0f32; env.obs_dim()], vec![0f32; vector.obs_dim()]);
    env.observe(&mut a);
    vector.observe(&mut b);
    assert_eq!(a, b);
}

#[test]
fn vec_env_sensor_entries_are_each_environments_in_turn() {
    let v = VecEnv::new(template("packbot_sensors.toml"), dict(), 2, 4, 2).unwrap();
    let n = v.envs()[0].sensor_obs_dim();
    let mut all = vec![0f32; 2 * n];
    v.observe_sensors(&mut all);
    for (i, e) in v.envs().iter().enumerate() {
        let mut o = vec![0f32; n];
        e.observe_sensors(&mut o);
        assert_eq!(&all[i * n..(i + 1) * n], o.as_slice());
    }
    // Seeds 4 and 5: other noise.
    assert_ne!(&all[..n], &all[n..]);
}
