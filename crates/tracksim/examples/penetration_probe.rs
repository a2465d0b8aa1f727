//! Where the deepest vehicle-terrain penetration of a Table IV run comes from (issue 11.5):
//! Quince at a step with the paper's 10 mm contact slop; every 10 ms the deepest touching pair
//! is found and classified (chassis, flipper, belt or grouser against the step box or the
//! ground), and the runs deeper than the slop are summarised by part, terrain piece and time.
//!
//! `cargo run --release -p tracksim --example penetration_probe [-- FRONT_DEG STEP_MM]`
//! (default 45 240).

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
    let (front, step_mm) = (arg(1, 45.0), arg(2, 240.0));
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let quince = tracksim::load_vehicle(&root.join("vehicles/quince.toml"))?;
    let sc = tracksim::validate::quince_step_scenario(
        &quince,
        front,
        step_mm / 1000.0,
        true,
        tracksim::validate::TABLE_IV_CONTACT_SLOP_M,
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
    // (part, terrain) -> (samples deeper than the slop, deepest m, first and last time s)
    let mut deep: BTreeMap<(String, String), (usize, f32, f64, f64)> = BTreeMap::new();
    let slop = tracksim::validate::TABLE_IV_CONTACT_SLOP_M as f32;
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
            if depth <= slop {
                continue;
            }
            let piece = match t.shape().as_cuboid() {
                Some(b) if b.half_extents.x >= 9.0 => "ground".to_string(),
                Some(b) => {
                    // Where on the step: its front top edge (within 15 mm), riser or top.
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
            let e = deep.entry(key).or_insert((0, 0.0, sim.time(), sim.time()));
            e.0 += 1;
            e.1 = e.1.max(depth);
            e.3 = sim.time();
        }
        if tracksim::run::check_outcome(&sc.outcome, &sim).is_some() {
            break;
        }
    }
    println!(
        "Quince, front {front} deg, step {step_mm} mm, slop {} mm: pairs deeper than the slop",
        slop * 1000.0
    );
    for ((part, piece), (n, d, t0, t1)) in &deep {
        println!(
            "{part:>12} on {piece:<10}: {n:4} samples, deepest {:.1} mm, t {t0:.2}..{t1:.2} s",
            d * 1000.0
        );
    }
    println!("body at the end: {:?}", sim.body_pose());
    Ok(())
}
