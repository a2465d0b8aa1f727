//! Issue 30: deformable soil. Physics checks of the soil model beside `tracksim validate`'s soil
//! cases (which the validation test runs): the same drive anywhere (translation by whole and by
//! odd metres, through the floating origin and the rut grid's indices), the time step, mirror
//! symmetry, the rut memory's bound on a long drive, and bad soil keys named with their fix.

use crate::common;
use common::root;
use tracksim::model::{load_vehicle, read_toml};
use tracksim::spec::ScenarioSpec;

/// The bundled `scenarios/soil/<name>.toml` with `edit` applied, compiled.
fn soil_file(name: &str, edit: impl FnOnce(&mut ScenarioSpec)) -> tracksim::Scenario {
    let dir = root().join("scenarios/soil");
    let mut spec: ScenarioSpec = read_toml(&dir.join(format!("{name}.toml"))).unwrap();
    edit(&mut spec);
    let vehicle = load_vehicle(&dir.join(spec.vehicle.file.as_ref().unwrap())).unwrap();
    tracksim::compile_scenario(&spec, vehicle, &dir).unwrap_or_else(|e| panic!("{e:?}"))
}

fn run(sc: &tracksim::Scenario) -> tracksim::RunResult {
    tracksim::run_scenario(sc, |_, _| {}).unwrap()
}

/// Mean over the samples from `t0` on of `f`.
fn mean_from(r: &tracksim::RunResult, t0: f64, f: impl Fn(&tracksim::world::Sample) -> f64) -> f64 {
    let s: Vec<f64> = r
        .samples
        .iter()
        .filter(|s| s.t >= t0)
        .map(|s| f(&s))
        .collect();
    s.iter().sum::<f64>() / s.len().max(1) as f64
}

fn sinkage(s: &tracksim::world::Sample) -> f64 {
    s.soil.iter().map(|g| g.sinkage_m).sum::<f64>() / s.soil.len().max(1) as f64
}

/// The same 4 s drive on dry sand started at x = 0, 1000 m and (3000.37, -2000.61) m: speed,
/// height and sinkage agree. Whole-metre offsets put the robot at the same place relative to
/// the rut grid's cells (1 cm, dividing a metre) and to the floating origin: the runs agree to
/// f64 rounding of the offset. The odd offset moves the cell boundaries under the robot by a
/// fraction of a cell: the grid's discretisation may then change the sinkage by a small part of
/// it (the patches average 30-40 cells each), within 3 %.
#[test]
fn a_drive_on_sand_is_the_same_anywhere() {
    let at = |dx: f64, dy: f64| {
        run(&soil_file("packbot_dry_sand", |s| {
            s.vehicle.x_m += dx;
            s.vehicle.y_m += dy;
            s.simulation.duration_s = 4.0;
            s.expect = Default::default();
        }))
    };
    let base = at(0.0, 0.0);
    let (v0, z0, k0) = (
        mean_from(&base, 1.0, |s| s.linvel[0]),
        mean_from(&base, 1.0, |s| s.pose.z),
        mean_from(&base, 1.0, sinkage),
    );
    assert!(k0 > 1e-3 && k0 < 3e-3, "sinkage {k0} m on dry sand");
    for (dx, dy, tol) in [(1000.0, 0.0, 1e-6), (3000.37, -2000.61, 0.03)] {
        let r = at(dx, dy);
        let (v, z, k) = (
            mean_from(&r, 1.0, |s| s.linvel[0]),
            mean_from(&r, 1.0, |s| s.pose.z),
            mean_from(&r, 1.0, sinkage),
        );
        println!("offset ({dx}, {dy}): speed {v:.6} m/s, height {z:.6} m, sinkage {k:.6} m");
        assert!((v - v0).abs() <= 1e-3 + tol * v0, "speed {v} against {v0}");
        assert!(
            (z - z0).abs() <= 1e-4 + tol * 1e-3,
            "height {z} against {z0}"
        );
        assert!(
            (k - k0).abs() <= 1e-6 + tol * k0,
            "sinkage {k} against {k0}"
        );
    }
}

/// Halving the step (1 ms to 0.5 ms) changes the drawbar pull-slip point and the sinkage by
/// little: the soil's filter and the shear displacement are integrated in time, not per step.
#[test]
fn the_soil_converges_with_the_time_step() {
    let at = |dt: f64| {
        let sc = soil_file("packbot_dry_sand", |s| {
            s.simulation.dt_s = dt;
            s.simulation.duration_s = 6.0;
            s.expect = Default::default();
            s.drawbar = Some(tracksim::spec::DrawbarSpec {
                pull_n: Some(100.0),
                stiffness_n_per_m: None,
                hitch_m: [0.0; 3],
                start_s: 0.5,
                ramp_s: 1.5,
            });
        });
        let r = run(&sc);
        let slip = mean_from(&r, 3.0, |s| {
            s.slip.iter().sum::<f64>() / s.slip.len() as f64
        });
        (slip, mean_from(&r, 3.0, sinkage))
    };
    let (s1, k1) = at(0.001);
    let (s2, k2) = at(0.0005);
    println!("1 ms: slip {s1:.4}, sinkage {k1:.5} m; 0.5 ms: slip {s2:.4}, sinkage {k2:.5} m");
    assert!(s1 > 0.03, "a 100 N pull on dry sand needs slip: {s1}");
    assert!(
        (s1 - s2).abs() <= 0.15 * s1,
        "slip {s1} at 1 ms against {s2} at 0.5 ms"
    );
    assert!(
        (k1 - k2).abs() <= 0.1 * k1,
        "sinkage {k1} at 1 ms against {k2} at 0.5 ms"
    );
}

