//! `tracksim import` (issue 42) end to end: the paper's example track imported from the shared
//! robots folder (skipped with a message when it is absent), the written files checked and
//! run; a model without tracks refused with exit code 2, naming the file.

use assert_cmd::Command;
use std::path::{Path, PathBuf};

const ROBOTS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/robots");

fn tracksim() -> Command {
    Command::cargo_bin("tracksim").unwrap()
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tracksim-cli-import-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn import_writes_files_that_check_and_run() {
    let model = Path::new(ROBOTS).join("okada_plugin_example/example_track_gazebo.urdf");
    if !model.exists() {
        println!(
            "SKIPPED: {} is absent (the shared robots folder)",
            model.display()
        );
        return;
    }
    let dir = scratch("okada");
    let out = dir.join("okada");
    let a = tracksim()
        .arg("import")
        .arg(&model)
        .arg("--out")
        .arg(&out)
        .assert()
        .success();
    let text = String::from_utf8_lossy(&a.get_output().stdout).to_string();
    assert!(
        text.contains("ContinuousTrack plugin") && text.contains("pitch 53.1 mm"),
        "{text}"
    );
    let vehicle = out.join("example_track_gazebo.toml");
    let scenario = out.join("flat.toml");
    tracksim()
        .arg("check")
        .arg(&vehicle)
        .arg(&scenario)
        .assert()
        .success();
    // A second import into the same folder keeps the files unless --force.
    tracksim()
        .arg("import")
        .arg(&model)
        .arg("--out")
        .arg(&out)
        .assert()
        .code(2);
    tracksim()
        .arg("import")
        .arg(&model)
        .arg("--out")
        .arg(&out)
        .arg("--force")
        .assert()
        .success();
    let a = tracksim()
        .current_dir(&dir)
        .arg("run")
        .arg(&scenario)
        .assert()
        .success();
    let text = String::from_utf8_lossy(&a.get_output().stdout).to_string();
    assert!(text.contains("completed"), "{text}");
}

#[test]
fn a_model_without_tracks_is_refused_naming_it() {
    let dir = scratch("none");
    let model = dir.join("plain.urdf");
    std::fs::write(
        &model,
        r#"<robot name="plain"><link name="base"><inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
<collision><geometry><box size="0.5 0.3 0.2"/></geometry></collision></link></robot>"#,
    )
    .unwrap();
    let a = tracksim()
        .arg("import")
        .arg(&model)
        .arg("--out")
        .arg(dir.join("out"))
        .assert()
        .code(2);
    let err = String::from_utf8_lossy(&a.get_output().stderr).to_string();
    assert!(
        err.contains("plain.urdf") && err.contains("no tracks found"),
        "{err}"
    );
    let missing = dir.join("missing.urdf");
    let a = tracksim().arg("import").arg(&missing).assert().code(2);
    let err = String::from_utf8_lossy(&a.get_output().stderr).to_string();
    assert!(err.contains("missing.urdf"), "{err}");
}
