//! Issue 14.1: torque-driven tracks. With `[tracks.motor]` the sprocket feels the load: the
//! link motors of a track together deliver at most the motor's belt force
//! `F_max = T G eta / r`, so a motor whose torque is below what a slope needs stalls on it and
//! one with enough climbs. Statics: a PackBot of mass m on a slope theta needs
//! `m g sin(theta)` from its two tracks, i.e. a motor torque of
//! `T* = m g sin(theta) r / (G eta 2)`. The threshold found by bisection agrees with T* within
//! the tolerance below.

use crate::common;
use common::root;
use tracksim::Scripted;
use tracksim::model::{DriveMotor, load_vehicle, read_toml};
use tracksim::spec::{CommandSpec, PerTrack, ScenarioSpec};

const G: f64 = 9.81;
const SLOPE_DEG: f64 = 20.0;
const GEAR: f64 = 50.0;
const EFFICIENCY: f64 = 0.8;

/// PackBot on the 20 deg plate driving uphill at 0.1 m/s with motors of driver torque limit
/// `torque` N m (a no-load speed far above what 0.1 m/s needs, so the limit decides).
fn climb(torque: f64) -> tracksim::Scenario {
    climb_with(torque, |c| c.belt_speed_mps = Some(PerTrack::All(0.1)))
}

/// [`climb`] with the first command set by `command`.
fn climb_with(torque: f64, command: impl FnOnce(&mut CommandSpec)) -> tracksim::Scenario {
    let (spec, vehicle, dir) = climb_parts(torque, command);
    tracksim::compile_scenario(&spec, vehicle, &dir).unwrap()
}

/// What [`climb_with`] compiles: the spec, the vehicle with its motors and the folder.
fn climb_parts(
    torque: f64,
    command: impl FnOnce(&mut CommandSpec),
) -> (ScenarioSpec, tracksim::VehicleModel, std::path::PathBuf) {
    let path = root().join("scenarios/packbot_parked_slope.toml");
    let mut spec: ScenarioSpec = read_toml(&path).unwrap();
    spec.simulation.duration_s = 3.0;
    spec.commands[0].belt_speed_mps = None;
    command(&mut spec.commands[0]);
    let dir = root().join("scenarios");
    let mut vehicle = load_vehicle(&dir.join(spec.vehicle.file.as_ref().unwrap())).unwrap();
    for t in &mut vehicle.tracks {
        t.motor = Some(DriveMotor {
            stall_torque: 10.0 * torque,
            no_load_speed: 5000.0,
            gear_ratio: GEAR,
            efficiency: EFFICIENCY,
            sprocket_radius: t.sprocket_radius.unwrap(),
            torque_limit: Some(torque),
            ..Default::default()
        });
    }
    (spec, vehicle, dir)
}

/// Progress up the slope from 1 s to 3 s, m, and the mean delivered belt force then, N.
fn progress(torque: f64) -> (f64, f64) {
    progress_of(&climb(torque))
}

/// [`progress`] of scenario `sc`.
fn progress_of(sc: &tracksim::Scenario) -> (f64, f64) {
    let mut sim = Scripted::new(sc).unwrap();
    common::run_until(&mut sim, 1.0);
    let a = sim.body_pose();
    let (mut force, mut k) = (0.0, 0.0);
    while sim.time() < 3.0 - 1e-9 {
        sim.step().unwrap();
        let s = sim.sample();
        force += s
            .drive
            .iter()
            .flatten()
            .map(|d| d.belt_force_n)
            .sum::<f64>();
        k += 1.0;
    }
    let b = sim.body_pose();
    let up = ((b.x - a.x).powi(2) + (b.z - a.z).powi(2)).sqrt() * (b.z - a.z).signum();
    (up, force / k)
}

