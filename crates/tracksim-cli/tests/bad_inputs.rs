//! The corpus of bad files (`crates/tracksim/tests/bad_inputs/`, issue 15) through the binary's
//! `check` and `run`: each must end with exit code 2, the key it names in its first line
//! (`# expect: KEY`) in the message, no panic, a short message and in bounded time; `check`
//! and `run` must agree. Plus what cannot be a committed file (a FIFO, `/dev/zero`, a 2 MB
//! line, a 20,000-point hull), the CLI's flags, a closed standard output, `compare` with every
//! method unstable (exit 3) and Ctrl-C during `run` (exit 130, the run written so far).

#![warn(clippy::too_many_lines)]

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn bin() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_tracksim"))
}

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tracksim/tests/bad_inputs")
}

/// Time limit of one command on bad input: a refusal is immediate (milliseconds); 60 s leaves
/// room for a loaded 2-core machine and still catches a hang or an n^3 check.
const LIMIT: Duration = Duration::from_secs(60);

/// Longest message allowed for one bad file (no 2 MB line echoed whole).
const MAX_MESSAGE: usize = 4_000;

#[path = "support/bounded.rs"]
mod bounded;
use bounded::Ran;

/// Runs the binary with `args` under [`LIMIT`] (killed past it: a hang fails the test).
fn run(args: &[&str]) -> Ran {
    bounded::run_bounded(args, LIMIT, None)
}

/// Asserts that `r` is a clean refusal (exit 2) naming `key`.
fn refused(what: &str, r: &Ran, key: &str) {
    assert!(!r.text.contains("panicked"), "{what}: panic: {}", r.text);
    assert_eq!(r.code, Some(2), "{what}: exit code, output:\n{}", r.text);
    assert!(
        r.text.contains(key),
        "{what}: message lacks {key:?}:\n{}",
        r.text
    );
    assert!(
        r.text.len() <= MAX_MESSAGE,
        "{what}: message of {} bytes",
        r.text.len()
    );
}

fn expected_key(file: &Path) -> String {
    let text = std::fs::read_to_string(file).unwrap();
    text.lines()
        .next()
        .and_then(|l| l.strip_prefix("# expect: "))
        .unwrap_or_else(|| panic!("{} lacks its `# expect: KEY` line", file.display()))
        .trim()
        .to_string()
}

fn toml_files(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    v.sort();
    v
}

/// `tracksim run FILE --quiet --no-plot --out OUT`.
fn run_quietly(file: &Path, out: &Path) -> Ran {
    run(&[
        "run",
        file.to_str().unwrap(),
        "--quiet",
        "--no-plot",
        "--out",
        out.to_str().unwrap(),
    ])
}

#[test]
fn every_bad_scenario_of_the_corpus_is_refused_by_check_and_run_alike() {
    let tmp = tempfile::tempdir().unwrap();
    let files = toml_files(&corpus());
    assert!(files.len() >= 15, "corpus has {} scenarios", files.len());
    for f in files {
        let key = expected_key(&f);
        let name = f.file_name().unwrap().to_string_lossy().into_owned();
        let c = run(&["check", f.to_str().unwrap()]);
        refused(&format!("check {name}"), &c, &key);
        let out = tmp.path().join(&name);
        let r = run_quietly(&f, &out);
        refused(&format!("run {name}"), &r, &key);
        assert!(
            !out.join("summary.json").exists(),
            "run {name} wrote a summary"
        );
        eprintln!("{name}: refused in {:?} / {:?}", c.took, r.took);
    }
}

#[test]
fn every_bad_vehicle_of_the_corpus_is_refused_by_check_and_run_alike() {
    let tmp = tempfile::tempdir().unwrap();
    let files = toml_files(&corpus().join("vehicles"));
    assert!(files.len() >= 10, "corpus has {} vehicles", files.len());
    for f in files {
        let key = expected_key(&f);
        let name = f.file_name().unwrap().to_string_lossy().into_owned();
        refused(
            &format!("check {name}"),
            &run(&["check", f.to_str().unwrap()]),
            &key,
        );
        let s = tmp.path().join(format!("s_{name}"));
        std::fs::write(
            &s,
            format!(
                "[vehicle]\nfile = {:?}\n[terrain.ground]\n[simulation]\nduration_s = 0.2\n",
                f.to_str().unwrap()
            ),
        )
        .unwrap();
        let r = run_quietly(&s, &tmp.path().join(&name));
        refused(&format!("run with {name}"), &r, &key);
    }
}

