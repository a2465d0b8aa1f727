//! Issue 42, "bring your own robot": `tracksim::import` against real models as they are found
//! (`../shared/robots/`, other people's files, never copied here; each test skips with a
//! message when the folder is absent) and against a two-track URDF written here with the
//! geometry of gz-sim's `simple_tracked` robot. Each imported model: the proposed path matches
//! the model's geometry, the written files load (what `check` does), and a run on flat ground at
//! a commanded belt speed moves the chassis at that speed within 2 %.

use std::path::{Path, PathBuf};
use tracksim::import::{ImportReport, ProposedPath, ProposedTrack};
use tracksim::spec::GrouserShapeSpec;
use tracksim::{Scripted, load_scenario, load_vehicle};

const ROBOTS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/robots");

/// The model `rel` under the shared robots folder, or `None` (with a skip message) without it.
fn model(rel: &str) -> Option<PathBuf> {
    let p = Path::new(ROBOTS).join(rel);
    if p.exists() {
        Some(p)
    } else {
        println!(
            "SKIPPED: {} is absent (the shared robots folder)",
            p.display()
        );
        None
    }
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tracksim-import-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn pulleys(t: &ProposedTrack) -> Vec<[f64; 3]> {
    match &t.path {
        ProposedPath::Pulleys(p) => p.iter().map(|q| [q.x, q.z, q.radius]).collect(),
        ProposedPath::Wheel(w) => vec![[w.x, w.z, w.radius]],
    }
}

/// Two pulleys at x = +-`half`, z = 0 of radius `r` (either order), within 1e-6 m (the
/// importer reads the numbers as written; only the f64 parsing rounds).
fn assert_two_pulleys(t: &ProposedTrack, half: f64, r: f64) {
    let mut p = pulleys(t);
    p.sort_by(|a, b| a[0].total_cmp(&b[0]));
    assert_eq!(p.len(), 2, "{p:?}");
    for (q, x) in p.iter().zip([-half, half]) {
        assert!(
            (q[0] - x).abs() < 1e-6 && q[1].abs() < 1e-6 && (q[2] - r).abs() < 1e-6,
            "{p:?}"
        );
    }
    let perimeter = 4.0 * half + std::f64::consts::TAU * r;
    let got = t.perimeter().unwrap();
    // The pulley loop is built in f64 from tangents: 1 um.
    assert!(
        (got - perimeter).abs() < 1e-6,
        "perimeter {got} m, geometry {perimeter} m"
    );
}

/// Imports `model` into a scratch folder and loads both files back (`tracksim check`).
fn import(model: &Path, name: &str) -> (ImportReport, PathBuf) {
    let out = scratch(name);
    let done = tracksim::import::import(model, &out, false).unwrap();
    load_vehicle(&done.vehicle).expect("the vehicle file loads");
    load_scenario(&done.scenario).expect("the scenario loads");
    let text = std::fs::read_to_string(&done.vehicle).unwrap();
    // The report is at the top of the file as comments, every guess included.
    for l in done.report.lines() {
        assert!(text.contains(&format!("# {l}")), "missing comment {l}");
    }
    (done.report, done.scenario)
}

/// Mean speed over the ground (m/s, from the body's x-y) and yaw rate (rad/s) over 2..6 s of
/// the written scenario, with its belt-speed line replaced by `cmd` if given. The window starts
/// at 2 s: the belt reaches its speed within the first steps and the body settles onto its
/// grousers within ~0.5 s; 4 s averages over many grouser pitches passing (0.05 m at 0.3 m/s
/// takes 0.17 s), so the grousers' ripple is averaged out.
fn run(scenario: &Path, cmd: Option<&str>) -> (Scripted, f64, f64) {
    let mut path = scenario.to_path_buf();
    if let Some(c) = cmd {
        let text = std::fs::read_to_string(scenario).unwrap();
        assert!(text.contains("belt_speed_mps = 0.3\n"), "{text}");
        path = scenario.with_file_name("turn.toml");
        std::fs::write(
            &path,
            text.replace("belt_speed_mps = 0.3\n", &format!("belt_speed_mps = {c}\n")),
        )
        .unwrap();
    }
    let sc = load_scenario(&path).unwrap();
    let mut sim = Scripted::new(&sc).unwrap();
    while sim.time() < 2.0 - 1e-9 {
        sim.step().unwrap();
    }
    let (p0, yaw0) = (sim.body_pose(), sim.body_pose().yaw);
    while sim.time() < 6.0 - 1e-9 {
        sim.step().unwrap();
    }
    let p1 = sim.body_pose();
    let dist = ((p1.x - p0.x).powi(2) + (p1.y - p0.y).powi(2)).sqrt();
    (sim, dist / 4.0, (p1.yaw - yaw0) / 4.0)
}

/// Within 2 % of the commanded 0.3 m/s (the issue's bound: with grousers or a belt on friction
/// 0.5-0.6 the tracks must not slip on flat ground).
fn assert_belt_speed(v: f64) {
    println!("mean speed over 2..6 s: {v:.5} m/s (commanded 0.3)");
    assert!(
        (v - 0.3).abs() < 0.02 * 0.3,
        "mean speed {v} m/s, commanded 0.3 m/s"
    );
}

#[test]
fn the_papers_plugin_gives_its_path_and_trapezoid_grousers() {
    let Some(m) = model("okada_plugin_example/example_track_gazebo.urdf") else {
        return;
    };
    let (r, scenario) = import(&m, "okada");
    assert_eq!(r.tracks.len(), 1);
    let t = &r.tracks[0];
    assert_eq!(t.link, "body", "the segments hang on the body");
    // Straights 0.7 m, arcs r 0.115 m about x = +-0.35 m.
    assert_two_pulleys(t, 0.35, 0.115);
    assert!((t.width - 0.5).abs() < 1e-9 && (t.belt_mass - 0.4).abs() < 1e-9);
    assert_eq!(t.sprocket_pitch_radius, Some(0.12));
    let g = t.grousers.as_ref().unwrap();
    assert_eq!(g.count, 40);
    // Pitch 53.1 mm (perimeter 2.1226 m / 40), to the README's 0.1 mm.
    let pitch = t.perimeter().unwrap() / g.count as f64;
    assert!((pitch - 0.0531).abs() < 0.00005, "pitch {pitch} m");
    match g.shapes.as_slice() {
        [
            GrouserShapeSpec::Box {
                length_m, height_m, ..
            },
            GrouserShapeSpec::Trapezoid {
                bottom_m,
                top_m,
                height_m: h,
                ..
            },
        ] => {
            // The plugin centres its 2 x 2 cm box and its 4/2 cm x 2 cm trapezoid on the path
            // (the belt segments' outer face), half inside the belt: what stands out of it is
            // a 2 cm x 1 cm box and a trapezoid 3 cm at the belt (halfway from 4 to 2), 2 cm
            // at its tip, 1 cm high.
            assert!((length_m - 0.02).abs() < 1e-9 && (height_m - 0.01).abs() < 1e-9);
            assert!((bottom_m - 0.03).abs() < 1e-9 && (top_m - 0.02).abs() < 1e-9);
            assert!((h - 0.01).abs() < 1e-9);
        }
        s => panic!("grousers {s:?}"),
    }
    // With the elements standing 2 cm out of the belt (the whole element on the path, before
    // the part inside the belt was cut) it ran 1.9 % fast: grouser tips on the 11.5 cm arcs
    // push off faster than the belt ((r + h) / r). With the model's 1 cm: 0.3021 m/s (+0.7 %).
    let (sim, v, _) = run(&scenario, None);
    assert_belt_speed(v);
    // One track on the mid-plane: the encoders give the forward speed (its odometry was 0
    // before issue 42), within 3 % of the distance.
    let (odom, true_x) = (sim.sample().odom, sim.body_pose().x);
    println!("odometry x {:.4} m, true x {true_x:.4} m", odom[0]);
    assert!(true_x > 1.5 && (odom[0] - true_x).abs() < 0.03 * true_x);
}

#[test]
fn the_simple_plugin_gives_its_geometry_and_runs_on_the_belt() {
    let Some(m) = model("okada_plugin_example/example_track_simple_gazebo.urdf") else {
        return;
    };
    let (r, scenario) = import(&m, "okada-simple");
    let t = &r.tracks[0];
    // The geometry (r 0.125 m) wins over the segments' pitch_diameter 0.24 m, which is reported.
    assert_two_pulleys(t, 0.35, 0.125);
    assert!(t.grousers.is_none(), "the simple plugin has no pattern");
    assert!(
        r.lines()
            .iter()
            .any(|l| l.contains("pitch_diameter 0.24 m")),
        "{:#?}",
        r.lines()
    );
    let (_, v, _) = run(&scenario, None);
    assert_belt_speed(v);
}

/// A two-track robot with the track geometry of gz-sim's `simple_tracked` (tracks: a box
/// 0.5 x 0.09728 x 0.18094 m with cylinders r 0.09047 m at x = +-0.25 m, on links at
/// y = +-0.1985 m) as URDF, with a TrackedVehicle plugin whose `tracks_separation` (0.63 m) is
/// far from the geometry's 0.397 m, as the issue reports.
fn two_track_urdf(dir: &Path) -> PathBuf {
    let track = |side: &str, y: f64| {
        format!(
            r#"<link name="{side}_track"><inertial><mass value="6.06"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
  <collision><origin xyz="0 0 0.01855"/><geometry><box size="0.5 0.09728 0.18094"/></geometry></collision>
  <collision><origin xyz="0.25 0 0.01855" rpy="1.5708 0 0"/><geometry><cylinder radius="0.09047" length="0.09728"/></geometry></collision>
  <collision><origin xyz="-0.25 0 0.01855" rpy="1.5708 0 0"/><geometry><cylinder radius="0.09047" length="0.09728"/></geometry></collision></link>
<joint name="{side}_track_j" type="fixed"><parent link="base_link"/><child link="{side}_track"/><origin xyz="0 {y} 0"/></joint>
"#
        )
    };
    let urdf = format!(
        r#"<robot name="two_track">
<link name="base_link"><inertial><origin xyz="-0.122 0 0.118"/><mass value="13.14"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.3" iyz="0" izz="0.3"/></inertial>
  <collision><origin xyz="-0.122 0 0.118"/><geometry><box size="0.50017 0.24093 0.139"/></geometry></collision></link>
{}{}<gazebo><plugin filename="gz-sim-tracked-vehicle-system" name="gz::sim::systems::TrackedVehicle">
  <left_track><link>left_track</link></left_track><right_track><link>right_track</link></right_track>
  <tracks_separation>0.63</tracks_separation><tracks_height>0.18094</tracks_height></plugin></gazebo>
</robot>"#,
        track("left", 0.1985),
        track("right", -0.1985)
    );
    let p = dir.join("two_track.urdf");
    std::fs::write(&p, urdf).unwrap();
    p
}

#[test]
fn a_two_track_robot_from_its_shapes_drives_turns_and_its_plugin_is_checked() {
    let dir = scratch("two-track-model");
    let (r, scenario) = import(&two_track_urdf(&dir), "two-track");
    let names: Vec<&str> = r.tracks.iter().map(|t| t.name.as_str()).collect();
    assert_eq!(names, ["left", "right"]);
    for t in &r.tracks {
        // The cylinders' circles (r 0.09047 m at x = +-0.25 m, z = 0.01855 m in the link).
        let mut p = pulleys(t);
        p.sort_by(|a, b| a[0].total_cmp(&b[0]));
        assert!(
            (p[0][0] + 0.25).abs() < 1e-6 && (p[1][0] - 0.25).abs() < 1e-6,
            "{p:?}"
        );
        assert!(
            p.iter()
                .all(|q| (q[1] - 0.01855).abs() < 1e-6 && (q[2] - 0.09047).abs() < 1e-6)
        );
        assert!((t.width - 0.09728).abs() < 1e-6);
        // Height 2 r = 0.18094 m: the plugin's tracks_height agrees (no warning for it).
        assert!((t.height() - 0.18094).abs() < 1e-6);
    }
    let g = r.geometry;
    assert!((g.separation.unwrap() - 0.397).abs() < 1e-6);
    let w = r.warnings();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("tracks_separation") && w[0].contains("0.63"),
        "{w:?}"
    );
    // `check` warns too (the vehicle compile's URDF report).
    let v = load_vehicle(&scenario.with_file_name("two_track.toml")).unwrap();
    let lines = v.urdf.as_ref().unwrap().lines().join("\n");
    assert!(
        lines.contains("warning") && lines.contains("tracks_separation"),
        "{lines}"
    );

    let (sim, v, _) = run(&scenario, None);
    assert_belt_speed(v);
    // The tracks are on the chassis: the odometry's distance follows the belts (3 %: the
    // encoders count belt travel, which equals ground travel without slip).
    let odom = sim.sample().odom;
    let true_x = sim.body_pose().x;
    println!("odometry x {:.4} m, true x {true_x:.4} m", odom[0]);
    assert!(
        (odom[0] - true_x).abs() < 0.03 * true_x,
        "odometry x {} m, true {true_x} m",
        odom[0]
    );

    // Left 0.1 m/s, right 0.3 m/s: a left turn (positive yaw). Without slip the rate would be
    // (0.3 - 0.1) / 0.397 = 0.504 rad/s; skid steering slips, so the rate is lower, but a
    // track length/separation ratio of 1.5 turns readily: between 30 % and 105 % of it.
    let (_, _, yaw_rate) = run(&scenario, Some("{ left = 0.1, right = 0.3 }"));
    let ideal = 0.2 / 0.397;
    println!("yaw rate {yaw_rate:.4} rad/s, no-slip {ideal:.4} rad/s");
    assert!(
        yaw_rate > 0.3 * ideal && yaw_rate < 1.05 * ideal,
        "yaw rate {yaw_rate} rad/s, no-slip {ideal} rad/s"
    );
}

