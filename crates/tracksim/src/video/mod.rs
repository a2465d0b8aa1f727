//! `tracksim video DIR`: a finished run (of `run`, `drive`, an environment's episode, or a team
//! run's folder of several robots) rendered to an MP4 (H.264, plays in a browser), seen from
//! the chase camera or a camera sensor of the vehicle, with the time, the speed and the
//! course's score or the outcome burnt in (docs/VIDEO.md).
//!
//! - [`record`]: the run folder read back (`scene.json`, `trajectory.csv`, `belts.csv`,
//!   `summary.json`), its state at any time;
//! - [`replay_scene`]: the scene as a [`crate::render::RenderScene`] at one time (the same
//!   tracer, light and colours as the live colour camera);
//! - [`hud`]: the text burnt into the frames;
//! - [`h264`]: frames to MP4 (OpenH264 and the `mp4` crate) and back.

pub mod h264;
pub mod hud;
pub mod record;
pub mod replay_scene;

pub use h264::psnr;

use crate::error::{Error, Result, SpecIssue};
use crate::render::{self, CameraPose, ChaseCamera, Frame, Intrinsics, Light};
use crate::sensors::sim_scene::CHASE_RANGE_M;
use glam::{DQuat, DVec3};
use record::{Recording, RobotState};
use replay_scene::ReplayWorld;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Default frame size, pixels.
pub const DEFAULT_SIZE: (usize, usize) = (640, 480);
/// Default frame rate, frames per second.
pub const DEFAULT_FPS: u32 = 25;
/// Highest frame rate accepted, frames per second.
pub const MAX_FPS: u32 = 120;
/// Largest frame side accepted, pixels (OpenH264's limit is 3840 x 2160).
pub const MAX_SIDE: usize = 3840;
/// Most frames a video holds (10 hours at 25 fps).
pub const MAX_FRAMES: usize = 900_000;
/// Horizontal field of view of an onboard camera without one in `scene.json`, degrees.
pub const ONBOARD_FOV_DEG: f64 = 80.0;

/// Which camera a video is seen from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Camera {
    /// Behind and above the robot, turning with its heading ([`ChaseCamera`]'s default place).
    Chase,
    /// A sensor of the vehicle by name (`[[sensors]]`): its frame, looking along its x axis.
    Sensor(String),
}

/// What to render.
#[derive(Clone, Debug, PartialEq)]
pub struct VideoOptions {
    /// The camera.
    pub camera: Camera,
    /// Frames per second (1..=[`MAX_FPS`]).
    pub fps: u32,
    /// Width, pixels (even).
    pub width: usize,
    /// Height, pixels (even).
    pub height: usize,
    /// In a team run, the robot the camera follows (its folder's name; `None`: the first).
    pub robot: Option<String>,
    /// Threads to render on (0: every core); the bytes do not depend on it.
    pub threads: usize,
}

impl Default for VideoOptions {
    fn default() -> Self {
        VideoOptions {
            camera: Camera::Chase,
            fps: DEFAULT_FPS,
            width: DEFAULT_SIZE.0,
            height: DEFAULT_SIZE.1,
            robot: None,
            threads: 0,
        }
    }
}

impl VideoOptions {
    /// The problems of these settings, each under its command-line flag.
    pub fn issues(&self) -> Vec<SpecIssue> {
        let mut out = Vec::new();
        if self.fps == 0 || self.fps > MAX_FPS {
            out.push(SpecIssue::new(
                "--fps",
                format!("{}: give 1 to {MAX_FPS} frames per second", self.fps),
            ));
        }
        for (k, v) in [("width", self.width), ("height", self.height)] {
            if v == 0 || !v.is_multiple_of(2) || v > MAX_SIDE {
                out.push(SpecIssue::new(
                    "--size",
                    format!(
                        "{k} {v}: give an even number of pixels from 2 to {MAX_SIDE} (H.264 4:2:0 needs even sides), e.g. --size 640x480"
                    ),
                ));
            }
        }
        out
    }
}

