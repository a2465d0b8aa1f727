//! Issue 40: several robots in one world. Files with `[[vehicles]]` refused with every problem
//! named; identical robots side by side mirror each other; a far neighbour changes nothing; a
//! head-on push balances momentum (Newton on the terrain's impulses); the world's outcome by
//! its rule; robots spreading beyond what one world holds stop the run with a message.

use crate::common::{contact_impulses, root};
use rapier3d::prelude::*;
use tracksim::Simulation;
use tracksim::model::{Scenario, TeamRule};
use tracksim::run::Outcome;

/// A `[[vehicles]]` entry: a PackBot 510 named `name` at (x, y) m heading `yaw` deg, driving
/// with `cmd` (a `[[vehicles.commands]]` body, e.g. `belt_speed_mps = 0.3`).
fn robot(name: &str, x: f64, y: f64, yaw: f64, cmd: &str) -> String {
    format!(
        "[[vehicles]]\nname = \"{name}\"\n[vehicles.vehicle]\nfile = \"{}\"\nx_m = {x}\n\
         y_m = {y}\nyaw_deg = {yaw}\n[[vehicles.commands]]\nt_s = 0.0\n{cmd}\n",
        root().join("vehicles/packbot510.toml").display()
    )
}

/// Loads a scenario from its text (written to a temporary file named after `tag`).
fn load(tag: &str, text: &str) -> tracksim::Result<Scenario> {
    let path =
        std::env::temp_dir().join(format!("tracksim_team_{}_{tag}.toml", std::process::id()));
    std::fs::write(&path, text).unwrap();
    let r = tracksim::load_scenario(&path);
    let _ = std::fs::remove_file(&path);
    r
}

/// Flat ground with friction 0.6, `duration` s, and the given robots.
fn flat(duration: f64, robots: &[String]) -> String {
    flat_with("", duration, robots)
}

/// [`flat`] with more top-level keys and tables (`top`).
fn flat_with(top: &str, duration: f64, robots: &[String]) -> String {
    format!(
        "description = \"team test\"\n[terrain.ground]\nfriction = 0.6\n[simulation]\n\
         duration_s = {duration}\n{top}\n{}",
        robots.join("")
    )
}

#[test]
fn bad_team_files_are_refused_with_every_problem_named() {
    let text = flat_with(
        "[outcome]\nteam = \"most\"\n[[commands]]\nt_s = 0.0\nbelt_speed_mps = 0.3\n",
        1.0,
        &[
            robot("alpha", 0.0, 0.0, 0.0, "belt_speed_mps = 0.3"),
            robot("alpha", 0.0, 2.0, 0.0, "belt_speed_mps = 0.3"),
            robot("Bad-Name", 0.0, -2.0, 0.0, "belt_speed_mps = 0.3"),
            robot("far", 12.0, 0.0, 0.0, "belt_speed_mps = 0.3"),
            robot("cmd", 0.0, 4.0, 0.0, "belt_speed_mps = { nope = 1.0 }"),
            robot("buried", 0.0, 6.0, 0.0, "belt_speed_mps = 0.3")
                .replace("x_m = 0", "z_m = -0.3\nx_m = 0"),
        ],
    );
    let e = load("bad", &text).unwrap_err().to_string();
    for want in [
        "commands: a file with [[vehicles]]",
        "outcome.team: unknown team rule `most`",
        "vehicles[1].name: `alpha` is also the name of vehicles[0]",
        "vehicles[2].name: `Bad-Name` is not ROS-safe",
        "vehicles[3].vehicle.x_m: `far` starts 12.00 m from `alpha`",
        "vehicles[4].commands[0].belt_speed_mps",
        "vehicles[5].vehicle.z_m: -0.3 m is 0.300 m below the terrain surface",
    ] {
        assert!(e.contains(want), "missing {want:?} in:\n{e}");
    }
    // A wrong rule is refused in a one-robot file too (where it has no effect).
    let one = format!(
        "[vehicle]\nfile = \"{}\"\n[outcome]\nteam = \"most\"\n",
        root().join("vehicles/packbot510.toml").display()
    );
    let e = load("one_bad_rule", &one).unwrap_err().to_string();
    assert!(e.contains("outcome.team: unknown team rule `most`"), "{e}");
    // More robots than a world holds.
    let many: Vec<String> = (0..17)
        .map(|i| {
            robot(
                &format!("r{i}"),
                0.0,
                0.6 * i as f64 - 4.8,
                0.0,
                "belt_speed_mps = 0.0",
            )
        })
        .collect();
    let e = load("many", &flat(1.0, &many)).unwrap_err().to_string();
    assert!(e.contains("17 robots; one world holds at most 16"), "{e}");
}

