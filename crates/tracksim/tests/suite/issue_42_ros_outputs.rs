//! Issue 42 ("bring your own robot and stack, as they are"), the ROS 2 and Foxglove part, read
//! back from `run.mcap` (what the node publishes is built by the same functions):
//! - `/odom` carries the covariance of a skid-steer encoder model (growing with distance),
//!   `/ground_truth/odom` a tiny one;
//! - a sensor's `frame_id` key names the frame of its messages and its `/tf_static` entry, and
//!   a frame id that is no ROS name is refused.

use crate::common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use tracksim::output::mcap::MCAP_FILE;
use tracksim::rosmsg::{self, CameraInfo, Image, Imu, Odometry, RosMessage, TFMessage};

/// Every message's bytes by topic, in log order, with the channel's schema name.
fn by_topic(bytes: &[u8]) -> BTreeMap<String, (String, Vec<Vec<u8>>)> {
    let mut out: BTreeMap<String, (String, Vec<Vec<u8>>)> = BTreeMap::new();
    for m in mcap::MessageStream::new(bytes).expect("mcap") {
        let m = m.expect("message");
        let schema = m
            .channel
            .schema
            .as_ref()
            .map_or(String::new(), |s| s.name.clone());
        out.entry(m.channel.topic.clone())
            .or_insert_with(|| (schema, Vec::new()))
            .1
            .push(m.data.to_vec());
    }
    out
}

fn decoded<T: RosMessage>(msgs: &[Vec<u8>]) -> Vec<T> {
    msgs.iter()
        .map(|d| rosmsg::decode::<T>(d).expect("decodes"))
        .collect()
}

