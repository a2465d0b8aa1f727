//! Issue 41 (learners and robot developers): frames of an environment (`Env::render`: the
//! chase camera or an rgb_camera sensor), batched by `VecEnv::render`, the camera image in a
//! dict observation, and a colour camera in `run.mcap`: `sensor_msgs/CompressedImage` (PNG)
//! and `sensor_msgs/CameraInfo` (K from the field of view) with the same stamps, the PNG
//! decoding to the bytes the camera rendered, the raw `Image` only on request.

use crate::common;

use std::collections::BTreeMap;
use std::sync::Arc;
use tracksim::env::{Env, EnvConfig, EnvValue, VecEnv};
use tracksim::output::mcap::MCAP_FILE;
use tracksim::rosmsg::{self, CameraInfo, CompressedImage, Image, RosMessage, TFMessage, Time};

const CAMERA: &str = "scenarios/packbot_camera.toml";

fn template(path: &str) -> Arc<tracksim::ScenarioTemplate> {
    Arc::new(tracksim::load_template(&common::root().join(path)).unwrap())
}

fn cfg(settings: &[(&str, EnvValue)]) -> EnvConfig {
    EnvConfig::from_settings(settings.iter().cloned()).unwrap()
}

/// The pixels of a PNG (any colour type the `png` crate reads), and its width and height.
fn decode_png(bytes: &[u8]) -> (Vec<u8>, u32, u32) {
    let mut d = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .expect("a PNG");
    let mut buf = vec![0; d.output_buffer_size().unwrap()];
    let info = d.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    buf.truncate(info.buffer_size());
    (buf, info.width, info.height)
}

#[test]
fn env_chase_frames_are_reproducible_move_with_the_robot_and_change_nothing() {
    let t = template(CAMERA);
    let c = cfg(&[("render_size_px", EnvValue::from((64i64, 48i64)))]);
    let mut a = Env::new(t.clone(), c.clone(), 1).unwrap();
    let mut b = Env::new(t.clone(), c.clone(), 1).unwrap();
    assert_eq!(a.render_size(), (64, 48));
    let first = a.render().clone();
    assert_eq!(
        (first.width, first.height, first.rgb.len()),
        (64, 48, 64 * 48 * 3)
    );
    assert_eq!(b.render().rgb, first.rgb, "same seed, same frame");
    // Sky at the top, ground at the bottom: not a flat image.
    let row = |f: &tracksim::render::Frame, v: usize| f.rgb[v * 64 * 3..(v + 1) * 64 * 3].to_vec();
    assert_ne!(row(&first, 0), row(&first, 47));
    // Rendering at every step changes nothing: `a` renders, `b` does not.
    for _ in 0..20 {
        a.step(&[1.0, 0.0, 0.0, 0.0]);
        a.render();
        b.step(&[1.0, 0.0, 0.0, 0.0]);
    }
    assert_eq!(a.simulation().sample(), b.simulation().sample());
    let later = a.render().clone();
    assert_eq!(b.render().rgb, later.rgb);
    let changed = first
        .rgb
        .chunks(3)
        .zip(later.rgb.chunks(3))
        .filter(|(p, q)| {
            p.iter()
                .zip(*q)
                .map(|(x, y)| x.abs_diff(*y) as u32)
                .sum::<u32>()
                > 30
        })
        .count();
    assert!(
        changed > 64 * 48 / 100,
        "{changed} pixels changed after 1 s of driving"
    );
}