#[test]
fn robots_placed_overlapping_are_refused_naming_both() {
    let sc = load(
        "overlap",
        &flat(
            1.0,
            &[
                robot("alpha", 0.0, 0.0, 0.0, "belt_speed_mps = 0.3"),
                robot("bravo", 0.3, 0.1, 0.0, "belt_speed_mps = 0.3"),
                robot("charlie", 0.0, 2.0, 0.0, "belt_speed_mps = 0.3"),
            ],
        ),
    )
    .unwrap();
    let e = Simulation::new(&sc).err().expect("refused").to_string();
    assert!(
        e.contains("vehicles[1].vehicle.x_m: `bravo` overlaps `alpha`"),
        "{e}"
    );
    assert!(!e.contains("charlie"), "{e}");
}

/// Runs a team scenario to its end.
fn run(sc: &Scenario) -> tracksim::run::TeamResult {
    tracksim::run::run_team(sc, Default::default()).unwrap()
}

#[test]
fn two_identical_robots_side_by_side_mirror_each_other() {
    // Turning away from each other: the left one left, the right one right.
    let sc = load(
        "mirror",
        &flat(
            6.0,
            &[
                robot(
                    "left",
                    0.0,
                    1.5,
                    0.0,
                    "forward_mps = 0.2\nyaw_rate_rad_s = 0.3",
                ),
                robot(
                    "right",
                    0.0,
                    -1.5,
                    0.0,
                    "forward_mps = 0.2\nyaw_rate_rad_s = -0.3",
                ),
            ],
        ),
    )
    .unwrap();
    let r = run(&sc);
    let (a, b) = (&r.robots[0].1.samples, &r.robots[1].1.samples);
    assert_eq!(a.len(), b.len());
    let mut worst = (0.0f64, 0.0f64);
    for (p, q) in a.iter().zip(b) {
        worst.0 = worst
            .0
            .max((p.pose.x - q.pose.x).abs())
            .max((p.pose.y + q.pose.y).abs());
        worst.1 = worst.1.max((p.pose.yaw + q.pose.yaw).abs());
    }
    let turned = a.last().unwrap().pose.yaw;
    println!(
        "mirror: worst {:.2e} m, {:.2e} rad; turned {turned:.3} rad",
        worst.0, worst.1
    );
    assert!(turned > 1.0, "the robots turned {turned} rad");
    // A skid-steer turn's yaw rate depends on the start position by up to 2.1 % (issue 38,
    // `a_skid_steer_turn_does_not_depend_on_where_it_starts`: the load share along the track
    // the solver's order sets). The mirror images (f32 rounding at y = +-1.5 m, the tracks'
    // order swapped by the mirror) agree within that: yaw within 2.5 % of the angle turned,
    // position within 1 % of the 1.2 m driven (measured: 0.37 %, 1.6 mm).
    assert!(worst.1 < 0.025 * turned, "{worst:?}");
    assert!(worst.0 < 0.01 * 1.2, "{worst:?}");
}

