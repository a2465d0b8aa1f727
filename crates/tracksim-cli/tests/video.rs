//! `tracksim video DIR` (issue 41) as a user runs it: a short run of a bundled scenario rendered
//! to an MP4 read back with the `mp4` crate (one H.264 track, avc1, the size asked, a sample per
//! frame), decoded with OpenH264 and compared with the replay renderer's own frames at the same
//! times (PSNR), the same bytes twice, colours from the scenario reaching the video, a team
//! run, an onboard camera, and every bad input refused with exit code 2 naming the flag or
//! the file.

#![warn(clippy::too_many_lines)]

use assert_cmd::Command;
use std::path::{Path, PathBuf};
use tracksim::video::{Camera, Replay, VideoOptions, h264, psnr};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn tracksim() -> Command {
    let mut c = Command::cargo_bin("tracksim").unwrap();
    c.current_dir(root());
    c
}

struct Out {
    code: i32,
    stdout: String,
    stderr: String,
}

fn run(args: &[&str]) -> Out {
    let o = tracksim().args(args).output().unwrap();
    Out {
        code: o.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&o.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&o.stderr).into_owned(),
    }
}

/// A 2 s run of `packbot_step` (climbing its step) into `dir`.
fn step_run(dir: &Path) {
    let o = run(&[
        "run",
        "packbot_step",
        "--out",
        dir.to_str().unwrap(),
        "--duration",
        "2",
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
}

/// PSNR a decoded frame must reach against the renderer's frame: H.264 at the fixed QP
/// (`h264::QP` = 24) loses a little at edges and in the HUD's text; 30 dB is "visually the
/// same" and far above what another frame of the run gives (checked below).
const MIN_PSNR_DB: f64 = 30.0;

#[test]
fn a_run_becomes_an_mp4_whose_frames_are_the_renderers() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("step");
    step_run(&dir);
    let o = run(&[
        "video",
        dir.to_str().unwrap(),
        "--fps",
        "10",
        "--size",
        "320x240",
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(o.stdout.contains("MB per minute"), "{}", o.stdout);
    let path = dir.join("video.mp4");
    let bytes = std::fs::read(&path).unwrap();

    // The container, read by the mp4 crate.
    let r = mp4::Mp4Reader::read_header(std::io::Cursor::new(&bytes), bytes.len() as u64).unwrap();
    assert_eq!(r.tracks().len(), 1, "one track");
    let t = r.tracks().values().next().unwrap();
    assert_eq!(t.media_type().unwrap(), mp4::MediaType::H264);
    assert_eq!(t.box_type().unwrap().to_string(), "avc1");
    assert_eq!((t.width(), t.height()), (320, 240));
    // 2 s at 10 fps: frames at 0, 0.1, ..., 2.0.
    let expected = 2.0 * 10.0;
    assert!(
        (t.sample_count() as f64 - expected).abs() <= 1.0,
        "{} samples",
        t.sample_count()
    );
    assert!((t.frame_rate() - 10.0).abs() < 0.01, "{}", t.frame_rate());

    // The frames, decoded, against the renderer's frames at the same times.
    let d = h264::decode_mp4(&bytes).unwrap();
    assert_eq!(d.frames.len() as u32, t.sample_count());
    let opts = VideoOptions {
        fps: 10,
        width: 320,
        height: 240,
        ..VideoOptions::default()
    };
    let replay = Replay::open(&dir, None).unwrap();
    let times = replay.frame_times(10);
    assert_eq!(times.len(), d.frames.len());
    let mut frame = tracksim::render::Frame::new(320, 240);
    let mid = times.len() / 2;
    let mut rendered = Vec::new();
    for k in [0, mid] {
        replay.render_frame(times[k], &opts, None, &mut frame);
        let p = psnr(&frame.rgb, &d.frames[k]);
        assert!(p > MIN_PSNR_DB, "frame {k}: {p:.1} dB");
        rendered.push(frame.rgb.clone());
    }
    // The comparison can fail: the robot moved (and the clock changed) between the two.
    let other = psnr(&rendered[0], &d.frames[mid]);
    let same = psnr(&rendered[1], &d.frames[mid]);
    assert!(other < same - 3.0, "{other:.1} dB against {same:.1} dB");

    // The same run renders to the same bytes, on one thread as on every core.
    let again = tmp.path().join("again.mp4");
    let o = run(&[
        "video",
        dir.to_str().unwrap(),
        "--fps",
        "10",
        "--size",
        "320x240",
        "--threads",
        "1",
        "--out",
        again.to_str().unwrap(),
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(std::fs::read(&again).unwrap() == bytes, "not deterministic");

    // A scene.json of before colours (every colour key removed) still renders, with the
    // palette's colours: the scenario sets none, so the bytes are the same.
    let text = std::fs::read_to_string(dir.join("scene.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    strip_colors(&mut v);
    assert!(!v.to_string().contains("\"#"), "colours left");
    std::fs::write(dir.join("scene.json"), v.to_string()).unwrap();
    let old = tmp.path().join("old.mp4");
    let o = run(&[
        "video",
        dir.to_str().unwrap(),
        "--fps",
        "10",
        "--size",
        "320x240",
        "--out",
        old.to_str().unwrap(),
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(std::fs::read(&old).unwrap() == bytes, "defaults differ");
}

fn strip_colors(v: &mut serde_json::Value) {
    match v {
        serde_json::Value::Object(m) => {
            m.retain(|k, _| !k.contains("color"));
            m.values_mut().for_each(strip_colors);
        }
        serde_json::Value::Array(a) => a.iter_mut().for_each(strip_colors),
        _ => {}
    }
}

/// Pixels of a frame that are strongly red (r > 150, g and b < 80).
fn red_pixels(rgb: &[u8]) -> usize {
    rgb.chunks_exact(3)
        .filter(|p| p[0] > 150 && p[1] < 80 && p[2] < 80)
        .count()
}

#[test]
fn a_terrain_colour_reaches_scene_json_and_the_video() {
    let tmp = tempfile::tempdir().unwrap();
    let vehicles = root().join("vehicles").canonicalize().unwrap();
    let text = |color: &str| {
        format!(
            r#"
[vehicle]
file = "{}/packbot510.toml"
[terrain.ground]
friction = 0.6
[[terrain.boxes]]
centre_m = [2.0, 0.0, 0.05]
size_m = [1.0, 2.0, 0.10]
friction = 0.6
{color}
[simulation]
duration_s = 0.2
[[commands]]
belt_speed_mps = 0.3
"#,
            vehicles.display()
        )
    };
    let mut reds = Vec::new();
    for (name, color) in [("red", "color = \"#e01010\""), ("plain", "")] {
        let file = tmp.path().join(format!("{name}.toml"));
        std::fs::write(&file, text(color)).unwrap();
        let dir = tmp.path().join(name);
        let o = run(&[
            "run",
            file.to_str().unwrap(),
            "--out",
            dir.to_str().unwrap(),
        ]);
        assert_eq!(o.code, 0, "{}", o.stderr);
        let scene = std::fs::read_to_string(dir.join("scene.json")).unwrap();
        let v: serde_json::Value = serde_json::from_str(&scene).unwrap();
        let c = v["terrain"]["boxes"][0]["color"]
            .as_str()
            .unwrap()
            .to_string();
        assert_eq!(c == "#e01010", name == "red", "{c}");
        assert!(
            v["vehicle"]["colors"]["body"]
                .as_str()
                .unwrap()
                .starts_with('#')
        );
        let o = run(&["video", dir.to_str().unwrap(), "--size", "160x120"]);
        assert_eq!(o.code, 0, "{}", o.stderr);
        let d = h264::decode_mp4(&std::fs::read(dir.join("video.mp4")).unwrap()).unwrap();
        reds.push(red_pixels(&d.frames[0]));
    }
    assert!(reds[0] > 100, "the red box is not seen: {reds:?}");
    assert_eq!(reds[1], 0, "{reds:?}");
}

#[test]
fn a_team_run_and_an_onboard_camera_render() {
    let tmp = tempfile::tempdir().unwrap();
    let team = tmp.path().join("team");
    let o = run(&[
        "run",
        "team/convoy",
        "--out",
        team.to_str().unwrap(),
        "--duration",
        "0.5",
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let names: Vec<String> = {
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(team.join("team.json")).unwrap())
                .unwrap();
        v["robots"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r["name"].as_str().unwrap().to_string())
            .collect()
    };
    assert!(names.len() >= 2);
    // The camera on the last robot: the others are in view ahead of it; on the first, they
    // are behind it. The frames differ.
    let mut firsts = Vec::new();
    for n in [&names[0], &names[names.len() - 1]] {
        let out = tmp.path().join(format!("{n}.mp4"));
        let o = run(&[
            "video",
            team.to_str().unwrap(),
            "--robot",
            n,
            "--size",
            "160x120",
            "--fps",
            "5",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(o.code, 0, "{}", o.stderr);
        let d = h264::decode_mp4(&std::fs::read(&out).unwrap()).unwrap();
        assert_eq!(d.frames.len(), 3);
        firsts.push(d.frames[0].clone());
    }
    assert!(
        psnr(&firsts[0], &firsts[1]) < 30.0,
        "the robots' views agree"
    );
    let o = run(&["video", team.to_str().unwrap(), "--robot", "nobody"]);
    assert_eq!(o.code, 2);
    assert!(
        o.stderr.contains("--robot") && o.stderr.contains(&names[0]),
        "{}",
        o.stderr
    );

    // An onboard camera: packbot_sensors' depth camera `front_camera` (its field of view).
    let dir = tmp.path().join("sensors");
    let o = run(&[
        "run",
        "packbot_sensors",
        "--out",
        dir.to_str().unwrap(),
        "--duration",
        "0.3",
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let replay = Replay::open(&dir, None).unwrap();
    let mut frames = Vec::new();
    for camera in [Camera::Chase, Camera::Sensor("front_camera".into())] {
        let opts = VideoOptions {
            camera,
            width: 160,
            height: 120,
            ..VideoOptions::default()
        };
        let mut f = tracksim::render::Frame::new(160, 120);
        replay.render_frame(0.1, &opts, None, &mut f);
        frames.push(f.rgb);
    }
    assert!(psnr(&frames[0], &frames[1]) < 25.0, "onboard = chase");
    let o = run(&[
        "video",
        dir.to_str().unwrap(),
        "--camera",
        "front_camera",
        "--size",
        "160x120",
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
}

#[test]
fn bad_inputs_exit_2_naming_the_flag_or_file() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("step");
    let o = run(&[
        "run",
        "packbot_step",
        "--out",
        dir.to_str().unwrap(),
        "--duration",
        "0.2",
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let d = dir.to_str().unwrap();
    for (args, needle) in [
        (vec!["--fps", "0"], "--fps"),
        (vec!["--fps", "121"], "--fps"),
        (vec!["--size", "321x240"], "--size"),
        (vec!["--size", "640x0"], "--size"),
        (vec!["--size", "big"], "--size"),
        (vec!["--camera", "nope"], "--camera"),
    ] {
        let mut a = vec!["video", d];
        a.extend(args.iter());
        let o = run(&a);
        assert_eq!(o.code, 2, "{args:?}: {}", o.stderr);
        assert!(o.stderr.contains(needle), "{args:?}: {}", o.stderr);
        assert!(!o.stderr.contains("panicked"), "{}", o.stderr);
    }
    assert!(!dir.join("video.mp4").exists(), "written on bad input");
    // Not a run folder, a missing folder, a missing trajectory, a cut trajectory.
    let o = run(&["video", tmp.path().to_str().unwrap()]);
    assert_eq!(o.code, 2);
    assert!(o.stderr.contains("scene.json") && o.stderr.contains("not the output folder"));
    let o = run(&["video", tmp.path().join("none").to_str().unwrap()]);
    assert_eq!(o.code, 2, "{}", o.stderr);
    let traj = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
    std::fs::write(dir.join("trajectory.csv"), &traj[..traj.len() / 2]).unwrap();
    let o = run(&["video", d]);
    assert_eq!(o.code, 2, "{}", o.stderr);
    assert!(o.stderr.contains("trajectory.csv"), "{}", o.stderr);
    std::fs::remove_file(dir.join("trajectory.csv")).unwrap();
    let o = run(&["video", d]);
    assert_eq!(o.code, 2, "{}", o.stderr);
    assert!(o.stderr.contains("trajectory.csv"), "{}", o.stderr);
    std::fs::write(dir.join("trajectory.csv"), &traj).unwrap();
    std::fs::write(dir.join("scene.json"), "{\"not\": 1}").unwrap();
    let o = run(&["video", d]);
    assert_eq!(o.code, 2, "{}", o.stderr);
    assert!(o.stderr.contains("scene.json"), "{}", o.stderr);
}
