//! Every bundled scenario (`scenarios/`, `classic/`, `random/` at its file's seed) loads and runs (shortened to at most 2 s simulated) without becoming
//! unstable, and the vehicle stays on its terrain at a plausible height (issue 3).

mod common;

#[test]
fn every_bundled_scenario_runs() {
    let files = common::all_bundled_scenarios();
    assert!(files.len() >= 4, "{files:?}");
    for f in files {
        let mut sc = tracksim::load_scenario(&f).unwrap_or_else(|e| panic!("{e}"));
        sc.duration = sc.duration.min(2.0);
        let r = tracksim::run_scenario(&sc, |_, _| {})
            .unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        let first = r.samples.first().unwrap().pose;
        let last = r.samples.last().unwrap().pose;
        // Never more than 1 m above where it started, nor sunk 0.5 m below it.
        assert!(
            last.z < first.z + 1.0 && last.z > first.z - 0.5,
            "{}: z {} -> {}",
            f.display(),
            first.z,
            last.z
        );
        assert!(
            r.summary.outcome != "failure" || r.summary.outcome_reason.starts_with("timeout"),
            "{}: {}",
            f.display(),
            r.summary.outcome_reason
        );
    }
}
