//! Issue 41: the colour camera checked against geometry and its light model. A red box lands
//! in the pixels a pinhole projection predicts, at its depth; a shadowed patch of ground is
//! exactly `ambient / (ambient + diffuse cos)` as bright as a lit one, where a ray towards the
//! sun meets the wall or not; the colour camera's depth equals the depth camera's on the same
//! mount; the chase camera sees the robot; images are the same bytes on one thread or two and
//! from run to run; noise is seeded with its stated spread; sensing leaves the trajectory
//! unchanged; bad keys are refused with their keys.

use super::issue_25_sensors::{ch, flat_with, sensors, settle};
use crate::common;
use glam::{DQuat, DVec3};
use tracksim::Simulation;
use tracksim::model::{compile_vehicle, read_toml};
use tracksim::render::{ChaseCamera, Frame, Light, Rgb, palette};
use tracksim::sensors::SensorSet;
use tracksim::sensors::sim_scene::{WorldShapes, render_chase};
use tracksim::spec::{BoxSpec, SensorSpec, VehicleSpec};

const W: usize = 64;
const H: usize = 48;

fn camera(extra: &str) -> String {
    format!(
        r#"
[[sensors]]
name = "rgb"
kind = "rgb_camera"
xyz_m = [0.25, 0.0, 0.05]
width_px = {W}
height_px = {H}
horizontal_fov_deg = 60.0
max_range_m = 10.0
{extra}
"#
    )
}

fn solid(centre: [f64; 3], size: [f64; 3], color: Option<&str>) -> BoxSpec {
    BoxSpec {
        centre_m: centre,
        size_m: size,
        yaw_deg: 0.0,
        pitch_deg: 0.0,
        friction: 0.6,
        soil: None,
        color: color.map(str::to_string),
    }
}

/// The world direction of pixel (u, v) of a camera at orientation `q`.
fn pixel_ray(q: DQuat, u: usize, v: usize) -> DVec3 {
    let f = (W as f64 / 2.0) / 30f64.to_radians().tan();
    q * DVec3::new(
        1.0,
        -(u as f64 + 0.5 - W as f64 / 2.0) / f,
        -(v as f64 + 0.5 - H as f64 / 2.0) / f,
    )
}

/// Entry time of ray `o + t d` into the axis-aligned box `centre +- half`.
fn enters(o: DVec3, d: DVec3, centre: DVec3, half: DVec3) -> Option<f64> {
    let (mut lo, mut hi) = (0.0f64, f64::INFINITY);
    for k in 0..3 {
        let (a, b) = (
            (centre[k] - half[k] - o[k]) / d[k],
            (centre[k] + half[k] - o[k]) / d[k],
        );
        lo = lo.max(a.min(b));
        hi = hi.min(a.max(b));
    }
    (lo <= hi).then_some(lo)
}

/// The camera's world position and orientation from its reading.
fn pose(set: &SensorSet) -> (DVec3, DQuat) {
    let s = set.sensor(0);
    let (p, q) = (ch(s, "position"), ch(s, "orientation"));
    (
        DVec3::new(p[0], p[1], p[2]),
        DQuat::from_xyzw(q[0], q[1], q[2], q[3]),
    )
}

fn rgb_at(set: &SensorSet, u: usize, v: usize) -> [u8; 3] {
    let f = set.sensor(0).frame().expect("a colour camera has a frame");
    let i = 3 * (v * W + u);
    [f.rgb[i], f.rgb[i + 1], f.rgb[i + 2]]
}

