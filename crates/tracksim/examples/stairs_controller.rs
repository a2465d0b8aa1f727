//! A small closed-loop controller in Rust, on the stepping API: the PackBot with flippers on
//! the bundled staircase, with the file's `[[commands]]` ignored. The controller drives forward
//! at 0.3 m/s with the flippers raised to 35 deg, so their tips reach the first nosing; when
//! the body pitches nose-up past 20 deg it is on the stairs (their slope is 26.6 deg) and the
//! flippers go down to 20 deg to carry the front over the nosings; should the pitch fall below
//! 10 deg again they are raised (hysteresis between the two thresholds). The run stops when
//! the body reaches the landing (the scenario's success height). It prints the pose every
//! 0.5 s and every flipper change, and exits 1 if the flippers never reacted or the robot did
//! not reach the landing. (Holding 35 deg on the stairs stalls the
//! robot at x = 1.88 m; holding 0 deg jams the tips against the first riser.)
//!
//! `cargo run --release -p tracksim --example stairs_controller`

use tracksim::run::check_outcome;
use tracksim::{Controls, Outcome, Simulation};

/// Nose-up pitch that lowers the flippers (on the stairs), rad (REP 103: nose-up is negative
/// pitch).
const ON_STAIRS_ABOVE: f64 = 20.0 * std::f64::consts::PI / 180.0;
/// Nose-up pitch below which they are raised again (level ground), rad.
const LEVEL_BELOW: f64 = 10.0 * std::f64::consts::PI / 180.0;
/// Flipper angles, rad.
const DOWN: f64 = 20.0 * std::f64::consts::PI / 180.0;
const UP: f64 = 35.0 * std::f64::consts::PI / 180.0;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let sc = tracksim::load_scenario(&root.join("scenarios/packbot_stairs.toml"))?;
    let mut sim = Simulation::new(&sc)?;
    let flippers = sim.flipper_names().len();
    let mut raised = true;
    let mut changes = 0;
    let set = |sim: &mut Simulation, angle: f64| {
        let mut c = Controls::twist(&sc.vehicle, 0.3, 0.0);
        for i in 0..flippers {
            c = c.with_flipper(i, angle);
        }
        sim.apply(&c);
    };
    set(&mut sim, UP);
    let mut outcome = None;
    while sim.time() < sc.duration && outcome.is_none() {
        sim.step()?;
        let nose_up = -sim.body_pose().pitch;
        if raised && nose_up > ON_STAIRS_ABOVE || !raised && nose_up < LEVEL_BELOW {
            raised = !raised;
            changes += 1;
            set(&mut sim, if raised { UP } else { DOWN });
            println!(
                "t = {:5.2} s  nose-up {:5.1} deg -> flippers {}",
                sim.time(),
                nose_up.to_degrees(),
                if raised {
                    "up to 35 deg"
                } else {
                    "down to 20 deg"
                }
            );
        }
        if sim.steps() % 500 == 0 {
            let p = sim.body_pose();
            println!(
                "t = {:5.2} s  x {:6.3} z {:6.3} m  pitch {:6.1} deg  flipper {:5.1} deg",
                sim.time(),
                p.x,
                p.z,
                p.pitch.to_degrees(),
                sim.flipper_angle(0).to_degrees()
            );
        }
        outcome = check_outcome(&sc.outcome, &sim);
    }
    let outcome = outcome.unwrap_or(Outcome::Failure("timeout".into()));
    println!(
        "outcome: {} ({}) after {changes} flipper changes",
        outcome.name(),
        outcome.reason()
    );
    if changes == 0 || !matches!(outcome, Outcome::Success(_)) {
        std::process::exit(1);
    }
    Ok(())
}
