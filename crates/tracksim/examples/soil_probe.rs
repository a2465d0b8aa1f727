//! Probe of the soil's balances (issue 38.4): PackBot 510 on a soil, driving at a constant
//! belt speed or parked, measured over a window: the work of the soil's traction against the
//! Bekker work of the ruts made, the momentum balance of the reported forces, the weight the
//! soil carries, the sinkage and the drift.
//!
//! `cargo run --release -p tracksim --example soil_probe -- PRESET SPEED T0 T1 [n=.. k_phi=..
//! k_c=.. mass=FACTOR method=..]`

use tracksim::model::{compile_scenario, load_vehicle};
use tracksim::spec::ScenarioSpec;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let preset = &args[1];
    let speed: f64 = args[2].parse()?;
    let t0: f64 = args[3].parse()?;
    let t1: f64 = args[4].parse()?;
    let mut soil_keys = String::new();
    let mut mass = 1.0;
    let mut method = "okada2020".to_string();
    let (mut iters, mut pgs, mut coulomb) = (None::<usize>, None::<usize>, false);
    for a in &args[5..] {
        let (k, v) = a.split_once('=').expect("key=value");
        match k {
            "mass" => mass = v.parse()?,
            "method" => method = v.to_string(),
            "iters" => iters = Some(v.parse()?),
            "pgs" => pgs = Some(v.parse()?),
            "coulomb" => coulomb = v == "1",
            _ => soil_keys += &format!("{k} = {v}\n"),
        }
    }
    let text = format!(
        r#"
description = "probe"
[vehicle]
file = "../vehicles/packbot510.toml"
[terrain.ground]
[terrain.ground.soil]
preset = "{preset}"
{soil_keys}
[simulation]
duration_s = {t1}
method = "{method}"
[outcome]
fail_off_terrain = false
max_tilt_deg = 89.0
[[commands]]
t_s = 0.0
belt_speed_mps = {speed}
"#
    );
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let spec: ScenarioSpec = toml::from_str(&text)?;
    let mut v = load_vehicle(&root.join("vehicles/packbot510.toml"))?;
    v.body.mass *= mass;
    for t in &mut v.tracks {
        t.belt_mass *= mass;
    }
    let sc = compile_scenario(&spec, v, &root.join("scenarios")).map_err(|e| format!("{e:?}"))?;
    let width = sc.vehicle.tracks[0].width;
    let mut soil = tracksim::terrain::soil::preset(preset).unwrap();
    for l in soil_keys.lines() {
        if let Some((k, v)) = l.split_once(" = ") {
            let v: f64 = v.parse()?;
            match k {
                "n" => soil.n = v,
                "k_phi" => soil.k_phi = v,
                "k_c" => soil.k_c = v,
                _ => {}
            }
        }
    }
    let mut sim = tracksim::Scripted::new(&sc)?;
    if let Some(i) = iters {
        sim.world.integration_parameters.num_solver_iterations = i;
    }
    if let Some(i) = pgs {
        sim.world.integration_parameters.num_internal_pgs_iterations = i;
    }
    if coulomb {
        sim.world.integration_parameters.friction_model = rapier3d::prelude::FrictionModel::Coulomb;
    }
    let substeps = sim.world.integration_parameters.num_solver_iterations as f64;
    let (mut w_motor, mut i_coulomb) = (0.0f64, 0.0f64);
    let (mut w_t, mut w_n) = (0.0f64, 0.0f64);
    let ke = |s: &tracksim::Scripted| -> f64 {
        s.vehicle_bodies()
            .iter()
            .map(|h| {
                let b = &s.world.bodies[*h];
                b.kinetic_energy() as f64 + (b.mass() * 9.81 * b.center_of_mass().z) as f64
            })
            .sum()
    };
    let mut ke0 = 0.0;
    let bodies = sim.vehicle_bodies();
    let m_total: f64 = bodies
        .iter()
        .map(|h| sim.world.bodies[*h].mass() as f64)
        .sum();
    let weight = m_total * 9.81;
    let dt = sim.dt();
    let px = |s: &tracksim::Scripted| -> f64 {
        bodies
            .iter()
            .map(|h| {
                let b = &s.world.bodies[*h];
                (b.mass() * b.linvel().x) as f64
            })
            .sum()
    };
    let (mut p0, mut x0, mut y0) = (0.0, 0.0, 0.0);
    let (mut w_thrust, mut w_thrust_belt, mut w_comp) = (0.0, 0.0, 0.0);
    let (mut i_thrust, mut i_comp, mut i_load_fric, mut i_normal) = (0.0, 0.0, 0.0, 0.0);
    let (mut sink, mut steps, mut dist, mut i_exact) = (0.0, 0usize, 0.0, 0.0f64);
    let ruts_before = Vec::new();
    let mut ruts_at_t0 = ruts_before;
    while sim.time() < t1 - 1e-9 {
        let before = sim.time();
        if (before - t0).abs() < 0.5 * dt {
            p0 = px(&sim);
            let p = sim.body_pose();
            x0 = p.x;
            y0 = p.y;
            ruts_at_t0 = sim.ruts();
            ke0 = ke(&sim);
        }
        sim.step()?;
        if before < t0 - 0.5 * dt {
            continue;
        }
        let ts = sim.track_soil();
        let owners = sim.track_owners();
        let mut exact = 0.0f64;
        for pr in sim.world.narrow_phase.contact_pairs() {
            let (c1, c2) = (
                &sim.world.colliders[pr.collider1],
                &sim.world.colliders[pr.collider2],
            );
            let veh = |c: &rapier3d::prelude::Collider| {
                c.parent()
                    .is_some_and(|b| owners.contains_key(&b) || b == sim.body_handle())
            };
            let sgn = if veh(c1) && !veh(c2) {
                1.0
            } else if veh(c2) && !veh(c1) {
                -1.0
            } else {
                continue;
            };
            for m in pr.manifolds().iter() {
                for pt in &m.points {
                    exact += sgn * (pt.data.impulse * m.data.normal.z) as f64;
                }
            }
        }
        i_exact += -exact;
        // Motor work: each link joint's motor impulse (last substep x substeps) times its
        // target velocity.
        for (_, j) in sim.world.impulse_joints.iter() {
            if !owners.contains_key(&j.body2()) {
                continue;
            }
            for i in [0usize, 3] {
                let m = &j.data.motors[i];
                w_motor += (m.impulse * m.target_vel) as f64 * substeps;
            }
        }
        // Coulomb: the total tangent impulses (deterministic basis from the normal).
        for pr in sim.world.narrow_phase.contact_pairs() {
            let (c1, c2) = (
                &sim.world.colliders[pr.collider1],
                &sim.world.colliders[pr.collider2],
            );
            let veh = |c: &rapier3d::prelude::Collider| {
                c.parent()
                    .is_some_and(|b| owners.contains_key(&b) || b == sim.body_handle())
            };
            let sgn = if veh(c1) && !veh(c2) {
                1.0f32
            } else if veh(c2) && !veh(c1) {
                -1.0
            } else {
                continue;
            };
            for m in pr.manifolds().iter() {
                let d = -m.data.normal;
                let sign = if d.z >= 0.0 { 1.0f32 } else { -1.0 };
                let a = -1.0 / (sign + d.z);
                let b = d.x * d.y * a;
                let t1 = rapier3d::prelude::Vector::new(b, sign + d.y * d.y * a, -d.y);
                let t2 = d.cross(t1);
                let (vc, lp) = if sgn > 0.0 { (c1, true) } else { (c2, false) };
                let rb = &sim.world.bodies[vc.parent().unwrap()];
                for pt in &m.points {
                    let ti = pt.data.tangent_impulse;
                    let w = t1 * ti.x + t2 * ti.y;
                    let nimp = -m.data.normal * pt.data.impulse;
                    i_coulomb += (sgn * (w + nimp)).x as f64;
                    let wp = if lp {
                        vc.position() * pt.local_p1
                    } else {
                        vc.position() * pt.local_p2
                    };
                    let v = rb.velocity_at_point(wp);
                    w_t += (sgn * w).dot(v) as f64;
                    w_n += (sgn * nimp).dot(v) as f64;
                }
            }
        }
        if std::env::var("TRACE").is_ok() && sim.steps() % 250 == 0 {
            let nn: f64 = ts.iter().map(|t| t.normal_n).sum();
            let a: f64 = ts.iter().map(|t| t.contact_area_m2).sum();
            let zb = soil.sinkage(weight / a.max(1e-9), width);
            let zm = ts.iter().map(|t| t.max_sinkage_m).fold(0.0, f64::max);
            let pp = sim.body_pose();
            println!(
                "t {:.2} carried {:.1} % sink {:.3} mm max {:.3} area {:.5} m2 bekker(W/A) {:.3} mm x {:.4} y {:.4} z {:.5} thrust {:.2}",
                sim.time(),
                100.0 * nn / weight,
                1e3 * ts.iter().map(|t| t.sinkage_m).sum::<f64>() / 2.0,
                1e3 * zm,
                a,
                1e3 * zb,
                pp.x,
                pp.y,
                pp.z,
                ts.iter().map(|t| t.thrust_n).sum::<f64>()
            );
        }
        let tl = sim.track_loads_last_step();
        let vx = sim.world.bodies[sim.body_handle()].linvel().x as f64;
        let vb: f64 = (0..ts.len())
            .map(|i| sim.measured_belt_speed(i))
            .sum::<f64>()
            / ts.len() as f64;
        let thrust: f64 = ts.iter().map(|t| t.thrust_n).sum();
        let comp: f64 = ts.iter().map(|t| t.compaction_n).sum();
        let normal: f64 = ts.iter().map(|t| t.normal_n).sum();
        let lf: f64 = tl.iter().map(|t| t.friction_traction_n).sum();
        w_thrust += thrust * vx * dt;
        w_thrust_belt += thrust * vb * dt;
        w_comp += comp * vx * dt;
        i_thrust += thrust * dt;
        i_comp += comp * dt;
        i_load_fric += lf * dt;
        i_normal += normal * dt;
        sink += ts.iter().map(|t| t.sinkage_m).sum::<f64>() / ts.len() as f64;
        dist += vx * dt;
        steps += 1;
    }
    let t = steps as f64 * dt;
    let dp = px(&sim) - p0;
    let p = sim.body_pose();
    // Ruts made in the window: Bekker's work of each cell's deepening over the window.
    let before: std::collections::HashMap<(i64, i64), f64> = ruts_at_t0
        .iter()
        .map(|c| {
            (
                ((c.x_m * 1e4).round() as i64, (c.y_m * 1e4).round() as i64),
                c.depth_m,
            )
        })
        .collect();
    let mut w_ruts = 0.0;
    let mut n_new = 0;
    let mut depth_sum = 0.0;
    for c in sim.ruts() {
        let z0 = before
            .get(&((c.x_m * 1e4).round() as i64, (c.y_m * 1e4).round() as i64))
            .copied()
            .unwrap_or(0.0);
        if z0 == 0.0 {
            n_new += 1;
            depth_sum += c.depth_m;
        }
        w_ruts += c.cell_m * c.cell_m * soil.compaction_work(z0, c.depth_m, width);
    }
    println!(
        "motor work (last substep x {substeps}) {w_motor:.3} J; coulomb total contact impulse x {i_coulomb:.3} N s"
    );
    println!(
        "energy: contact friction work on vehicle {w_t:.3} J, normal work {w_n:.3} J, d(KE+PE) {:.3} J",
        ke(&sim) - ke0
    );
    println!("traction impulse x distance {:.3} J", i_thrust / t * dist);
    println!("window {t0}-{t1} s, mass {m_total:.2} kg, W {weight:.1} N, distance {dist:.4} m");
    println!(
        "work: thrust*v_body {w_thrust:.3} J, thrust*v_belt {w_thrust_belt:.3} J, compaction given back {w_comp:.3} J, ruts (Bekker, {n_new} new cells, mean depth {:.2} mm) {w_ruts:.3} J",
        1e3 * depth_sum / n_new.max(1) as f64
    );
    println!(
        "impulses: thrust {i_thrust:.3} N s (track_loads friction {i_load_fric:.3}), compaction {i_comp:.3} N s, thrust-compaction {:.3}, dp_x {dp:.3} N s",
        i_thrust - i_comp
    );
    println!(
        "mean thrust {:.2} N, compaction {:.2} N, normal {:.2} N = {:.1} % of W, sinkage {:.3} mm",
        i_thrust / t,
        i_comp / t,
        i_normal / t,
        100.0 * i_normal / t / weight,
        1e3 * sink / steps as f64
    );
    println!(
        "exact vertical contact impulse: {:.2} % of W",
        100.0 * i_exact / t / weight
    );
    println!(
        "drift: dx {:.3} mm dy {:.3} mm",
        1e3 * (p.x - x0),
        1e3 * (p.y - y0)
    );
    Ok(())
}