/// A red box 2 m ahead covers exactly the pixels whose rays enter it before the ground (edge
/// pixels, where a box 1 cm smaller or larger decides otherwise, left out), at the depth of
/// the face it enters.
#[test]
fn a_red_box_lands_in_the_pixels_geometry_predicts() {
    let (c, half) = (DVec3::new(2.1, 0.3, 0.25), DVec3::new(0.1, 0.2, 0.15));
    let red = solid(c.to_array(), (2.0 * half).to_array(), Some("#ff0000"));
    let (mut sim, mut set) = flat_with(&camera(""), vec![red], 0.0);
    settle(&mut sim, &mut set, 0.5);
    let (o, q) = pose(&set);
    let depth = ch(set.sensor(0), "depth");
    let (mut inside, mut outside) = (0, 0);
    for v in 0..H {
        for u in 0..W {
            let d = pixel_ray(q, u, v);
            let ground = if d.z < 0.0 { -o.z / d.z } else { f64::INFINITY };
            let hit =
                |grow: f64| enters(o, d, c, half + DVec3::splat(grow)).is_some_and(|t| t < ground);
            let (small, big) = (hit(-0.01), hit(0.01));
            if small != big {
                continue; // an edge pixel
            }
            let px = rgb_at(&set, u, v);
            let is_red = px[0] > 90 && px[1] == 0 && px[2] == 0;
            assert_eq!(is_red, small, "pixel ({u}, {v}): {px:?}");
            if small {
                let t = enters(o, d, c, half).unwrap();
                assert!(
                    (depth[v * W + u] - t).abs() < 2e-3,
                    "({u}, {v}) depth {} vs {t}",
                    depth[v * W + u]
                );
                inside += 1;
            } else {
                outside += 1;
            }
        }
    }
    assert!(
        inside > 40 && outside > 1000,
        "{inside} box pixels, {outside} others"
    );
}

/// Ground in a wall's shadow is drawn at `ambient` times its colour, lit ground at
/// `ambient + diffuse * sin(elevation)` (the sun's cosine on level ground), to the rounding
/// of an 8-bit level; which is which follows from a ray towards the sun meeting the wall.
#[test]
fn a_shadowed_patch_is_darker_by_the_light_model() {
    let (c, half) = (DVec3::new(1.8, -0.3, 1.0), DVec3::new(0.05, 0.3, 1.0));
    let wall = solid(c.to_array(), (2.0 * half).to_array(), None);
    // On a mast, looking down at the ground (a level camera 14 cm up sees it at a grazing
    // angle, a few rows).
    let mast = camera("").replace(
        "xyz_m = [0.25, 0.0, 0.05]",
        "xyz_m = [0.25, 0.0, 0.8]\nrpy_deg = [0.0, 20.0, 0.0]",
    );
    let (mut sim, mut set) = flat_with(&mast, vec![wall], 0.0);
    settle(&mut sim, &mut set, 0.5);
    let (o, q) = pose(&set);
    let light = Light::default();
    let sun = light.sun.as_dvec3();
    let want = |f: f32| Light::apply(palette::GROUND, f);
    let (lit_f, shade_f) = (light.ambient + light.diffuse * light.sun.z, light.ambient);
    let (mut lit, mut shaded) = (0, 0);
    for v in 0..H {
        for u in 0..W {
            let d = pixel_ray(q, u, v);
            if d.z >= 0.0 || enters(o, d, c, half + DVec3::splat(0.02)).is_some() {
                continue;
            }
            let t = -o.z / d.z;
            let p = o + d * t;
            if p.x < 1.0 || t > 9.0 {
                continue; // the robot's own shadow may fall nearer; the range is 10 m
            }
            let blocked = |grow: f64| {
                enters(p, sun, c, half + DVec3::splat(grow))
                    .is_some_and(|t| t <= light.shadow_range as f64)
            };
            let (small, big) = (blocked(-0.02), blocked(0.02));
            if small != big {
                continue; // the shadow's edge
            }
            let px = rgb_at(&set, u, v);
            let expect = want(if small { shade_f } else { lit_f });
            for k in 0..3 {
                assert!(
                    (px[k] as i32 - expect[k] as i32).abs() <= 1,
                    "({u}, {v}) at {p}: {px:?}, expected {expect:?} ({})",
                    if small { "shadow" } else { "lit" }
                );
            }
            if small { shaded += 1 } else { lit += 1 }
        }
    }
    assert!(
        shaded > 60 && lit > 300,
        "{shaded} shadowed, {lit} lit pixels"
    );
}

