//! Issue 28.3, courses: gates passed in order, repetition times at the crossing samples, gate
//! lines crossed only forwards, a marked obstacle touched once per episode by a query that
//! leaves the trajectory byte-identical, the time limit, tip-over and reset faults, a completed
//! course ending a run with success; and `tracksim sessions`' table sorted and as CSV.
//!
//! One straight PackBot drive on flat ground (0.3 m/s along +x) is scored by several trackers
//! at once (`CourseTracker::update` at every sample, as the `Runner` does), so most rules cost
//! one short run.

use crate::common;

use tracksim::model::{CourseModel, Scenario, load_vehicle};
use tracksim::run::{CourseScore, CourseTracker, End, Runner};
use tracksim::spec::ScenarioSpec;

/// A PackBot scenario on flat ground driving straight at 0.3 m/s for `duration` s, with the
/// TOML `extra` (a `[course]`, `[outcome]`, ...) added.
fn scenario(duration: f64, extra: &str) -> Scenario {
    scenario_with(duration, extra, |_| {})
}

/// [`scenario`] with `edit` applied to its spec.
fn scenario_with(duration: f64, extra: &str, edit: impl FnOnce(&mut ScenarioSpec)) -> Scenario {
    let text = format!(
        "[vehicle]\nfile = \"x\"\n[terrain.ground]\nfriction = 0.6\n[simulation]\n\
         duration_s = {duration}\n[[commands]]\nt_s = 0.0\nbelt_speed_mps = 0.3\n{extra}"
    );
    let mut spec: ScenarioSpec = tracksim::toml::from_str(&text).expect("scenario parses");
    edit(&mut spec);
    let vehicle = load_vehicle(&common::root().join("vehicles/packbot510.toml")).unwrap();
    tracksim::compile_scenario(&spec, vehicle, &common::root().join("scenarios"))
        .expect("scenario compiles")
}

/// The course of `toml` (a `[course]` table).
fn course(toml: &str) -> CourseModel {
    scenario(1.0, toml).course.clone().expect("a course")
}

/// Drives the straight run, scoring every tracker at every sample; returns the samples'
/// (t, x) and the scores.
fn drive(courses: &[CourseModel], duration: f64) -> (Vec<(f64, f64)>, Vec<CourseScore>) {
    let sc = scenario(duration, "");
    let mut runner = Runner::new(&sc).unwrap().without_sensors();
    let tilt = sc.outcome.max_tilt;
    let mut trackers: Vec<CourseTracker> = courses
        .iter()
        .map(|c| CourseTracker::new(c, tilt))
        .collect();
    let mut xs = Vec::new();
    while !runner.finished() {
        runner.step().unwrap();
        if runner.at_sample() {
            let t = runner.time();
            xs.push((t, runner.sim().body_pose().x));
            for tr in &mut trackers {
                tr.update(runner.sim(), t);
            }
        }
    }
    (xs, trackers.iter().map(CourseTracker::score).collect())
}

/// The first sample time at which x reaches `x`, s.
fn first_at(xs: &[(f64, f64)], x: f64) -> f64 {
    xs.iter().find(|(_, v)| *v >= x).expect("reached").0
}

fn waypoint(x: f64, y: f64, r: f64) -> String {
    format!("[[course.gates]]\nx_m = {x:?}\ny_m = {y:?}\nradius_m = {r:?}\n")
}

fn line(x: f64, yaw_deg: f64) -> String {
    format!("[[course.gates]]\nx_m = {x:?}\ny_m = 0.0\nwidth_m = 1.2\nyaw_deg = {yaw_deg:?}\n")
}

