//! A Table IV case with compliant grousers and belts (issue 11.6): Quince at a step, rigid
//! terrain, no slop, the tracks' rubber of Young's modulus `E_MPA` (grouser and belt
//! stiffness follow from it, `tracksim::validate::rubber_compliance_with`). Prints the springs,
//! the outcome, and every 10 ms the deepest vehicle-terrain penetration by part and terrain
//! piece (step riser, edge, top, ground).
//!
//! `cargo run --release -p tracksim --example compliance_probe [-- FRONT_DEG STEP_MM E_MPA]`
//! (default 0 120 5).

use rapier3d::prelude::*;
use std::collections::BTreeMap;
use tracksim::Method;
use tracksim::tracks::WORLD_GROUP;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let arg = |i: usize, d: f64| {
        std::env::args()
            .nth(i)
            .and_then(|a| a.parse().ok())
            .unwrap_or(d)
    };
    let (front, step_mm, e_mpa) = (arg(1, 0.0), arg(2, 120.0), arg(3, 5.0));
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let quince = tracksim::load_vehicle(&root.join("vehicles/quince.toml"))?;
    let v = tracksim::validate::with_rubber_of(&quince, e_mpa * 1e6);
    for t in &v.tracks {
        println!("{:>16}: {:?}", t.name, t.compliance);
    }
    let sc = tracksim::validate::quince_step_scenario(
        &v,
        front,
        step_mm / 1000.0,
        true,
        0.0,
        Method::Okada2020,
        &root,
    )?;
    let mut sim = tracksim::Scripted::new(&sc)?;
    let body = sim.body_handle();
    let bodies = sim.vehicle_bodies();
    let flippers = sim.flipper_names().len();
    let part = |h: RigidBodyHandle, shape: &dyn rapier3d::parry::shape::Shape| -> String {
        if h == body {
            "chassis".into()
        } else if bodies[1..=flippers].contains(&h) {
            "flipper arm".into()
        } else if shape.as_convex_polyhedron().is_some() {
            "grouser".into()
        } else {
            "belt".into()
        }
    };
    // (part, terrain) -> (samples deeper than 1 mm, deepest m, largest normal force N)
    let mut deep: BTreeMap<(String, String), (usize, f32, f32)> = BTreeMap::new();
    let dt = sc.solver.dt as f32;
    let mut outcome = None;
    while sim.time() < sc.duration {
        sim.step()?;
        if sim.steps() % 10 != 0 {
            continue;
        }
        let w = &sim.world;
        for p in w.narrow_phase.contact_pairs() {
            if !p.has_any_active_contact() {
                continue;
            }
            let (c1, c2) = (&w.colliders[p.collider1], &w.colliders[p.collider2]);
            let terrain = |c: &Collider| c.collision_groups().memberships.contains(WORLD_GROUP);
            let (t, v) = match (terrain(c1), terrain(c2)) {
                (true, false) => (c1, c2),
                (false, true) => (c2, c1),
                _ => continue,
            };
            let force: f32 = p
                .manifolds()
                .iter()
                .flat_map(|m| m.points.iter().map(|q| q.data.impulse))
                .sum::<f32>()
                / dt;
            let Ok(Some(c)) = rapier3d::parry::query::contact(
                v.position(),
                v.shape(),
                t.position(),
                t.shape(),
                0.0,
            ) else {
                continue;
            };
            let depth = -c.dist;
            if depth <= 0.001 {
                continue;
            }
            let piece = match t.shape().as_cuboid() {
                Some(b) if b.half_extents.x >= 9.0 => "ground".to_string(),
                Some(b) => {
                    let l = t.position().inverse_transform_point(c.point2);
                    let h = b.half_extents;
                    let (dx, dz) = (l.x + h.x, h.z - l.z);
                    if dx.abs() < 0.015 && dz.abs() < 0.015 {
                        "step edge".to_string()
                    } else if dx.abs() < 0.015 {
                        "step riser".to_string()
                    } else {
                        "step top".to_string()
                    }
                }
                None => "other".to_string(),
            };
            let key = (part(v.parent().unwrap(), v.shape()), piece);
            let e = deep.entry(key).or_insert((0, 0.0, 0.0));
            e.0 += 1;
            e.1 = e.1.max(depth);
            e.2 = e.2.max(force);
        }
        if let Some(o) = tracksim::run::check_outcome(&sc.outcome, &sim) {
            outcome = Some(o);
            break;
        }
    }
    println!("Quince, front {front} deg, step {step_mm} mm, E {e_mpa} MPa, no slop");
    for ((part, piece), (n, d, fmax)) in &deep {
        println!(
            "{part:>12} on {piece:<10}: {n:5} samples > 1 mm, deepest {:.1} mm, largest force {fmax:.0} N",
            d * 1000.0
        );
    }
    println!(
        "t {:.1} s, outcome {outcome:?}, body at the end: {:?}",
        sim.time(),
        sim.body_pose()
    );
    Ok(())
}
