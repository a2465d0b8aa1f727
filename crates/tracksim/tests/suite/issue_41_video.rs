//! Issue 41, videos: the replay page's `/video.mp4` (`tracksim view`), through the library's
//! server: rendered on the first request as an H.264 MP4 of the run (the same bytes as
//! `video::render_video` with the default settings), `video/mp4`, announced in `/session.json`;
//! not offered for a compare folder; a broken run answers 503 with the command to run.
//! (`tracksim video` itself: `crates/tracksim-cli/tests/video.rs`.)

use crate::common;
use std::io::{Read, Write};
use std::net::TcpStream;
use tracksim::live::{Mode, Server, ViewVideo};

fn get(addr: std::net::SocketAddr, target: &str) -> (String, Vec<u8>) {
    let mut s = TcpStream::connect(addr).unwrap();
    write!(
        s,
        "GET {target} HTTP/1.1\r\nHost: localhost:{}\r\n\r\n",
        addr.port()
    )
    .unwrap();
    let mut bytes = Vec::new();
    s.read_to_end(&mut bytes).unwrap();
    let end = bytes.windows(4).position(|w| w == b"\r\n\r\n").unwrap();
    (
        String::from_utf8_lossy(&bytes[..end]).into_owned(),
        bytes[end + 4..].to_vec(),
    )
}

fn temp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("tracksim-i41-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn the_view_server_renders_the_runs_video_on_request() {
    let sc = common::load_for("scenarios/packbot_step.toml", 0.4);
    let r = tracksim::run_scenario(&sc, |_, _| {}).unwrap();
    let dir = temp("view");
    let which = tracksim::output::Outputs {
        replay: true,
        plots: false,
        mcap: false,
        raw_images: false,
    };
    tracksim::output::write_outputs(&sc, &r, &dir, which).unwrap();
    let files = tracksim::live::view_files(&dir).unwrap();
    let video = ViewVideo::of(&dir);
    assert!(video.is_some());
    let server =
        Server::start(tracksim::live::DEFAULT_BIND, 0, Mode::View { files, video }).unwrap();
    let (head, body) = get(server.addr(), "/session.json");
    assert!(head.contains("200"), "{head}");
    let s: serde_json::Value = serde_json::from_slice(&body).unwrap();
    assert_eq!(s["video"], true);
    let (head, body) = get(server.addr(), "/video.mp4");
    assert!(
        head.contains("200") && head.contains("Content-Type: video/mp4"),
        "{head}"
    );
    assert_eq!(&body[4..8], b"ftyp");
    let want = tracksim::video::render_video(&dir, &tracksim::video::VideoOptions::default())
        .unwrap()
        .0;
    assert!(body == want, "not the video of the run");
    // Kept: a second request gets the same bytes.
    assert!(get(server.addr(), "/video.mp4").1 == want);
    let d = tracksim::video::h264::decode_mp4(&body).unwrap();
    assert_eq!((d.width, d.height), tracksim::video::DEFAULT_SIZE);
    assert_eq!(d.frames.len(), 11, "0.4 s at 25 fps");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn no_video_for_a_compare_folder_and_503_for_a_broken_run() {
    let base = temp("compare");
    for m in ["plates", "okada2020"] {
        std::fs::create_dir_all(base.join(m)).unwrap();
    }
    assert!(ViewVideo::of(&base).is_none());
    let broken = temp("broken");
    for f in ["scene.json", "trajectory.csv", "belts.csv"] {
        std::fs::write(broken.join(f), "not a run").unwrap();
    }
    let video = ViewVideo::of(&broken);
    let server = Server::start(
        tracksim::live::DEFAULT_BIND,
        0,
        Mode::View {
            files: Vec::new(),
            video,
        },
    )
    .unwrap();
    let (head, body) = get(server.addr(), "/video.mp4");
    assert!(head.contains("503"), "{head}");
    let text = String::from_utf8_lossy(&body);
    assert!(
        text.contains("scene.json") && text.contains("tracksim video"),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(&base);
    let _ = std::fs::remove_dir_all(&broken);
}