/// A symmetric robot on symmetric soil drives straight, both tracks sink alike, and turning
/// left and right mirror each other.
#[test]
fn mirror_symmetry_on_sand() {
    let turn = |left: f64, right: f64| {
        run(&soil_file("packbot_dry_sand", |s| {
            s.simulation.duration_s = 4.0;
            s.expect = Default::default();
            let mut speeds = toml::Table::new();
            speeds.insert("left".into(), left.into());
            speeds.insert("right".into(), right.into());
            s.commands[0].belt_speed_mps = Some(toml::Value::Table(speeds).try_into().unwrap());
        }))
    };
    let a = turn(0.2, 0.3);
    let b = turn(0.3, 0.2);
    let (pa, pb) = (
        a.samples.last().unwrap().pose,
        b.samples.last().unwrap().pose,
    );
    println!(
        "left turn end ({:.4}, {:.4}) yaw {:.4}; right turn ({:.4}, {:.4}) yaw {:.4}",
        pa.x, pa.y, pa.yaw, pb.x, pb.y, pb.yaw
    );
    assert!(pa.yaw > 0.05, "0.2/0.3 m/s turns left: yaw {}", pa.yaw);
    // Measured: ends 0.6 mm and 3.9 mm apart, yaws 0.008 rad (1 %) apart; on rigid ground the
    // same turns mirror within 2 mm and 0.001 rad. What is left follows the tracks' order in
    // the file (the solver's Gauss-Seidel order): with the right track first the other turn is
    // the wider. (An edge cell taken on one side only made it 9 mm and 0.017 rad.) The bounds
    // are about twice what was measured.
    assert!(
        (pa.x - pb.x).abs() < 0.005 && (pa.y + pb.y).abs() < 0.008,
        "mirrored ends"
    );
    assert!((pa.yaw + pb.yaw).abs() < 0.017, "mirrored yaw");
    let straight = run(&soil_file("packbot_dry_sand", |s| {
        s.simulation.duration_s = 6.0
    }));
    let last = straight.samples.last().unwrap();
    assert!(
        last.pose.y.abs() < 0.02 && last.pose.yaw.abs() < 0.02,
        "straight: {:?}",
        last.pose
    );
    let (l, r) = (
        mean_from(&straight, 2.0, |s| s.soil[0].sinkage_m),
        mean_from(&straight, 2.0, |s| s.soil[1].sinkage_m),
    );
    assert!((l - r).abs() < 0.05 * l, "left sinks {l} m, right {r} m");
}

/// The rut grid keeps at most `max_tiles` tiles: a 20 s drive (6 m, some 20 tiles of 0.64 m)
/// with room for 4 forgets the oldest and drives on unchanged; with the default bound it keeps
/// every tile. The grid's memory is reported in summary.json.
#[test]
fn the_rut_memory_is_bounded() {
    let at = |max_tiles: Option<u32>| {
        run(&soil_file("packbot_dry_sand", |s| {
            s.simulation.duration_s = 20.0;
            s.expect = Default::default();
            s.terrain
                .ground
                .as_mut()
                .unwrap()
                .soil
                .as_mut()
                .unwrap()
                .max_tiles = max_tiles;
        }))
    };
    let small = at(Some(4));
    let full = at(None);
    let (gs, gf) = (
        small.summary.soil.as_ref().unwrap().rut_grid,
        full.summary.soil.as_ref().unwrap().rut_grid,
    );
    println!("bounded: {gs:?}; default: {gf:?}");
    assert!(gs.tiles <= 4 && gs.evicted > 0, "{gs:?}");
    assert_eq!(gs.bytes, gs.tiles * 64 * 64 * 16);
    assert!(
        gf.tiles > 4 && gf.evicted == 0 && gf.bytes <= gf.max_bytes,
        "{gf:?}"
    );
    // The robot does not look back: forgetting old ruts changes nothing ahead of it.
    let (a, b) = (
        small.samples.last().unwrap().pose,
        full.samples.last().unwrap().pose,
    );
    assert!(
        (a.x - b.x).abs() < 1e-9 && (a.z - b.z).abs() < 1e-9,
        "{a:?} against {b:?}"
    );
    assert!(small.ruts.len() < full.ruts.len());
}

