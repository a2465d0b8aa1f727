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

/// Starts of the turn, m: every 0.5 m across the floating origin's +-2 m, and two beyond it.
const TURN_STARTS: [f64; 11] = [-2.0, -1.5, -1.0, -0.5, 0.0, 0.37, 0.5, 1.0, 1.5, 2.0, 10.7];

/// PackBot turning at 0.2 m/s and 0.6 rad/s on friction 0.6, started at (`x` m, yaw `yaw_deg`):
/// the mean yaw rate over 2-4 s, rad/s (the heading's change, unwrapped). `damping_ratio` is
/// the file's `simulation.terrain_contact_damping_ratio` when given.
fn turn_rate(x: f64, yaw_deg: f64, damping_ratio: Option<f32>) -> f64 {
    let key = damping_ratio.map_or(String::new(), |z| {
        format!("terrain_contact_damping_ratio = {z}\n")
    });
    let sc = scenario(&format!(
        "[vehicle]\nfile = \"VEHICLE\"\nx_m = {x}\nyaw_deg = {yaw_deg}\n\
         [terrain.ground]\nfriction = 0.6\n[simulation]\nduration_s = 4.0\n{key}"
    ));
    let mut sim = tracksim::Simulation::new(&sc).unwrap();
    sim.set_twist(0.2, 0.6);
    let (mut yaw, mut prev, mut at_2s) = (0.0, sim.body_pose().yaw, 0.0);
    for i in 1..=4000 {
        sim.step().unwrap();
        let y = sim.body_pose().yaw;
        let d = y - prev;
        yaw += d - std::f64::consts::TAU * (d / std::f64::consts::TAU).round();
        prev = y;
        if i == 2000 {
            at_2s = yaw;
        }
    }
    (yaw - at_2s) / 2.0
}

/// (max - min) / min of a list of yaw rates.
fn spread(rates: &[f64]) -> f64 {
    let lo = rates.iter().copied().fold(f64::MAX, f64::min);
    let hi = rates.iter().copied().fold(f64::MIN, f64::max);
    (hi - lo) / lo
}

/// The turn's start yaws, deg: 1e-4 deg apart (a change no file means; it moves the grousers'
/// f32 poses by ulps).
const TURN_YAWS: [f64; 9] = [0.0, 1e-4, 2e-4, 3e-4, 4e-4, 5e-4, 6e-4, 7e-4, 8e-4];

/// The turn's yaw rates over [`TURN_YAWS`] at x = 0, and their spread.
fn yaw_spread(damping_ratio: Option<f32>) -> (f64, Vec<f64>) {
    let rates: Vec<f64> = TURN_YAWS
        .iter()
        .map(|&y| turn_rate(0.0, y, damping_ratio))
        .collect();
    (spread(&rates), rates)
}

/// Where the robot starts on level ground does not change its turn at all: the Rapier world's
/// origin starts at the start position (`world/build.rs`), so every start is the same f32 world.
/// Before, the start x reached the solver through f32 rounding and the rate fell on one of
/// several levels: 0.4278-0.4367 rad/s over 41 starts -2..2 m (2.1 %; docs/DESIGN.md).
#[test]
fn a_skid_steer_turn_does_not_depend_on_where_it_starts() {
    let rates: Vec<f64> = TURN_STARTS
        .iter()
        .map(|&x| turn_rate(x, 0.0, None))
        .collect();
    let s = spread(&rates);
    assert!(s < 0.005, "yaw rates {rates:?}: spread {s:.5}");
    // A rate the turn's kinematics allow: below the commanded 0.6 rad/s (the belts slip), and
    // within the 0.4278-0.4367 rad/s of the levels measured before.
    assert!((0.42..0.44).contains(&rates[0]), "{rates:?}");
    eprintln!("turn over starts {TURN_STARTS:?} m: {rates:?} rad/s, spread {s:.2e}");
}

/// What is left: the rigid track's pressure along its length is statically indeterminate, and
/// Rapier's overdamped terrain contacts (damping ratio 10) keep the share the first steps gave,
/// more or less concentrated under the middle. A change of the start yaw by 1e-4 deg (no
/// file's meaning) moves the grousers by f32 ulps and can move the turn to another level:
/// bounded at 2.5 % (`tracksim run --ensemble` reports it for a scenario). Critically damped
/// (damping ratio 1) the share relaxes to the contacts' springs within milliseconds and the
/// levels merge (under 0.5 %). Not the default: it changes the drawbar, motor, step, long-run,
/// soil and Table IV results (docs/DESIGN.md).
#[test]
fn the_turns_remaining_spread_is_the_overdamped_contacts_load_share() {
    let (stiff, rates) = yaw_spread(None);
    assert!(stiff < 0.025, "yaw rates {rates:?}: spread {stiff:.4}");
    let (damped, rates) = yaw_spread(Some(1.0));
    assert!(
        damped < 0.005,
        "damped yaw rates {rates:?}: spread {damped:.4}"
    );
    eprintln!("turn over start yaws {TURN_YAWS:?} deg: spread {stiff:.4}, damped {damped:.4}");
}
