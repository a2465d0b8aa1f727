//! Shared helpers: the bundled PackBot scenario, modified in code.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use tracksim::Scripted;
use tracksim::compile_scenario;
use tracksim::model::{Scenario, load_vehicle, read_toml};
use tracksim::spec::ScenarioSpec;

/// Repository root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The bundled flat-ground PackBot scenario, with `edit` applied to its spec and `vehicle_edit`
/// to the compiled vehicle.
pub fn packbot(
    edit: impl FnOnce(&mut ScenarioSpec),
    vehicle_edit: impl FnOnce(&mut tracksim::VehicleModel),
) -> Scenario {
    with_vehicle("vehicles/packbot510.toml", edit, vehicle_edit)
}

/// The bundled flat-ground scenario with another vehicle file (relative to the repository).
pub fn with_vehicle(
    vehicle_file: &str,
    edit: impl FnOnce(&mut ScenarioSpec),
    vehicle_edit: impl FnOnce(&mut tracksim::VehicleModel),
) -> Scenario {
    let path = root().join("scenarios/packbot_flat.toml");
    let mut spec: ScenarioSpec = read_toml(&path).expect("bundled scenario parses");
    edit(&mut spec);
    let mut vehicle = load_vehicle(&root().join(vehicle_file)).expect("vehicle");
    vehicle_edit(&mut vehicle);
    compile_scenario(&spec, vehicle, &root().join("scenarios")).expect("scenario compiles")
}

/// The scenario file `file` (relative to the repository) loaded with `overrides` written into
/// its keys: a compiled scenario is not changed, a test varies the file.
pub fn load_with(file: &str, overrides: tracksim::Overrides) -> Scenario {
    tracksim::load_scenario_with(&root().join(file), &overrides).unwrap_or_else(|e| panic!("{e}"))
}

/// A session's replay, as `tracksim run FILE --commands DIR/commands.toml --duration T` loads
/// it: `file` with the commands the session in `dir` recorded, for `duration_s` s.
pub fn session_replay(file: &Path, dir: &Path, duration_s: f64) -> Scenario {
    tracksim::load_scenario_with(
        file,
        &tracksim::Overrides {
            commands: Some(dir.join("commands.toml")),
            duration_s: Some(duration_s),
            ..Default::default()
        },
    )
    .unwrap()
}

/// The scenario file `file` (relative to the repository) with its `simulation.duration_s` set
/// to `duration` s.
pub fn load_for(file: &str, duration: f64) -> Scenario {
    load_with(
        file,
        tracksim::Overrides {
            duration_s: Some(duration),
            ..Default::default()
        },
    )
}

/// The one-robot scenario file `file` (relative to the repository, its vehicle a
/// `vehicle.file`) compiled with `edit` applied to its spec and `vehicle_edit` to its vehicle.
pub fn file_with(
    file: &str,
    edit: impl FnOnce(&mut ScenarioSpec),
    vehicle_edit: impl FnOnce(&mut tracksim::VehicleModel),
) -> Scenario {
    let path = root().join(file);
    let mut spec: ScenarioSpec = read_toml(&path).expect("scenario parses");
    edit(&mut spec);
    let dir = path.parent().expect("a folder");
    let vehicle_file = spec.vehicle.file.as_ref().expect("a vehicle file");
    let mut vehicle = load_vehicle(&dir.join(vehicle_file)).expect("vehicle");
    vehicle_edit(&mut vehicle);
    compile_scenario(&spec, vehicle, dir).expect("scenario compiles")
}

/// A step for the PackBot tests: a box `depth` m long (x), 2 m wide, `h` m high, friction 0.6,
/// its edge at x = `edge_x` m.
pub fn step_box(edge_x: f64, depth: f64, h: f64) -> tracksim::spec::BoxSpec {
    tracksim::spec::BoxSpec {
        centre_m: [edge_x + depth / 2.0, 0.0, h / 2.0],
        size_m: [depth, 2.0, h],
        yaw_deg: 0.0,
        pitch_deg: 0.0,
        friction: 0.6,
        soil: None,
        color: None,
    }
}

/// Runs `sim` until time `t`, s.
pub fn run_until(sim: &mut Scripted, t: f64) {
    while sim.time() < t - 1e-9 {
        sim.step().expect("stable");
    }
}

/// Body position (x, y, z), m.
pub fn pos(sim: &Scripted) -> (f64, f64, f64) {
    let p = sim.body_pose();
    (p.x, p.y, p.z)
}

