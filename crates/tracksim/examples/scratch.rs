use tracksim::model::{compile_scenario, load_vehicle, read_toml};
use tracksim::spec::ScenarioSpec;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mu: f64 = args[1].parse().unwrap();
    let ng: usize = args[2].parse().unwrap();
    let mut spec: ScenarioSpec = read_toml("scenarios/packbot_flat.toml".as_ref()).unwrap();
    spec.terrain.ground.as_mut().unwrap().friction = mu;
    spec.vehicle.grouser_count = Some(ng);
    let v = load_vehicle("vehicles/packbot510.toml".as_ref()).unwrap();
    let sc = compile_scenario(&spec, v).unwrap();
    let mut sim = tracksim::Simulation::new(&sc).unwrap();
    for i in 0..3000 {
        sim.step().unwrap();
        if i % 250 == 0 {
            let p = sim.body_pose();
            let s = sim.sample();
            println!("t {:.3} x {:.5} y {:.5} z {:.5} pitch {:.5} vx {:.4} c {}", sim.time(), p.x, p.y, p.z, p.pitch, s.linvel[0], s.contacts);
        }
    }
}
