//! Probe of the per-track loads (issue 38): for a scenario, every step in [T0, T1] s, the
//! terrain's contact impulses on each track split by where they act (chassis frame about the
//! centre of mass), and the vehicle's momentum balance.
//!
//! `cargo run --release -p tracksim --example loads_probe -- SCENARIO [T0 T1]` (TRACE=1 in the
//! environment: every step's loads, roll and yaw rate).

use rapier3d::prelude::*;
use tracksim::tracks::WORLD_GROUP;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let path = std::path::PathBuf::from(&args[1]);
    let t0: f64 = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(2.0);
    let t1: f64 = args.get(3).and_then(|a| a.parse().ok()).unwrap_or(4.0);
    let sc = tracksim::load_scenario(&path)?;
    let mut sim = tracksim::Scripted::new(&sc)?;
    let body = sim.body_handle();
    let owners = sim.track_owners();
    let vehicle = sim.vehicle_bodies();
    let dt = sc.solver.dt as f32;
    let n = sim.track_names().len();
    // per track: sum F, sum F*y, sum F*x, contacts, manifolds ; whole-vehicle momentum balance
    let mut acc = vec![[0.0f64; 6]; n];
    let mut steps = 0usize;
    let mut pz_prev: Option<f64> = None;
    let mut net_z = 0.0f64;
    let mut mass = 0.0f64;
    for h in &vehicle {
        mass += sim.world.bodies[*h].mass() as f64;
    }
    while sim.time() < t1 {
        sim.step()?;
        let w = &sim.world;
        let pz: f64 = vehicle
            .iter()
            .map(|h| {
                let b = &w.bodies[*h];
                (b.mass() * b.linvel().z) as f64
            })
            .sum();
        if sim.time() < t0 {
            pz_prev = Some(pz);
            continue;
        }
        net_z += (pz - pz_prev.unwrap()) / dt as f64;
        pz_prev = Some(pz);
        steps += 1;
        if std::env::var("TRACE").is_ok() {
            let l = sim.track_loads_last_step();
            let b = &sim.world.bodies[body];
            println!(
                "step {} L {:.2} R {:.2} wx {:+.5} wz {:+.5} vz {:+.6} fL {:.2} fR {:.2}",
                sim.steps(),
                l[0].normal_n,
                l[1].normal_n,
                b.angvel().x,
                b.angvel().z,
                b.linvel().z,
                l[0].friction_traction_n,
                l[1].friction_traction_n
            );
        }
        let cb = &w.bodies[body];
        let com = cb.center_of_mass();
        let inv = cb.position().rotation.inverse();
        for p in w.narrow_phase.contact_pairs() {
            let (c1, c2) = (&w.colliders[p.collider1], &w.colliders[p.collider2]);
            let terrain = |c: &Collider| c.collision_groups().memberships.contains(WORLD_GROUP);
            let owner = |c: &Collider| c.parent().and_then(|b| owners.get(&b).copied());
            let (track, vc, first) = match (owner(c1), owner(c2)) {
                (Some(t), None) if terrain(c2) => (t, c1, true),
                (None, Some(t)) if terrain(c1) => (t, c2, false),
                _ => continue,
            };
            for m in p.solver_manifolds() {
                if m.data.solver_contacts.is_empty() {
                    continue;
                }
                acc[track][4] += 1.0;
                for sc in &m.data.solver_contacts {
                    let id = (sc.contact_id[0] & !NEW_CONTACT_BIT) as usize;
                    let Some(pt) = m.points.get(id) else { continue };
                    let lp = if first { pt.local_p1 } else { pt.local_p2 };
                    let wp = vc.position().transform_point(lp);
                    let r = inv * (wp - com);
                    let f = (pt.data.impulse / dt) as f64;
                    acc[track][0] += f;
                    acc[track][1] += f * r.y as f64;
                    acc[track][2] += f * r.x as f64;
                    acc[track][3] += 1.0;
                }
            }
        }
    }
    let s = steps as f64;
    let mut tot = [0.0f64; 3];
    for (i, a) in acc.iter().enumerate() {
        let f = a[0] / s;
        println!(
            "track {i}: N {:.2} N, centre of load y {:+.4} m x {:+.4} m, moment_x {:+.3} N m, contacts {:.1}, manifolds {:.1}",
            f,
            a[1] / a[0],
            a[2] / a[0],
            a[1] / s,
            a[3] / s,
            a[4] / s
        );
        tot[0] += f;
        tot[1] += a[1] / s;
        tot[2] += a[2] / s;
    }
    println!(
        "sum N {:.2} (m g {:.2}, d(pz)/dt {:+.3}) ; roll moment of loads about COM {:+.3} N m ; pitch moment {:+.3}",
        tot[0],
        mass * 9.81,
        net_z / s,
        tot[1],
        tot[2]
    );
    let b = &sim.world.bodies[body];
    println!(
        "chassis z {:.5} roll-rate {:+.5}",
        b.translation().z,
        b.angvel().x
    );
    Ok(())
}