#[test]
fn gates_in_order_lines_forwards_touches_once_time_limit() {
    let start_x = scenario(0.1, "").start_xy.0;
    let ordered = course(&format!(
        "[course]\nname = \"ordered\"\n{}{}{}",
        waypoint(start_x + 0.3, 0.0, 0.05),
        line(start_x + 0.6, 0.0),
        waypoint(start_x + 0.9, 0.0, 0.05)
    ));
    // Gate 1 lies 1 m to the side: the waypoint after it is reached but not counted.
    let skipped = course(&format!(
        "[course]\nname = \"skipped\"\n{}{}{}",
        waypoint(start_x + 0.3, 0.0, 0.05),
        waypoint(start_x + 0.6, 1.0, 0.3),
        waypoint(start_x + 0.9, 0.0, 0.05)
    ));
    let backwards = course(&format!(
        "[course]\nname = \"backwards\"\n{}",
        line(start_x + 0.6, 180.0)
    ));
    let limited = course(&format!(
        "[course]\nname = \"limited\"\ntime_limit_s = 1.0\n{}",
        waypoint(start_x + 5.0, 0.0, 0.5)
    ));
    // A marked volume across the path (the PackBot's chassis is about 0.09-0.18 m high)
    // that the robot drives through, and one off the path.
    let marked = course(&format!(
        "[course]\nname = \"marked\"\n{}\
         [[course.obstacles]]\nname = \"tape\"\nx_m = {:?}\ny_m = 0.0\nz_m = 0.1\n\
         half_m = [0.02, 0.6, 0.1]\n\
         [[course.obstacles]]\nx_m = {:?}\ny_m = 2.0\nz_m = 0.1\nhalf_m = [0.1, 0.1, 0.1]\n\
         [course.penalty_s]\ntouch = 5.0",
        waypoint(start_x + 5.0, 0.0, 0.5),
        start_x + 0.7,
        start_x + 0.7
    ));
    let (xs, s) = drive(&[ordered, skipped, backwards, limited, marked], 4.0);
    let travelled = xs.last().unwrap().1 - start_x;
    assert!(travelled > 1.0, "drove {travelled} m");

    // In order: one repetition, completed at the sample the last waypoint was reached (the
    // body's origin within 5 cm of x0 + 0.9 m: x >= x0 + 0.85 m on a straight path along y = 0;
    // lateral drift stays below 1 cm over 1 m, docs/DESIGN.md).
    let o = &s[0];
    assert_eq!(o.repetitions_done, 1, "{o:?}");
    assert_eq!(o.status, "completed");
    let t_rep = first_at(&xs, start_x + 0.85);
    assert!((o.rep_times_s[0] - t_rep).abs() < 1e-9, "{o:?} vs {t_rep}");
    let gate_times: Vec<f64> = o
        .events
        .iter()
        .filter(|e| e.kind == "gate")
        .map(|e| e.t_s)
        .collect();
    assert_eq!(gate_times.len(), 3, "{:?}", o.events);
    assert!((gate_times[0] - first_at(&xs, start_x + 0.25)).abs() < 1e-9);
    // The line: the first sample past it.
    assert!((gate_times[1] - first_at(&xs, start_x + 0.6)).abs() < 1e-9);
    assert!(
        o.score.time_s == t_rep && o.score.score_s == t_rep,
        "{:?}",
        o.score
    );

    // Skipped: gate 0 only; gate 2 reached out of order is not counted.
    let k = &s[1];
    assert_eq!((k.next_gate, k.repetitions_done), (1, 0), "{k:?}");
    assert_eq!(k.events.iter().filter(|e| e.kind == "gate").count(), 1);

    // A gate line crossed against its direction does not count.
    let b = &s[2];
    assert_eq!((b.next_gate, b.repetitions_done), (0, 0), "{b:?}");
    assert!(b.events.is_empty(), "{:?}", b.events);

    // The time limit: finished at the first sample past 1 s.
    let l = &s[3];
    assert_eq!(l.status, "time_limit", "{l:?}");
    assert!(l.finished);
    assert!((l.elapsed_s - 1.01).abs() < 1e-6, "{}", l.elapsed_s);

    // The tape is touched once (one episode over the many samples the robot is in it), the
    // far obstacle never; the penalty is counted.
    let m = &s[4];
    assert_eq!(m.faults.touch, 1, "{:?}", m.events);
    assert!((m.penalty_s - 5.0).abs() < 1e-12);
    let touch = m.events.iter().find(|e| e.kind == "fault").unwrap();
    assert!(touch.detail.contains("tape"), "{touch:?}");
    // The robot's front (about 0.45 m ahead of the body origin) reaches the tape first.
    let t_touch = touch.t_s;
    let x_touch = xs.iter().find(|(t, _)| *t == t_touch).unwrap().1 - start_x;
    assert!((0.1..0.5).contains(&x_touch), "touched at x0 + {x_touch} m");
}