/// What a video took.
#[derive(Clone, Debug, PartialEq)]
pub struct VideoReport {
    /// Frames.
    pub frames: usize,
    /// Length, s.
    pub duration_s: f64,
    /// Size of the MP4, bytes.
    pub bytes: usize,
    /// Wall time spent rendering (HUD included), s.
    pub render_s: f64,
    /// Wall time spent encoding and muxing, s.
    pub encode_s: f64,
}

impl VideoReport {
    /// Megabytes (10^6 bytes) per minute of video.
    pub fn mb_per_minute(&self) -> f64 {
        if self.duration_s <= 0.0 {
            return 0.0;
        }
        self.bytes as f64 / 1e6 * 60.0 / self.duration_s
    }
}

/// A run folder ready to render: its recordings (one, or a team run's robots) and its scene.
pub struct Replay {
    runs: Vec<Recording>,
    world: ReplayWorld,
    /// The robot the camera follows.
    focus: usize,
}

fn settings(key: &str, message: String) -> Error {
    Error::Settings {
        what: "video".into(),
        issues: vec![SpecIssue::new(key, message)],
    }
}

/// The robots' folders of a team run (`team.json`'s `robots`, in order).
fn team_dirs(dir: &Path) -> Result<Vec<PathBuf>> {
    let p = dir.join("team.json");
    let text = std::fs::read_to_string(&p).map_err(|source| Error::Io {
        path: p.clone(),
        source,
    })?;
    let v: serde_json::Value = serde_json::from_str(&text).map_err(|e| Error::Parse {
        path: p.clone(),
        message: e.to_string(),
    })?;
    let names: Vec<String> = v
        .get("robots")
        .and_then(|r| r.as_array())
        .map(|a| {
            a.iter()
                .filter_map(|r| Some(r.get("name")?.as_str()?.to_string()))
                .collect()
        })
        .unwrap_or_default();
    // Names are folder names written by tracksim: refuse anything that leaves the folder.
    let ok = |n: &String| !n.is_empty() && !n.contains(['/', '\\']) && n != ".." && n != ".";
    if names.is_empty() || !names.iter().all(ok) {
        return Err(Error::Invalid {
            path: p,
            issues: vec![SpecIssue::new(
                "robots",
                "no robot folders listed: not a team run's team.json; run the team scenario again",
            )],
        });
    }
    Ok(names.iter().map(|n| dir.join(n)).collect())
}

impl Replay {
    /// Reads the run folder `dir` (a team run's folder: every robot, the camera on `robot` or
    /// the first).
    pub fn open(dir: &Path, robot: Option<&str>) -> Result<Replay> {
        crate::output::incomplete::check_complete(dir)?;
        let runs = if dir.join("team.json").is_file() && !dir.join("scene.json").is_file() {
            team_dirs(dir)?
                .iter()
                .map(|d| Recording::read_session(d))
                .collect::<Result<Vec<_>>>()?
        } else {
            if !dir.is_dir() {
                return Err(record::missing(dir, "scene.json"));
            }
            vec![Recording::read(dir)?]
        };
        let focus = match robot {
            None => 0,
            Some(n) => runs.iter().position(|r| r.name == n).ok_or_else(|| {
                let names: Vec<&str> = runs.iter().map(|r| r.name.as_str()).collect();
                settings(
                    "--robot",
                    format!("{n}: no such robot here; give one of: {}", names.join(", ")),
                )
            })?,
        };
        let world = ReplayWorld::new(&runs);
        Ok(Replay { runs, world, focus })
    }

    /// The recording the camera follows.
    pub fn focus(&self) -> &Recording {
        &self.runs[self.focus]
    }

    /// Number of frames at `fps`: from the first sample to the last, both included.
    pub fn frame_count(&self, fps: u32) -> usize {
        let r = self.focus();
        let span = (r.end_s() - r.start_s()) * fps as f64 + 1e-6;
        // `as` saturates: a NaN span gives 0, a huge one usize::MAX (refused by the caller).
        (span.floor().max(0.0) as usize).saturating_add(1)
    }

