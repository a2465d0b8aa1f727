//! An ensemble of a world of several robots (`tracksim run TEAM_FILE --ensemble N`, refused
//! before): each member moves and turns every robot's start on its own, so a verdict that hangs
//! on how the robots meet shows as marginal; the report gives the world's verdict, the winner's
//! and each robot's.

use crate::common::root;

use tracksim::ScenarioTemplate;
use tracksim::ensemble::{EnsembleOptions, EnsembleReport, Perturbations, run_ensemble};

/// Each robot draws its own offset; robot 0's are the one-robot member's; member 0 is the file.
#[test]
fn each_robot_of_a_member_draws_its_own_start() {
    let p = Perturbations::default();
    for k in 0..12 {
        let m = p.team_member(5, k, 3);
        let one = p.member(5, k);
        assert_eq!(m.robots.len(), 3);
        assert_eq!(
            (m.robots[0].dx_m, m.robots[0].dy_m, m.robots[0].dyaw_deg),
            (one.dx_m, one.dy_m, one.dyaw_deg)
        );
        assert_eq!(m, p.team_member(5, k, 3), "seeded");
        for o in &m.robots {
            assert!(o.dx_m.abs() <= 1e-3 && o.dy_m.abs() <= 1e-3 && o.dyaw_deg.abs() <= 0.05);
            if k == 0 {
                assert_eq!((o.dx_m, o.dy_m, o.dyaw_deg), (0.0, 0.0, 0.0));
            }
        }
        if k > 0 {
            assert!(m.robots[1].dx_m != m.robots[0].dx_m && m.robots[2].dx_m != m.robots[1].dx_m);
        }
    }
}