const FLAT: &str = "[terrain.ground]\n[simulation]\nduration_s = 0.2\n[[commands]]\nt_s = 0.0\nbelt_speed_mps = 0.3\n";

fn vehicle_line() -> String {
    let v = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../vehicles/packbot510.toml");
    format!("[vehicle]\nfile = {:?}\n", v.to_str().unwrap())
}

/// Writes `dir/s.toml`: the PackBot on flat ground ([`FLAT`]) with `from` replaced by `to`.
fn flat_scenario(dir: &Path, from: &str, to: &str) -> PathBuf {
    let s = dir.join("s.toml");
    std::fs::write(&s, format!("{}{}", vehicle_line(), FLAT.replace(from, to))).unwrap();
    s
}

#[test]
fn special_files_long_lines_and_huge_hulls_are_refused_quickly() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    // A FIFO as the scenario and as the vehicle file: never opened, so never blocks.
    let fifo = d.join("fifo.toml");
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    refused(
        "fifo scenario",
        &run(&["check", fifo.to_str().unwrap()]),
        "FIFO",
    );
    let s = d.join("fifo_vehicle.toml");
    std::fs::write(&s, format!("[vehicle]\nfile = \"fifo.toml\"\n{FLAT}")).unwrap();
    refused(
        "fifo vehicle",
        &run(&["check", s.to_str().unwrap()]),
        "vehicle.file",
    );
    refused("/dev/zero", &run(&["check", "/dev/zero"]), "a device");
    let out = d.join("o");
    refused(
        "run /dev/zero",
        &run(&["run", "/dev/zero", "--out", out.to_str().unwrap()]),
        "a device",
    );
    // A 2 MB line (a method name) is not echoed whole.
    let s = d.join("long_line.toml");
    let long = "x".repeat(2_000_000);
    std::fs::write(
        &s,
        format!(
            "{}{}",
            vehicle_line(),
            FLAT.replace(
                "duration_s = 0.2",
                &format!("duration_s = 0.2\nmethod = \"{long}\"")
            )
        ),
    )
    .unwrap();
    refused(
        "long line",
        &run(&["check", s.to_str().unwrap()]),
        "simulation.method",
    );
    // A hull of 20,000 points: beyond the limit, refused without an n^3 scan.
    let pts: Vec<String> = (0..20_000)
        .map(|i| {
            let a = i as f64 * 0.618;
            format!(
                "[{:.4}, {:.4}, {:.4}]",
                0.2 * a.cos(),
                0.1 * a.sin(),
                0.05 * (i % 7) as f64 / 7.0
            )
        })
        .collect();
    let v = d.join("hull.toml");
    let veh = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../vehicles/packbot510.toml"),
    )
    .unwrap()
    .replace(
        "shape = { type = \"box\", size_m = [0.50, 0.25, 0.10] }",
        &format!(
            "shape = {{ type = \"convex\", points_m = [{}] }}",
            pts.join(", ")
        ),
    );
    std::fs::write(&v, veh).unwrap();
    let r = run(&["check", v.to_str().unwrap()]);
    refused("20,000-point hull", &r, "body.shape.points_m");
    // A file past the size limit (16 MiB) is refused before it is read.
    let big = d.join("big.toml");
    let f = std::fs::File::create(&big).unwrap();
    f.set_len(17 << 20).unwrap();
    refused(
        "17 MiB file",
        &run(&["check", big.to_str().unwrap()]),
        "limit of",
    );
}