#[test]
fn the_gz_sim_example_in_sdf_is_imported_drives_turns_and_keeps_its_odometry() {
    let Some(m) = model("gz_sim_examples/tracked_vehicle_simple.sdf") else {
        return;
    };
    let r = tracksim::import::propose(&m).unwrap();
    // gz-sim lists each side's flippers under <left_track> / <right_track> too: told by link.
    let main: Vec<&ProposedTrack> = r
        .tracks
        .iter()
        .filter(|t| !t.link.contains("flipper"))
        .collect();
    assert_eq!(main.len(), 2, "left and right");
    for t in main {
        assert_two_pulleys_at(t, 0.25, 0.09047);
        assert!((t.chassis_y.abs() - 0.1985).abs() < 1e-4);
    }
    let flippers: Vec<&ProposedTrack> = r
        .tracks
        .iter()
        .filter(|t| t.link.contains("flipper"))
        .collect();
    assert_eq!(flippers.len(), 4);
    for f in flippers {
        let mut radii: Vec<f64> = pulleys(f).iter().map(|q| q[2]).collect();
        radii.sort_by(f64::total_cmp);
        assert!(
            (radii[0] - 0.029).abs() < 1e-6 && (radii[1] - 0.089).abs() < 1e-6,
            "{radii:?}"
        );
    }

    // The whole of it: imported, run on flat ground at 0.3 m/s (the written scenario).
    let (_, scenario) = import(&m, "gz-simple-tracked");
    // The file is a world: world.toml holds its static models as terrain (the ground and the
    // 21 boxes of its stairs and obstacles; the cylinder and the Fuel pallet are listed as left
    // out) with the robot at its pose there, (3, 0).
    let world = scenario.with_file_name(tracksim::import::WORLD_FILE);
    let text = std::fs::read_to_string(&world).unwrap();
    assert!(
        text.contains("left out of the world") && text.contains("cylinder"),
        "{text}"
    );
    let ws = load_scenario(&world).unwrap();
    assert_eq!(ws.start_xy, (3.0, 0.0));
    // Run to its end (20 s at 0.3 m/s): it completes, and the robot drives ahead and onto the
    // world's stairs (measured: x 8.19 m, z 1.42 m; the bounds keep a wide margin, as the climb
    // itself is issue 38's concern).
    let mut sim = Scripted::new(&ws).unwrap();
    while sim.time() < ws.duration - 1e-9 {
        sim.step().unwrap();
    }
    let p = sim.body_pose();
    println!(
        "world.toml at its end: x {:.3} z {:.3} m, pitch {:.3} rad",
        p.x, p.z, p.pitch
    );
    assert!(p.x > 6.0 && p.z > 0.5 && p.y.abs() < 0.5, "{p:?}");
    let sc = load_scenario(&scenario).unwrap();
    // The plugin names the sides: Gazebo's rule, one speed per side, B its tracks_separation.
    assert!(sc.vehicle.steering.per_side && sc.vehicle.steering.separation == 0.4);
    let (sim, v, _) = run(&scenario, None);
    assert_belt_speed(v);
    // Odometry against the truth over the whole run (3 % of the distance, the issue's bound).
    let (odom, p) = (sim.sample().odom, sim.body_pose());
    let (x0, y0) = sc.start_xy;
    let truth = (p.x - x0).hypot(p.y - y0);
    let err = (odom[0] - (p.x - x0)).hypot(odom[1] - (p.y - y0));
    println!("odometry error {err:.4} m over {truth:.4} m");
    assert!(
        truth > 1.5 && err < 0.03 * truth,
        "error {err} m over {truth} m"
    );

    // A twist: 0.2 m/s and 0.4 rad/s, every track of a side at one speed as gz gives it. The
    // robot turns left; skid steering slips (six tracks, the four flippers' among them), so
    // the rate is below the commanded 0.4 rad/s, and above a third of it.
    let text = std::fs::read_to_string(&scenario).unwrap();
    let twist = scenario.with_file_name("twist.toml");
    std::fs::write(
        &twist,
        text.replace(
            "belt_speed_mps = 0.3\n",
            "forward_mps = 0.2\nyaw_rate_rad_s = 0.4\n",
        ),
    )
    .unwrap();
    let sc = load_scenario(&twist).unwrap();
    let mut sim = Scripted::new(&sc).unwrap();
    while sim.time() < 2.0 - 1e-9 {
        sim.step().unwrap();
    }
    let (yaw0, odom0) = (sim.body_pose().yaw, sim.sample().odom[2]);
    let belts0 = sim.sample().belt_speed.clone();
    while sim.time() < 6.0 - 1e-9 {
        sim.step().unwrap();
    }
    let rate = (sim.body_pose().yaw - yaw0) / 4.0;
    let odom_rate = (sim.sample().odom[2] - odom0) / 4.0;
    println!("twist: yaw rate {rate:.4} rad/s (odometry {odom_rate:.4}), belts {belts0:.4?}");
    assert!(rate > 0.4 / 3.0 && rate < 0.4, "yaw rate {rate} rad/s");
    // One speed per side: every left belt at 0.2 - 0.4 * 0.2 = 0.12 m/s, every right one at
    // 0.28 m/s (the belts follow their motors within 2 %).
    for (t, b) in sc.vehicle.tracks.iter().zip(&belts0) {
        let want = if t.lateral_offset() > 0.0 { 0.12 } else { 0.28 };
        assert!(
            (b - want).abs() < 0.02 * want,
            "{}: {b} m/s, want {want}",
            t.name
        );
    }
}