/// The colour camera's depth is the depth camera's on the same mount and image (its rays are
/// the same; the hits come through other code: closed forms against parry's casts).
#[test]
fn colour_and_depth_agree_with_the_depth_camera() {
    let text = format!(
        "{}\n[[sensors]]\nname = \"depth\"\nkind = \"depth_camera\"\nxyz_m = [0.25, 0.0, 0.05]\n\
         width_px = {W}\nheight_px = {H}\nhorizontal_fov_deg = 60.0\nmax_range_m = 10.0\n",
        camera("")
    );
    let boxes = vec![
        solid([2.1, 0.3, 0.25], [0.2, 0.4, 0.5], Some("#ff0000")),
        solid([3.0, -0.8, 0.1], [0.5, 0.5, 0.2], None),
    ];
    let (mut sim, mut set) = flat_with(&text, boxes, 5.0);
    settle(&mut sim, &mut set, 0.5);
    let (a, b) = (ch(set.sensor(0), "depth"), ch(set.sensor(1), "depth"));
    let mut differ = 0;
    for (x, y) in a.iter().zip(b) {
        if x.is_finite() && y.is_finite() {
            assert!((x - y).abs() < 1e-3, "{x} vs {y}");
        } else if x != y {
            differ += 1;
        }
    }
    assert!(
        differ <= a.len() / 200,
        "{differ} pixels see something in one camera only"
    );
    // Colour edges are depth edges: a red pixel's depth is the box's.
    let f = set.sensor(0).frame().unwrap();
    for (i, d) in a.iter().enumerate() {
        if f.rgb[3 * i] > 90 && f.rgb[3 * i + 1] == 0 {
            assert!(*d < 2.05 - 0.25 + 0.2, "a red pixel at depth {d}");
        }
    }
}

/// Renders robot 0 of `sim` with the default chase camera.
fn chase(sim: &Simulation) -> Frame {
    let cam = ChaseCamera::default();
    let mut frame = Frame::new(cam.intrinsics.width, cam.intrinsics.height);
    render_chase(sim, &cam, &mut WorldShapes::default(), &mut frame);
    frame
}

/// The chase camera sees the robot: its body's colour (shaded) at 1-3 m in the middle of the
/// image; and the same state gives the same bytes.
#[test]
fn the_chase_camera_sees_the_robot() {
    let (mut sim, mut set) = flat_with(&camera(""), vec![], 0.0);
    settle(&mut sim, &mut set, 0.3);
    let frame = chase(&sim);
    let body = palette::BODY.0.map(|v| v as f32);
    let seen = (0..frame.width * frame.height)
        .filter(|&i| {
            let px = &frame.rgb[3 * i..3 * i + 3];
            let f = px[1] as f32 / body[1];
            (0.35..=1.05).contains(&f)
                && (0..3).all(|k| (px[k] as f32 - body[k] * f).abs() <= 2.0)
                && (1.0..3.0).contains(&frame.depth[i])
        })
        .count();
    assert!(seen > 200, "{seen} body pixels");
    assert_eq!(chase(&sim), frame, "the same state, the same image");
}

/// One thread or two, this run or the next: the same bytes. Noise of `pixel_noise` levels has
/// that spread (10 %), is the same for the same seed and leaves the mean.
#[test]
fn images_are_the_same_bytes_and_noise_is_seeded() {
    let boxes = || vec![solid([2.1, 0.3, 0.25], [0.2, 0.4, 0.5], Some("#ff0000"))];
    let frame = |extra: &str| {
        let (mut sim, mut set) = flat_with(&camera(extra), boxes(), 0.0);
        settle(&mut sim, &mut set, 0.3);
        set.sensor(0).frame().unwrap().clone()
    };
    let one = frame("");
    assert_eq!(frame(""), one);
    assert_eq!(frame("threads = 2"), one);
    assert_eq!(frame("threads = 0"), one);
    let noisy = frame("pixel_noise = 6.0");
    assert_eq!(frame("pixel_noise = 6.0"), noisy);
    let diffs: Vec<f64> = one
        .rgb
        .iter()
        .zip(&noisy.rgb)
        .filter(|(a, _)| (30..225).contains(*a))
        .map(|(a, b)| *b as f64 - *a as f64)
        .collect();
    let n = diffs.len() as f64;
    let mean = diffs.iter().sum::<f64>() / n;
    let sd = (diffs.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / n).sqrt();
    assert!(
        n > 3000.0 && mean.abs() < 0.3 && (sd - 6.0).abs() < 0.6,
        "n {n} mean {mean} sd {sd}"
    );
}

/// A run with a colour camera has the trajectory of the run without it.
#[test]
fn a_colour_camera_does_not_change_the_trajectory() {
    let run = |with: bool| {
        let s = if with {
            camera("")
        } else {
            "sensors = []".to_string()
        };
        let (mut sim, mut set) = flat_with(&s, vec![], 0.0);
        sim.set_twist(0.3, 0.2);
        settle(&mut sim, &mut set, 1.0);
        let p = sim.body_pose();
        (p.x.to_bits(), p.y.to_bits(), p.z.to_bits(), p.yaw.to_bits())
    };
    assert_eq!(run(true), run(false));
}