#[test]
fn bad_flags_are_refused_with_the_limit() {
    let flat = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/packbot_flat.toml");
    let f = flat.to_str().unwrap();
    for d in ["1e300", "nan", "-1", "86401"] {
        let arg = format!("--duration={d}");
        refused(&arg, &run(&["run", f, &arg]), "--duration");
    }
    refused(
        "--jobs 2^63",
        &run(&["bench", "--jobs", "9223372036854775808"]),
        "--jobs",
    );
    refused(
        "--repeat huge",
        &run(&["bench", "--repeat", "18446744073709551615"]),
        "--repeat",
    );
    // `tracksim ros`: refused before any DDS socket is opened.
    for d in ["nan", "-1", "86401"] {
        let arg = format!("--duration={d}");
        refused(&arg, &run(&["ros", f, &arg]), "--duration");
    }
    refused(
        "--domain-id 300",
        &run(&["ros", f, "--domain-id", "300"]),
        "--domain-id",
    );
    refused(
        "--network foo",
        &run(&["ros", f, "--network", "foo"]),
        "--network",
    );
    // `drive` refuses its own flags before it listens on any port.
    for g in ["nan", "-1", "1e9"] {
        let arg = format!("--reconnect-grace={g}");
        refused(&arg, &run(&["drive", f, &arg]), "--reconnect-grace");
    }
    // A solver setting (issue 58): refused with its flag, by `validate` before any case is
    // built and by `run` as the file's key it overrides.
    for d in ["0", "nan", "1", "-1e-3"] {
        let arg = format!("--dt={d}");
        refused(&arg, &run(&["validate", "--accuracy", &arg]), "--dt");
        refused(
            &arg,
            &run(&["run", f, &arg]),
            "simulation.dt_s (overridden: --dt)",
        );
    }
    refused(
        "--iterations 0",
        &run(&["validate", "--accuracy", "--iterations", "0"]),
        "--solver-iterations",
    );
    refused(
        "--stabilization-iterations 17",
        &run(&["validate", "--stabilization-iterations", "17"]),
        "--stabilization-iterations",
    );
    refused(
        "--solver-iterations 0",
        &run(&["run", f, "--solver-iterations", "0"]),
        "simulation.solver_iterations (overridden: --solver-iterations)",
    );
    let long = "x".repeat(101);
    for name in ["", "tab\there", long.as_str()] {
        refused(
            "--trainee",
            &run(&["drive", f, "--trainee", name]),
            "--trainee",
        );
    }
}

#[test]
fn a_closed_standard_output_ends_quietly() {
    let flat = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/packbot_flat.toml");
    for args in [vec!["check", flat.to_str().unwrap()], vec!["list"]] {
        let mut child = Command::new(bin())
            .args(&args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take()); // the reader goes away before anything is written
        let o = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert_eq!(o.status.code(), Some(0), "{args:?}: {err}");
    }
}

