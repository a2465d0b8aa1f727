//! Issue 58: how accurate a solver setting is.
//!
//! - A spin-up is never silent: a PackBot tethered on friction 0.9 ground at the default
//!   setting (1 ms, 4 iterations) spun up to 447 rad/s and ran on; now either it is held
//!   without spinning, or the run stops with a message naming the spin.
//! - At 8 solver iterations the same tether holds the robot where the pull is Coulomb's
//!   mu m g (the accuracy suite's row), within 3 %.
//! - Newton on the reported forces: there the reported traction equals the pull within 1 %.
//! - A solver setting reaches every case it is given to (`SolverSetting`, `run --dt`).

use crate::common::root;
use tracksim::model::{Overrides, VehicleModel};
use tracksim::run::RunResult;
use tracksim::validate::SolverSetting;

/// The PackBot (belts and body of friction `mu`) on flat ground of friction `mu`, driving at
/// 0.3 m/s against a 150 N/m tether for `duration` s, with `setting`.
fn tether(mu: f64, duration: f64, setting: SolverSetting) -> tracksim::Result<RunResult> {
    let dir = root().join("scenarios");
    let mut v: VehicleModel =
        tracksim::model::load_vehicle(&root().join("vehicles/packbot510.toml")).unwrap();
    v.body.friction = mu;
    for t in &mut v.tracks {
        t.friction = mu;
    }
    let text = format!(
        "[vehicle]\nfile = \"../vehicles/packbot510.toml\"\n[terrain.ground]\nfriction = {mu}\n\
         [simulation]\nduration_s = {duration}\n\
         [drawbar]\nstiffness_n_per_m = 150.0\nhitch_m = [-0.25, 0.0, 0.0]\n\
         [[commands]]\nt_s = 0.0\nbelt_speed_mps = 0.3\n"
    );
    let sc =
        tracksim::model::compile_scenario_text("tether", &text, v, &dir, &setting.overrides())?;
    tracksim::run_scenario(&sc, |_, _| {})
}

fn max_yaw_rate(r: &RunResult) -> f64 {
    r.samples
        .iter()
        .map(|s| s.angvel[2].abs())
        .fold(0.0, f64::max)
}

#[test]
fn a_spin_up_near_the_friction_limit_is_never_silent() {
    match tether(0.9, 10.0, SolverSetting::default()) {
        Ok(r) => {
            let rate = max_yaw_rate(&r);
            println!("held: max yaw rate {rate:.3} rad/s");
            assert!(rate < 0.5, "a run that goes on must not spin: {rate} rad/s");
        }
        Err(e) => {
            let msg = e.to_string();
            println!("stopped: {msg}");
            assert!(
                matches!(e, tracksim::Error::Unstable { .. }) && msg.contains("rad/s"),
                "{msg}"
            );
        }
    }
}

#[test]
fn at_eight_iterations_the_tether_holds_the_robot_at_coulombs_pull() {
    let setting = SolverSetting {
        iterations: Some(8),
        ..Default::default()
    };
    let r = tether(0.9, 30.0, setting).expect("held at 8 iterations");
    let d = r.summary.drawbar.clone().expect("drawbar summary");
    let weight = r.summary.mass.total_simulated_kg * 9.81;
    let err = d.mean_pull_n / (0.9 * weight) - 1.0;
    println!(
        "mean pull {:.2} N against mu m g {:.2} N ({:+.2} %), max yaw rate {:.3} rad/s",
        d.mean_pull_n,
        0.9 * weight,
        100.0 * err,
        max_yaw_rate(&r)
    );
    assert!(err.abs() < 0.03, "{err}");
    assert!(max_yaw_rate(&r) < 0.5);
    // Newton on the reported forces: at rest on average the ground's push on the belts equals
    // the pull. Scaled from Rapier's last substep alone the traction read 8.3 % high at 8
    // iterations; corrected to the robot's momentum balance, 0.24 %. 1 %: the window mean of
    // the stick-slip's m a over 15 s.
    let newton = d.mean_traction_n / d.mean_pull_n - 1.0;
    println!(
        "mean traction {:.2} N ({:+.2} % of the pull)",
        d.mean_traction_n,
        100.0 * newton
    );
    assert!(newton.abs() < 0.01, "{newton}");
    assert_eq!(r.summary.outcome, "completed");
}

#[test]
fn a_solver_setting_reaches_the_compiled_scenario_and_is_named_as_overridden() {
    let setting = SolverSetting {
        dt_s: Some(0.004),
        iterations: Some(8),
        stabilization: Some(3),
    };
    let path = root().join("scenarios/packbot_flat.toml");
    let sc = tracksim::model::load_scenario_with(&path, &setting.overrides()).unwrap();
    assert_eq!(sc.solver.dt, 0.004);
    assert_eq!(sc.solver.iterations, 8);
    assert_eq!(sc.solver.stabilization_iterations, 3);
    for k in [
        "simulation.dt_s",
        "simulation.solver_iterations",
        "simulation.stabilization_iterations",
    ] {
        assert!(sc.overridden.iter().any(|o| o == k), "{k}");
    }
    // A bad value is the file's key, marked as the caller's.
    let bad = SolverSetting {
        dt_s: Some(-1.0),
        ..Default::default()
    };
    let e = tracksim::model::load_scenario_with(&path, &bad.overrides())
        .unwrap_err()
        .to_string();
    assert!(e.contains("simulation.dt_s (overridden: --dt)"), "{e}");
    assert_eq!(Overrides::default(), SolverSetting::default().overrides());
}