/// The time limit and a completed course through the `Runner`: success ends a run that is
/// asked to stop there, and a marked obstacle (queried every sample) leaves the trajectory
/// byte-identical to the same run without a course.
#[test]
fn completed_course_ends_the_run_and_queries_change_nothing() {
    let start_x = scenario(0.1, "").start_xy.0;
    let extra = format!(
        "[course]\nname = \"short\"\n{}\
         [[course.obstacles]]\nx_m = {:?}\ny_m = 0.0\nz_m = 0.1\nhalf_m = [0.02, 0.6, 0.1]\n",
        line(start_x + 0.5, 0.0),
        start_x + 0.3
    );
    let sc = scenario(4.0, &extra);
    let with = tracksim::run_scenario(&sc, |_, _| {}).unwrap();
    assert_eq!(with.outcome.name(), "success", "{:?}", with.outcome);
    assert!(
        with.summary
            .outcome_reason
            .contains("course completed: 1 repetitions"),
        "{}",
        with.summary.outcome_reason
    );
    let t_end = with.summary.sim_time_s;
    assert!(t_end < 3.0, "the run stopped at {t_end} s");
    let c = with.summary.course.as_ref().unwrap();
    assert_eq!((c.faults.touch, c.repetitions_done), (1, 1), "{c:?}");
    let json = serde_json::to_value(&with.summary).unwrap();
    assert_eq!(json["course"]["score"]["repetitions"], 1);
    assert!(json["trainee"].is_null());
    assert!(json["started_utc"].as_str().unwrap().ends_with('Z'));
    let without = tracksim::run_scenario(&scenario(t_end, ""), |_, _| {}).unwrap();
    assert!(without.summary.course.is_none());
    assert_eq!(
        tracksim::output::trajectory_csv(&with),
        tracksim::output::trajectory_csv(&without),
        "the course's queries changed the trajectory"
    );
    // The scene holds the course and the tip-over limit; none without a course.
    let scene = serde_json::to_value(tracksim::output::Scene::new(&sc)).unwrap();
    assert_eq!(scene["course"]["gates"][0]["kind"], "line");
    assert_eq!(scene["max_tilt_deg"], 75.0);
    let plain = serde_json::to_value(tracksim::output::Scene::new(&scenario(1.0, ""))).unwrap();
    assert!(plain["course"].is_null());
}

/// A reset counts a fault and restarts the course (the resets carry over with their
/// penalty); a tip-over counts a fault and remains the scenario's failure.
#[test]
fn reset_and_tip_over_are_faults() {
    let start_x = scenario(0.1, "").start_xy.0;
    let sc = scenario(
        10.0,
        &format!(
            "[course]\n{}{}[course.penalty_s]\nreset = 30.0",
            waypoint(start_x + 0.15, 0.0, 0.05),
            waypoint(start_x + 5.0, 0.0, 0.05)
        ),
    );
    let mut r = Runner::new(&sc).unwrap().without_sensors();
    while r.time() < 1.0 {
        r.step().unwrap();
    }
    assert_eq!(r.course().unwrap().next_gate, 1);
    r.reset(None).unwrap();
    let c = r.course().unwrap();
    assert_eq!(
        (c.faults.reset, c.next_gate, c.elapsed_s),
        (1, 0, 0.0),
        "{c:?}"
    );
    assert!((c.penalty_s - 30.0).abs() < 1e-12);
    assert!(c.events[0].detail.contains("reset 1"), "{:?}", c.events);
    while r.time() < 1.0 {
        r.step().unwrap();
    }
    let c = r.course().unwrap();
    assert_eq!((c.faults.reset, c.next_gate), (1, 1), "{c:?}");
    let res = r.finish(End::ByOperator);
    assert_eq!(res.summary.course.unwrap().status, "not_completed");

    // Dropped from 10 deg of pitch with a 5 deg limit: tipped at the first sample.
    let spec_sc = scenario_with(
        0.3,
        "[outcome]\nmax_tilt_deg = 5.0\n[course]\n[[course.gates]]\nx_m = 9.0\ny_m = 0.0\nradius_m = 0.5",
        |s| s.vehicle.pitch_deg = 10.0,
    );
    let res = tracksim::run_scenario(&spec_sc, |_, _| {}).unwrap();
    assert!(
        res.summary.outcome_reason.contains("tipped over"),
        "{}",
        res.summary.outcome_reason
    );
    let c = res.summary.course.unwrap();
    assert_eq!(c.faults.tip_over, 1, "{c:?}");
}

