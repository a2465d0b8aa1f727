//! Issue 38.4: soil that balances. PackBot 510 on soil: the work of the soil's traction on the
//! vehicle covers the Bekker work of the ruts it leaves, the reported thrust and compaction
//! impulses add up to the vehicle's change of momentum, and the soil's reported normal load
//! carries the weight.

use crate::common::root;
use tracksim::model::{compile_scenario, load_vehicle};
use tracksim::spec::ScenarioSpec;

/// What a window of a run on soil measured.
#[derive(Debug)]
struct Window {
    /// Work of the reported soil thrust on the chassis, `integral F v dt`, J.
    traction_work: f64,
    /// Bekker's work of every cell's deepening over the window (`integral p dz` over its
    /// area, from its depth at the window's start to its depth at the end), J.
    rut_work: f64,
    /// Reported thrust impulse (both tracks), N s.
    thrust_impulse: f64,
    /// Reported compaction impulse (both tracks), N s.
    compaction_impulse: f64,
    /// The vehicle's change of momentum along x, N s.
    momentum_change: f64,
    /// Mean reported soil normal load over the weight, -.
    carried: f64,
    /// Mean load-weighted sinkage, m.
    sinkage: f64,
}

/// PackBot (its masses times `mass`) on soil `preset` with `keys` (TOML lines) at belt speed
/// `speed` m/s, measured over [`t0`, `t1`] s.
fn measure(preset: &str, keys: &str, mass: f64, speed: f64, t0: f64, t1: f64) -> Window {
    let text = format!(
        "description = \"soil balance\"\n[vehicle]\nfile = \"../vehicles/packbot510.toml\"\n\
         [terrain.ground]\n[terrain.ground.soil]\npreset = \"{preset}\"\n{keys}\n\
         [simulation]\nduration_s = {t1}\n[outcome]\nfail_off_terrain = false\n\
         [[commands]]\nt_s = 0.0\nbelt_speed_mps = {speed}\n"
    );
    let spec: ScenarioSpec = tracksim::toml::from_str(&text).unwrap();
    let mut v = load_vehicle(&root().join("vehicles/packbot510.toml")).unwrap();
    v.body.mass *= mass;
    for t in &mut v.tracks {
        t.belt_mass *= mass;
    }
    let sc = compile_scenario(&spec, v, &root().join("scenarios")).unwrap();
    let soil = sc.terrain.soils[sc.terrain.ground_soil.expect("soil")].clone();
    let width = sc.vehicle.tracks[0].width;
    let mut sim = tracksim::Scripted::new(&sc).unwrap();
    let bodies = sim.vehicle_bodies();
    let momentum = |s: &tracksim::Scripted| -> f64 {
        bodies
            .iter()
            .map(|h| {
                let b = &s.world.bodies[*h];
                (b.mass() * b.linvel().x) as f64
            })
            .sum()
    };
    let weight: f64 = bodies
        .iter()
        .map(|h| sim.world.bodies[*h].mass() as f64 * 9.81)
        .sum();
    let dt = sim.dt();
    while sim.time() < t0 - 1e-9 {
        sim.step().unwrap();
    }
    let key =
        |c: &tracksim::world::RutCell| ((c.x_m * 1e4).round() as i64, (c.y_m * 1e4).round() as i64);
    let before: std::collections::HashMap<_, f64> =
        sim.ruts().iter().map(|c| (key(c), c.depth_m)).collect();
    let p0 = momentum(&sim);
    let mut w = Window {
        traction_work: 0.0,
        rut_work: 0.0,
        thrust_impulse: 0.0,
        compaction_impulse: 0.0,
        momentum_change: 0.0,
        carried: 0.0,
        sinkage: 0.0,
    };
    let mut steps = 0usize;
    while sim.time() < t1 - 1e-9 {
        sim.step().unwrap();
        let ts = sim.track_soil();
        let vx = sim.world.bodies[sim.body_handle()].linvel().x as f64;
        let thrust: f64 = ts.iter().map(|t| t.thrust_n).sum();
        w.traction_work += thrust * vx * dt;
        w.thrust_impulse += thrust * dt;
        w.compaction_impulse += ts.iter().map(|t| t.compaction_n).sum::<f64>() * dt;
        w.carried += ts.iter().map(|t| t.normal_n).sum::<f64>() / weight;
        w.sinkage += ts.iter().map(|t| t.sinkage_m).sum::<f64>() / ts.len() as f64;
        steps += 1;
    }
    w.carried /= steps as f64;
    w.sinkage /= steps as f64;
    w.momentum_change = momentum(&sim) - p0;
    for c in sim.ruts() {
        let z0 = before.get(&key(&c)).copied().unwrap_or(0.0);
        w.rut_work += c.cell_m * c.cell_m * soil.compaction_work(z0, c.depth_m, width);
    }
    w
}

#[test]
fn belts_work_covers_compaction_and_forces_balance_at_steady_speed() {
    // The case: snow at 0.3 m/s, steady from 3 s (1.8 m driven over the window).
    // Before: the reported thrust was the solver's last substep times the substeps, 2.4x the
    // compaction it had to carry (thrust x speed 2.36 J against 0.97 J of ruts over 3-6 s),
    // and thrust minus compaction was 4.84 N s with no change of momentum.
    for preset in ["snow", "dry_sand"] {
        let w = measure(preset, "", 1.0, 0.3, 3.0, 9.0);
        println!("{preset}: {w:?}");
        // 5 %: the compaction impulse is the work of the cells pressed in a step over the
        // speed of that step; new cells are entered a 1 cm column at a time, so the impulse
        // comes in lumps the speed answers (measured +3 % on snow, +4 % on sand).
        let ratio = w.traction_work / w.rut_work;
        assert!(
            (ratio - 1.0).abs() < 0.05,
            "{preset}: traction work {:.3} J against the ruts' {:.3} J",
            w.traction_work,
            w.rut_work
        );
        // Newton along x: the soil's thrust and the compaction given back are the only
        // horizontal forces on the vehicle (level ground, no drawbar); 3 % of the thrust.
        let residual = w.thrust_impulse - w.compaction_impulse - w.momentum_change;
        assert!(
            residual.abs() < 0.03 * w.thrust_impulse.abs(),
            "{preset}: thrust {:.3} N s, compaction {:.3} N s, momentum change {:.3} N s",
            w.thrust_impulse,
            w.compaction_impulse,
            w.momentum_change
        );
    }
}

#[test]
fn the_soil_carries_the_weight_on_grouser_tips_and_on_belts() {
    // Belts: a soft soil with n = 0.5 under twice PackBot's weight, still settling 3-6 s
    // after the landing (the reported load was the low-pass filtered one the sinkage follows:
    // 85 % of the weight over 3-6 s). Tips: clayey soil keeps the heavy robot on its grouser
    // tips (sinkage 0 at belt level).
    for (preset, keys, tips) in [
        ("snow", "n = 0.5\nk_phi = 2e4", false),
        ("clayey_soil", "", true),
    ] {
        let w = measure(preset, keys, 2.0, 0.0, 3.0, 6.0);
        println!("{preset}: {w:?}");
        assert_eq!(w.sinkage == 0.0, tips, "{preset}: sinkage {} m", w.sinkage);
        assert!(
            (w.carried - 1.0).abs() < 0.02,
            "{preset}: the soil carries {:.1} % of the weight",
            100.0 * w.carried
        );
    }
}