#[test]
fn gz_sims_track_drive_wheels_become_the_belts_path() {
    let Some(m) = model("gz_sim_examples/track_drive.sdf") else {
        return;
    };
    // Two robots in the file: without a name it is refused, naming both.
    let e = tracksim::import::propose(&m).unwrap_err().to_string();
    assert!(
        e.contains("vehicle_blue") && e.contains("vehicle_green"),
        "{e}"
    );
    let out = scratch("track-drive");
    let done = tracksim::import::import_model(&m, Some("vehicle_blue"), &out, false).unwrap();
    // Its "tracks" are eight road wheels (r 0.09047 m, x from -0.25 to 0.25 m) a side turning
    // on their joints under a small box: the wheels' hull is the belt's path.
    assert_eq!(done.report.tracks.len(), 2, "{:#?}", done.report.lines());
    for t in &done.report.tracks {
        assert_two_pulleys_at(t, 0.25, 0.09047);
        assert!((t.chassis_y.abs() - 0.1985).abs() < 1e-4);
    }
    assert!(done.world.is_some(), "the file is a world");
    let (sim, v, _) = run(&done.scenario, None);
    assert_belt_speed(v);
    let sc = load_scenario(&done.scenario).unwrap();
    let (odom, p) = (sim.sample().odom, sim.body_pose());
    let (x0, y0) = sc.start_xy;
    let truth = (p.x - x0).hypot(p.y - y0);
    let err = (odom[0] - (p.x - x0)).hypot(odom[1] - (p.y - y0));
    println!("track_drive: odometry error {err:.4} m over {truth:.4} m");
    assert!(
        truth > 1.5 && err < 0.03 * truth,
        "error {err} m over {truth} m"
    );
    // Sides at 0.1 and 0.3 m/s: a left turn, slower than the no-slip 0.2 / 0.397 rad/s.
    let (_, _, rate) = run(
        &done.scenario,
        Some("{ left_track = 0.1, right_track = 0.3 }"),
    );
    let ideal = 0.2 / 0.397;
    println!("track_drive: yaw rate {rate:.4} rad/s, no-slip {ideal:.4}");
    assert!(
        rate > 0.3 * ideal && rate < 1.05 * ideal,
        "yaw rate {rate} rad/s"
    );
}