/// Every bundled scenario file, sorted.
pub fn bundled_scenarios() -> Vec<PathBuf> {
    let mut files: Vec<_> = std::fs::read_dir(root().join("scenarios"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
}

/// The task suite's scenario files (`scenarios/tasks/`, docs/TASKS.md), sorted.
#[allow(dead_code)]
pub fn task_scenarios() -> Vec<PathBuf> {
    scenarios_in("tasks")
}

/// The deformable-soil scenario files (`scenarios/soil/`, docs/SOIL.md), sorted.
#[allow(dead_code)]
pub fn soil_scenarios() -> Vec<PathBuf> {
    scenarios_in("soil")
}

/// The scenario files of `scenarios/<dir>/`, sorted.
fn scenarios_in(dir: &str) -> Vec<PathBuf> {
    let mut files: Vec<_> = std::fs::read_dir(root().join("scenarios").join(dir))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
}

/// Every bundled scenario file: `scenarios/` and its `classic/`, `random/`, `tasks/`, `soil/`
/// and `team/` folders.
pub fn all_bundled_scenarios() -> Vec<PathBuf> {
    let mut files = bundled_scenarios();
    for dir in ["classic", "random", "tasks", "soil", "team"] {
        let mut more: Vec<_> = std::fs::read_dir(root().join("scenarios").join(dir))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
            .collect();
        more.sort();
        files.extend(more);
    }
    files
}

/// The scenario files with several robots (`scenarios/team/`, issue 40), sorted.
#[allow(dead_code)]
pub fn team_scenarios() -> Vec<PathBuf> {
    scenarios_in("team")
}

/// The contact impulses on `bodies` from every collider not on them over the last step, world
/// frame, N s: (friction, normal), from Rapier's Coulomb writeback (the total over the
/// substeps; the world must use `FrictionModel::Coulomb`). `from` picks the other colliders
/// counted (e.g. the terrain's).
pub fn contact_impulses(
    sim: &tracksim::Simulation,
    bodies: &[rapier3d::prelude::RigidBodyHandle],
    from: impl Fn(&rapier3d::prelude::Collider) -> bool,
) -> (rapier3d::prelude::Vector, rapier3d::prelude::Vector) {
    use rapier3d::prelude::*;
    let (mut friction, mut normal) = (Vector::ZERO, Vector::ZERO);
    let on = |c: &Collider| c.parent().is_some_and(|b| bodies.contains(&b));
    for pair in sim.world.narrow_phase.contact_pairs() {
        let (c1, c2) = (
            &sim.world.colliders[pair.collider1],
            &sim.world.colliders[pair.collider2],
        );
        // The impulses are written on collider 1.
        let sign = match (on(c1), on(c2)) {
            (true, false) if from(c2) => 1.0f32,
            (false, true) if from(c1) => -1.0,
            _ => continue,
        };
        for m in pair.solver_manifolds() {
            // Rapier's tangent basis (`compute_tangent_contact_directions`): Pixar's
            // orthonormal vector of the force direction, then their cross product.
            let d = -m.data.normal;
            let s = if d.z >= 0.0 { 1.0f32 } else { -1.0 };
            let a = -1.0 / (s + d.z);
            let b = d.x * d.y * a;
            let t1 = Vector::new(b, s + d.y * d.y * a, -d.y);
            let t2 = d.cross(t1);
            // The points the solver saw (a manifold's other points keep stale impulses).
            for sc in &m.data.solver_contacts {
                let Some(p) = m.points.get((sc.contact_id[0] & !NEW_CONTACT_BIT) as usize) else {
                    continue;
                };
                let t = p.data.tangent_impulse;
                friction += sign * (t1 * t.x + t2 * t.y);
                normal += sign * -m.data.normal * p.data.impulse;
            }
        }
    }
    (friction, normal)
}

/// The 12 triangles of the axis-aligned box [lo, hi] (m), each counter-clockwise seen from
/// outside: for the tests' STL files.
pub fn box_triangles(lo: glam::DVec3, hi: glam::DVec3) -> Vec<[glam::DVec3; 3]> {
    let c = |i: usize| {
        glam::DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    };
    [
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ]
    .iter()
    .map(|f| f.map(c))
    .collect()
}

/// Every message of the MCAP file `bytes` by topic: (log time ns, its bytes), in log order.
pub fn mcap_messages(bytes: &[u8]) -> std::collections::BTreeMap<String, Vec<(u64, Vec<u8>)>> {
    let mut out: std::collections::BTreeMap<String, Vec<(u64, Vec<u8>)>> = Default::default();
    for m in mcap::MessageStream::new(bytes).expect("mcap") {
        let m = m.expect("message");
        out.entry(m.channel.topic.clone())
            .or_default()
            .push((m.log_time, m.data.to_vec()));
    }
    out
}

/// The CDR messages `msgs` (as [`mcap_messages`] gives them) decoded as `T`.
pub fn decoded<T: tracksim::rosmsg::RosMessage>(msgs: &[(u64, Vec<u8>)]) -> Vec<T> {
    msgs.iter()
        .map(|(_, d)| tracksim::rosmsg::decode::<T>(d).expect("decodes"))
        .collect()
}

/// A `[[vehicles]]` entry of a team file: a PackBot 510 named `name` at (0, `y`) m heading +x,
/// with the `[[vehicles.commands]]` entries `commands` (each a TOML body).
pub fn team_robot(name: &str, y: f64, commands: &[&str]) -> String {
    let mut text = format!(
        "[[vehicles]]\nname = \"{name}\"\n[vehicles.vehicle]\nfile = \"{}\"\nx_m = 0.0\n\
         y_m = {y}\n",
        root().join("vehicles/packbot510.toml").display()
    );
    for c in commands {
        text.push_str(&format!("[[vehicles.commands]]\n{c}\n"));
    }
    text
}
