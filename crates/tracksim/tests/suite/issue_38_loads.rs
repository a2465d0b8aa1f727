//! Issue 38.3: per-track loads obey Newton wherever the robot starts. The mirror-symmetric
//! PackBot at 0.3 m/s on level rigid ground (friction 1.0) read 94.5/36.4 N at start x -1.98 m
//! and 63.7/63.8 N at 0: a rocking of the chassis at half the step rate, sampled on one phase
//! every 10 steps (world/track_loads.rs). Loads are now the mean over the output interval and
//! the solver runs 2 position-correction passes (docs/DESIGN.md).

use crate::common::root;

/// Where the robot starts, m: the worst cases and the origin.
const STARTS: [f64; 4] = [0.0, -1.98, -1.5, 10.7];

fn scenario(text: &str) -> tracksim::Scenario {
    let vehicle = root().join("vehicles/packbot510.toml");
    let text = text.replace("VEHICLE", &vehicle.to_string_lossy());
    let spec: tracksim::spec::ScenarioSpec = toml::from_str(&text).unwrap();
    let v = tracksim::model::load_vehicle(&vehicle).unwrap();
    tracksim::compile_scenario(&spec, v, &root().join("scenarios")).unwrap()
}

/// Mean (normal L, normal R, traction L + R) over samples with t in [t0, t1], N, and the mean
/// yaw rate, rad/s.
fn means(r: &tracksim::RunResult, t0: f64, t1: f64) -> (f64, f64, f64, f64) {
    let s: Vec<_> = r
        .samples
        .iter()
        .filter(|s| s.t >= t0 && s.t <= t1)
        .collect();
    let n = s.len() as f64;
    let m = |f: &dyn Fn(&tracksim::world::Sample) -> f64| s.iter().map(|x| f(x)).sum::<f64>() / n;
    (
        m(&|x| x.loads[0].normal_n),
        m(&|x| x.loads[1].normal_n),
        m(&|x| x.loads[0].traction_n + x.loads[1].traction_n),
        m(&|x| x.angvel[2]),
    )
}

fn weight(sc: &tracksim::Scenario) -> f64 {
    let sim = tracksim::Simulation::new(sc).unwrap();
    sim.mass_report().total_simulated_kg * 9.81
}

fn run(sc: &tracksim::Scenario) -> tracksim::RunResult {
    tracksim::run_scenario(sc, |_, _| {}).unwrap()
}

#[test]
fn level_ground_loads_are_equal_and_sum_to_the_weight_wherever_it_starts() {
    for x in STARTS {
        let sc = scenario(&format!(
            "[vehicle]\nfile = \"VEHICLE\"\nx_m = {x}\n[terrain.ground]\nfriction = 1.0\n\
             [simulation]\nduration_s = 4.0\n[[commands]]\nt_s = 0.0\nbelt_speed_mps = 0.3\n"
        ));
        let mg = weight(&sc);
        let (l, r, _, _) = means(&run(&sc), 2.0, 4.0);
        // Symmetric robot: equal within 5 % (measured 0.5-1.1 %); Newton: the sum is m g
        // within 2 % (measured 0.00 %).
        assert!((l / r - 1.0).abs() < 0.05, "x {x}: L {l:.1} R {r:.1} N");
        assert!(
            ((l + r) / mg - 1.0).abs() < 0.02,
            "x {x}: {:.1} of {mg:.1} N",
            l + r
        );
    }
}

#[test]
fn traction_on_a_plate_balances_the_weight_along_it_wherever_it_starts() {
    for deg in [12.0f64, 25.0] {
        for x in [-1.98, 0.0] {
            let a = deg.to_radians();
            // The plate's top face passes through the start point.
            let (cx, cz) = (x * a.cos() + 0.5 * a.sin(), x * a.sin() - 0.5 * a.cos());
            let sc = scenario(&format!(
                "[vehicle]\nfile = \"VEHICLE\"\nx_m = {}\npitch_deg = {}\n\
                 [[terrain.boxes]]\ncentre_m = [{cx}, 0.0, {cz}]\nsize_m = [30.0, 4.0, 1.0]\n\
                 pitch_deg = {}\nfriction = 1.0\n[simulation]\nduration_s = 5.0\n\
                 [[commands]]\nt_s = 0.0\nbelt_speed_mps = 0.3\n",
                x * a.cos(),
                -deg,
                -deg
            ));
            let mg = weight(&sc);
            let (l, r, t, _) = means(&run(&sc), 3.0, 5.0);
            let (need_n, need_t) = (mg * a.cos(), mg * a.sin());
            assert!(
                ((l + r) / need_n - 1.0).abs() < 0.02,
                "{deg} deg x {x}: normal {:.2} N, m g cos {need_n:.2} N",
                l + r
            );
            // Within 3 % + 1 N (measured +0.11..+0.17 N; before: -2.67..+2.93 N).
            assert!(
                (t - need_t).abs() < 0.03 * need_t + 1.0,
                "{deg} deg x {x}: traction {t:.2} N, m g sin {need_t:.2} N"
            );
        }
    }
}

#[test]
fn a_skid_steer_turn_does_not_depend_on_where_it_starts() {
    let rates: Vec<f64> = [0.0, -1.98, 1.0]
        .iter()
        .map(|x| {
            let sc = scenario(&format!(
                "[vehicle]\nfile = \"VEHICLE\"\nx_m = {x}\n[terrain.ground]\nfriction = 0.6\n\
                 [simulation]\nduration_s = 4.0\n[[commands]]\nt_s = 0.0\nforward_mps = 0.2\n\
                 yaw_rate_rad_s = 0.6\n"
            ));
            means(&run(&sc), 2.0, 4.0).3
        })
        .collect();
    let (lo, hi) = rates
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &r| (a.min(r), b.max(r)));
    // Measured spread 0.84 % over five starts (before: 3.4 %); the target is 0.5 %,
    // not reached (docs/DESIGN.md). Bound: 1.5 %.
    assert!((hi - lo) / lo < 0.015, "yaw rates {rates:?}");
}