/// Every bad camera key and colour is refused with its key and the fix.
#[test]
fn bad_camera_keys_and_colours_are_refused_with_their_keys() {
    let text = r##"
[[sensors]]
name = "a"
kind = "rgb_camera"
width_px = 0
height_px = 10
[[sensors]]
name = "b"
kind = "rgb_camera"
width_px = 100000
height_px = 100000
[[sensors]]
name = "c"
kind = "rgb_camera"
width_px = 10
height_px = 10
horizontal_fov_deg = 0.0
[[sensors]]
name = "d"
kind = "rgb_camera"
width_px = 10
height_px = 10
horizontal_fov_deg = 180.0
[[sensors]]
name = "e"
kind = "rgb_camera"
width_px = 10
height_px = 10
pixel_noise = -1.0
threads = 1000
[[sensors]]
name = "f"
kind = "rgb_camera"
width_px = 10
height_px = 10
range_noise_m = 0.01
"##;
    #[derive(serde::Deserialize)]
    struct File {
        sensors: Vec<SensorSpec>,
    }
    let mut spec: VehicleSpec =
        read_toml(&common::root().join("vehicles/packbot510.toml")).unwrap();
    spec.sensors = toml::from_str::<File>(text).unwrap().sensors;
    spec.colors = Some(tracksim::spec::ColorsSpec {
        body: Some("red".into()),
        tracks: Some("#12345".into()),
        flippers: None,
    });
    let issues = compile_vehicle(&spec).expect_err("refused");
    let all: Vec<String> = issues.iter().map(|i| i.to_string()).collect();
    let has = |key: &str, words: &str| {
        assert!(
            all.iter().any(|m| m.contains(key) && m.contains(words)),
            "no `{key}` ... `{words}` in {all:#?}"
        )
    };
    has("sensors[0].width_px", "between 1 and");
    has("sensors[1].height_px", "pixels per update is more than");
    has("sensors[2].horizontal_fov_deg", "field of view");
    has("sensors[3].horizontal_fov_deg", "170");
    has("sensors[4].pixel_noise", "0 to 255");
    has("sensors[4].threads", "every core");
    has(
        "sensors[5].range_noise_m",
        "not a key of a `rgb_camera` sensor",
    );
    has("colors.body", "#rrggbb");
    has("colors.tracks", "#rrggbb");
    // A rate above one update per step, and a terrain colour that is not one.
    let s = sensors(
        "vehicles/packbot510.toml",
        "[[sensors]]\nname = \"fast\"\nkind = \"rgb_camera\"\nwidth_px = 8\nheight_px = 8\nrate_hz = 2000.0\n",
    );
    let mut sc: tracksim::spec::ScenarioSpec =
        read_toml(&common::root().join("scenarios/packbot_flat.toml")).unwrap();
    sc.terrain
        .boxes
        .push(solid([3.0, 0.0, 0.1], [0.2, 0.2, 0.2], Some("#zz0000")));
    let mut v = tracksim::load_vehicle(&common::root().join("vehicles/packbot510.toml")).unwrap();
    v.sensors = s;
    let e =
        tracksim::compile_scenario(&sc, v, &common::root().join("scenarios")).expect_err("refused");
    let msg: Vec<String> = e.iter().map(|i| i.to_string()).collect();
    for (key, words) in [
        ("sensors[0].rate_hz", "1000 Hz"),
        ("terrain.boxes[0].color", "#rrggbb"),
    ] {
        assert!(
            msg.iter().any(|m| m.contains(key) && m.contains(words)),
            "no `{key}` ... `{words}` in {msg:#?}"
        );
    }
    assert_eq!(Rgb::parse("#ff0000"), Some(Rgb([255, 0, 0])));
}

