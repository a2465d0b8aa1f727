//! The `tracksim` binary as a user runs it (issue 3): each subcommand, each output file and its
//! columns, each exit code, and the message every kind of bad input gets.

#![warn(clippy::too_many_lines)]

use assert_cmd::Command;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn tracksim() -> Command {
    let mut c = Command::cargo_bin("tracksim").unwrap();
    c.current_dir(root());
    c
}

/// Writes a scenario into a temp dir, its vehicle path made absolute.
fn scenario(dir: &Path, name: &str, text: &str) -> PathBuf {
    let vehicles = root().join("vehicles").canonicalize().unwrap();
    let text = text.replace("VEHICLES", &vehicles.display().to_string());
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

const FLAT: &str = r#"
[vehicle]
file = "VEHICLES/packbot510.toml"
[terrain.ground]
friction = 0.6
[simulation]
duration_s = 0.3
[[commands]]
belt_speed_mps = 0.3
"#;

struct Out {
    code: i32,
    stdout: String,
    stderr: String,
}

fn run(args: &[&str]) -> Out {
    let o = tracksim().args(args).output().unwrap();
    Out {
        code: o.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&o.stdout).into(),
        stderr: String::from_utf8_lossy(&o.stderr).into(),
    }
}

#[test]
fn run_writes_summary_and_trajectory_with_their_columns() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let o = run(&[
        "run",
        "scenarios/packbot_flat.toml",
        "--duration",
        "0.5",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(o.stdout.contains("real-time factor"), "{}", o.stdout);
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    for k in [
        "sim_time_s",
        "wall_time_s",
        "real_time_factor",
        "mean_speed_mps",
        "outcome",
    ] {
        assert!(s.get(k).is_some(), "summary lacks {k}: {s}");
    }
    for k in ["x", "y", "z", "roll", "pitch", "yaw"] {
        assert!(s["final_pose"][k].is_f64(), "final_pose.{k}");
    }
    assert!((s["sim_time_s"].as_f64().unwrap() - 0.5).abs() < 1e-9);
    assert!(s["final_pose"]["x"].as_f64().unwrap() > 0.1, "it drove");
    let csv = std::fs::read_to_string(out.join("trajectory.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    for c in [
        "t_s",
        "x_m",
        "y_m",
        "z_m",
        "roll_rad",
        "pitch_rad",
        "yaw_rad",
        "vx_mps",
        "vy_mps",
        "vz_mps",
        "wx_rad_s",
        "wy_rad_s",
        "wz_rad_s",
        "belt_speed_left_mps",
        "belt_speed_right_mps",
        "belt_phase_left_m",
        "belt_phase_right_m",
        "contacts",
        "penetration_m",
    ] {
        assert!(header.contains(&c), "missing column {c} in {header:?}");
    }
    let rows: Vec<&str> = lines.collect();
    // 0.5 s at the default 10 ms interval, plus the row at t = 0.
    assert_eq!(rows.len(), 51);
    assert!(rows.iter().all(|r| r.split(',').count() == header.len()));
    for f in ["plot.png", "plot.svg"] {
        assert!(out.join(f).is_file(), "{f} not written");
    }
}

#[test]
fn run_json_prints_the_summary() {
    let tmp = tempfile::tempdir().unwrap();
    let f = scenario(tmp.path(), "s.toml", FLAT);
    let o = run(&[
        "run",
        f.to_str().unwrap(),
        "--json",
        "--no-plot",
        "--out",
        tmp.path().join("o").to_str().unwrap(),
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let s: serde_json::Value = serde_json::from_str(&o.stdout).unwrap();
    assert_eq!(s["outcome"], "completed");
    assert_eq!(s["method"], "okada2020");
}

#[test]
fn strict_exits_1_when_the_outcome_is_failure() {
    let tmp = tempfile::tempdir().unwrap();
    let text = format!("{FLAT}\n[outcome]\nsuccess_x_m = 5.0\n");
    let f = scenario(tmp.path(), "s.toml", &text);
    let out = tmp.path().join("o");
    let args = ["run", f.to_str().unwrap(), "--quiet", "--no-plot", "--out"];
    let o = run(&[&args[..], &[out.to_str().unwrap()]].concat());
    assert_eq!(
        o.code, 0,
        "without --strict a failed outcome is still a run"
    );
    let o = run(&[&args[..], &[out.to_str().unwrap(), "--strict"]].concat());
    assert_eq!(o.code, 1, "{}", o.stderr);
    let s = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(s.contains("\"failure\"") && s.contains("timeout"), "{s}");
}

#[test]
fn an_exploding_simulation_exits_3_saying_when_and_which_body() {
    let tmp = tempfile::tempdir().unwrap();
    let f = scenario(
        tmp.path(),
        "s.toml",
        &FLAT.replace("belt_speed_mps = 0.3", "belt_speed_mps = 500.0"),
    );
    let o = run(&[
        "run",
        f.to_str().unwrap(),
        "--no-plot",
        "--out",
        tmp.path().join("o").to_str().unwrap(),
    ]);
    assert_eq!(o.code, 3, "{}", o.stderr);
    assert!(
        o.stderr.contains("unstable at t = ") && o.stderr.contains("body"),
        "{}",
        o.stderr
    );
}

#[test]
fn check_accepts_every_bundled_file() {
    let mut files: Vec<String> = Vec::new();
    for d in ["vehicles", "scenarios"] {
        for e in std::fs::read_dir(root().join(d)).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|e| e == "toml") {
                files.push(format!("{d}/{}", p.file_name().unwrap().to_str().unwrap()));
            }
        }
    }
    assert!(files.len() >= 5);
    let mut args = vec!["check".to_string()];
    args.extend(files.iter().cloned());
    let args: Vec<&str> = args.iter().map(|s| s.as_str()).collect();
    let o = run(&args);
    assert_eq!(o.code, 0, "{}{}", o.stdout, o.stderr);
    assert_eq!(o.stdout.matches("ok ").count(), files.len(), "{}", o.stdout);
}

/// Issue 26: `check` on a URDF vehicle prints what was imported: each link with its joint, the
/// body it became part of, its mass and the track it carries; each arm with limits and torque.
#[test]
fn check_prints_the_links_masses_joints_and_tracks_of_a_urdf_robot() {
    for file in [
        "vehicles/packbot510_urdf.toml",
        "scenarios/packbot_urdf_stairs.toml",
    ] {
        let o = run(&["check", file]);
        assert_eq!(o.code, 0, "{file}: {}{}", o.stdout, o.stderr);
        for want in [
            "robot \"packbot510_flippers\"): 5 links",
            "link base_link: root, part of chassis, 11.000 kg",
            "link left_track: fixed joint left_track_joint, part of chassis",
            "carries track left",
            "carries track right",
            "link front_left_flipper: revolute joint front_left, part of arm front_left, 1.000 kg",
            "carries track flipper_left",
            "arm front_left",
            "arm front_right",
        ] {
            assert!(
                o.stdout.contains(want),
                "{file}: {want:?} not in:\n{}",
                o.stdout
            );
        }
    }
}

#[test]
fn list_names_bundled_files_with_descriptions() {
    let o = run(&["list"]);
    assert_eq!(o.code, 0);
    // Every bundled TOML file on disk is listed, sub-folders included, by name.
    let mut on_disk = Vec::new();
    for top in ["vehicles", "scenarios"] {
        for e in walk(&root().join(top)) {
            if e.extension().is_some_and(|x| x == "toml") {
                let rel = e.strip_prefix(root().join(top)).unwrap();
                on_disk.push(rel.with_extension("").display().to_string());
            }
        }
    }
    assert!(on_disk.len() >= 25, "{on_disk:?}");
    let mut descriptions = Vec::new();
    for name in &on_disk {
        let line = o
            .stdout
            .lines()
            .find(|l| l.split_whitespace().next() == Some(name.as_str()))
            .unwrap_or_else(|| panic!("{name} not listed:\n{}", o.stdout));
        let d = line.trim_start().trim_start_matches(name.as_str()).trim();
        assert!(!d.is_empty(), "{name} has no description");
        descriptions.push(d.to_string());
    }
    let mut distinct = descriptions.clone();
    distinct.sort();
    distinct.dedup();
    assert_eq!(
        distinct.len(),
        descriptions.len(),
        "shared descriptions: {descriptions:#?}"
    );
}

fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(walk(&p));
        } else {
            out.push(p);
        }
    }
    out
}

