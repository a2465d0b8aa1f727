//! One physics step of the PackBot 510 Table II scene (flat ground, 0.3 m/s, dt 1 ms) for each
//! track method, after 0.5 s of driving. `cargo bench -p tracksim`.

use criterion::{Criterion, criterion_group, criterion_main};
use tracksim::Method as TrackMethod;
use tracksim::Scripted;

fn step(c: &mut Criterion) {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let file = root.join("scenarios/packbot_flat.toml");
    let mut group = c.benchmark_group("packbot_flat_step");
    for m in TrackMethod::COMPARED {
        let o = tracksim::Overrides {
            method: Some(*m),
            ..Default::default()
        };
        let sc = tracksim::load_scenario_with(&file, &o).expect("bundled scenario");
        let Ok(mut sim) = Scripted::new(&sc) else {
            continue;
        };
        for _ in 0..500 {
            sim.step().expect("stable");
        }
        group.bench_function(m.name(), |b| b.iter(|| sim.step().expect("stable")));
    }
    group.finish();
}

criterion_group!(benches, step);
criterion_main!(benches);