/// A URDF robot's body takes its root link's material colour (given in the visual or named in
/// the robot); the vehicle file's `[colors] body` wins over it.
#[test]
fn a_urdf_body_takes_its_root_material_colour() {
    let dir = std::env::temp_dir().join(format!("tracksim_urdf_colour_{}", std::process::id()));
    std::fs::create_dir_all(dir.join("urdf")).unwrap();
    let urdf =
        std::fs::read_to_string(common::root().join("vehicles/urdf/packbot510_flippers.urdf"))
            .unwrap();
    let toml =
        std::fs::read_to_string(common::root().join("vehicles/packbot510_urdf.toml")).unwrap();
    let shape = "<geometry><box size=\"0.50 0.25 0.10\"/></geometry>\n    </visual>";
    assert!(urdf.contains(shape));
    let cases = [
        (
            "<material name=\"red\"><color rgba=\"1 0 0 1\"/></material>",
            "",
            Rgb([255, 0, 0]),
        ),
        (
            "<material name=\"teal\"/>",
            "<material name=\"teal\"><color rgba=\"0 0.5 0.5 1\"/></material>",
            Rgb([0, 128, 128]),
        ),
    ];
    for (material, named, want) in cases {
        let text = urdf.replacen(
            shape,
            &format!(
                "<geometry><box size=\"0.50 0.25 0.10\"/></geometry>{material}\n    </visual>"
            ),
            1,
        );
        let text = text.replacen(
            "<link name=\"base_link\">",
            &format!("{named}\n  <link name=\"base_link\">"),
            1,
        );
        std::fs::write(dir.join("urdf/packbot510_flippers.urdf"), &text).unwrap();
        std::fs::write(dir.join("v.toml"), &toml).unwrap();
        let v = tracksim::load_vehicle(&dir.join("v.toml")).expect("loads");
        assert_eq!(v.colors.body, want);
        std::fs::write(
            dir.join("v.toml"),
            format!("{toml}\n[colors]\nbody = \"#010203\"\n"),
        )
        .unwrap();
        let v = tracksim::load_vehicle(&dir.join("v.toml")).expect("loads");
        assert_eq!(v.colors.body, Rgb([1, 2, 3]));
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// The camera's first frame (t = 0, the robot at its start pose: no solver has moved it, so
/// only the scene differs between calls) with `boxes` (relative to the robot's start `x0`).
fn parked_frame(boxes: Vec<BoxSpec>, x0: f64) -> Frame {
    let (_sim, set) = flat_with(&camera(""), boxes, x0);
    set.sensor(0).frame().unwrap().clone()
}

/// Where the robot and its scene are does not change the image: the same scene 37.3 m further
/// along x (another floating origin, other f32 roundings) gives the same frame to one level in
/// colour and 1 mm in depth.
#[test]
fn the_image_does_not_depend_on_where_the_scene_is() {
    let boxes = || {
        vec![
            solid([2.1, 0.3, 0.25], [0.2, 0.4, 0.5], Some("#ff0000")),
            solid([1.8, -0.3, 1.0], [0.1, 0.6, 2.0], None),
        ]
    };
    let (a, b) = (parked_frame(boxes(), 0.0), parked_frame(boxes(), 37.3));
    let off = a
        .rgb
        .iter()
        .zip(&b.rgb)
        .filter(|(x, y)| x.abs_diff(**y) > 1)
        .count();
    let deep = a
        .depth
        .iter()
        .zip(&b.depth)
        .filter(|(x, y)| !(x == y || (*x - *y).abs() < 1e-3))
        .count();
    // Edge pixels may turn (a ray grazing a box edge); at most 1 % of them.
    assert!(
        off <= a.rgb.len() / 100,
        "{off} channels differ by more than a level"
    );
    assert!(
        deep <= a.depth.len() / 100,
        "{deep} depths differ by more than 1 mm"
    );
}

/// Mirror symmetry: a box 0.3 m to the left and the same box 0.3 m to the right give depth
/// images that are each other's mirror (columns reversed) within 1 mm. (Colours are not
/// mirrored: the sun is not.)
#[test]
fn a_mirrored_scene_gives_a_mirrored_depth_image() {
    let left = parked_frame(vec![solid([2.1, 0.3, 0.25], [0.2, 0.4, 0.5], None)], 0.0);
    let right = parked_frame(vec![solid([2.1, -0.3, 0.25], [0.2, 0.4, 0.5], None)], 0.0);
    let mut checked = 0;
    for v in 0..H {
        for u in 0..W {
            let (a, b) = (left.depth[v * W + u], right.depth[v * W + (W - 1 - u)]);
            if a.is_finite() && b.is_finite() {
                assert!((a - b).abs() < 1e-3, "({u}, {v}): {a} against {b}");
                checked += 1;
            } else {
                assert_eq!(a, b, "({u}, {v})");
            }
        }
    }
    assert!(checked > 1000, "{checked} pixels compared");
}
