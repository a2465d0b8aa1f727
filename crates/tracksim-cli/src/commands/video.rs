//! `tracksim video`: a finished run rendered to an MP4 (H.264) with its HUD burnt in.

use super::{Failure, bad_arg};
use std::path::PathBuf;
use tracksim::video::{self, Camera, VideoOptions};

/// Render a finished run (of `run`, `drive`, an environment's episode, or a team run's folder)
/// to an MP4 (H.264, plays in a browser): the chase camera or a camera sensor of the vehicle,
/// with the time, the speed and the course's score or the outcome burnt in (docs/VIDEO.md).
#[derive(clap::Args)]
pub struct VideoArgs {
    /// The run's output folder (holding scene.json and trajectory.csv), or a team run's folder
    /// (team.json and a folder per robot).
    pub dir: PathBuf,
    /// The MP4 to write (default DIR/video.mp4).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// `chase` (behind and above the robot) or the name of a sensor of the vehicle (its frame,
    /// looking along its x axis).
    #[arg(long, default_value = "chase")]
    pub camera: String,
    /// Frames per second (1 to 120).
    #[arg(long, default_value_t = video::DEFAULT_FPS)]
    pub fps: u32,
    /// Frame size WIDTHxHEIGHT in pixels, both even (H.264 4:2:0).
    #[arg(long, default_value = "640x480")]
    pub size: String,
    /// In a team run, the robot the camera follows (its folder's name; default the first).
    #[arg(long)]
    pub robot: Option<String>,
    /// Threads to render on (0: every core); the bytes do not depend on it.
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
}

/// Reads `WIDTHxHEIGHT`.
fn parse_size(s: &str) -> Result<(usize, usize), Failure> {
    let bad = || {
        bad_arg(
            "--size",
            format!("{s}: give WIDTHxHEIGHT in pixels, both even, e.g. --size 640x480"),
        )
    };
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    Ok((
        w.trim().parse().map_err(|_| bad())?,
        h.trim().parse().map_err(|_| bad())?,
    ))
}

/// `tracksim video`.
pub fn video(a: VideoArgs) -> Result<(), Failure> {
    let (width, height) = parse_size(&a.size)?;
    let opts = VideoOptions {
        camera: if a.camera == "chase" {
            Camera::Chase
        } else {
            Camera::Sensor(a.camera.clone())
        },
        fps: a.fps,
        width,
        height,
        robot: a.robot.clone(),
        threads: a.threads,
    };
    if let Some(i) = opts.issues().into_iter().next() {
        return Err(bad_arg(&i.key, i.message));
    }
    let out = a.out.clone().unwrap_or_else(|| a.dir.join("video.mp4"));
    let r = video::write_video(&a.dir, &out, &opts)?;
    out!("wrote      {}", out.display());
    out!(
        "video      {} frames, {:.2} s at {} fps, {}x{}, {:.2} MB ({:.2} MB per minute)",
        r.frames,
        r.duration_s,
        opts.fps,
        width,
        height,
        r.bytes as f64 / 1e6,
        r.mb_per_minute()
    );
    let per = |s: f64| 1000.0 * s / r.frames.max(1) as f64;
    out!(
        "time       render {:.1} ms a frame, encode {:.1} ms a frame",
        per(r.render_s),
        per(r.encode_s)
    );
    Ok(())
}
