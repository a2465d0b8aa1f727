//! Issue 39: one session skeleton. A control source run through `run::run_session` is logged
//! in one `CommandLog`, written by one writer, and `run --commands` replays it byte for byte;
//! the end rule is one (interrupt, then the source's word, then `max_time`).

use crate::common::root;
use std::sync::atomic::{AtomicBool, Ordering};
use tracksim::run::{ControlSource, End, LogHeader, Runner, SessionLimits, run_session};
use tracksim::spec::{CommandSpec, PerTrack};

/// Drives by a script of (time s, command) entries keyed to the runner's clock, resets once
/// at `reset_at` s, and ends itself at `end_at` s.
struct Script {
    entries: Vec<(f64, CommandSpec)>,
    next: usize,
    reset_at: Option<f64>,
    reset_pending: bool,
    end_at: Option<f64>,
    samples_seen: usize,
    steps_seen: usize,
    clock: f64,
}

impl Script {
    fn new(entries: Vec<(f64, CommandSpec)>) -> Self {
        Script {
            entries,
            next: 0,
            reset_at: None,
            reset_pending: false,
            end_at: None,
            samples_seen: 0,
            steps_seen: 0,
            clock: 0.0,
        }
    }
}

impl ControlSource for Script {
    fn end(&mut self, runner: &Runner) -> Option<End> {
        self.clock = runner.time();
        self.end_at
            .filter(|e| runner.time() >= *e)
            .map(|_| End::ByOperator)
    }

    fn reset(&mut self) -> bool {
        if self.reset_at.is_some_and(|r| self.clock >= r) {
            self.reset_at = None;
            self.reset_pending = true;
            self.next = 0;
            return true;
        }
        false
    }

    fn controls(&mut self, runner: &Runner) -> Option<CommandSpec> {
        let t = runner.time();
        if self.reset_pending {
            self.reset_pending = false;
            assert_eq!(t, 0.0, "a reset starts the clock again");
        }
        let (at, c) = self.entries.get(self.next)?;
        if t + 1e-9 < *at {
            return None;
        }
        self.next += 1;
        Some(CommandSpec {
            t_s: t,
            ..c.clone()
        })
    }

    fn after_step(&mut self, _runner: &Runner) {
        self.steps_seen += 1;
    }

    fn after_sample(&mut self, _runner: &Runner) {
        self.samples_seen += 1;
    }
}

fn twist(v: f64, w: f64) -> CommandSpec {
    CommandSpec {
        forward_mps: Some(v),
        yaw_rate_rad_s: Some(w),
        ..CommandSpec::default()
    }
}

fn runner(file: &std::path::Path) -> (tracksim::Scenario, Runner) {
    let sc = tracksim::load_scenario(file).unwrap();
    let r = Runner::new(&sc).unwrap().without_commands().unbounded();
    (sc, r)
}