/// Pulleys at x = +-`half` of radius `r` (any z), 1e-5 m (an SDF pose's rounding).
fn assert_two_pulleys_at(t: &ProposedTrack, half: f64, r: f64) {
    let mut p = pulleys(t);
    p.sort_by(|a, b| a[0].total_cmp(&b[0]));
    assert_eq!(p.len(), 2, "{p:?}");
    assert!(
        (p[0][0] + half).abs() < 1e-5 && (p[1][0] - half).abs() < 1e-5,
        "{p:?}"
    );
    assert!(p.iter().all(|q| (q[2] - r).abs() < 1e-5), "{p:?}");
}

#[test]
fn a_model_without_tracks_is_refused_naming_the_file() {
    let dir = scratch("no-tracks");
    let p = dir.join("box_robot.urdf");
    std::fs::write(
        &p,
        r#"<robot name="box"><link name="base"><inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
<collision><geometry><box size="0.5 0.3 0.2"/></geometry></collision></link></robot>"#,
    )
    .unwrap();
    let e = tracksim::import::import(&p, &dir.join("out"), false)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("box_robot.urdf") && e.contains("no tracks found"),
        "{e}"
    );
    assert!(
        !dir.join("out").exists(),
        "nothing is written for a model without tracks"
    );
}

#[test]
fn track_links_found_by_name_with_boxes_only_get_a_stadium() {
    // No plugin: links named "*track*" with collisions are the tracks; a box 0.6 x 0.08 x
    // 0.16 m gives the stadium of its x-z extent: ends of radius 0.08 m at x = +-0.22 m.
    let dir = scratch("named-model");
    let track = |side: &str, y: f64| {
        format!(
            r#"<link name="{side}_track"><inertial><mass value="2"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
  <collision><geometry><box size="0.6 0.08 0.16"/></geometry></collision></link>
<joint name="{side}_j" type="fixed"><parent link="base"/><child link="{side}_track"/><origin xyz="0 {y} 0"/></joint>
"#
        )
    };
    let p = dir.join("boxes.urdf");
    std::fs::write(
        &p,
        format!(
            r#"<robot name="boxes"><link name="base"><inertial><mass value="8"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.2"/></inertial>
<collision><origin xyz="0 0 0.05"/><geometry><box size="0.5 0.2 0.1"/></geometry></collision></link>{}{}</robot>"#,
            track("left", 0.15),
            track("right", -0.15)
        ),
    )
    .unwrap();
    let (r, scenario) = import(&p, "named");
    assert_eq!(r.source, tracksim::import::TrackSource::LinkNames);
    assert_eq!(r.tracks.len(), 2);
    for t in &r.tracks {
        assert_two_pulleys(t, 0.22, 0.08);
        assert!((t.width - 0.08).abs() < 1e-9);
        // 10 % of the link's 2 kg.
        assert!((t.belt_mass - 0.2).abs() < 1e-9);
    }
    assert!((r.geometry.separation.unwrap() - 0.3).abs() < 1e-9);
    let (_, v, _) = run(&scenario, None);
    assert_belt_speed(v);
}

#[test]
fn the_bundled_packbot_urdf_gives_the_hand_measured_main_tracks() {
    // vehicles/packbot510_urdf.toml measured the main tracks by hand: pulleys at x = +-0.255 m
    // of r 0.082 m, width 0.075 m, on left_track / right_track (0.325 m apart, as the plugin's
    // tracks_separation). The import finds them from the plugin and the links' boxes.
    let urdf = crate::common::root().join("vehicles/urdf/packbot510_flippers.urdf");
    let r = tracksim::import::propose(&urdf).unwrap();
    assert_eq!(r.source, tracksim::import::TrackSource::TrackedVehicle);
    for (name, link) in [("left", "left_track"), ("right", "right_track")] {
        let t = r.tracks.iter().find(|t| t.name == name).unwrap();
        assert_eq!(t.link, link);
        assert_two_pulleys(t, 0.255, 0.082);
        assert!((t.width - 0.075).abs() < 1e-9);
    }
    assert_eq!(r.flippers, ["front_left", "front_right"]);
    assert!((r.geometry.separation.unwrap() - 0.325).abs() < 1e-9);
    assert!(r.warnings().is_empty(), "{:?}", r.warnings());
}