#[test]
fn a_far_neighbour_does_not_change_a_robots_run() {
    let drive = "forward_mps = 0.3\nyaw_rate_rad_s = 0.2";
    let alone = load("alone", &flat(6.0, &[robot("alpha", 0.0, 0.0, 0.0, drive)])).unwrap();
    let pair = load(
        "pair",
        &flat(
            6.0,
            &[
                robot("alpha", 0.0, 0.0, 0.0, drive),
                robot("parked", 0.0, 8.0, 0.0, "belt_speed_mps = 0.0"),
            ],
        ),
    )
    .unwrap();
    assert_eq!(alone.robot_count(), 1);
    let a = tracksim::run_scenario(&alone, |_, _| {}).unwrap();
    let b = run(&pair);
    let (pa, pb) = (a.summary.final_pose, b.robots[0].1.summary.final_pose);
    let d = ((pa.x - pb.x).powi(2) + (pa.y - pb.y).powi(2)).sqrt();
    println!(
        "alone ({:.4}, {:.4}, {:.4} rad), with a neighbour 8 m away ({:.4}, {:.4}, {:.4} rad): \
         {d:.2e} m apart",
        pa.x, pa.y, pa.yaw, pb.x, pb.y, pb.yaw
    );
    // The neighbour moves the floating origin 4 m away (f32 spacing 0.48 um instead of
    // 0.24 um): for the stick-slip turn that is a change of start position, whose effect on
    // the yaw rate is up to 0.84 % (issue 38). Within 1 % of the angle turned and 0.5 % of the
    // 1.8 m driven (measured: 0.1 %, 2.1 mm).
    assert!(
        (pa.yaw - pb.yaw).abs() < 0.01 * pa.yaw.abs(),
        "{} {}",
        pa.yaw,
        pb.yaw
    );
    assert!(d < 0.005 * 1.8, "{d}");
    // The parked neighbour stayed where it was.
    let q = b.robots[1].1.summary.final_pose;
    assert!(q.x.abs() < 1e-3 && (q.y - 8.0).abs() < 1e-3, "{q:?}");
}

#[test]
fn robots_pushing_head_on_balance_momentum_and_never_pass_through() {
    let sc = load(
        "push",
        &flat(
            6.0,
            &[
                robot("west", -1.2, 0.0, 0.0, "belt_speed_mps = 0.3"),
                robot("east", 1.2, 0.0, 180.0, "belt_speed_mps = 0.3"),
            ],
        ),
    )
    .unwrap();
    let mut sim = Simulation::new(&sc).unwrap();
    sim.world.integration_parameters.friction_model = FrictionModel::Coulomb;
    let mut bodies = Vec::new();
    for k in 0..2 {
        sim.select(k);
        sim.set_belt_speed(0, 0.3);
        sim.set_belt_speed(1, 0.3);
        bodies.extend(sim.vehicle_bodies());
    }
    sim.select(0);
    let momentum = |s: &Simulation| -> Vector {
        bodies
            .iter()
            .map(|h| {
                let b = &s.world.bodies[*h];
                b.linvel() * b.mass()
            })
            .sum()
    };
    let terrain = |c: &Collider| {
        c.collision_groups()
            .memberships
            .contains(tracksim::tracks::WORLD_GROUP)
    };
    let (mut impulse, mut pushed) = (Vector::ZERO, 0.0f64);
    let (t0, mut p0) = (3.0, Vector::ZERO);
    let mut gap = f64::MAX;
    while sim.time() < 6.0 - 1e-9 {
        sim.step().unwrap();
        if (sim.time() - t0).abs() < 1e-9 {
            p0 = momentum(&sim);
        }
        if sim.time() > t0 + 1e-9 {
            let (f, n) = contact_impulses(&sim, &bodies, terrain);
            impulse += f + n;
            // The push: the other robot's impulse on robot 0.
            let (f, n) = contact_impulses(&sim, &bodies[..bodies.len() / 2], |c| !terrain(c));
            pushed += ((f + n).x as f64).abs();
        }
        sim.select(1);
        let east = sim.body_pose().x;
        sim.select(0);
        gap = gap.min(east - sim.body_pose().x);
    }
    let dp = momentum(&sim) - p0;
    let dt = 6.0 - t0;
    println!(
        "push over {dt} s: mean push {:.1} N; momentum change x {:.4} N s, terrain impulse x \
         {:.4} N s; closest chassis origins {gap:.3} m",
        pushed / dt,
        dp.x,
        impulse.x
    );
    // They met and pushed (the robots' friction 0.6 x 13 kg x 9.81: ~77 N each).
    assert!(pushed / dt > 40.0, "mean push {} N", pushed / dt);
    // Newton: the robots' contact with each other is internal; their momentum changes by the
    // terrain's impulse alone (Coulomb writeback: the total over the substeps). Measured equal
    // to 1e-4 N s over 3 s; bound 0.02 N s, 0.01 % of the 230 N s each robot's belts push
    // with, so a push force lost or counted twice (e.g. a robot's contact with the other
    // counted as terrain) fails.
    assert!(
        f64::from((dp.x - impulse.x).abs()) < 0.02,
        "dp {dp:?} impulse {impulse:?}"
    );
    // Never through each other: two PackBots (0.69 m long) nose to nose.
    assert!(gap > 0.6, "{gap}");
}