#[test]
fn render_camera_names_an_rgb_camera_or_is_refused_with_its_key() {
    let t = template(CAMERA);
    let mut e = Env::new(t.clone(), cfg(&[("render_camera", "front_rgb".into())]), 0).unwrap();
    assert_eq!(e.render_size(), (160, 120));
    for _ in 0..4 {
        e.step(&[1.0, 0.0, 0.0, 0.0]);
    }
    // The sensor's latest frame, as its `rgb` channel holds it.
    let f = e.render().clone();
    let s = e.sensors().find("front_rgb").unwrap();
    let ch = s.channels().iter().find(|c| c.name == "rgb").unwrap();
    let levels: Vec<u8> = ch.data.iter().map(|v| *v as u8).collect();
    assert_eq!(f.rgb, levels);
    assert!(f.rgb.iter().any(|x| *x != f.rgb[0]));
    for (name, says) in [
        ("rear", "is no sensor of the vehicle"),
        ("chase ", "is no sensor"),
    ] {
        let e = Env::new(t.clone(), cfg(&[("render_camera", name.into())]), 0)
            .err()
            .expect("refused");
        let i = &e.issues()[0];
        assert_eq!(i.key, "render_camera", "{e}");
        assert!(
            i.message.contains(says) && i.message.contains("\"front_rgb\""),
            "{e}"
        );
    }
    let e = Env::new(
        template("scenarios/packbot_sensors.toml"),
        cfg(&[("render_camera", "front_camera".into())]),
        0,
    )
    .err()
    .expect("a depth camera is refused");
    assert!(
        e.issues()[0].message.contains("is not an rgb_camera"),
        "{e}"
    );
    let e =
        EnvConfig::from_settings([("render_size_px", EnvValue::from((0i64, 10i64)))]).unwrap_err();
    assert_eq!(e.issues()[0].key, "render_size_px", "{e}");
    let e = EnvConfig::from_settings([("render_size_px", EnvValue::from((2048i64, 2048i64)))])
        .unwrap_err();
    assert!(e.issues()[0].message.contains("pixels"), "{e}");
}

#[test]
fn vec_env_frames_are_the_single_envs_frames_batched() {
    let t = template(CAMERA);
    let c = cfg(&[("render_size_px", EnvValue::from((40i64, 30i64)))]);
    let mut v = VecEnv::new(t.clone(), c.clone(), 3, 7, 2).unwrap();
    let mut obs = vec![0f32; 3 * v.obs_dim()];
    for _ in 0..5 {
        v.step(&[0.5, 0.2, 0.0, 0.0].repeat(3), &mut obs).unwrap();
    }
    let mut out = Vec::new();
    assert_eq!(v.render(&mut out).unwrap(), (40, 30));
    assert_eq!(out.len(), 3 * 30 * 40 * 3);
    for i in 0..3 {
        let mut e = Env::new(t.clone(), c.clone(), 7 + i as u64).unwrap();
        for _ in 0..5 {
            e.step(&[0.5, 0.2, 0.0, 0.0]);
        }
        assert_eq!(
            &out[i * 3600..(i + 1) * 3600],
            &e.render().rgb[..],
            "env {i}"
        );
    }
}

#[test]
fn an_rgb_camera_is_a_dict_observation_entry_of_its_image() {
    let mut e = Env::new(template(CAMERA), cfg(&[("observation", "dict".into())]), 0).unwrap();
    let spec = e.sensor_obs_spec();
    assert_eq!(spec.len(), 1);
    assert_eq!(
        (spec[0].name.as_str(), spec[0].kind, spec[0].shape.clone()),
        ("front_rgb", "rgb_camera", vec![120, 160, 3])
    );
    assert_eq!((spec[0].low, spec[0].high), (0.0, 255.0));
    for _ in 0..4 {
        e.step(&[1.0, 0.0, 0.0, 0.0]);
    }
    let mut o = vec![0f32; e.sensor_obs_dim()];
    e.observe_sensors(&mut o);
    let frame = e
        .sensors()
        .find("front_rgb")
        .unwrap()
        .frame()
        .unwrap()
        .clone();
    let as_bytes: Vec<u8> = o.iter().map(|x| *x as u8).collect();
    assert_eq!(as_bytes, frame.rgb);
    assert!(
        o.iter()
            .all(|x| (0.0..=255.0).contains(x) && x.fract() == 0.0)
    );
}

/// Messages of a topic: (log time ns, CDR bytes) each.
type Messages = Vec<(u64, Vec<u8>)>;
/// Frames by reading time: (t s, rgb8 bytes) each.
type Frames = Vec<(f64, Vec<u8>)>;

