//! Issue 44: speculative contact manifolds with the ground that cannot act in a step are not
//! solved (`world/speculative_cull.rs`). The cull is exact if the solver would have given every
//! manifold it drops no impulse: the check mode keeps them, records them, and this reads the
//! impulses the solver gave them, over whole runs of the bundled scenarios the cull acts on.

use crate::common::{file_with, load_with};
use tracksim::Runner;

/// What a run in check mode saw: manifolds the cull would have dropped, how many of them the
/// solver pushed, the largest impulse it gave one (N s), and the steps.
struct Checked {
    marked: usize,
    pushed: usize,
    largest: f32,
    steps: u64,
    outcome: String,
}

/// Runs `file` to its end in check mode.
fn checked_run(file: &str) -> Checked {
    let sc = load_with(file, Default::default());
    let mut run = Runner::new(&sc).unwrap().unrecorded();
    run.sim_mut().set_cull_check(true);
    let (mut marked, mut pushed, mut largest) = (0, 0, 0.0f32);
    while !run.finished() {
        run.step().unwrap();
        let marks = run.sim_mut().take_cull_marks();
        let np = &run.sim().world.narrow_phase;
        for mark in marks {
            let pair = np
                .contact_pair(mark.collider1, mark.collider2)
                .expect("a marked pair is in the narrow phase");
            let manifold = pair
                .manifolds()
                .iter()
                .find(|m| m.subshape1 == mark.subshape1 && m.subshape2 == mark.subshape2)
                .expect("the marked manifold");
            marked += 1;
            // The impulses of the points the solver had (a manifold may hold more points
            // than it solves; the others keep what they had).
            let impulse = manifold
                .data
                .solver_contacts
                .iter()
                .map(|c| {
                    let id = (c.contact_id[0] & !rapier3d::geometry::NEW_CONTACT_BIT) as usize;
                    manifold.points[id].data.impulse.abs()
                })
                .fold(0.0f32, f32::max);
            if impulse > 0.0 {
                pushed += 1;
            }
            largest = largest.max(impulse);
        }
    }
    let outcome = run
        .decided()
        .map(|(o, t)| format!("{} at {t:.2} s", o.name()))
        .unwrap_or_else(|| "undecided".into());
    Checked {
        marked,
        pushed,
        largest,
        steps: run.sim().steps(),
        outcome,
    }
}

#[test]
fn every_manifold_the_cull_drops_would_have_carried_no_impulse() {
    // The stairs up and down, the stairs course and a course with ramps (a contact slop:
    // every vehicle contact goes through the hook; the cull is checked on whatever it would
    // act on, whether the file turns it on or not): whole runs.
    for file in [
        "scenarios/packbot_stairs.toml",
        "scenarios/tasks/packbot_stairs_down.toml",
        "scenarios/course_stairs.toml",
        "scenarios/course_figure8_ramps.toml",
    ] {
        let c = checked_run(file);
        println!(
            "{file}: {} steps, {} manifolds the cull would drop ({:.1} a step), {} of them \
             pushed by the solver, largest impulse {:e} N s; {}",
            c.steps,
            c.marked,
            c.marked as f64 / c.steps as f64,
            c.pushed,
            c.largest,
            c.outcome
        );
        // Not vacuous: the cull has work on every one of these (stairs: 27 a step).
        assert!(
            c.marked as f64 > 2.0 * c.steps as f64,
            "{file}: only {} manifolds marked in {} steps",
            c.marked,
            c.steps
        );
        assert_eq!(
            c.pushed, 0,
            "{file}: the solver pushed {} of the manifolds the cull would drop (largest {} N s)",
            c.pushed, c.largest
        );
    }
}

#[test]
fn the_stairs_climb_is_the_same_with_and_without_the_cull() {
    // The cull changes the solver's order of visits, so the two runs differ at f32 rounding
    // and then chaotically, as any two members of the stairs ensemble do (spread 0.29 s over
    // 16 members, docs/ENSEMBLE.md): the climb time must agree within that spread.
    let mut times = Vec::new();
    for cull in [true, false] {
        let sc = file_with(
            "scenarios/packbot_stairs.toml",
            |s| s.simulation.cull_speculative_contacts = cull,
            |_| {},
        );
        let mut run = Runner::new(&sc).unwrap().unrecorded();
        while !run.finished() {
            run.step().unwrap();
        }
        let (outcome, t) = run.decided().cloned().expect("decided");
        println!(
            "cull {cull}: {} at {t:.3} s, {} manifolds culled in {} steps",
            outcome.name(),
            run.sim().culled_manifolds(),
            run.sim().steps()
        );
        assert_eq!(outcome.name(), "success", "cull {cull}");
        if cull {
            assert!(run.sim().culled_manifolds() > run.sim().steps());
        } else {
            assert_eq!(run.sim().culled_manifolds(), 0);
        }
        times.push(t);
    }
    assert!(
        (times[0] - times[1]).abs() <= 0.29,
        "climb times {times:?} differ by more than the ensemble's spread"
    );
}