#[test]
fn compare_with_every_method_unstable_exits_3() {
    let tmp = tempfile::tempdir().unwrap();
    // 500 m/s belts throw the PackBot off (as in cli.rs's exploding simulation).
    let s = flat_scenario(tmp.path(), "belt_speed_mps = 0.3", "belt_speed_mps = 500.0");
    let out = tmp.path().join("cmp");
    let r = run(&[
        "compare",
        s.to_str().unwrap(),
        "--methods",
        "okada2020,okada2020_no_grousers",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!r.text.contains("panicked"), "{}", r.text);
    assert_eq!(r.code, Some(3), "{}", r.text);
    assert!(r.text.contains("unstable"), "{}", r.text);
    assert!(
        out.join("compare.csv").is_file(),
        "the table is written too"
    );
}

#[test]
fn a_run_that_blows_up_keeps_what_was_simulated_and_exits_3() {
    let tmp = tempfile::tempdir().unwrap();
    // 500 m/s belts throw the PackBot off within milliseconds.
    let s = flat_scenario(tmp.path(), "belt_speed_mps = 0.3", "belt_speed_mps = 500.0");
    let out = tmp.path().join("run");
    let r = run(&["run", s.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(!r.text.contains("panicked"), "{}", r.text);
    assert_eq!(r.code, Some(3), "{}", r.text);
    assert!(r.text.contains("unstable"), "{}", r.text);
    // Written up to the blow-up, and complete: not an INCOMPLETE folder.
    assert!(!out.join("INCOMPLETE").exists());
    let traj = std::fs::read_to_string(out.join("trajectory.csv")).unwrap();
    assert!(traj.lines().count() >= 2, "{traj}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["outcome"], "failure");
    let why = summary["outcome_reason"].as_str().unwrap();
    assert!(why.contains("simulation unstable"), "{why}");
}

/// Issue 59: a world whose two robots part further than it holds stops, writes every robot's
/// run up to there with the reason, and exits 3; never a folder holding only `INCOMPLETE`.
#[test]
fn a_team_run_whose_robots_part_keeps_every_robot_and_exits_3() {
    let tmp = tempfile::tempdir().unwrap();
    let v = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../vehicles/packbot510.toml");
    let robot = |name: &str, x: f64, belts: f64| {
        format!(
            "[[vehicles]]\nname = \"{name}\"\n[vehicles.vehicle]\nfile = \"{}\"\nx_m = {x}\n\
             [[vehicles.commands]]\nt_s = 0.0\nbelt_speed_mps = {belts}\n",
            v.display()
        )
    };
    let s = tmp.path().join("part.toml");
    std::fs::write(
        &s,
        format!(
            "[terrain.ground]\nfriction = 0.8\n[simulation]\nduration_s = 30.0\n{}{}",
            robot("a", -4.7, -0.3),
            robot("b", 4.7, 0.3)
        ),
    )
    .unwrap();
    let out = tmp.path().join("run");
    let r = run(&[
        "run",
        s.to_str().unwrap(),
        "--no-plot",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!r.text.contains("panicked"), "{}", r.text);
    assert_eq!(r.code, Some(3), "{}", r.text);
    assert!(r.text.contains("m apart"), "{}", r.text);
    assert!(r.text.contains("every robot's"), "{}", r.text);
    assert!(!out.join("INCOMPLETE").exists());
    let team: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("team.json")).unwrap()).unwrap();
    let why = team["stopped"].as_str().expect("team.json says why");
    assert!(why.contains("m apart"), "{why}");
    for name in ["a", "b"] {
        let traj = std::fs::read_to_string(out.join(name).join("trajectory.csv")).unwrap();
        // 0.6 m/s of parting from 9.4 m to 10 m: about 1 s of samples.
        assert!(traj.lines().count() > 10, "{name}: {traj}");
    }
}

#[test]
fn ctrl_c_during_run_writes_what_was_simulated_as_interrupted() {
    let tmp = tempfile::tempdir().unwrap();
    let s = flat_scenario(tmp.path(), "duration_s = 0.2", "duration_s = 3600.0");
    let out = tmp.path().join("o");
    let child = Command::new(bin())
        .args([
            "run",
            s.to_str().unwrap(),
            "--quiet",
            "--no-plot",
            "--out",
            out.to_str().unwrap(),
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Let it simulate a little (loading and building take well under a second).
    std::thread::sleep(Duration::from_secs(3));
    let pid = child.id().to_string();
    assert!(
        Command::new("kill")
            .args(["-INT", &pid])
            .status()
            .unwrap()
            .success()
    );
    let t0 = Instant::now();
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(t0.elapsed() < LIMIT, "took {:?} to stop", t0.elapsed());
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["outcome"], "interrupted", "{summary}");
    let t = summary["sim_time_s"].as_f64().unwrap();
    assert!(t > 0.0 && t < 3600.0, "simulated {t} s");
    let rows = std::fs::read_to_string(out.join("trajectory.csv"))
        .unwrap()
        .lines()
        .count();
    // One row per 10 ms output interval plus the header and the row at the interruption.
    assert!(rows as f64 >= t / 0.01, "{rows} rows for {t} s");
    // No temporary file left behind.
    for e in std::fs::read_dir(&out).unwrap() {
        let n = e.unwrap().file_name().to_string_lossy().into_owned();
        assert!(!n.starts_with(".tmp-"), "left {n}");
    }
}

// ---- Issue 24.5: first contact ------------------------------------------------------------

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A 0.2 s flat-ground scenario without `[randomize]` (the vehicle named by absolute path).
fn short_fixed(dir: &Path) -> PathBuf {
    let p = dir.join("short.toml");
    let vehicle = repo().join("vehicles/packbot510.toml");
    std::fs::write(
        &p,
        format!(
            "[vehicle]\nfile = {:?}\n[terrain.ground]\nfriction = 0.6\n[simulation]\nduration_s = 0.2\n",
            vehicle.to_str().unwrap()
        ),
    )
    .unwrap();
    p
}

#[test]
fn run_on_a_vehicle_file_says_it_is_one_and_how_to_use_it() {
    let tmp = tempfile::tempdir().unwrap();
    let v = repo().join("vehicles/packbot510.toml");
    let r = run_quietly(&v, &tmp.path().join("out"));
    refused("run vehicle", &r, "this is a vehicle file");
    assert!(
        r.text.contains("`file = \"packbot510.toml\"`"),
        "{}",
        r.text
    );
    assert!(r.text.contains("tracksim check"), "{}", r.text);
    assert!(!r.text.contains("unknown"), "{}", r.text);
    // `check` reads it as the vehicle it is.
    let c = run(&["check", v.to_str().unwrap()]);
    assert_eq!(c.code, Some(0), "{}", c.text);
}

#[test]
fn a_typo_in_a_key_gets_did_you_mean_and_every_accepted_key() {
    let tmp = tempfile::tempdir().unwrap();
    let p = short_fixed(tmp.path());
    let text = std::fs::read_to_string(&p).unwrap();
    std::fs::write(&p, text.replace("duration_s", "duraton_s")).unwrap();
    let r = run(&["check", p.to_str().unwrap()]);
    refused(
        "typo",
        &r,
        "unknown key `duraton_s`: did you mean `duration_s`?",
    );
    for k in ["`dt_s`", "`floating_origin`", "`method`", "`seed`"] {
        assert!(r.text.contains(k), "{k} missing: {}", r.text);
    }
    assert!(!r.text.contains("cut"), "{}", r.text);
}

#[test]
fn pulleys_on_one_line_are_named_by_check() {
    let tmp = tempfile::tempdir().unwrap();
    let v = std::fs::read_to_string(repo().join("vehicles/packbot510.toml")).unwrap();
    let v = v.replace(
        "  { x_m = 0.255, z_m = 0.0, radius_m = 0.082 },\n]",
        "  { x_m = 0.255, z_m = 0.0, radius_m = 0.082 },\n  { x_m = 0.0, z_m = 0.0, radius_m = 0.06 },\n]",
    );
    let p = tmp.path().join("v.toml");
    std::fs::write(&p, v).unwrap();
    let r = run(&["check", p.to_str().unwrap()]);
    refused("collinear", &r, "tracks[0].path.pulleys[2]");
    assert!(
        r.text.contains("on the line between pulleys 1 and 0"),
        "{}",
        r.text
    );
    assert!(!r.text.contains("720"), "{}", r.text);
}

#[test]
fn sweep_plans_are_refused_by_the_library_with_their_keys() {
    let tmp = tempfile::tempdir().unwrap();
    let p = short_fixed(tmp.path());
    let f = p.to_str().unwrap();
    let out = tmp.path().join("sweep");
    let o = out.to_str().unwrap();
    let r = run(&["sweep", f, "--out", o, "--runs", "0"]);
    refused("--runs 0", &r, "runs: must be from 1 to 10000000, got 0");
    let r = run(&["sweep", f, "--out", o, "--grid", "friction=0.5,inf"]);
    refused("--grid inf", &r, "grid.friction: values must be finite");
    let r = run(&["sweep", f, "--out", o, "--jobs", "0"]);
    refused("--jobs 0", &r, "jobs: must be from 1 to 1024");
    let r = run(&["sweep", f, "--out", o, "--shard", "2/2"]);
    refused("--shard 2/2", &r, "--shard");
}

#[test]
fn a_sweep_of_a_file_without_randomize_warns_that_its_runs_are_identical() {
    let tmp = tempfile::tempdir().unwrap();
    let p = short_fixed(tmp.path());
    let out = tmp.path().join("sweep");
    let r = run(&[
        "sweep",
        p.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--runs",
        "2",
        "--quiet",
    ]);
    assert_eq!(r.code, Some(0), "{}", r.text);
    assert!(
        r.text.contains("warning: ") && r.text.contains("its 2 runs will be identical"),
        "{}",
        r.text
    );
    assert!(out.join("manifest.jsonl").is_file());
}