/// A run of the camera scenario for `duration` s, stepped by hand to keep every frame the
/// camera rendered (by reading time), and the bytes of its `run.mcap` (with `raw_images`)
/// and of its run folder's PNG of reading 3.
fn camera_run(duration: f64, raw_images: bool) -> (Frames, Vec<u8>, Vec<u8>) {
    let sc = common::load_for(CAMERA, duration);
    let mut runner = tracksim::run::runner::Runner::new(&sc).unwrap();
    let mut frames: Frames = Vec::new();
    while !runner.finished() {
        runner.step().unwrap();
        let t = runner.sensors().reading_time(0);
        if frames.last().is_none_or(|f| f.0 < t) {
            let f = runner.sensors().sensor(0).frame().unwrap();
            frames.push((t, f.rgb.clone()));
        }
    }
    let result = runner.finish(tracksim::run::End::Reached);
    static RUNS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let k = RUNS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("tracksim-i41-{}-{k}", std::process::id()));
    let which = tracksim::output::Outputs {
        replay: false,
        plots: false,
        mcap: true,
        raw_images,
    };
    tracksim::output::write_outputs(&sc, &result, &dir, which).expect("writes");
    let bytes = std::fs::read(dir.join(MCAP_FILE)).unwrap();
    let png3 = std::fs::read(dir.join("sensors/front_rgb/000003.png")).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    (frames, bytes, png3)
}

/// Every topic's schema name and messages (log time, CDR bytes).
fn topics(bytes: &[u8]) -> BTreeMap<String, (String, Messages)> {
    let mut out: BTreeMap<String, (String, Messages)> = BTreeMap::new();
    for m in mcap::MessageStream::new(bytes).expect("mcap") {
        let m = m.expect("message");
        let schema = m.channel.schema.as_ref().expect("schema");
        if m.channel.topic == "/scene" {
            continue;
        }
        assert_eq!(schema.encoding, "ros2msg");
        assert_eq!(m.channel.message_encoding, "cdr");
        out.entry(m.channel.topic.clone())
            .or_insert_with(|| (schema.name.clone(), Vec::new()))
            .1
            .push((m.log_time, m.data.to_vec()));
    }
    out
}

fn decoded<T: RosMessage>(msgs: &[(u64, Vec<u8>)]) -> Vec<T> {
    msgs.iter()
        .map(|(_, d)| rosmsg::decode::<T>(d).expect("decodes"))
        .collect()
}

#[test]
fn run_mcap_holds_png_compressed_images_and_camera_info_of_the_rendered_frames() {
    let (frames, bytes, png3) = camera_run(1.0, false);
    assert!(
        frames.len() >= 10,
        "{} frames in 1 s at 10 Hz",
        frames.len()
    );
    let msgs = topics(&bytes);
    let (ty, compressed) = &msgs["/front_rgb/compressed"];
    assert_eq!(ty, "sensor_msgs/msg/CompressedImage");
    let (ty, info) = &msgs["/front_rgb/camera_info"];
    assert_eq!(ty, "sensor_msgs/msg/CameraInfo");
    assert!(
        !msgs.contains_key("/front_rgb"),
        "the raw topic only on request"
    );
    assert_eq!(compressed.len(), frames.len());
    assert_eq!(info.len(), frames.len());
    let images: Vec<CompressedImage> = decoded(compressed);
    let infos: Vec<CameraInfo> = decoded(info);
    // K from the field of view: 160 x 120 pixels, 70 deg across.
    let f = 80.0 / 35f64.to_radians().tan();
    for (k, ((img, ci), (t, rgb))) in images.iter().zip(&infos).zip(&frames).enumerate() {
        assert_eq!(img.header.stamp, Time::from_secs(*t));
        assert_eq!(compressed[k].0, Time::from_secs(*t).nanos());
        assert_eq!(ci.header, img.header);
        assert_eq!(img.header.frame_id, "front_rgb_optical_frame");
        assert_eq!(img.format, "rgb8; png compressed bgr8");
        let (pixels, w, h) = decode_png(&img.data);
        assert_eq!((w, h), (160, 120));
        assert_eq!(&pixels, rgb, "reading {k}: the PNG is the frame rendered");
        assert_eq!((ci.width, ci.height), (160, 120));
        assert_eq!(ci.distortion_model, "plumb_bob");
        assert_eq!(ci.d, vec![0.0; 5]);
        for (got, want) in ci.k.iter().zip([f, 0.0, 80.0, 0.0, f, 60.0, 0.0, 0.0, 1.0]) {
            assert!((got - want).abs() < 1e-9, "K {:?}", ci.k);
        }
        assert!((ci.k[0] - 114.2518).abs() < 1e-3);
        assert_eq!(ci.r, [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]);
        assert_eq!(
            ci.p,
            [
                ci.k[0], 0.0, 80.0, 0.0, 0.0, ci.k[4], 60.0, 0.0, 0.0, 0.0, 1.0, 0.0
            ]
        );
    }
    // The run folder's PNG is the message's.
    assert_eq!(images[3].data, png3);
    // The frames change as the robot drives.
    assert_ne!(frames[0].1, frames.last().unwrap().1);
    // The optical frame is on /tf_static.
    let stat: Vec<TFMessage> = decoded(&msgs["/tf_static"].1);
    assert!(
        stat[0]
            .transforms
            .iter()
            .any(|t| t.header.frame_id == "front_rgb_link"
                && t.child_frame_id == "front_rgb_optical_frame")
    );
}