fn fake_summary(dir: &std::path::Path, trainee: &str, reps: u32, score: f64, date: &str) {
    std::fs::create_dir_all(dir).unwrap();
    let json = serde_json::json!({
        "scenario": "course_figure8_ramps.toml",
        "outcome": if reps > 0 { "success" } else { "failure" },
        "trainee": trainee,
        "started_utc": date,
        "course": {
            "name": "figure-8",
            "repetitions_required": 1,
            "score": {
                "repetitions": reps, "time_s": score - 5.0, "faults": 1, "penalty_s": 5.0,
                "score_s": score
            }
        }
    });
    std::fs::write(dir.join("summary.json"), json.to_string()).unwrap();
}

#[test]
fn sessions_table_sorts_and_writes_csv() {
    use tracksim::sessions::{SortKey, scan_sessions, sort_rows, table_csv, table_text};
    let root = std::env::temp_dir().join(format!("tracksim_issue28_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    fake_summary(&root.join("a"), "Zoe", 1, 50.0, "2026-12-01T10:00:00Z");
    fake_summary(&root.join("b/1"), "Adam", 1, 40.0, "2026-12-02T10:00:00Z");
    fake_summary(&root.join("c"), "Mia", 0, 20.0, "2026-11-30T10:00:00Z");
    // A run without a course: no score, listed after every scored session.
    std::fs::create_dir_all(root.join("plain")).unwrap();
    std::fs::write(
        root.join("plain/summary.json"),
        r#"{"scenario": "packbot_flat.toml", "outcome": "completed", "trainee": "Noah"}"#,
    )
    .unwrap();
    std::fs::create_dir_all(root.join("broken")).unwrap();
    std::fs::write(root.join("broken/summary.json"), "{ not json").unwrap();
    let mut t = scan_sessions(&root).unwrap();
    assert_eq!(t.rows.len(), 4);
    assert_eq!(t.warnings.len(), 1, "{:?}", t.warnings);
    assert!(t.warnings[0].contains("broken"), "{:?}", t.warnings);
    // Score: most repetitions first, then the lowest time plus penalties.
    sort_rows(&mut t.rows, SortKey::Score, false);
    let names: Vec<&str> = t.rows.iter().map(|r| r.trainee.as_str()).collect();
    assert_eq!(names, ["Adam", "Zoe", "Mia", "Noah"]);
    sort_rows(&mut t.rows, SortKey::Repetitions, false);
    assert_eq!(t.rows.last().unwrap().trainee, "Noah");
    sort_rows(&mut t.rows, SortKey::Date, true);
    let names: Vec<&str> = t.rows.iter().map(|r| r.trainee.as_str()).collect();
    assert_eq!(names, ["Adam", "Zoe", "Mia", "Noah"]);
    sort_rows(&mut t.rows, SortKey::Trainee, false);
    let csv = table_csv(&t.rows);
    let lines: Vec<&str> = csv.lines().collect();
    assert!(lines[0].starts_with("trainee,scenario,course,status,repetitions,time_s,faults"));
    assert!(
        lines[1].starts_with(
            "Adam,course_figure8_ramps.toml,figure-8,completed,1/1,35.00,1,5.00,40.00,success,"
        ),
        "{}",
        lines[1]
    );
    assert_eq!(lines.len(), 5, "a header and 4 sessions");
    assert!(table_text(&t.rows).lines().count() == 5);
    assert!(scan_sessions(&root.join("missing")).is_err());
    assert!(scan_sessions(&root.join("a/summary.json")).is_err());
    assert_eq!(SortKey::parse("score"), Some(SortKey::Score));
    assert_eq!(SortKey::parse("nope"), None);
    let _ = std::fs::remove_dir_all(&root);
}