    /// Times of the frames at `fps`, s: from the first sample to the last, both included (at
    /// most [`MAX_FRAMES`]).
    pub fn frame_times(&self, fps: u32) -> Vec<f64> {
        let t0 = self.focus().start_s();
        let n = self.frame_count(fps).min(MAX_FRAMES);
        (0..n).map(|k| t0 + k as f64 / fps as f64).collect()
    }

    /// Checks that `camera` exists; names the choices when it does not.
    pub fn check_camera(&self, camera: &Camera) -> Result<()> {
        let Camera::Sensor(name) = camera else {
            return Ok(());
        };
        if self.focus().scene.sensors.iter().any(|s| &s.name == name) {
            return Ok(());
        }
        let names: Vec<&str> = self
            .focus()
            .scene
            .sensors
            .iter()
            .map(|s| s.name.as_str())
            .collect();
        Err(settings(
            "--camera",
            format!(
                "{name}: no sensor of that name on the vehicle; give `chase`{}",
                if names.is_empty() {
                    " (this vehicle has no sensors)".to_string()
                } else {
                    format!(" or a sensor: {}", names.join(", "))
                }
            ),
        ))
    }

    /// The camera's pose and intrinsics at the robots' `states`, and its range (m).
    fn camera(
        &self,
        camera: &Camera,
        states: &[RobotState],
        width: usize,
        height: usize,
    ) -> (CameraPose, Intrinsics, f32) {
        let st = &states[self.focus];
        let chase = || {
            let c = ChaseCamera {
                intrinsics: Intrinsics {
                    width,
                    height,
                    horizontal_fov: ChaseCamera::default().intrinsics.horizontal_fov,
                },
                ..ChaseCamera::default()
            };
            (
                c.pose(st.position, st.rotation),
                c.intrinsics,
                CHASE_RANGE_M,
            )
        };
        let Camera::Sensor(name) = camera else {
            return chase();
        };
        let Some(s) = self.focus().scene.sensors.iter().find(|s| &s.name == name) else {
            return chase();
        };
        let q = s.quat_xyzw;
        let mount_rot = DQuat::from_xyzw(q[0], q[1], q[2], q[3]).normalize();
        let mount_pos = DVec3::from_array(s.xyz_m);
        // A flipper's mount turns with it about its pivot.
        let (fr, ft) = usize::try_from(s.mount_index)
            .ok()
            .and_then(|i| {
                let f = self.focus().scene.vehicle.flippers.get(i)?;
                let axis = DVec3::from_array(f.axis).try_normalize()?;
                let a = st.flippers.get(i).copied().unwrap_or(0.0);
                let r = DQuat::from_axis_angle(axis, a);
                let pivot = DVec3::from_array(f.pivot_m);
                Some((r, pivot - r * pivot))
            })
            .unwrap_or((DQuat::IDENTITY, DVec3::ZERO));
        let image = s.rgb_camera.as_ref().or(s.depth_camera.as_ref());
        let fov = image.map_or(ONBOARD_FOV_DEG.to_radians(), |c| c.horizontal_fov_rad);
        let range = image.map_or(CHASE_RANGE_M, |c| c.max_range_m as f32);
        let pose = CameraPose {
            position: st.position + st.rotation * (ft + fr * mount_pos),
            rotation: (st.rotation * fr * mount_rot).normalize(),
        };
        let i = Intrinsics {
            width,
            height,
            horizontal_fov: fov,
        };
        (pose, i, range)
    }