#[test]
fn a_motor_stalls_below_the_static_torque_and_climbs_above_it() {
    let sc = climb(1.0);
    let m = Scripted::new(&sc).unwrap().mass_report().total_simulated_kg;
    let r = sc.vehicle.tracks[0].sprocket_radius.unwrap();
    let need = m * G * SLOPE_DEG.to_radians().sin();
    let t_star = need * r / (GEAR * EFFICIENCY * 2.0);
    let (weak, f_weak) = progress(0.8 * t_star);
    let (slides, _) = progress(0.5 * t_star);
    let (strong, f_strong) = progress(1.25 * t_star);
    println!(
        "T* = {t_star:.4} N m (m g sin = {need:.2} N): 0.5 T* -> {slides:.4} m; 0.8 T* -> {weak:.4} m, belt force {f_weak:.2} N; 1.25 T* -> {strong:.4} m, {f_strong:.2} N"
    );
    // Below T* it cannot climb; back-driven, the gear's friction helps the motor hold (issue
    // 23.5: a torque T holds T G / (eta r)), so down to eta^2 T* = 0.64 T* it stalls, and
    // below that it slides back.
    assert!(weak.abs() < 0.002, "0.8 T* should stall: {weak} m");
    assert!(slides < -0.01, "0.5 T* should slide back: {slides} m");
    assert!(
        strong > 0.15,
        "1.25 T* should climb at ~0.1 m/s: {strong} m in 2 s"
    );
    // Not saturated (it climbs at the command), the belt force is the traction the slope takes:
    // m g sin within 5 % (the links' inertia and the solver's residual).
    assert!(
        (f_strong - need).abs() < 0.05 * need,
        "climbing force {f_strong} N vs {need} N"
    );
    // The threshold, by bisection: within 5 % of the statics.
    let (mut lo, mut hi) = (0.8 * t_star, 1.25 * t_star);
    for _ in 0..5 {
        let mid = 0.5 * (lo + hi);
        // Climbing: more than 5 mm/s (a stalled robot settles by a fraction of a mm).
        if progress(mid).0 > 0.01 {
            hi = mid
        } else {
            lo = mid
        }
    }
    let found = 0.5 * (lo + hi);
    println!("threshold {found:.4} N m = {:.3} T*", found / t_star);
    assert!(
        (found / t_star - 1.0).abs() < 0.05,
        "threshold {found} vs {t_star}"
    );
}

#[test]
fn a_motor_on_a_method_without_one_is_refused() {
    let (mut spec, vehicle, dir) =
        climb_parts(1.0, |c| c.belt_speed_mps = Some(PerTrack::All(0.1)));
    spec.simulation.method = tracksim::Method::Wheels(4).name();
    let Err(issues) = tracksim::compile_scenario(&spec, vehicle, &dir) else {
        panic!("a motor on wheels4 was accepted");
    };
    let err = format!("{issues:?}");
    assert!(err.contains("okada2020"), "{err}");
}

/// The bundled motor-limited climb (`scenarios/classic/packbot_motor_slope.toml`): the small
/// motors cannot hold the commanded 0.3 m/s up 25 deg. Statics: the belt speed at which the two
/// motors' line gives m g sin 25 is 0.207 m/s. The belt runs as one (no link runs away: an
/// earlier version let the unloaded top-run links slide back at metres per second), without slip.
#[test]
fn the_bundled_motor_limited_climb_settles_between_the_statics_and_the_command() {
    let sc = tracksim::load_scenario(&root().join("scenarios/classic/packbot_motor_slope.toml"))
        .unwrap();
    let r = tracksim::run_scenario(&sc, |_, _| {}).unwrap();
    let m = &sc.vehicle.tracks[0].motor.clone().unwrap();
    let mass: f64 = r.summary.mass.total_simulated_kg;
    let per_track = mass * G * 25f64.to_radians().sin() / 2.0;
    // F(v) = T_s (1 - v G / (r w0)) G eta / r  =>  v = (1 - F r / (T_s G eta)) w0 r / G.
    let v_statics = (1.0
        - per_track * m.sprocket_radius / (m.stall_torque * m.gear_ratio * m.efficiency))
        * m.no_load_speed
        * m.sprocket_radius
        / m.gear_ratio;
    let late: Vec<_> = r
        .samples
        .iter()
        .filter(|s| s.t >= 3.0 && s.t <= 9.0)
        .collect();
    let belt = late.iter().map(|s| s.belt_speed[0]).sum::<f64>() / late.len() as f64;
    let slip = late.iter().map(|s| s.slip[0].abs()).fold(0.0, f64::max);
    let fastest = r
        .samples
        .iter()
        .map(|s| s.belt_speed[0].abs())
        .fold(0.0, f64::max);
    println!(
        "statics {v_statics:.4} m/s, belt {belt:.4} m/s, largest |slip| {slip:.4}, fastest belt {fastest:.3} m/s"
    );
    assert_eq!(r.summary.outcome, "success");
    // Motor-limited: well below the command, within 20 % of the statics (the off-ground links
    // are held by their own weight on top of the motor's share, a few per cent more force).
    assert!(belt < 0.85 * 0.3, "{belt}");
    assert!(
        (belt - v_statics).abs() < 0.2 * v_statics,
        "{belt} vs {v_statics}"
    );
    assert!(slip < 0.02, "slip {slip}");
    assert!(fastest < 0.31, "a belt ran at {fastest} m/s");
}