/// Runs `check` on a scenario text and returns (exit code, everything printed).
fn check_text(text: &str) -> (i32, String) {
    let tmp = tempfile::tempdir().unwrap();
    // Files some cases point at: a "PNG" that is text, and a mesh with vertices but no faces.
    std::fs::write(tmp.path().join("notapng.png"), "hello").unwrap();
    std::fs::write(tmp.path().join("empty.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
    let f = scenario(tmp.path(), "bad.toml", text);
    let o = run(&["check", f.to_str().unwrap()]);
    (o.code, format!("{}{}", o.stdout, o.stderr))
}

/// The bad-input table (docs/ERRORS.md lists the same cases with their messages).
#[test]
fn bad_inputs_exit_2_naming_the_file_the_key_and_the_fix() {
    let cases: Vec<(&str, String, Vec<&str>)> = vec![
        (
            "wrong type",
            FLAT.replace("duration_s = 0.3", "duration_s = \"long\""),
            vec!["bad.toml", "duration_s", "invalid type"],
        ),
        (
            "unknown key",
            FLAT.replace("friction = 0.6", "friction = 0.6\nfrcition = 0.5"),
            vec![
                "bad.toml",
                "line 6",
                "unknown key `frcition`: did you mean `friction`?",
                "The accepted keys are: `friction`",
            ],
        ),
        (
            "negative size",
            format!("{FLAT}\n[[terrain.boxes]]\ncentre_m = [1, 0, 0]\nsize_m = [1, -2, 0.1]\n"),
            vec!["bad.toml", "terrain.boxes[0].size_m[1]", "> 0"],
        ),
        (
            "NaN",
            FLAT.replace("belt_speed_mps = 0.3", "belt_speed_mps = nan"),
            vec!["bad.toml", "commands[0].belt_speed_mps", "finite"],
        ),
        (
            "huge dt",
            FLAT.replace("duration_s = 0.3", "duration_s = 0.3\ndt_s = 0.5"),
            vec!["bad.toml", "simulation.dt_s", "at most 0.01"],
        ),
        (
            "contact slop too deep",
            FLAT.replace("duration_s = 0.3", "duration_s = 0.3\ncontact_slop_m = 0.5"),
            vec![
                "bad.toml",
                "simulation.contact_slop_m",
                "between 0 and 0.02",
            ],
        ),
        (
            "zero duration",
            FLAT.replace("duration_s = 0.3", "duration_s = 0.0"),
            vec!["bad.toml", "simulation.duration_s", "> 0"],
        ),
        (
            "missing vehicle",
            FLAT.replace("packbot510.toml", "nosuch.toml"),
            vec!["bad.toml", "vehicle.file", "nosuch.toml", "not found"],
        ),
        (
            "unknown track in a command",
            FLAT.replace("belt_speed_mps = 0.3", "belt_speed_mps = { lft = 0.3 }"),
            vec![
                "commands[0].belt_speed_mps.lft",
                "no track called",
                "\"left\"",
            ],
        ),
        (
            "unreadable PNG",
            format!(
                "{FLAT}\n[[terrain.heightfields]]\nfile = \"notapng.png\"\nsize_x_m = 2.0\nsize_y_m = 2.0\nmin_z_m = 0.0\nmax_z_m = 0.1\n"
            ),
            vec!["bad.toml", "terrain.heightfields[0].file", "notapng.png"],
        ),
        (
            "mesh with no triangles",
            format!("{FLAT}\n[[terrain.meshes]]\nfile = \"empty.obj\"\n"),
            vec![
                "bad.toml",
                "terrain.meshes[0].file",
                "empty.obj",
                "no triangles",
            ],
        ),
        (
            "not TOML",
            "this is [not toml".to_string(),
            vec!["bad.toml", "TOML parse error"],
        ),
    ];
    for (what, text, needles) in cases {
        let (code, out) = check_text(&text);
        assert_eq!(code, 2, "{what}: exit code, output:\n{out}");
        for n in needles {
            assert!(out.contains(n), "{what}: message lacks {n:?}:\n{out}");
        }
        assert!(!out.contains("panicked"), "{what}: {out}");
    }
}

#[test]
fn a_missing_file_exits_2() {
    let o = run(&[
        "run",
        "scenarios/nosuch.toml",
        "--out",
        "/tmp/tracksim-never",
    ]);
    assert_eq!(o.code, 2);
    assert!(
        o.stderr.contains("scenarios/nosuch.toml") && o.stderr.contains("No such file"),
        "{}",
        o.stderr
    );
    let o = run(&["check", "nosuch.toml"]);
    assert_eq!(o.code, 2);
}

#[test]
fn a_broken_vehicle_lists_every_problem_with_its_key() {
    let text = std::fs::read_to_string(root().join("vehicles/packbot510.toml")).unwrap();
    let text = text
        .replace("mass_kg = 11.0", "mass_kg = -11.0")
        .replace(
            "{ x_m = 0.255, z_m = 0.0, radius_m = 0.082 }",
            "{ x_m = 0.255, z_m = 0.0, radius_m = 0.0 }",
        )
        .replace("count = 40", "count = 0");
    let tmp = tempfile::tempdir().unwrap();
    let f = tmp.path().join("v.toml");
    std::fs::write(&f, text).unwrap();
    let o = run(&["check", f.to_str().unwrap()]);
    assert_eq!(o.code, 2);
    for n in [
        "body.mass_kg",
        "tracks[0].path.pulleys[1]",
        "radius",
        "tracks[0].grousers.count",
    ] {
        assert!(o.stdout.contains(n), "lacks {n}: {}", o.stdout);
    }
}

#[test]
fn compare_runs_the_methods_and_writes_a_table_and_a_plot() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("cmp");
    let o = run(&[
        "compare",
        "scenarios/packbot_flat.toml",
        "--duration",
        "0.3",
        "--methods",
        "okada2020,wheels4,constraint_to_ground",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    for m in ["okada2020", "wheels4", "constraint_to_ground"] {
        assert!(o.stdout.contains(m), "{}", o.stdout);
        assert!(out.join(m).join("trajectory.csv").is_file());
    }
    let csv = std::fs::read_to_string(out.join("compare.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4, "{csv}");
    assert!(out.join("compare.png").is_file() && out.join("compare.svg").is_file());
    let o = run(&[
        "compare",
        "scenarios/packbot_flat.toml",
        "--methods",
        "tank",
    ]);
    assert_eq!(o.code, 2);
    assert!(
        o.stderr.contains("unknown track method \"tank\""),
        "{}",
        o.stderr
    );
}

#[test]
fn run_accepts_a_method_and_rejects_an_unknown_one() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("o");
    let o = run(&[
        "run",
        "scenarios/packbot_flat.toml",
        "--method",
        "wheels13",
        "--duration",
        "0.2",
        "--json",
        "--no-plot",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let s: serde_json::Value = serde_json::from_str(&o.stdout).unwrap();
    assert_eq!(s["method"], "wheels13");
    let o = run(&["run", "scenarios/packbot_flat.toml", "--method", "wheels0"]);
    assert_eq!(o.code, 2);
}

#[test]
fn bench_reports_every_field_as_json_and_writes_csv_and_markdown() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("b");
    let o = run(&[
        "bench",
        "--repeat",
        "2",
        "--duration",
        "0.05",
        "--cases",
        "packbot",
        "--methods",
        "okada2020,wheels4",
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let v: serde_json::Value = serde_json::from_str(&o.stdout).unwrap();
    let methods = v["methods"].as_array().unwrap();
    assert_eq!(methods.len(), 2);
    for m in methods {
        for k in [
            "name",
            "rtf_median",
            "rtf_min",
            "rtf_max",
            "us_per_step",
            "contacts_per_step",
            "ratio_to_4_wheels",
            "paper_rtf",
        ] {
            assert!(m.get(k).is_some(), "{k} missing in {m}");
        }
        assert!(m["rtf_min"].as_f64().unwrap() <= m["rtf_median"].as_f64().unwrap());
        assert!(m["rtf_median"].as_f64().unwrap() <= m["rtf_max"].as_f64().unwrap());
        assert!(m["contacts_per_step"].as_f64().unwrap() > 0.0);
    }
    assert_eq!(methods[1]["ratio_to_4_wheels"].as_f64().unwrap(), 1.0);
    assert_eq!(methods[0]["paper_rtf"].as_f64().unwrap(), 2.79);
    assert_eq!(v["settings"]["dt_s"].as_f64().unwrap(), 0.001);
    assert!(out.join("bench.csv").is_file() && out.join("bench.md").is_file());
    let o = run(&["bench", "--repeat", "0"]);
    assert_eq!(o.code, 2);
}

/// Runs `tracksim ARGS` with a standard output whose reading end is already closed, so that
/// its first write fails with a broken pipe, every time (a `| head` in a shell only sometimes
/// closes before the program writes).
fn with_closed_stdout(args: &[&str]) -> (i32, String) {
    let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("tracksim"))
        .args(args)
        .current_dir(root())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

#[test]
fn a_closed_stdout_ends_the_program_quietly() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let out = out.to_str().unwrap();
    let run = [
        "run",
        "scenarios/packbot_flat.toml",
        "--duration",
        "0.05",
        "--no-plot",
        "--json",
        "--out",
        out,
    ];
    let check = [
        "check",
        "scenarios/packbot_flat.toml",
        "vehicles/packbot510.toml",
    ];
    for args in [&check[..], &["list"], &run] {
        let (code, stderr) = with_closed_stdout(args);
        assert_eq!(code, 0, "{args:?}: {stderr}");
        assert!(stderr.is_empty(), "{args:?}: {stderr}");
    }
}

#[test]
fn realtime_reports_paced_and_compute_speed_apart() {
    let dir = tempfile::tempdir().unwrap();
    let o = run(&[
        "run",
        "scenarios/packbot_flat.toml",
        "--realtime",
        "--json",
        "--no-plot",
        "--duration",
        "0.5",
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let s: serde_json::Value = serde_json::from_str(&o.stdout).unwrap();
    assert_eq!(s["paced"], true);
    // Paced to the wall clock: 0.5 s simulated take at least 0.5 s (sleep granularity 2 ms).
    // (How far below 1 it falls on a loaded machine is the machine's, not a property of the
    // pacing: a lower bound here failed at 0.78 while CI ran beside it.)
    let paced = s["paced_real_time_factor"].as_f64().unwrap();
    assert!(paced > 0.0 && paced <= 1.01, "paced {paced}");
    assert!(s["elapsed_time_s"].as_f64().unwrap() >= 0.49);
    // The compute speed is the stepping alone, and stepping is faster than the wall clock.
    let compute = s["real_time_factor"].as_f64().unwrap();
    assert!(compute > paced, "compute {compute} vs paced {paced}");
}

#[test]
fn bench_jobs_runs_every_selected_case_and_method() {
    let o = run(&[
        "bench",
        "--jobs",
        "2",
        "--repeat",
        "1",
        "--duration",
        "0.1",
        "--cases",
        "packbot,quince",
        "--methods",
        "okada2020,wheels4",
        "--json",
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let v: serde_json::Value = serde_json::from_str(&o.stdout).unwrap();
    let got: Vec<(String, String)> = v
        .as_array()
        .unwrap()
        .iter()
        .map(|e| {
            (
                e["case"].as_str().unwrap().to_string(),
                e["method"].as_str().unwrap().to_string(),
            )
        })
        .collect();
    let want: Vec<(String, String)> = [
        ("packbot", "okada2020"),
        ("packbot", "wheels4"),
        ("quince", "okada2020"),
        ("quince", "wheels4"),
    ]
    .iter()
    .map(|(a, b)| (a.to_string(), b.to_string()))
    .collect();
    assert_eq!(got, want);
    for e in v.as_array().unwrap() {
        assert_eq!(e["batch"]["runs"], 2);
        assert!((e["batch"]["simulated_s"].as_f64().unwrap() - 0.2).abs() < 1e-6);
    }
}

#[test]
fn check_prints_masses_design_figures_and_warnings() {
    let o = run(&["check", "scenarios/packbot_flat.toml"]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(
        o.stdout
            .contains("mass simulated 13.000 kg (file 13.000 kg)"),
        "{}",
        o.stdout
    );
    assert!(o.stdout.contains("track left"), "{}", o.stdout);
    assert!(
        o.stdout
            .contains("40 grousers: pitch 38.4 mm, grouser 5.0 mm, gap 33.4 mm"),
        "{}",
        o.stdout
    );
    // 3,600 grousers on a 1.5 m loop overlap: a warning, not an error.
    let dir = tempfile::tempdir().unwrap();
    let text = FLAT.replace("[terrain.ground]", "grouser_count = 3600\n[terrain.ground]");
    let f = scenario(dir.path(), "dense.toml", &text);
    let o = run(&["check", f.to_str().unwrap()]);
    assert_eq!(o.code, 0, "{}", o.stdout);
    assert!(
        o.stdout
            .contains("warning: track left: its 3600 grousers overlap"),
        "{}",
        o.stdout
    );
}

/// Issue 28.3: `run --trainee` records the trainee and the start date; `sessions` tabulates the
/// folder (text and CSV into a file), warns about a broken summary and refuses a bad folder or
/// sort key with exit 2.
#[test]
fn sessions_tabulates_runs_with_their_trainee() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let text = format!(
        "{FLAT}[course]\nname = \"line\"\n[[course.gates]]\nx_m = 0.05\ny_m = 0.0\nwidth_m = 1.0\n"
    );
    let s = scenario(d, "s.toml", &text);
    let out = d.join("runs/a");
    let (s, o) = (s.to_str().unwrap(), out.to_str().unwrap());
    let r = run(&["run", s, "--out", o, "--no-plot", "--trainee", "Ada"]);
    assert_eq!(r.code, 0, "{}{}", r.stdout, r.stderr);
    assert!(
        r.stdout.contains("course     line: 1 of 1 repetitions"),
        "{}",
        r.stdout
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["trainee"], "Ada");
    assert_eq!(summary["course"]["score"]["repetitions"], 1);
    std::fs::create_dir_all(d.join("runs/broken")).unwrap();
    std::fs::write(d.join("runs/broken/summary.json"), "nope").unwrap();
    let runs = d.join("runs");
    let r = run(&["sessions", runs.to_str().unwrap(), "--sort", "score"]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    let lines: Vec<&str> = r.stdout.lines().collect();
    assert_eq!(lines[0], "course line: 1 sessions", "{}", r.stdout);
    assert!(lines[2].starts_with("Ada "), "{}", r.stdout);
    // The status and the folder relative to the folder given.
    assert!(
        lines[2].contains(" completed ") && lines[2].ends_with(" a"),
        "{}",
        r.stdout
    );
    assert!(r.stderr.contains("broken/summary.json"), "{}", r.stderr);
    let r = run(&["sessions", runs.to_str().unwrap(), "--leaderboard"]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    let l: Vec<&str> = r.stdout.lines().collect();
    assert!(l[0].starts_with("course  rank  trainee"), "{}", r.stdout);
    assert!(
        l[1].starts_with("line    1     Ada      1          1  "),
        "{}",
        r.stdout
    );
    let csv = d.join("t.csv");
    let r = run(&[
        "sessions",
        runs.to_str().unwrap(),
        "--csv",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    let t = std::fs::read_to_string(&csv).unwrap();
    assert!(t.lines().nth(1).unwrap().starts_with("Ada,"), "{t}");
    let r = run(&["sessions", d.join("missing").to_str().unwrap()]);
    assert_eq!(r.code, 2, "{}", r.stderr);
    let r = run(&["sessions", runs.to_str().unwrap(), "--sort", "speed"]);
    assert_eq!(r.code, 2, "{}", r.stderr);
    assert!(r.stderr.contains("--sort"), "{}", r.stderr);
    let r = run(&["run", s, "--out", o, "--trainee", ""]);
    assert_eq!(r.code, 2, "{}", r.stderr);
}

/// Issue 38: `run --ensemble N` writes every member's folder and the ensemble's files and
/// prints the verdict; `--strict` exits 1 when the file's `[expect]` ensemble bounds are
/// missed; a bad size names its flag; `compare --ensemble` prints a verdict per method.
#[test]
fn run_and_compare_ensembles() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("ens");
    let step = root().join("scenarios/packbot_step.toml");
    let o = run(&[
        "run",
        step.to_str().unwrap(),
        "--ensemble",
        "3",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.code, 0, "{}{}", o.stdout, o.stderr);
    assert!(o.stdout.contains("S 3/3"), "{}", o.stdout);
    assert!(
        o.stdout.contains("[expect] ensemble bounds met"),
        "{}",
        o.stdout
    );
    for f in ["ensemble.json", "ensemble.csv", "member-002/trajectory.csv"] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let csv = std::fs::read_to_string(out.join("ensemble.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4, "{csv}");
    // A scenario whose bounds cannot hold: 0.3 s is too short to climb, the file wants all 3.
    let short = scenario(
        dir.path(),
        "short.toml",
        &format!(
            "{FLAT}[outcome]\nsuccess_x_m = 5.0\n[expect]\nensemble_members = 3\nsuccess_fraction = [1.0, 1.0]\n"
        ),
    );
    let o = run(&[
        "run",
        short.to_str().unwrap(),
        "--ensemble",
        "3",
        "--strict",
        "--out",
        dir.path().join("short").to_str().unwrap(),
    ]);
    assert_eq!(o.code, 1, "{}{}", o.stdout, o.stderr);
    assert!(
        o.stdout.contains("F 3/3") && o.stdout.contains("missed"),
        "{}",
        o.stdout
    );
    let o = run(&[
        "run",
        step.to_str().unwrap(),
        "--ensemble",
        "4",
        "--ensemble-start-mm",
        "500",
    ]);
    assert_ne!(o.code, 0);
    assert!(o.stderr.contains("--ensemble-start-mm"), "{}", o.stderr);
    let o = run(&[
        "compare",
        step.to_str().unwrap(),
        "--methods",
        "okada2020,constraint_to_ground",
        "--duration",
        "1",
        "--ensemble",
        "2",
        "--out",
        dir.path().join("cmp").to_str().unwrap(),
    ]);
    assert_eq!(o.code, 0, "{}{}", o.stdout, o.stderr);
    assert!(
        o.stdout.contains("| okada2020 | F 2/2 |") && o.stdout.contains("| constraint_to_ground |"),
        "{}",
        o.stdout
    );
}

/// Issue 45: a run folder is marked INCOMPLETE while its run writes it; a run killed with
/// SIGKILL (nothing can clean up) leaves the mark beside an earlier run's files, and `sessions`
/// skips the folder, `video` refuses it naming the mark; a run that finishes leaves none.
#[test]
fn a_killed_runs_folder_is_never_read_as_a_result() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("runs/a");
    let o = out.to_str().unwrap();
    let r = run(&[
        "run",
        "scenarios/packbot_flat.toml",
        "--duration",
        "0.3",
        "--out",
        o,
    ]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    assert!(!out.join("INCOMPLETE").exists());
    let runs = tmp.path().join("runs");
    let r = run(&["sessions", runs.to_str().unwrap()]);
    assert!(r.stdout.contains("no course: 1 sessions"), "{}", r.stdout);
    // A second, long run into the same folder, killed while it simulates.
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_tracksim"))
        .args(["run", "scenarios/packbot_flat.toml", "--duration", "600"])
        .args(["--out", o, "--quiet"])
        .current_dir(root())
        .spawn()
        .unwrap();
    let t0 = std::time::Instant::now();
    while !out.join("INCOMPLETE").exists() && t0.elapsed().as_secs() < 60 {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    assert!(
        out.join("INCOMPLETE").is_file(),
        "the run marked its folder"
    );
    assert!(
        out.join("summary.json").is_file(),
        "the earlier run's files are still there"
    );
    let r = run(&["sessions", runs.to_str().unwrap()]);
    assert_eq!(r.code, 0, "{}", r.stderr);
    // Listed as incomplete (issue 59: a lost session is said, not skipped), never as the
    // earlier run's result it still holds.
    let row = r
        .stdout
        .lines()
        .find(|l| l.ends_with(" a"))
        .unwrap_or_default();
    assert!(row.contains("incomplete"), "{}", r.stdout);
    assert!(!r.stdout.contains("ran to the end"), "{}", r.stdout);
    assert!(r.stderr.contains("INCOMPLETE"), "{}", r.stderr);
    let r = run(&["video", o]);
    assert_eq!(r.code, 2, "{}", r.stderr);
    assert!(
        r.stderr.contains("INCOMPLETE") && r.stderr.contains("killed"),
        "{}",
        r.stderr
    );
}

/// Issue 45: each method's folder of `compare` is marked while its run writes it: a compare
/// that finishes leaves no mark; one killed while a method simulates leaves that method's
/// folder marked beside the earlier compare's files, and `video` refuses it.
#[test]
fn a_killed_compares_method_folder_is_never_read_as_a_result() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("cmp");
    let o = out.to_str().unwrap();
    let args = |d: &'static str| {
        [
            "compare",
            "scenarios/packbot_flat.toml",
            "--methods",
            "okada2020",
            "--duration",
            d,
            "--out",
            o,
        ]
        .map(str::to_string)
    };
    let first = args("0.3");
    let r = run(&first.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(r.code, 0, "{}", r.stderr);
    let dir = out.join("okada2020");
    assert!(dir.join("summary.json").is_file());
    assert!(
        !dir.join("INCOMPLETE").exists(),
        "a finished compare leaves no mark"
    );
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_tracksim"))
        .args(args("600"))
        .current_dir(root())
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let t0 = std::time::Instant::now();
    while !dir.join("INCOMPLETE").exists() && t0.elapsed().as_secs() < 60 {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    assert!(
        dir.join("INCOMPLETE").is_file(),
        "the method's run marked its folder"
    );
    assert!(
        dir.join("summary.json").is_file(),
        "the earlier compare's files stay"
    );
    let r = run(&["video", dir.to_str().unwrap()]);
    assert_eq!(r.code, 2, "{}", r.stderr);
    assert!(r.stderr.contains("INCOMPLETE"), "{}", r.stderr);
}