    /// The HUD's lines at time `t` for the followed robot in state `st`.
    pub fn hud_lines(&self, st: &RobotState) -> Vec<String> {
        let r = self.focus();
        let t = st.t;
        let mut lines = vec![
            format!("t {:7.2} s", t - r.start_s()),
            format!("speed {:5.2} m/s", st.speed),
        ];
        if self.runs.len() > 1 {
            lines.insert(0, format!("robot {}", r.name));
        }
        let s = r.summary_at(t);
        if let Some((gates, reps)) = s.course_gates {
            let seen = |k: &str| {
                s.course_events
                    .iter()
                    .filter(|(te, kind)| *te <= t + 1e-9 && kind == k)
                    .count()
            };
            lines.push(format!(
                "course gates {} ({gates} a lap) laps {}/{reps} faults {}",
                seen("gate"),
                seen("repetition"),
                seen("fault")
            ));
        }
        if let (Some(o), Some(to)) = (&s.outcome, s.outcome_time_s)
            && t + 1e-9 >= to
        {
            let score = s
                .course_score_s
                .map(|x| format!(" score {x:.2} s"))
                .unwrap_or_default();
            lines.push(format!("{o}{score}"));
        }
        lines
    }

    /// Renders the frame at time `t` (s) with its HUD into `frame` (of the options' size).
    pub fn render_frame(
        &self,
        t: f64,
        opts: &VideoOptions,
        pool: Option<&rayon::ThreadPool>,
        frame: &mut Frame,
    ) {
        let states: Vec<RobotState> = self.runs.iter().map(|r| r.state_at(t)).collect();
        let (pose, i, range) = self.camera(&opts.camera, &states, opts.width, opts.height);
        let corner = i.corner_factor();
        let hide = matches!(opts.camera, Camera::Sensor(_)).then_some(self.focus);
        let scene = self
            .world
            .scene(&states, pose.position, range as f64 * corner, hide);
        let rays = i.pixel_rays_f32();
        render::render(
            &scene,
            &i,
            &rays,
            &pose,
            &Light::default(),
            0.0,
            range,
            pool,
            frame,
        );
        hud::draw_lines(
            &mut frame.rgb,
            frame.width,
            frame.height,
            &self.hud_lines(&states[self.focus]),
        );
    }
}

/// Renders the run in `dir` to MP4 bytes.
pub fn render_video(dir: &Path, opts: &VideoOptions) -> Result<(Vec<u8>, VideoReport)> {
    let issues = opts.issues();
    if !issues.is_empty() {
        return Err(Error::Settings {
            what: "video".into(),
            issues,
        });
    }
    let replay = Replay::open(dir, opts.robot.as_deref())?;
    replay.check_camera(&opts.camera)?;
    let n = replay.frame_count(opts.fps);
    if n > MAX_FRAMES {
        return Err(settings(
            "--fps",
            format!(
                "{n} frames: more than {MAX_FRAMES} ({} to {} s); give a lower --fps",
                replay.focus().start_s(),
                replay.focus().end_s()
            ),
        ));
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.threads)
        .build()
        .ok();
    let mut enc = h264::Mp4Encoder::new(opts.width, opts.height, opts.fps)?;
    let mut frame = Frame::new(opts.width, opts.height);
    let times = replay.frame_times(opts.fps);
    let (mut render_s, mut encode_s) = (0.0, 0.0);
    for &t in &times {
        let a = Instant::now();
        replay.render_frame(t, opts, pool.as_ref(), &mut frame);
        let b = Instant::now();
        enc.push(&frame.rgb)?;
        render_s += (b - a).as_secs_f64();
        encode_s += b.elapsed().as_secs_f64();
    }
    let a = Instant::now();
    let bytes = enc.finish()?;
    encode_s += a.elapsed().as_secs_f64();
    let report = VideoReport {
        frames: times.len(),
        duration_s: times.len() as f64 / opts.fps as f64,
        bytes: bytes.len(),
        render_s,
        encode_s,
    };
    Ok((bytes, report))
}

/// Renders the run in `dir` to the MP4 file `out` (written whole or not at all).
pub fn write_video(dir: &Path, out: &Path, opts: &VideoOptions) -> Result<VideoReport> {
    let (bytes, report) = render_video(dir, opts)?;
    if let Some(parent) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).map_err(|source| Error::Io {
            path: parent.to_path_buf(),
            source,
        })?;
    }
    crate::files::write_atomic(out, &bytes)?;
    Ok(report)
}
