//! Validation (issue 6): the paper's Table IV with Quince, the slope limit and skid steering.

use std::path::Path;
use tracksim::model::TrackMethod;

fn root() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[test]
fn explore() {
    let rep =
        tracksim::validate::run_validation(&root(), TrackMethod::Okada2020, |s| eprintln!("{s}"))
            .unwrap();
    eprintln!("{}", rep.to_markdown());
    rep.write(Path::new("/tmp/val")).unwrap();
}

#[test]
#[ignore]
fn debug_case() {
    let a: f64 = std::env::var("A").unwrap().parse().unwrap();
    let h: f64 = std::env::var("H").unwrap().parse().unwrap();
    let g = std::env::var("G").map(|s| s == "1").unwrap_or(true);
    let mut q = tracksim::load_vehicle(&root().join("vehicles/quince.toml")).unwrap();
    if let Ok(m) = std::env::var("BODYCOM") {
        q.body.com.x = m.parse().unwrap();
    }
    let mut sc = tracksim::validate::quince_step_scenario(
        &q,
        a,
        h / 1000.0,
        g,
        TrackMethod::Okada2020,
        &root(),
    )
    .unwrap();
    if let Ok(m) = std::env::var("MINLINK") {
        sc.solver.min_link_mass = m.parse().unwrap();
    }
    if let Ok(m) = std::env::var("ITER") {
        sc.solver.iterations = m.parse().unwrap();
    }
    if let Ok(m) = std::env::var("DUR") {
        sc.duration = m.parse().unwrap();
    }
    let r = tracksim::run_scenario(&sc, |_, _| {}).unwrap();
    for s in r.samples.iter().step_by(50) {
        eprintln!(
            "t {:5.1} x {:.3} z {:.3} pitch {:6.1} belts {:?} flip {:?} c {}",
            s.t,
            s.pose.x,
            s.pose.z,
            s.pose.pitch.to_degrees(),
            s.belt_speed
                .iter()
                .map(|v| (v * 1000.0).round() / 1000.0)
                .collect::<Vec<_>>(),
            s.flipper_angle
                .iter()
                .map(|v| (v.to_degrees() * 10.0).round() / 10.0)
                .collect::<Vec<_>>(),
            s.contacts
        );
    }
    eprintln!("{:?} rtf {:.1}", r.outcome, r.summary.real_time_factor);
}