#[test]
fn raw_images_add_the_rgb8_image_topic_equal_to_the_png() {
    let (frames, with_raw, _) = camera_run(0.5, true);
    let (_, without, _) = camera_run(0.5, false);
    let msgs = topics(&with_raw);
    let (ty, raw) = &msgs["/front_rgb"];
    assert_eq!(ty, "sensor_msgs/msg/Image");
    let raw: Vec<Image> = decoded(raw);
    let png: Vec<CompressedImage> = decoded(&msgs["/front_rgb/compressed"].1);
    assert_eq!(raw.len(), frames.len());
    for ((r, p), (_, rgb)) in raw.iter().zip(&png).zip(&frames) {
        assert_eq!(
            (r.encoding.as_str(), r.width, r.height, r.step),
            ("rgb8", 160, 120, 480)
        );
        assert_eq!(&r.data, rgb);
        assert_eq!(decode_png(&p.data).0, r.data);
        assert_eq!(r.header, p.header);
        // PNG is smaller than raw.
        assert!(
            p.data.len() < r.data.len() / 2,
            "{} vs {}",
            p.data.len(),
            r.data.len()
        );
    }
    assert!(with_raw.len() > without.len() + frames.len() * 57_600);
}

/// The stated bound of docs/MCAP.md: a 160 x 120 frame's PNG (rgb8) is at most
/// [`PNG_BOUND_160X120`] bytes even when nothing compresses (random pixels), and its depth PNG
/// at most [`DEPTH_PNG_BOUND_160X120`].
const PNG_BOUND_160X120: usize = 60_000;
const DEPTH_PNG_BOUND_160X120: usize = 40_000;

#[test]
fn incompressible_160x120_frames_stay_within_the_stated_png_bound() {
    let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut next = || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        x
    };
    let rgb: Vec<u8> = (0..160 * 120 * 3).map(|_| next() as u8).collect();
    let png = tracksim::render::encode::rgb8_png(160, 120, &rgb);
    let depth: Vec<f32> = (0..160 * 120)
        .map(|_| (next() % 65_000) as f32 / 1000.0 + 0.001)
        .collect();
    let dpng = tracksim::render::encode::depth16_png(160, 120, &depth);
    println!(
        "random 160 x 120: rgb PNG {} bytes, depth PNG {} bytes",
        png.len(),
        dpng.len()
    );
    assert!(png.len() <= PNG_BOUND_160X120, "{}", png.len());
    assert!(dpng.len() <= DEPTH_PNG_BOUND_160X120, "{}", dpng.len());
    assert_eq!(decode_png(&png).0, rgb);
}