/// The electrical model (`voltage_v`, `stall_current_a`, `no_load_current_a` of
/// vehicles/packbot510_motors.toml: 24 V, 2.04 A, 0.15 A). A tether on a 60 N/m spring
/// (`[drawbar] stiffness_n_per_m`) pulls harder the farther the PackBot drives, until the pull
/// equals what both motors give at stall, 2 x 0.07 x 50 x 0.8 / 0.082 = 68.3 N (below the
/// 76.5 N friction holds): there the belts stop, each motor draws its stall current at the full
/// supply voltage, and all of that power is heat (the belt does no work). Along the torque-speed
/// line the approach is exponential with time constant 68.3 / (0.98 m/s x 60 N/m) = 1.16 s, so
/// after 10 s the belts are within a few mm/s of rest. A constant pull below the stall (20 N):
/// the controller holds 0.3 m/s and the supply gives more than the belt receives.
#[test]
fn a_stalled_motor_draws_its_stall_current_and_a_running_one_loses_power_to_heat() {
    let dir = root().join("scenarios/classic");
    let mut spec: ScenarioSpec = read_toml(&dir.join("packbot_drawbar.toml")).unwrap();
    spec.vehicle.file = Some("../../vehicles/packbot510_motors.toml".into());
    let run = |spec: &ScenarioSpec| {
        let v = load_vehicle(&dir.join(spec.vehicle.file.as_ref().unwrap())).unwrap();
        let sc = tracksim::compile_scenario(spec, v, &dir).unwrap();
        tracksim::run_scenario(&sc, |_, _| {}).unwrap()
    };
    let mut tether = spec.clone();
    tether.simulation.duration_s = 10.0;
    let d = tether.drawbar.as_mut().unwrap();
    (d.pull_n, d.stiffness_n_per_m, d.ramp_s) = (None, Some(60.0), 0.0);
    let stalled = run(&tether);
    let last = stalled.samples.last().unwrap();
    let pull = last.drawbar_n.unwrap();
    println!("tether pull at 10 s: {pull:.2} N (stall 68.29 N)");
    // 5 %: the links off the ground may each use 5 % of an even split of the motor's force
    // (FREE_LINK_SHARE in tracks/okada2020.rs), which does not reach the ground: 65.7 N
    // measured, 3.8 % short (as the slope threshold above is 2.4 % over the statics).
    assert!((pull - 68.29).abs() < 0.05 * 68.29, "pull {pull}");
    for (i, d) in last.drive.iter().enumerate() {
        let d = d.unwrap();
        let e = d.electrical.unwrap();
        println!(
            "stalled track {i}: belt {:.4} m/s, force {:.2} N, {:.3} A, {:.2} V, {:.2} W",
            last.belt_speed[i], d.belt_force_n, e.current, e.voltage, e.power
        );
        assert!(last.belt_speed[i].abs() < 0.01);
        assert!((e.current - 2.04).abs() < 0.04, "current {}", e.current);
        assert!((e.voltage - 24.0).abs() < 0.5, "voltage {}", e.voltage);
        assert!(d.power_w.abs() < 0.02 * e.power);
    }
    spec.drawbar.as_mut().unwrap().pull_n = Some(20.0);
    let running = run(&spec);
    // Both belts are held at 0.3 m/s by stiff speed controllers on one rigid chassis, so how
    // the pull splits between them is the solver's (statically indeterminate); the sums are
    // physical. At 0.3 m/s: 20 N over the 4.5 s after the ramp (27 J), 10 N on average over
    // the 1 s ramp (3 J) and the 0.5 N rolling resistance over 6 s (0.9 J): 30.9 J to the
    // belts; the supply gives that over the gearbox (0.8) and the winding (I^2 R) losses.
    let sum = |f: &dyn Fn(&tracksim::run::DriveSummary) -> f64| -> f64 {
        running
            .summary
            .tracks
            .iter()
            .map(|t| f(t.drive.as_ref().unwrap()))
            .sum()
    };
    let mech = sum(&|d| d.mechanical_energy_j);
    let elec = sum(&|d| d.electrical_energy_j.unwrap());
    println!("running: belts {mech:.2} J, supply {elec:.2} J");
    assert!((mech - 30.9).abs() < 0.1 * 30.9, "{mech}");
    assert!(elec > mech / 0.8, "{mech} {elec}");
}

