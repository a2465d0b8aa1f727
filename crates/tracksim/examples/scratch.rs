use tracksim::model::{compile_scenario, load_vehicle, read_toml};
use tracksim::spec::{BoxSpec, ScenarioSpec};
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mu: f64 = args[1].parse().unwrap();
    let ng: usize = args[2].parse().unwrap();
    let h: f64 = args[3].parse().unwrap();
    let mut spec: ScenarioSpec = read_toml("scenarios/packbot_flat.toml".as_ref()).unwrap();
    spec.terrain.ground.as_mut().unwrap().friction = mu;
    spec.terrain.boxes.push(BoxSpec { centre_m: [1.0, 0.0, h / 2.0], size_m: [1.0, 2.0, h], yaw_deg: 0.0, pitch_deg: 0.0, friction: mu });
    spec.vehicle.grouser_count = Some(ng);
    let v = load_vehicle("vehicles/packbot510.toml".as_ref()).unwrap();
    let sc = compile_scenario(&spec, v).unwrap();
    let mut sim = tracksim::Simulation::new(&sc).unwrap();
    let mut maxpitch: f64 = 0.0;
    for i in 0..8000 {
        sim.step().unwrap();
        maxpitch = maxpitch.max(-sim.body_pose().pitch);
        if i % 1000 == 999 {
            let p = sim.body_pose();
            println!("t {:.3} x {:.4} z {:.4} pitch {:.3}", sim.time(), p.x, p.z, p.pitch.to_degrees());
        }
    }
    let p = sim.body_pose();
    println!("h {h} ng {ng} final x {:.3} z {:.3} climbed {} maxpitch {:.1}", p.x, p.z, p.z > h + 0.05, maxpitch.to_degrees());
}