#[test]
fn the_worlds_outcome_follows_its_rule() {
    let names: Vec<String> = ["a", "b"].iter().map(|s| s.to_string()).collect();
    let ok = |t| Some((Outcome::Success("in".into()), t));
    let bad = |t| Some((Outcome::Failure("tipped".into()), t));
    let decide = tracksim::run::team::decide;
    assert_eq!(decide(TeamRule::All, &names, &[ok(2.0), None], false), None);
    let all = decide(TeamRule::All, &names, &[ok(2.0), ok(3.0)], false).unwrap();
    assert!(matches!(all.0, Outcome::Success(_)) && all.1 == 3.0);
    let one_fails = decide(TeamRule::All, &names, &[ok(2.0), bad(1.0)], false).unwrap();
    assert!(matches!(&one_fails.0, Outcome::Failure(r) if r.contains("`b` failed")));
    let race = decide(TeamRule::First, &names, &[None, ok(4.0)], false).unwrap();
    assert!(matches!(&race.0, Outcome::Success(r) if r.contains("`b` finished first")));
    assert_eq!(
        decide(TeamRule::First, &names, &[bad(1.0), None], false),
        None
    );
    let lost = decide(TeamRule::First, &names, &[bad(1.0), bad(2.0)], false).unwrap();
    assert!(matches!(lost.0, Outcome::Failure(_)) && lost.1 == 2.0);
}

#[test]
fn robots_spreading_beyond_one_world_stop_the_run_with_a_message() {
    let sc = load(
        "spread",
        &flat(
            10.0,
            &[
                robot("west", -4.5, 0.0, 180.0, "belt_speed_mps = 0.5"),
                robot("east", 4.5, 0.0, 0.0, "belt_speed_mps = 0.5"),
            ],
        ),
    )
    .unwrap();
    let e = tracksim::run::run_team(&sc, Default::default())
        .map(|r| r.outcome)
        .expect_err("stopped");
    assert!(matches!(e, tracksim::Error::Limit { .. }), "{e}");
    let e = e.to_string();
    assert!(e.contains("more than the 10 m one world holds"), "{e}");
    // At 2 x 0.5 m/s from 9 m apart the limit is reached near t = 1 s (after the start-up).
    assert!(e.contains("run stopped at t = 1."), "{e}");
}