/// A torque command (`motor_torque_nm`): a current-controlled driver delivers the torque at
/// any speed, so on the 20 deg slope 10 % above the static torque T* the PackBot climbs, the
/// belts below the no-load target, and the drive reports the commanded torque's belt force,
/// T G eta / r per track (2 %). 10 % below T* it stalls (back-driven, the gear's friction
/// helps: T G / (eta r) holds more than the slope takes, issue 23.5); at half T* it slides
/// back, the belt force then T G / (eta r).
#[test]
fn a_torque_command_climbs_above_the_static_torque_and_slides_below_it() {
    let (up, _) = progress(1.0);
    assert!(up > 0.0);
    // T* from the statics, with the simulated mass (13.0 kg) and r = 0.082 m.
    let m = 13.0;
    let t_star = m * G * SLOPE_DEG.to_radians().sin() * 0.082 / (GEAR * EFFICIENCY * 2.0);
    for (frac, motion) in [(0.5, -1), (0.9, 0), (1.1, 1)] {
        let t = frac * t_star;
        let sc = climb_with(1.0, |c| c.motor_torque_nm = Some(PerTrack::All(t)));
        let (up, force) = progress_of(&sc);
        let gear = if motion < 0 {
            1.0 / EFFICIENCY
        } else {
            EFFICIENCY
        };
        let expected = 2.0 * t * GEAR * gear / 0.082;
        println!(
            "torque {frac} T* = {t:.4} N m: {up:.4} m up in 2 s, belt force {force:.2} N (T G eta^+-1 / r x 2 = {expected:.2} N)"
        );
        match motion {
            1 => assert!(up > 0.01, "{frac} T*: {up} m"),
            0 => assert!(up.abs() < 0.002, "{frac} T*: {up} m"),
            _ => assert!(up < -0.01, "{frac} T*: {up} m"),
        }
        if motion != 0 {
            assert!((force - expected).abs() < 0.02 * expected, "force {force}");
        }
    }
}

/// A duty command (`motor_duty`): the DC motor follows its line scaled by the duty, so on
/// flat ground with nothing to pull (0.5 N of rolling resistance) the belts settle at the
/// duty times the no-load belt speed: 0.25 x 600 rad/s x 0.082 m / 50 = 0.246 m/s (2 %).
#[test]
fn a_duty_command_runs_at_the_duty_times_the_no_load_speed() {
    let dir = root().join("scenarios/classic");
    let mut spec: ScenarioSpec = read_toml(&dir.join("packbot_drawbar.toml")).unwrap();
    spec.vehicle.file = Some("../../vehicles/packbot510_motors.toml".into());
    spec.drawbar = None;
    spec.simulation.duration_s = 4.0;
    spec.commands[0].belt_speed_mps = None;
    spec.commands[0].motor_duty = Some(PerTrack::All(0.25));
    let v = load_vehicle(&dir.join(spec.vehicle.file.as_ref().unwrap())).unwrap();
    let sc = tracksim::compile_scenario(&spec, v, &dir).unwrap();
    let r = tracksim::run_scenario(&sc, |_, _| {}).unwrap();
    let last = r.samples.last().unwrap();
    let expected = 0.25 * 600.0 * 0.082 / 50.0;
    println!(
        "duty 0.25: belts {:?} m/s, body {:.4} m/s (expected {expected:.4})",
        last.belt_speed, last.linvel[0]
    );
    for v in &last.belt_speed {
        assert!((v - expected).abs() < 0.02 * expected, "belt {v}");
    }
    assert!((last.linvel[0] - expected).abs() < 0.02 * expected);
    // A duty command on a track without a motor is refused, naming the key.
    let mut bad = spec.clone();
    bad.vehicle.file = Some("../../vehicles/packbot510.toml".into());
    let v = load_vehicle(&dir.join(bad.vehicle.file.as_ref().unwrap())).unwrap();
    let err = tracksim::compile_scenario(&bad, v, &dir).unwrap_err();
    assert!(
        err.iter()
            .any(|i| i.to_string().contains("commands[0].motor_duty")),
        "{err:?}"
    );
}