/// Bad soil keys are refused with the key and the fix, never a panic.
#[test]
fn bad_soil_keys_are_named() {
    let dir = root().join("scenarios");
    let vehicle = load_vehicle(&dir.join("../vehicles/packbot510.toml")).unwrap();
    for (soil, key, words) in [
        (
            "preset = \"dry_snad\"",
            "terrain.ground.soil.preset",
            "dry_sand",
        ),
        (
            "preset = \"snow\"\ncell_m = 0.03",
            "terrain.ground.soil.cell_m",
            "divide a metre",
        ),
        ("n = 1.0\nk_c = 0.0", "terrain.ground.soil.k_phi", "missing"),
        (
            "preset = \"snow\"\nfriction_angle_deg = 75.0",
            "terrain.ground.soil.friction_angle_deg",
            "between",
        ),
        (
            "preset = \"snow\"\nshear_modulus_m = -0.01",
            "terrain.ground.soil.shear_modulus_m",
            "between",
        ),
    ] {
        let text = format!(
            "[vehicle]\nfile = \"../vehicles/packbot510.toml\"\n[terrain.ground]\n[terrain.ground.soil]\n{soil}\n"
        );
        let spec: ScenarioSpec =
            tracksim::model::parse_toml(&dir.join("test.toml"), &text).unwrap();
        let issues = tracksim::compile_scenario(&spec, vehicle.clone(), &dir).unwrap_err();
        let hit = issues.iter().find(|i| i.key == key);
        assert!(
            hit.is_some_and(|i| i.message.contains(words)),
            "{soil}: expected {key} with \"{words}\", got {issues:?}"
        );
    }
}

/// No energy appears from the soil: standing on snow (the softest preset, 11 mm of sinkage)
/// with the belts held for 10 s, the chassis's mechanical energy after the landing never rises
/// by more than 0.1 mm of height would give (the soil's elastic rebound, `p / K_e`, is of that
/// order), and from 3 s to 10 s it creeps less than 5 mm (the solver's creep, see below). Driven 3 s on dry sand and then held, it stops within a second and does
/// not creep.
#[test]
fn no_energy_appears_from_the_soil() {
    let held = run(&soil_file("packbot_dry_sand", |s| {
        s.simulation.duration_s = 10.0;
        s.expect = Default::default();
        s.commands.clear();
        s.terrain
            .ground
            .as_mut()
            .unwrap()
            .soil
            .as_mut()
            .unwrap()
            .preset = Some("snow".into());
    }));
    // Mechanical energy per kilogram of the chassis, g z + v^2 / 2, J/kg: it may only fall
    // (the soil dissipates) once the landing is over.
    let energy = |s: &tracksim::world::Sample| {
        9.81 * s.pose.z + 0.5 * s.linvel.iter().map(|v| v * v).sum::<f64>()
    };
    let after: Vec<_> = held.samples.iter().filter(|s| s.t >= 1.0).collect();
    let e0 = energy(&after[0]);
    let gain = after
        .iter()
        .map(|s| energy(s) - e0)
        .fold(f64::MIN, f64::max);
    // From 3 s to the end: how far the chassis moved. Measured 2.4 mm in 7 s, sideways (0.34
    // mm/s): the solver's creep of a held robot with fresh contacts every step (rigid ground
    // without contact recycling creeps 0.23 mm/s, world/step.rs; soil contacts cannot be
    // recycled, the hook must see every step). Bound: 5 mm.
    let p3 = after.iter().find(|s| s.t >= 3.0).unwrap().pose;
    let p_end = after.last().unwrap().pose;
    let moved =
        ((p_end.x - p3.x).powi(2) + (p_end.y - p3.y).powi(2) + (p_end.z - p3.z).powi(2)).sqrt();
    let sink = mean_from(&held, 1.0, sinkage);
    println!(
        "held on snow: sinkage {sink:.5} m, energy gain {gain:.2e} J/kg, moved {moved:.2e} m from 3 s to 10 s"
    );
    assert!(sink > 0.005, "snow sinks: {sink} m");
    // 0.1 mm of rise, the elastic rebound's order.
    assert!(gain < 9.81 * 1e-4, "gained {gain} J/kg");
    assert!(moved < 5e-3, "moved {moved} m: {p3:?} to {p_end:?}");

    let stopped = run(&soil_file("packbot_dry_sand", |s| {
        s.simulation.duration_s = 6.0;
        s.expect = Default::default();
        s.commands.push(tracksim::spec::CommandSpec {
            t_s: 3.0,
            belt_speed_mps: Some(tracksim::spec::PerTrack::All(0.0)),
            ..Default::default()
        });
    }));
    let x_at = |t: f64| {
        stopped
            .samples
            .iter()
            .find(|s| s.t >= t - 1e-9)
            .unwrap()
            .pose
            .x
    };
    let creep = (x_at(6.0) - x_at(4.0)).abs();
    println!("stopped on sand: moved {creep:.2e} m from 4 s to 6 s");
    assert!(x_at(3.0) > 0.8, "it drove");
    assert!(creep < 1e-3, "crept {creep} m after stopping");
}