/// A fresh folder for one test.
fn temp(tag: &str) -> PathBuf {
    static N: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let k = N.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let d = std::env::temp_dir().join(format!("tracksim-i42r-{tag}-{}-{k}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(d.join("vehicles")).unwrap();
    std::fs::create_dir_all(d.join("scenarios")).unwrap();
    d
}

/// `scenarios/packbot_sensors.toml` and its vehicle copied into `dir`, the vehicle's text
/// changed by `edit`; returns the scenario's path.
fn sensors_fixture(dir: &Path, edit: impl Fn(String) -> String) -> PathBuf {
    let root = common::root();
    let v = std::fs::read_to_string(root.join("vehicles/packbot510_sensors.toml")).unwrap();
    std::fs::write(dir.join("vehicles/packbot510_sensors.toml"), edit(v)).unwrap();
    let s = std::fs::read_to_string(root.join("scenarios/packbot_sensors.toml")).unwrap();
    let path = dir.join("scenarios/packbot_sensors.toml");
    std::fs::write(&path, s).unwrap();
    path
}

/// A run of `path` for `duration` s, its `run.mcap` read back.
fn recorded(path: &Path, duration: f64) -> (tracksim::RunResult, Vec<u8>) {
    let o = tracksim::Overrides {
        duration_s: Some(duration),
        ..Default::default()
    };
    let sc = tracksim::load_scenario_with(path, &o).expect("loads");
    let r = tracksim::run_scenario(&sc, |_, _| {}).expect("runs");
    // Never beside a bundled scenario: a fresh folder of its own.
    let dir = temp("rec").join("out");
    let which = tracksim::output::Outputs {
        replay: false,
        plots: false,
        mcap: true,
        raw_images: false,
    };
    tracksim::output::write_outputs(&sc, &r, &dir, which).expect("writes");
    let bytes = std::fs::read(dir.join(MCAP_FILE)).unwrap();
    let _ = std::fs::remove_dir_all(dir.parent().unwrap());
    (r, bytes)
}

#[test]
fn odom_covariance_grows_with_the_distance_and_the_truth_is_exact() {
    let path = common::root().join("scenarios/packbot_flat.toml");
    let (r, bytes) = recorded(&path, 3.0);
    let msgs = by_topic(&bytes);
    let odom: Vec<Odometry> = decoded(&msgs["/odom"].1);
    let truth: Vec<Odometry> = decoded(&msgs["/ground_truth/odom"].1);
    assert_eq!(odom.len(), r.samples.len());
    for o in &odom {
        assert!(o.pose.covariance.iter().any(|c| *c != 0.0));
        assert!(o.twist.covariance.iter().any(|c| *c != 0.0));
        // z, roll, pitch: not measured by planar odometry.
        for k in [2, 3, 4] {
            assert_eq!(o.pose.covariance[7 * k], 1e6);
        }
    }
    let first = &odom[0].pose.covariance;
    let last = &odom.last().unwrap().pose.covariance;
    assert_eq!(first[0], 1e-6);
    // The robot drove; x's variance grows with the distance, 0.01 m^2/m per side, halved.
    let (p0, p1) = (
        &r.samples.first().unwrap().odom,
        &r.samples.last().unwrap().odom,
    );
    let dist = (p1[0] - p0[0]).hypot(p1[1] - p0[1]);
    assert!(dist > 0.3, "{dist}");
    let expect = 1e-6 + 0.005 * dist;
    assert!(
        (last[0] - expect).abs() < 0.2 * expect,
        "var x {} for {dist} m (expected about {expect})",
        last[0]
    );
    // The variance never shrinks.
    for w in odom.windows(2) {
        for k in [0, 7, 35] {
            assert!(w[1].pose.covariance[k] >= w[0].pose.covariance[k] - 1e-15);
        }
    }
    // The twist's variance follows the belt speed.
    let moving = odom.last().unwrap();
    assert!(moving.twist.covariance[0] > odom[0].twist.covariance[0]);
    for t in &truth {
        for k in 0..6 {
            assert_eq!(t.pose.covariance[7 * k], 1e-12);
            assert_eq!(t.twist.covariance[7 * k], 1e-12);
        }
    }
}

#[test]
fn a_sensors_frame_id_names_its_messages_frame_and_its_mount() {
    let dir = temp("frame");
    let path = sensors_fixture(&dir, |v| {
        let v = v
            .replace(
                "name = \"imu\"\nkind = \"imu\"",
                "name = \"imu\"\nkind = \"imu\"\nframe_id = \"imu_frame\"",
            )
            .replace(
                "name = \"front_camera\"\nkind = \"depth_camera\"",
                "name = \"front_camera\"\nkind = \"depth_camera\"\nframe_id = \"depth/optical\"",
            );
        v + "\n[[sensors]]\nname = \"rgb\"\nkind = \"rgb_camera\"\nxyz_m = [0.2, 0.0, 0.1]\nrate_hz = 10.0\nwidth_px = 32\nheight_px = 24\nframe_id = \"camera_color_optical_frame\"\n"
    });
    let (_, bytes) = recorded(&path, 0.3);
    let msgs = by_topic(&bytes);
    let imu: Vec<Imu> = decoded(&msgs["/imu"].1);
    assert!(!imu.is_empty());
    assert!(imu.iter().all(|m| m.header.frame_id == "imu_frame"));
    let depth: Vec<Image> = decoded(&msgs["/front_camera"].1);
    assert!(depth.iter().all(|m| m.header.frame_id == "depth/optical"));
    let info: Vec<CameraInfo> = decoded(&msgs["/rgb/camera_info"].1);
    assert!(!info.is_empty());
    assert!(
        info.iter()
            .all(|m| m.header.frame_id == "camera_color_optical_frame")
    );
    let st: Vec<TFMessage> = decoded(&msgs["/tf_static"].1);
    let pairs: Vec<(String, String)> = st[0]
        .transforms
        .iter()
        .map(|t| (t.header.frame_id.clone(), t.child_frame_id.clone()))
        .collect();
    for want in [
        ("base_link", "imu_frame"),
        ("base_link", "front_camera_link"),
        ("front_camera_link", "depth/optical"),
        ("rgb_link", "camera_color_optical_frame"),
        ("base_link", "scan_link"),
    ] {
        assert!(
            pairs.contains(&(want.0.into(), want.1.into())),
            "{want:?} not in {pairs:?}"
        );
    }
    // Not a ROS name: refused, naming the key.
    for bad in ["1imu", "/imu", "imu frame", "a//b", "imu-1", ""] {
        let path = sensors_fixture(&dir, |v| {
            v.replace(
                "name = \"imu\"\nkind = \"imu\"",
                &format!("name = \"imu\"\nkind = \"imu\"\nframe_id = \"{bad}\""),
            )
        });
        let Err(e) = tracksim::load_scenario(&path) else {
            panic!("{bad}: accepted");
        };
        let text = e.to_string();
        assert!(text.contains("frame_id"), "{bad}: {text}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn robot_description_is_a_urdf_of_the_model_or_the_urdf_files_own_text() {
    use tracksim::output::urdf_export::{robot_description, vehicle_urdf};
    use tracksim::rosmsg::RosString;
    // A TOML vehicle: a URDF generated from the model, which urdf-rs reads back.
    let path = common::root().join("scenarios/packbot_sensors.toml");
    let (_, bytes) = recorded(&path, 0.05);
    let msgs = by_topic(&bytes);
    let (schema, data) = &msgs["/robot_description"];
    assert_eq!(schema, "std_msgs/msg/String");
    assert_eq!(data.len(), 1, "once, latched");
    let text = decoded::<RosString>(data).remove(0).data;
    let sc = tracksim::load_scenario(&path).unwrap();
    assert_eq!(text, vehicle_urdf(&sc.vehicle));
    let robot = urdf_rs::read_from_string(&text).expect("a URDF");
    let links: Vec<&str> = robot.links.iter().map(|l| l.name.as_str()).collect();
    for want in [
        "base_link",
        "front_left_flipper_link",
        "front_right_flipper_link",
        "left_track_link",
        "imu_link",
        "front_camera_link",
        "front_camera_optical_frame",
        "flipper_imu_link",
    ] {
        assert!(links.contains(&want), "{want} not in {links:?}");
    }
    assert!(!links.contains(&"encoders_link"));
    let base = robot.links.iter().find(|l| l.name == "base_link").unwrap();
    assert!(!base.visual.is_empty());
    let track = robot
        .links
        .iter()
        .find(|l| l.name == "left_track_link")
        .unwrap();
    assert_eq!(track.visual.len(), 24);
    // Each flipper a revolute joint named as in /joint_states, at its pivot, with its limits.
    for f in &sc.vehicle.flippers {
        let j = robot
            .joints
            .iter()
            .find(|j| j.name == f.name)
            .expect("joint");
        assert_eq!(j.parent.link, "base_link");
        assert_eq!(j.child.link, format!("{}_flipper_link", f.name));
        for k in 0..3 {
            assert!((j.origin.xyz[k] - f.pivot.to_array()[k]).abs() < 1e-12);
        }
        match f.limits {
            Some([lo, hi]) => {
                assert!(matches!(j.joint_type, urdf_rs::JointType::Revolute));
                assert!((j.limit.lower - lo).abs() < 1e-12 && (j.limit.upper - hi).abs() < 1e-12);
            }
            None => assert!(matches!(j.joint_type, urdf_rs::JointType::Continuous)),
        }
    }
    // A sensor on a flipper hangs from the flipper's link.
    let j = robot
        .joints
        .iter()
        .find(|j| j.child.link == "flipper_imu_link")
        .unwrap();
    assert_eq!(j.parent.link, "front_left_flipper_link");

    // A URDF vehicle: the file's own text.
    let sc = tracksim::load_scenario(&common::root().join("scenarios/packbot_urdf_stairs.toml"))
        .unwrap();
    let file = common::root().join("vehicles/urdf/packbot510_flippers.urdf");
    assert_eq!(
        robot_description(&sc),
        std::fs::read_to_string(file).unwrap()
    );
}

#[test]
fn a_urdf_robots_links_are_on_tf_under_their_own_names() {
    use glam::{DQuat, DVec3};
    use tracksim::output::ros_messages::{
        encoder_model, encoder_odometry, tf_of_sample, tf_static,
    };
    // The bundled URDF PackBot with its root link renamed `chassis`.
    let dir = temp("urdf");
    let root = common::root();
    std::fs::create_dir_all(dir.join("vehicles/urdf")).unwrap();
    let urdf = std::fs::read_to_string(root.join("vehicles/urdf/packbot510_flippers.urdf"))
        .unwrap()
        .replace("\"base_link\"", "\"chassis\"");
    std::fs::write(dir.join("vehicles/urdf/packbot510_flippers.urdf"), urdf).unwrap();
    let v = std::fs::read_to_string(root.join("vehicles/packbot510_urdf.toml")).unwrap();
    std::fs::write(dir.join("vehicles/packbot510_urdf.toml"), v).unwrap();
    let s = std::fs::read_to_string(root.join("scenarios/packbot_urdf_stairs.toml")).unwrap();
    let path = dir.join("scenarios/packbot_urdf_stairs.toml");
    std::fs::write(&path, s).unwrap();
    let sc = tracksim::load_scenario(&path).expect("loads");

    let statics = tf_static(&sc).transforms;
    let find = |ts: &[tracksim::rosmsg::TransformStamped], p: &str, c: &str| {
        ts.iter()
            .find(|t| t.header.frame_id == p && t.child_frame_id == c)
            .cloned()
            .unwrap_or_else(|| panic!("{p} -> {c} not in {ts:?}"))
    };
    // base_link is the root link's frame: identity.
    let b = find(&statics, "base_link", "chassis");
    assert_eq!(b.transform.translation.x, 0.0);
    assert_eq!(b.transform.rotation.w, 1.0);
    // A fixed link at its joint's origin.
    let l = find(&statics, "chassis", "left_track");
    assert!((l.transform.translation.y - 0.1625).abs() < 1e-12);
    // The arms are not static.
    assert!(
        statics
            .iter()
            .all(|t| t.child_frame_id != "front_left_flipper")
    );

    // /tf: each arm link moving with its joint (the flipper of the same name).
    let mut sample = tracksim::world::Sample {
        flipper_angle: vec![0.0; sc.vehicle.flippers.len()],
        belt_speed: vec![0.0; sc.vehicle.tracks.len()],
        ..Default::default()
    };
    let fl = sc.vehicle.flipper_index("front_left").expect("flipper");
    sample.flipper_angle[fl] = 0.5;
    let odom = encoder_odometry(&sample, &mut encoder_model(&sc));
    let tf = tf_of_sample(&sc, &sample, &odom, false).transforms;
    let a = find(&tf, "chassis", "front_left_flipper");
    assert!((a.transform.translation.x - 0.255).abs() < 1e-12);
    assert!((a.transform.translation.y - 0.225).abs() < 1e-12);
    let q = a.transform.rotation;
    let want = DQuat::from_axis_angle(DVec3::new(0.0, -1.0, 0.0), 0.5);
    assert!(
        (q.x - want.x).abs() < 1e-12
            && (q.y - want.y).abs() < 1e-12
            && (q.z - want.z).abs() < 1e-12
            && (q.w - want.w).abs() < 1e-12,
        "{q:?}"
    );
    // The joint_states names are the URDF's joint names.
    let names = tracksim::output::ros_messages::joint_names(&sc);
    assert!(names.contains(&"front_left".to_string()));
    // The old flipper frame stays (sensors may hang from it).
    find(&tf, "base_link", "front_left_flipper_link");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn run_mcap_has_a_foxglove_scene_of_the_terrain_and_the_robot_and_soil_figures() {
    let path = common::root().join("scenarios/packbot_sensors.toml");
    let sc = tracksim::load_scenario(&path).unwrap();
    let (_, bytes) = recorded(&path, 0.05);
    let msgs = by_topic(&bytes);
    let (schema, data) = &msgs["/scene"];
    assert_eq!(schema, "foxglove.SceneUpdate");
    assert_eq!(data.len(), 1, "once, at t = 0");
    let scene: serde_json::Value = serde_json::from_slice(&data[0]).expect("JSON");
    let entities = scene["entities"].as_array().unwrap();
    let entity = |id: &str| {
        entities
            .iter()
            .find(|e| e["id"] == id)
            .unwrap_or_else(|| panic!("no entity {id}"))
    };
    // The terrain in map: the ground plane, then every box; the stairs' nosings as cylinders.
    let t = entity("terrain");
    assert_eq!(t["frame_id"], "map");
    let cubes = t["cubes"].as_array().unwrap();
    assert_eq!(cubes.len(), 1 + sc.terrain.boxes.len());
    assert!(!sc.terrain.boxes.is_empty());
    let b = &sc.terrain.boxes[0];
    let c = &cubes[1];
    for (k, axis) in ["x", "y", "z"].iter().enumerate() {
        let size = c["size"][axis].as_f64().unwrap();
        let at = c["pose"]["position"][axis].as_f64().unwrap();
        assert!((size - 2.0 * b.half.to_array()[k]).abs() < 1e-12, "{axis}");
        assert!((at - b.centre.to_array()[k]).abs() < 1e-12, "{axis}");
    }
    assert_eq!(
        t["cylinders"].as_array().unwrap().len(),
        sc.terrain.cylinders.len()
    );
    // The robot in its frames, moved by /tf.
    let body = entity("robot/body");
    assert_eq!(body["frame_id"], "base_link");
    assert_eq!(body["frame_locked"], true);
    assert!(!body["cubes"].as_array().unwrap().is_empty());
    let track = entity("robot/track/left");
    assert_eq!(track["cubes"].as_array().unwrap().len(), 24);
    for f in &sc.vehicle.flippers {
        let e = entity(&format!("robot/flipper/{}", f.name));
        assert_eq!(e["frame_id"], format!("{}_flipper_link", f.name));
    }
    assert!(!msgs.contains_key("/soil"), "no soil, no /soil");

    // A soil run: each track's sinkage and thrust at every sample.
    let path = common::root().join("scenarios/soil/packbot_dry_sand.toml");
    let (r, bytes) = recorded(&path, 0.2);
    let msgs = by_topic(&bytes);
    let (schema, data) = &msgs["/soil"];
    assert_eq!(schema, "tracksim.TrackSoil");
    assert_eq!(data.len(), r.samples.len());
    let last: serde_json::Value = serde_json::from_slice(data.last().unwrap()).unwrap();
    let s = r.samples.last().unwrap();
    let tracks = last["tracks"].as_array().unwrap();
    assert_eq!(tracks.len(), s.soil.len());
    assert_eq!(tracks[0]["name"], r.track_names[0].as_str());
    assert_eq!(
        tracks[0]["sinkage_m"].as_f64().unwrap(),
        s.soil[0].sinkage_m
    );
    assert_eq!(tracks[0]["thrust_n"].as_f64().unwrap(), s.soil[0].thrust_n);
    assert!(s.soil.iter().any(|g| g.sinkage_m > 0.0), "{:?}", s.soil);
}
