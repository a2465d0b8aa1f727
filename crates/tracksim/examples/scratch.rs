use tracksim::model::{compile_scenario, load_vehicle, read_toml};
use tracksim::spec::ScenarioSpec;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let minm: f64 = args[1].parse().unwrap();
    let iters: usize = args[2].parse().unwrap();
    let clus: bool = args[3].parse().unwrap();
    let mut spec: ScenarioSpec = read_toml("scenarios/packbot_flat.toml".as_ref()).unwrap();
    spec.simulation.min_link_mass_kg = minm;
    spec.simulation.solver_iterations = iters;
    spec.simulation.contact_clustering = clus;
    if args.len() > 4 {
        let h: f64 = args[4].parse().unwrap();
        spec.terrain.boxes.push(tracksim::spec::BoxSpec {
            centre_m: [1.5, 0.0, h / 2.0],
            size_m: [2.0, 2.0, h],
            yaw_deg: 0.0,
            pitch_deg: 0.0,
            friction: 0.6,
        });
    }
    let v = load_vehicle("vehicles/packbot510.toml".as_ref()).unwrap();
    let sc = compile_scenario(&spec, v).unwrap();
    let mut sim = tracksim::Simulation::new(&sc).unwrap();
    for _ in 0..1000 {
        sim.step().unwrap();
    }
    sim.reset_max_link_error();
    let (mut zmin, mut zmax) = (1.0f64, 0.0f64);
    let t0 = std::time::Instant::now();
    let x0 = sim.body_pose().x;
    for _ in 0..9000 {
        sim.step().unwrap();
        let z = sim.body_pose().z;
        zmin = zmin.min(z);
        zmax = zmax.max(z);
    }
    let el = t0.elapsed().as_secs_f64();
    let (em, er) = sim.max_link_error();
    println!(
        "final z {:.3} x {:.3} ",
        sim.body_pose().z,
        sim.body_pose().x
    );
    println!(
        "minmass {minm} iters {iters} clustering {clus}: v {:.4} z [{:.5},{:.5}] link err {:.2e} m {:.2e} rad, rtf {:.1}",
        (sim.body_pose().x - x0) / 9.0,
        zmin,
        zmax,
        em,
        er,
        9.0 / el
    );
}