#[test]
fn a_session_log_replays_byte_for_byte_after_a_reset() {
    let file = root().join("scenarios/tasks/packbot_flat.toml");
    let (sc, r) = runner(&file);
    assert!(!sc.vehicle.flippers.is_empty(), "a vehicle with flippers");
    let flip = |deg: f64| {
        let mut c = CommandSpec::default();
        for f in &sc.vehicle.flippers {
            c.flipper_angle_deg.insert(f.name.clone(), deg);
        }
        c
    };
    let belts = CommandSpec {
        belt_speed_mps: Some(PerTrack::ByName(
            sc.vehicle
                .tracks
                .iter()
                .enumerate()
                .map(|(i, t)| (t.name.clone(), 0.2 + 0.05 * i as f64))
                .collect(),
        )),
        ..CommandSpec::default()
    };
    let mut script = Script::new(vec![
        (0.0, twist(0.3, 0.0)),
        (0.25, twist(0.3, 0.0)), // the same controls: not logged again
        (0.5, flip(1.0 / 3.0)),
        (1.0, belts),
        (1.5, twist(0.2, 0.4)),
    ]);
    script.reset_at = Some(0.7);
    let limits = SessionLimits {
        max_time: Some(2.0),
        interrupt: None,
    };
    let run = run_session(r, &mut script, limits).unwrap();
    assert_eq!(run.end, End::Reached);
    // After the reset at 0.7 s the script starts again: 5 entries, one repeated.
    assert_eq!(run.log.len(), 4, "{:?}", run.log);
    assert_eq!(run.log.commands()[0].t_s, 0.0);
    let result = run.runner.finish(run.end);
    let end_t = result.samples.last().unwrap().t;
    assert!((end_t - 2.0).abs() < 1e-9, "ended at {end_t} s");
    assert_eq!(
        script.samples_seen,
        script.steps_seen / 10,
        "a sample every 10 steps"
    );

    let dir = std::env::temp_dir().join(format!("tracksim-issue39-session-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let header = LogHeader {
        what: "A scripted session",
        notes: &[],
        seed: None,
    };
    let path = run.log.write(header, &file, &dir, end_t).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        text.contains(&format!("--commands {}", path.display())),
        "{text}"
    );
    let replay = tracksim::load_scenario_with(
        &file,
        &tracksim::Overrides {
            commands: Some(path),
            duration_s: Some(end_t),
            ..Default::default()
        },
    )
    .unwrap();
    let r = tracksim::run_scenario(&replay, |_, _| {}).unwrap();
    assert_eq!(
        tracksim::output::trajectory_csv(&r),
        tracksim::output::trajectory_csv(&result),
        "the replay is the session"
    );
    // The script's controls reached the physics: the belts ran at their speeds (within 2 %:
    // a loaded belt's measured speed) and the twist turned the robot left.
    let at = |t: f64| {
        result
            .samples
            .iter()
            .find(|s| (s.t - t).abs() < 1e-6)
            .unwrap()
    };
    for (got, want) in at(1.4).belt_speed.iter().zip([0.2, 0.25]) {
        assert!(
            (got - want).abs() < 0.02 * want,
            "belt {got} m/s, commanded {want}"
        );
    }
    let turned = at(2.0).pose.yaw - at(1.5).pose.yaw;
    assert!(
        turned > 0.05,
        "yaw turned {turned} rad in 0.5 s at 0.4 rad/s"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_end_rule_is_interrupt_then_source_then_max_time() {
    let file = root().join("scenarios/packbot_flat.toml");
    static FLAG: AtomicBool = AtomicBool::new(false);
    // The source ends at 0.3 s, before max_time.
    let (_, r) = runner(&file);
    let mut s = Script::new(vec![(0.0, twist(0.3, 0.0))]);
    s.end_at = Some(0.3);
    let limits = SessionLimits {
        max_time: Some(0.3),
        interrupt: Some(&FLAG),
    };
    let run = run_session(r, &mut s, limits).unwrap();
    assert_eq!(run.end, End::ByOperator, "the source's word beats max_time");
    assert!((run.runner.time() - 0.3).abs() < 1e-9);
    // max_time alone: reached within half a step.
    let (_, r) = runner(&file);
    let mut s = Script::new(vec![]);
    let limits = SessionLimits {
        max_time: Some(0.1004),
        interrupt: Some(&FLAG),
    };
    let run = run_session(r, &mut s, limits).unwrap();
    assert_eq!(run.end, End::Reached);
    assert!(
        (run.runner.time() - 0.1).abs() < 1e-9,
        "{}",
        run.runner.time()
    );
    // An interrupt beats both.
    FLAG.store(true, Ordering::SeqCst);
    let (_, r) = runner(&file);
    let mut s = Script::new(vec![]);
    s.end_at = Some(0.0);
    let run = run_session(r, &mut s, limits).unwrap();
    assert_eq!(run.end, End::Interrupted);
    assert_eq!(run.runner.sim().steps(), 0);
    FLAG.store(false, Ordering::SeqCst);
}

#[test]
fn a_control_the_scenario_refuses_stops_the_session_with_its_key() {
    let file = root().join("scenarios/packbot_flat.toml");
    let (_, r) = runner(&file);
    let mut bad = CommandSpec::default();
    bad.flipper_angle_deg.insert("no_such_flipper".into(), 10.0);
    let mut s = Script::new(vec![(0.0, bad)]);
    let limits = SessionLimits {
        max_time: Some(0.1),
        interrupt: None,
    };
    let e = run_session(r, &mut s, limits).err().expect("refused");
    let text = e.to_string();
    assert!(
        text.contains("session control at t = 0 s") && text.contains("no_such_flipper"),
        "{text}"
    );
}