#[test]
fn a_team_run_folder_is_written_per_robot_and_viewed_whole() {
    let sc = load(
        "view",
        &flat(
            0.5,
            &[
                robot("alpha", 0.0, 0.0, 0.0, "belt_speed_mps = 0.3"),
                robot("bravo", 0.0, 2.0, 0.0, "belt_speed_mps = 0.2"),
            ],
        ),
    )
    .unwrap();
    let r = run(&sc);
    let dir = std::env::temp_dir().join(format!("tracksim_team_view_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let which = tracksim::output::Outputs {
        replay: true,
        plots: false,
        mcap: false,
        raw_images: false,
    };
    tracksim::output::write_team(&sc, &r, &dir, which).unwrap();
    let team: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("team.json")).unwrap()).unwrap();
    assert_eq!(team["robots"][1]["name"], "bravo");
    // Each robot's folder is a one-robot run folder; `tracksim view DIR` serves both.
    let files = tracksim::live::server::view_files(&dir).unwrap();
    let runs = files.iter().find(|f| f.0 == "/runs.json").unwrap();
    let runs: serde_json::Value = serde_json::from_slice(&runs.2).unwrap();
    let names: Vec<&str> = runs["runs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["alpha", "bravo"]);
    // Bravo's trajectory is its own: 0.5 s at 0.2 m/s along y = 2 m (t, x, y).
    let csv = std::fs::read_to_string(dir.join("bravo/trajectory.csv")).unwrap();
    let last: Vec<f64> = csv
        .lines()
        .last()
        .unwrap()
        .split(',')
        .take(3)
        .map(|v| v.parse().unwrap())
        .collect();
    assert!((last[0] - 0.5).abs() < 1e-9, "{last:?}");
    assert!(last[1] > 0.05 && last[1] < 0.1, "{last:?}");
    assert!((last[2] - 2.0).abs() < 1e-3, "{last:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The nearest range within 5 deg of straight ahead of the selected robot's lidar `scan` after
/// 0.2 s (m; +inf when nothing is in range), and the nearest over every ray.
fn lidar_ahead(sc: &Scenario) -> (f64, f64) {
    let mut sim = Simulation::new(sc).unwrap();
    sim.select(0);
    let mut set = tracksim::sensors::SensorSet::new(&sim, false);
    for _ in 0..200 {
        sim.step().unwrap();
        set.update(&sim);
    }
    let i = (0..set.len())
        .find(|&i| set.sensor(i).model().name == "scan")
        .expect("a lidar called scan");
    let s = set.sensor(i);
    let azimuth = s
        .axes()
        .into_iter()
        .find(|c| c.name == "azimuth")
        .unwrap()
        .data;
    let range = &s
        .channels()
        .iter()
        .find(|c| c.name == "range")
        .unwrap()
        .data;
    let n = azimuth.len();
    let ahead = range
        .iter()
        .enumerate()
        .filter(|(k, _)| azimuth[k % n].abs() < 5f64.to_radians())
        .map(|(_, r)| *r)
        .fold(f64::INFINITY, f64::min);
    let nearest = range
        .iter()
        .copied()
        .filter(|r| r.is_finite())
        .fold(f64::INFINITY, f64::min);
    (ahead, nearest)
}

#[test]
fn a_robots_lidar_sees_the_other_robots_and_never_itself() {
    let seer = |x: f64| {
        format!(
            "[[vehicles]]\nname = \"seer\"\n[vehicles.vehicle]\nfile = \"{}\"\nx_m = {x}\n",
            root().join("vehicles/packbot510_sensors.toml").display()
        )
    };
    // A 0.1 m platform under the target lifts it into the lidar's plane (0.19 m up, above a
    // PackBot on the ground); the platform's top stays below the plane.
    let platform = "[[terrain.boxes]]\ncentre_m = [2.0, 0.0, 0.05]\nsize_m = [1.2, 1.0, 0.1]\n";
    let alone = load("seer_alone", &flat_with(platform, 0.3, &[seer(0.0)])).unwrap();
    let with = load(
        "seer_with",
        &flat_with(
            platform,
            0.3,
            &[
                seer(0.0),
                robot("target", 2.0, 0.0, 0.0, "belt_speed_mps = 0.0"),
            ],
        ),
    )
    .unwrap();
    let (a, near_a) = lidar_ahead(&alone);
    let (b, near_b) = lidar_ahead(&with);
    println!(
        "ahead alone {a} m (nearest {near_a}), with a robot 2 m ahead {b} m (nearest {near_b})"
    );
    // Alone: nothing ahead within 10 m. With the other PackBot's rear pulley 2 - 0.345 m ahead
    // of the chassis origin and the lidar 0.15 m forward: about 1.5 m.
    assert!(a.is_infinite(), "{a}");
    assert!((b - 1.5).abs() < 0.1, "{b}");
    // Never its own body: the nearest return alone is beyond the robot (0.5 m from the lidar).
    assert!(near_a > 0.5, "{near_a}");
}

/// A race on a course (`scenarios/team/race_step.toml`): the standings rank the robots by the
/// course's score, name the winner, and their times follow their speeds: the same step and
/// gates at 0.35 and 0.30 m/s take times in the ratio 0.35 / 0.30 = 1.167 (within 3 %: both
/// slip alike on the same step).
#[test]
fn a_race_on_a_course_is_ranked_by_the_course_and_its_times_follow_the_speeds() {
    let file = root().join("scenarios/team/race_step.toml");
    let sc = tracksim::load_scenario(&file).unwrap();
    let r = tracksim::run::run_team(&sc, Default::default()).unwrap();
    let st = r.standings.as_ref().expect("a course: standings");
    let names: Vec<&str> = st.robots.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["red", "blue"]);
    assert_eq!(st.winner.as_deref(), Some("red"));
    assert_eq!(st.completed, 2);
    let (red, blue) = (&st.robots[0], &st.robots[1]);
    assert!(red.status == "completed" && blue.status == "completed");
    let ratio = blue.time_s / red.time_s;
    assert!(
        (ratio / (0.35 / 0.30) - 1.0).abs() < 0.03,
        "time ratio {ratio:.4} (red {:.2} s, blue {:.2} s)",
        red.time_s,
        blue.time_s
    );
    // The world's outcome is the race's: decided when red completed.
    assert_eq!(r.outcome.name(), "success");
    assert!((r.outcome_time - red.time_s).abs() < 1e-9);
    let json = serde_json::to_value(tracksim::output::TeamSummary::of(&sc, &r)).unwrap();
    assert_eq!(json["standings"]["winner"], "red");
}

/// Every message's CDR bytes of a recording by topic, in log order.
fn mcap_topics(bytes: &[u8]) -> std::collections::BTreeMap<String, Vec<Vec<u8>>> {
    let mut out: std::collections::BTreeMap<String, Vec<Vec<u8>>> = Default::default();
    for m in mcap::MessageStream::new(bytes).expect("mcap") {
        let m = m.expect("message");
        out.entry(m.channel.topic.clone())
            .or_default()
            .push(m.data.to_vec());
    }
    out
}

fn decoded<T: tracksim::rosmsg::RosMessage>(msgs: &[Vec<u8>]) -> Vec<T> {
    msgs.iter()
        .map(|d| tracksim::rosmsg::decode::<T>(d).expect("decodes"))
        .collect()
}

#[test]
fn the_worlds_mcap_holds_each_robots_namespaced_topics_and_its_trajectory() {
    use tracksim::rosmsg::{Clock, Imu, Odometry, TFMessage};
    let sensing = |name: &str, y: f64, cmd: &str| {
        format!(
            "[[vehicles]]\nname = \"{name}\"\n[vehicles.vehicle]\nfile = \"{}\"\ny_m = {y}\n\
             [[vehicles.commands]]\nt_s = 0.0\n{cmd}\n",
            root().join("vehicles/packbot510_sensors.toml").display()
        )
    };
    let text = flat(
        1.0,
        &[
            sensing("a", 0.0, "belt_speed_mps = 0.3"),
            sensing("b", 1.5, "belt_speed_mps = -0.2"),
        ],
    );
    let sc = load("mcap", &text).unwrap();
    let r = run(&sc);
    let msgs = mcap_topics(&tracksim::output::mcap::team_mcap_bytes(&sc, &r).unwrap());
    let shared = ["/clock", "/tf", "/tf_static", "/scene"];
    let of = |p: &str| -> std::collections::BTreeSet<String> {
        msgs.keys()
            .filter_map(|t| t.strip_prefix(p).map(str::to_string))
            .collect()
    };
    for t in msgs.keys() {
        assert!(
            shared.contains(&t.as_str()) || t.starts_with("/a/") || t.starts_with("/b/"),
            "{t}: every topic is the world's or a robot's"
        );
    }
    let (a, b) = (of("/a/"), of("/b/"));
    assert_eq!(a, b, "the robots have the same topics, each under its name");
    for t in ["odom", "ground_truth/odom", "joint_states", "tracks", "imu"] {
        assert!(a.contains(t), "/a/{t} in {:?}", msgs.keys());
    }
    let n = r.robots[0].1.samples.len();
    assert_eq!(decoded::<Clock>(&msgs["/clock"]).len(), n, "one /clock");
    let tf: Vec<TFMessage> = decoded(&msgs["/tf"]);
    assert_eq!(tf.len(), n, "one /tf message per sample, every robot in it");
    for m in &tf {
        let pairs: Vec<(String, String)> = m
            .transforms
            .iter()
            .map(|t| (t.header.frame_id.clone(), t.child_frame_id.clone()))
            .collect();
        for name in ["a", "b"] {
            let odom = format!("{name}/odom");
            assert!(pairs.contains(&(odom.clone(), format!("{name}/base_link"))));
            assert!(pairs.contains(&("map".into(), odom)));
        }
        let mut children: Vec<&String> = pairs.iter().map(|p| &p.1).collect();
        children.sort();
        children.dedup();
        assert_eq!(children.len(), pairs.len(), "each frame has one parent");
    }
    let statics: Vec<TFMessage> = decoded(&msgs["/tf_static"]);
    for t in &statics[0].transforms {
        let name = &t.header.frame_id[..1];
        assert!(t.header.frame_id.starts_with(&format!("{name}/")));
        assert!(t.child_frame_id.starts_with(&format!("{name}/")), "{t:?}");
    }
    for (k, (name, run)) in r.robots.iter().enumerate() {
        let truth: Vec<Odometry> = decoded(&msgs[&format!("/{name}/ground_truth/odom")]);
        assert_eq!(truth.len(), run.samples.len());
        for (m, s) in truth.iter().zip(&run.samples) {
            assert_eq!(m.header.frame_id, "map");
            assert_eq!(m.child_frame_id, format!("{name}/base_link"));
            let p = &m.pose.pose.position;
            assert_eq!(
                [p.x, p.y, p.z],
                [s.pose.x, s.pose.y, s.pose.z],
                "{name} at {}",
                s.t
            );
        }
        let odom: Vec<Odometry> = decoded(&msgs[&format!("/{name}/odom")]);
        assert_eq!(odom[0].header.frame_id, format!("{name}/odom"));
        let last = odom.last().unwrap().pose.pose.position.x;
        assert_eq!(last, run.samples.last().unwrap().odom[0]);
        let imu: Vec<Imu> = decoded(&msgs[&format!("/{name}/imu")]);
        assert!(imu[0].header.frame_id.starts_with(&format!("{name}/")));
        let moved = run.samples.last().unwrap().pose.x - run.samples.first().unwrap().pose.x;
        assert!(
            if k == 0 { moved > 0.15 } else { moved < -0.1 },
            "{name} moved {moved} m as commanded"
        );
    }
}

/// The team vector environment (`env::TeamVecEnv`): world `i` equals a lone `env::TeamEnv` with
/// its seed and actions, bit for bit, on 1 or 3 threads; the step after every agent of a world
/// ended resets it (the next seed, no rewards, no agent active) to a lone world's first state.
#[test]
fn team_vector_worlds_equal_lone_worlds_whatever_the_threads_and_autoreset() {
    use std::sync::Arc;
    use tracksim::env::{TEAM_OBS_SIZE, TeamEnv, TeamSettings, TeamVecEnv, next_seed};
    let t = Arc::new(
        tracksim::load_template(&root().join("scenarios/team/corridor_head_on.toml")).unwrap(),
    );
    let s = TeamSettings {
        control_hz: 5.0,
        max_time_s: Some(1.0),
        ..TeamSettings::default()
    };
    let (n, agents, steps) = (3, 2, 6); // 5 periods of an episode, then an autoreset
    let action = |k: usize, i: usize, j: usize| ((k * 7 + i * 3 + j) % 11) as f32 / 5.0 - 1.0;
    let actions = |k: usize| -> Vec<f32> {
        (0..n * agents * 2)
            .map(|x| action(k, x / (agents * 2), x % (agents * 2)))
            .collect()
    };
    let mut runs = Vec::new();
    for threads in [1, 3] {
        let mut v = TeamVecEnv::new(t.clone(), &s, n, 20, threads).unwrap();
        let mut obs = vec![0f32; v.obs_len()];
        let mut out = Vec::new();
        for k in 0..steps {
            let st = v.step(&actions(k), &mut obs).unwrap();
            out.push((obs.clone(), format!("{st:?}")));
        }
        runs.push(out);
    }
    assert_eq!(runs[0], runs[1], "the thread count changed a result");
    let per = agents * TEAM_OBS_SIZE;
    for i in 0..n {
        let mut lone = TeamEnv::new(t.clone(), &s, 20 + i as u64).unwrap();
        let mut o = vec![0f32; per];
        for (k, (obs, _)) in runs[0].iter().enumerate().take(steps - 1) {
            let a = actions(k);
            lone.step(&a[i * agents * 2..(i + 1) * agents * 2]);
            lone.observe(&mut o);
            assert_eq!(
                o.as_slice(),
                &obs[i * per..(i + 1) * per],
                "world {i} step {k}"
            );
        }
        assert!(lone.done(), "every agent truncated at 1 s");
        let fresh = TeamEnv::new(t.clone(), &s, next_seed(20 + i as u64)).unwrap();
        fresh.observe(&mut o);
        assert_eq!(o.as_slice(), &runs[0][steps - 1].0[i * per..(i + 1) * per]);
    }
    let last = &runs[0][steps - 1].1;
    assert!(
        last.contains("reset: true") && !last.contains("reset: false"),
        "{last}"
    );
    assert!(!last.contains("active: true"), "{last}");
}

/// A team run started again (`TeamRunner::reset`, what a session's restart does) runs exactly
/// as a fresh one: every robot's samples are byte-identical (the world, its commands, sensors
/// and outcomes all start over).
#[test]
fn a_team_run_reset_runs_as_a_fresh_one() {
    let sc = tracksim::load_scenario(&root().join("scenarios/team/convoy.toml")).unwrap();
    let run_for = |r: &mut tracksim::run::TeamRunner, steps: usize| {
        for _ in 0..steps {
            r.step().unwrap();
        }
    };
    let mut fresh = tracksim::run::TeamRunner::new(&sc).unwrap();
    run_for(&mut fresh, 1500);
    let mut again = tracksim::run::TeamRunner::new(&sc).unwrap();
    run_for(&mut again, 700);
    again.reset().unwrap();
    assert_eq!(again.sim().time(), 0.0);
    run_for(&mut again, 1500);
    let (a, b) = (
        fresh.finish(tracksim::run::End::Reached),
        again.finish(tracksim::run::End::Reached),
    );
    for ((name, ra), (_, rb)) in a.robots.iter().zip(&b.robots) {
        assert_eq!(
            tracksim::output::trajectory_csv(ra),
            tracksim::output::trajectory_csv(rb),
            "robot {name}"
        );
    }
    assert!(a.robots[0].1.summary.final_pose.x > 0.2, "the leader drove");
}