/// The bundled race as an ensemble of 4 (2 shards merged): the member's keys put each robot
/// where it started; member 0 is the file's run; red wins every member, each robot succeeds,
/// and the finishing times are in the ratio of the speeds (7/6 within 1 %, as the race's own
/// test); the report reads back from its JSON.
#[test]
fn the_bundled_race_as_an_ensemble() {
    let path = root().join("scenarios/team/race_step.toml");
    let t = ScenarioTemplate::load(&path).unwrap();
    let sc = t.file_scenario().unwrap();
    let out = std::env::temp_dir().join(format!("tracksim_team_ensemble_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let shard = |i: usize| {
        let mut opts = EnsembleOptions::new(4);
        opts.jobs = 2;
        opts.shard = Some((i, 2));
        opts.out = Some(out.clone());
        run_ensemble(&t, &opts, |_, _| {}).unwrap()
    };
    let r = EnsembleReport::merge(vec![shard(1), shard(0)]).unwrap();
    assert_eq!(r.members.len(), 4);
    assert_eq!(r.verdict(), "S 4/4", "{}", r.text());
    assert_eq!(
        r.winner_verdict().as_deref(),
        Some("red 4/4"),
        "{}",
        r.text()
    );
    let direct = tracksim::run::run_team(&sc, Default::default()).unwrap();
    for m in &r.members {
        // The member's keys put each robot where its run started (the file's start plus its
        // offset): the member's own folder says so.
        for (k, (name, run)) in direct.robots.iter().enumerate() {
            let x = m.keys[3 * k].1;
            let y = m.keys[3 * k + 1].1;
            assert_eq!(m.keys[3 * k].0, format!("vehicles[{k}].vehicle.x_m"));
            let view = sc.robot_view(k);
            let o = &m.member.robots[k];
            assert!((x - (view.start_xy.0 + o.dx_m)).abs() < 1e-12);
            assert!((y - (view.start_xy.1 + o.dy_m)).abs() < 1e-12);
            let first = std::fs::read_to_string(
                out.join(format!("member-{:03}", m.member.index))
                    .join(name)
                    .join("trajectory.csv"),
            )
            .unwrap();
            let row: Vec<f64> = first
                .lines()
                .nth(1)
                .unwrap()
                .split(',')
                .take(3)
                .map(|v| v.parse().unwrap())
                .collect();
            // The body frame's origin starts where the keys put it (the CSV to 1e-6 m; the
            // body starts above the ground, so only x and y).
            let file_row: Vec<f64> = direct_first_row(run);
            assert!(
                (row[1] - file_row[1] - o.dx_m).abs() < 2e-6,
                "{name}: {row:?} {file_row:?} {o:?}"
            );
            assert!(
                (row[2] - file_row[2] - o.dy_m).abs() < 2e-6,
                "{name}: {row:?} {file_row:?} {o:?}"
            );
        }
        let red = &m.robots[0];
        let blue = &m.robots[1];
        assert_eq!((red.name.as_str(), blue.name.as_str()), ("red", "blue"));
        assert_eq!(
            (red.outcome.as_str(), blue.outcome.as_str()),
            ("success", "success")
        );
        let ratio = blue.outcome_time_s / red.outcome_time_s;
        assert!(
            (ratio / (7.0 / 6.0) - 1.0).abs() < 0.01,
            "member {}: {ratio}",
            m.member.index
        );
    }
    // Member 0 is the file as written: its robots end where a plain run of the file ends,
    // bit for bit.
    let m0 = &r.members[0];
    for (k, (_, run)) in direct.robots.iter().enumerate() {
        assert_eq!(m0.robots[k].final_pose, run.summary.final_pose);
    }
    // A member is reproduced by its keys written into the file: every robot's trajectory
    // byte for byte.
    replays_from_its_keys(&path, &out, &r.members[2]);
    // The merged report is written and reads back whole (the robots' results with it).
    r.write(&out).unwrap();
    let back =
        EnsembleReport::from_json(&std::fs::read_to_string(out.join("ensemble.json")).unwrap())
            .unwrap();
    assert_eq!(back.winner_verdict(), r.winner_verdict());
    assert_eq!(back.robot_verdicts().len(), 2);
    let csv = std::fs::read_to_string(out.join("ensemble.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(header.ends_with(",winner,red.outcome,red.outcome_time_s,red.final_x_m,red.final_y_m,red.progress_m,blue.outcome,blue.outcome_time_s,blue.final_x_m,blue.final_y_m,blue.progress_m"), "{header}");
    assert_eq!(csv.lines().count(), 5);
    let _ = std::fs::remove_dir_all(&out);
}

/// The first sample (t, x, y) of a run.
fn direct_first_row(run: &tracksim::RunResult) -> Vec<f64> {
    let s = run.samples.first().unwrap();
    let p = s.pose;
    vec![s.t, p.x, p.y]
}

/// Member `m` of the ensemble in `out` of the file `path` replayed from its keys written into
/// the file: every robot's trajectory byte for byte the member's.
fn replays_from_its_keys(
    path: &std::path::Path,
    out: &std::path::Path,
    m: &tracksim::ensemble::MemberResult,
) {
    let mut doc: toml::Table = toml::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let robots = doc["vehicles"].as_array_mut().unwrap();
    for (k, robot) in robots.iter_mut().enumerate() {
        let v = robot["vehicle"].as_table_mut().unwrap();
        v.insert(
            "file".into(),
            root()
                .join("vehicles/packbot510.toml")
                .display()
                .to_string()
                .into(),
        );
        for (key, value) in &m.keys {
            if let Some(name) = key.strip_prefix(&format!("vehicles[{k}].vehicle.")) {
                v.insert(name.into(), (*value).into());
            }
        }
    }
    let salt = m
        .keys
        .iter()
        .find(|(k, _)| k == "simulation.order_salt")
        .unwrap()
        .1;
    doc["simulation"]
        .as_table_mut()
        .unwrap()
        .insert("order_salt".into(), (salt as i64).into());
    let again = out.join("again");
    std::fs::create_dir_all(&again).unwrap();
    let file = again.join("member.toml");
    std::fs::write(&file, toml::to_string(&doc).unwrap()).unwrap();
    let msc = tracksim::load_scenario(&file).unwrap();
    let rerun = tracksim::run::run_team(&msc, Default::default()).unwrap();
    let which = tracksim::output::Outputs::data(false);
    tracksim::output::write_team(&msc, &rerun, &again, which).unwrap();
    for name in ["red", "blue"] {
        let a = std::fs::read(again.join(name).join("trajectory.csv")).unwrap();
        let b = std::fs::read(
            out.join(format!("member-{:03}", m.member.index))
                .join(name)
                .join("trajectory.csv"),
        )
        .unwrap();
        assert!(
            a == b,
            "member {}'s {name} does not replay byte for byte",
            m.member.index
        );
    }
}

/// The bundled head-on push (a neutral equilibrium: which way the pair drifts is the solver's
/// coin toss) as an ensemble of 8: every member keeps the gap between the robots (they push,
/// neither passes through) and meets every robot's `[expect]` bounds, which the file derives
/// from the belt speed rather than from one member's drift.
#[test]
fn the_head_on_push_meets_its_bounds_in_every_member() {
    let path = root().join("scenarios/team/corridor_head_on.toml");
    let t = ScenarioTemplate::load(&path).unwrap();
    let sc = t.file_scenario().unwrap();
    let mut opts = EnsembleOptions::new(8);
    opts.jobs = 2;
    let r = run_ensemble(&t, &opts, |_, _| {}).unwrap();
    assert_eq!(r.verdict(), "C 8/8", "{}", r.text());
    let west: Vec<f64> = r.members.iter().map(|m| m.robots[0].final_pose.x).collect();
    for m in &r.members {
        let (w, e) = (&m.robots[0], &m.robots[1]);
        let gap = e.final_pose.x - w.final_pose.x;
        assert!(
            (0.68..0.70).contains(&gap),
            "member {}: gap {gap}",
            m.member.index
        );
        for (k, robot) in m.robots.iter().enumerate() {
            let expect = sc.robot_view(k).expect.clone();
            let p = robot.final_pose;
            for (what, v, range) in [
                ("x", p.x, expect.final_x),
                ("y", p.y, expect.final_y),
                ("z", p.z, expect.final_z),
            ] {
                let [lo, hi] = range.expect("bounded");
                assert!(
                    (lo..=hi).contains(&v),
                    "member {}: {} final {what} {v} outside [{lo}, {hi}]",
                    m.member.index,
                    robot.name
                );
            }
        }
    }
    // The drift does go both ways: a bound set from member 0's drift would not hold.
    let (lo, hi) = west
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
    assert!(hi - lo > 0.5, "west's final x {lo}..{hi}");
}
