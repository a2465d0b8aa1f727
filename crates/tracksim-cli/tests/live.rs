//! `tracksim drive` and `tracksim view` as a user starts them (issue 12): loopback by default,
//! another address only with `--bind` and a warning, a drive session (here ended by
//! `--duration`) written as a run with the replay files, and clear errors for bad input.

#![warn(clippy::too_many_lines)]

use assert_cmd::Command;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn tracksim(args: &[&str]) -> (i32, String, String) {
    let o = Command::cargo_bin("tracksim")
        .unwrap()
        .current_dir(root())
        .args(args)
        .output()
        .unwrap();
    (
        o.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn drive_listens_on_loopback_and_writes_a_run() {
    let out = tempfile::tempdir().unwrap();
    let o = out.path().to_str().unwrap();
    let (code, stdout, stderr) = tracksim(&[
        "drive",
        "scenarios/packbot_flat.toml",
        "--port",
        "0",
        "--duration",
        "0.2",
        "--speed",
        "50",
        "--out",
        o,
        "--no-plot",
    ]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(stdout.contains("open http://127.0.0.1:"), "{stdout}");
    assert!(!stderr.contains("warning"), "{stderr}");
    for f in [
        "summary.json",
        "trajectory.csv",
        "scene.json",
        "belts.csv",
        "commands.toml",
        "controls.csv",
    ] {
        assert!(out.path().join(f).is_file(), "{f} missing: {stdout}");
    }
    let csv = std::fs::read_to_string(out.path().join("trajectory.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 21, "t = 0 .. 0.2 s every 10 ms");
}

#[test]
fn another_address_only_with_bind_and_a_warning() {
    let out = tempfile::tempdir().unwrap();
    let (code, stdout, stderr) = tracksim(&[
        "drive",
        "scenarios/packbot_flat.toml",
        "--port",
        "0",
        "--duration",
        "0.05",
        "--speed",
        "50",
        "--bind",
        "0.0.0.0",
        "--no-plot",
        "--out",
        out.path().to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stderr.contains("warning: listening on 0.0.0.0, not loopback"),
        "{stderr}"
    );
    assert!(stdout.contains("open http://0.0.0.0:"), "{stdout}");
}

#[test]
fn bad_drive_and_view_input_is_named() {
    let (code, _, stderr) = tracksim(&["drive", "scenarios/packbot_flat.toml", "--speed", "0"]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("--speed") && stderr.contains("1 = real time"),
        "{stderr}"
    );
    let empty = tempfile::tempdir().unwrap();
    let (code, _, stderr) = tracksim(&["view", empty.path().to_str().unwrap(), "--port", "0"]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("scene.json") && stderr.contains("re-run"),
        "{stderr}"
    );
}

#[test]
fn every_run_writes_the_replay_files() {
    let out = tempfile::tempdir().unwrap();
    let (code, stdout, stderr) = tracksim(&[
        "run",
        "scenarios/packbot_flat.toml",
        "--duration",
        "0.1",
        "--no-plot",
        "--quiet",
        "--out",
        out.path().to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    let scene: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("scene.json")).unwrap())
            .unwrap();
    assert_eq!(scene["format"], "tracksim-scene-1");
    assert_eq!(scene["vehicle"]["tracks"].as_array().unwrap().len(), 2);
    let belts = std::fs::read_to_string(out.path().join("belts.csv")).unwrap();
    assert!(
        belts.starts_with("t_s,belt_position_left_m,belt_position_right_m\n"),
        "{belts}"
    );
}
