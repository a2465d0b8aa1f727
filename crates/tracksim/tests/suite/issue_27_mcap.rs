//! Issue 27 (MCAP recordings): `run.mcap` of a run read back with the `mcap` crate. The file
//! has the ROS 2 profile, every channel a `ros2msg` schema and `cdr` messages, one message per
//! sample (or per sensor reading) on each topic, and the messages decode (with this crate's
//! CDR) to the run's values: poses, encoder odometry, flipper angles, belts, an IMU reading.
//! The CDR bytes of a header are checked byte by byte against the XCDR1 layout.

use crate::common;

use std::collections::BTreeMap;
use tracksim::output::mcap::{MCAP_FILE, pose_rotation};
use tracksim::rosmsg::{
    self, Header, Imu, JointState, LaserScan, Odometry, RosMessage, TFMessage, Time, TrackStates,
};

/// A 1 s run of the PackBot with its sensors, written with `run.mcap`.
fn recorded() -> (tracksim::Scenario, tracksim::RunResult, Vec<u8>) {
    let (sc, r, bytes, _) = recorded_with_csv();
    (sc, r, bytes)
}

/// [`recorded`] and the run's `trajectory.csv`.
fn recorded_with_csv() -> (tracksim::Scenario, tracksim::RunResult, Vec<u8>, String) {
    let sc = common::load_for("scenarios/packbot_sensors.toml", 1.0);
    let r = tracksim::run_scenario(&sc, |_, _| {}).expect("runs");
    static RUNS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let k = RUNS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("tracksim-i27-{}-{k}", std::process::id()));
    let which = tracksim::output::Outputs {
        replay: false,
        plots: false,
        mcap: true,
        raw_images: false,
    };
    let written = tracksim::output::write_outputs(&sc, &r, &dir, which).expect("writes");
    assert!(written.contains(&dir.join(MCAP_FILE)));
    let bytes = std::fs::read(dir.join(MCAP_FILE)).unwrap();
    let csv = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    (sc, r, bytes, csv)
}

/// Every message's CDR bytes by topic, in log order, with their log times (ns).
fn by_topic(bytes: &[u8]) -> BTreeMap<String, Vec<(u64, Vec<u8>)>> {
    let mut out: BTreeMap<String, Vec<(u64, Vec<u8>)>> = BTreeMap::new();
    for m in mcap::MessageStream::new(bytes).expect("mcap") {
        let m = m.expect("message");
        let schema = m
            .channel
            .schema
            .as_ref()
            .expect("every channel has a schema");
        if m.channel.topic == "/scene" {
            // Foxglove's scene (issue 42): JSON with its JSON schema.
            assert_eq!(schema.encoding, "jsonschema");
            assert_eq!(m.channel.message_encoding, "json");
            continue;
        }
        assert_eq!(schema.encoding, "ros2msg", "{}", m.channel.topic);
        assert_eq!(m.channel.message_encoding, "cdr", "{}", m.channel.topic);
        assert!(!schema.data.is_empty(), "{}", m.channel.topic);
        out.entry(m.channel.topic.clone())
            .or_default()
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
fn run_mcap_has_every_topic_with_its_schema_and_counts() {
    let (_sc, r, bytes) = recorded();
    // The ROS 2 profile in the header.
    let profile = mcap::read::LinearReader::new(&bytes)
        .unwrap()
        .find_map(|rec| match rec.unwrap() {
            mcap::records::Record::Header(h) => Some(h.profile),
            _ => None,
        });
    assert_eq!(profile.as_deref(), Some("ros2"));
    let summary = mcap::Summary::read(&bytes).unwrap().expect("summary");
    let mut types = BTreeMap::new();
    for c in summary.channels.values() {
        let s = c.schema.as_ref().expect("schema");
        types.insert(c.topic.clone(), s.name.clone());
        assert!(c.metadata.contains_key("offered_qos_profiles"));
    }
    let expect = [
        ("/clock", "rosgraph_msgs/msg/Clock"),
        ("/tf", "tf2_msgs/msg/TFMessage"),
        ("/tf_static", "tf2_msgs/msg/TFMessage"),
        ("/odom", "nav_msgs/msg/Odometry"),
        ("/ground_truth/odom", "nav_msgs/msg/Odometry"),
        ("/joint_states", "sensor_msgs/msg/JointState"),
        ("/tracks", "tracksim_msgs/msg/TrackStates"),
        ("/imu", "sensor_msgs/msg/Imu"),
        ("/flipper_imu", "sensor_msgs/msg/Imu"),
        ("/encoders", "sensor_msgs/msg/JointState"),
        ("/scan", "sensor_msgs/msg/LaserScan"),
        ("/elevation", "sensor_msgs/msg/PointCloud2"),
        ("/front_camera", "sensor_msgs/msg/Image"),
        ("/robot_description", "std_msgs/msg/String"),
        ("/scene", "foxglove.SceneUpdate"),
    ];
    for (topic, ty) in expect {
        assert_eq!(types.get(topic).map(String::as_str), Some(ty), "{topic}");
    }
    assert_eq!(types.len(), expect.len(), "{types:?}");
    let msgs = by_topic(&bytes);
    let n = r.samples.len();
    assert!(n > 50);
    for topic in [
        "/clock",
        "/tf",
        "/odom",
        "/ground_truth/odom",
        "/joint_states",
        "/tracks",
    ] {
        assert_eq!(msgs[topic].len(), n, "{topic}");
    }
    assert_eq!(msgs["/tf_static"].len(), 1);
    for s in &r.sensors {
        let topic = format!("/{}", s.name);
        assert_eq!(msgs[&topic].len(), s.len(), "{topic}");
        for ((t, _), ts) in msgs[&topic].iter().zip(&s.times()) {
            assert_eq!(*t, Time::from_secs(*ts).nanos());
        }
    }
    // Log times never go back.
    let all: Vec<u64> = mcap::MessageStream::new(&bytes)
        .unwrap()
        .map(|m| m.unwrap().log_time)
        .collect();
    assert!(all.windows(2).all(|w| w[0] <= w[1]));
    // The default outputs do not write it.
    const { assert!(!tracksim::output::Outputs::ALL.mcap) };
}

#[test]
fn run_mcap_messages_carry_the_run_values() {
    let (sc, r, bytes) = recorded();
    let msgs = by_topic(&bytes);
    let truth: Vec<Odometry> = decoded(&msgs["/ground_truth/odom"]);
    let odom: Vec<Odometry> = decoded(&msgs["/odom"]);
    let tf: Vec<TFMessage> = decoded(&msgs["/tf"]);
    let joints: Vec<JointState> = decoded(&msgs["/joint_states"]);
    let tracks: Vec<TrackStates> = decoded(&msgs["/tracks"]);
    for k in [0, r.samples.len() / 2, r.samples.len() - 1] {
        let s = &r.samples.get(k).unwrap();
        let stamp = Time::from_secs(s.t);
        // Ground truth: the body pose in map, the velocity in base_link.
        let g = &truth[k];
        assert_eq!(g.header.stamp, stamp);
        assert_eq!(
            (g.header.frame_id.as_str(), g.child_frame_id.as_str()),
            ("map", "base_link")
        );
        let p = g.pose.pose.position;
        assert_eq!([p.x, p.y, p.z], [s.pose.x, s.pose.y, s.pose.z]);
        let q = g.pose.pose.orientation;
        let rot = glam::DQuat::from_xyzw(q.x, q.y, q.z, q.w);
        let (yaw, pitch, roll) = rot.to_euler(glam::EulerRot::ZYX);
        assert!((yaw - s.pose.yaw).abs() < 1e-9 && (pitch - s.pose.pitch).abs() < 1e-9);
        assert!((roll - s.pose.roll).abs() < 1e-9);
        let v = rot
            * glam::DVec3::new(
                g.twist.twist.linear.x,
                g.twist.twist.linear.y,
                g.twist.twist.linear.z,
            );
        assert!((v - glam::DVec3::from_array(s.linvel)).length() < 1e-9);
        // Encoder odometry: Sample::odom.
        let o = &odom[k];
        let op = o.pose.pose.position;
        assert_eq!([op.x, op.y], [s.odom[0], s.odom[1]]);
        let oq = o.pose.pose.orientation;
        assert!((2.0 * oq.z.atan2(oq.w) - s.odom[2]).abs() < 1e-9);
        check_tf(&tf[k].transforms, s, &sc);
        // /joint_states: flippers, then belts.
        let j = &joints[k];
        let nf = r.flipper_names.len();
        assert_eq!(j.name[..nf], r.flipper_names[..]);
        assert_eq!(j.name[nf], format!("{}_belt", r.track_names[0]));
        assert_eq!(j.position[..nf], s.flipper_angle[..]);
        assert_eq!(j.position[nf..], s.belt_position[..]);
        assert_eq!(j.velocity[nf..], s.belt_speed[..]);
        // /tracks.
        let tk = &tracks[k];
        assert_eq!(tk.name, r.track_names);
        assert_eq!(tk.slip, s.slip);
        let normal: Vec<f64> = s.loads.iter().map(|l| l.normal_n).collect();
        assert_eq!(tk.normal_load, normal);
    }
    // The robot drives: odometry and the flippers move.
    let last = odom.last().unwrap().pose.pose.position.x;
    assert!(last > odom[0].pose.pose.position.x + 0.1, "{last}");
    check_sensor_messages(&msgs, &r);
}

/// `/tf` at the sample `s`: odom -> base_link (the encoders, as /odom), each flipper turned by
/// its angle at its pivot, and map -> odom, with which map -> base_link is the true pose.
fn check_tf(
    t: &[tracksim::rosmsg::TransformStamped],
    s: &tracksim::world::Sample,
    sc: &tracksim::Scenario,
) {
    assert_eq!(t.len(), 2 + sc.vehicle.flippers.len());
    assert_eq!(t[0].transform.translation.x, s.odom[0]);
    assert_eq!(t[0].transform.translation.y, s.odom[1]);
    assert_eq!(t[0].child_frame_id, "base_link");
    let m = t.last().unwrap();
    assert_eq!(
        (m.header.frame_id.as_str(), m.child_frame_id.as_str()),
        ("map", "odom")
    );
    let iso = |tr: &tracksim::rosmsg::Transform| {
        let (v, q) = (tr.translation, tr.rotation);
        glam::DAffine3::from_rotation_translation(
            glam::DQuat::from_xyzw(q.x, q.y, q.z, q.w),
            glam::DVec3::new(v.x, v.y, v.z),
        )
    };
    let composed = iso(&m.transform) * iso(&t[0].transform);
    let at = composed.translation;
    assert!(
        (at - glam::DVec3::new(s.pose.x, s.pose.y, s.pose.z)).length() < 1e-9,
        "map -> odom -> base_link {at:?} is not the true position at t = {} s",
        s.t
    );
    let (yaw_c, pitch_c, roll_c) =
        glam::DQuat::from_mat3(&composed.matrix3).to_euler(glam::EulerRot::ZYX);
    assert!((yaw_c - s.pose.yaw).abs() < 1e-9 && (pitch_c - s.pose.pitch).abs() < 1e-9);
    assert!((roll_c - s.pose.roll).abs() < 1e-9);
    for (i, f) in sc.vehicle.flippers.iter().enumerate() {
        let tr = &t[1 + i];
        assert_eq!(tr.header.frame_id, "base_link");
        assert_eq!(tr.child_frame_id, format!("{}_flipper_link", f.name));
        assert_eq!(tr.transform.translation.x, f.pivot.x);
        let q = tr.transform.rotation;
        let (axis, angle) = glam::DQuat::from_xyzw(q.x, q.y, q.z, q.w).to_axis_angle();
        let signed = if angle.abs() < 1e-12 {
            0.0
        } else {
            angle * axis.dot(f.axis).signum()
        };
        assert!(
            (signed - s.flipper_angle[i]).abs() < 1e-9,
            "{signed} {:?}",
            s.flipper_angle
        );
    }
}

/// The sensors' messages: the IMU's are the stream's readings (gravity at the first), the scan
/// has 720 rays, `/tf_static` holds the sensor mounts.
fn check_sensor_messages(msgs: &BTreeMap<String, Vec<(u64, Vec<u8>)>>, r: &tracksim::RunResult) {
    let imu_stream = r.sensors.iter().find(|s| s.name == "imu").unwrap();
    let imu: Vec<Imu> = decoded(&msgs["/imu"]);
    assert_eq!(imu[0].header.frame_id, "imu_link");
    assert!((imu[0].linear_acceleration.z - 9.81).abs() < 0.1);
    let accel = imu_stream.channel_log(
        imu_stream
            .channels
            .iter()
            .position(|c| c.name == "accel")
            .unwrap(),
    );
    let tracksim::sensors::LogData::F64(a) = accel else {
        panic!("IMU logs in f64")
    };
    let k = imu.len() / 2;
    let m = &imu[k].linear_acceleration;
    assert_eq!([m.x, m.y, m.z], a[3 * k..3 * k + 3]);
    // The scan: one line of 720 rays over the full turn.
    let scan: Vec<LaserScan> = decoded(&msgs["/scan"]);
    assert_eq!(scan[0].ranges.len(), 720);
    assert_eq!(scan[0].header.frame_id, "scan_link");
    // /tf_static: the sensor mounts.
    let st: Vec<TFMessage> = decoded(&msgs["/tf_static"]);
    let children: Vec<&str> = st[0]
        .transforms
        .iter()
        .map(|t| t.child_frame_id.as_str())
        .collect();
    for f in [
        "imu_link",
        "scan_link",
        "front_camera_optical_frame",
        "flipper_imu_link",
    ] {
        assert!(children.contains(&f), "{children:?}");
    }
}

#[test]
fn cdr_layout_and_schema_text_follow_ros2() {
    // Header: the encapsulation, sec, nanosec, then the string with its length and NUL.
    let h = Header {
        stamp: Time { sec: 1, nanosec: 2 },
        frame_id: "ab".into(),
    };
    let b = rosmsg::encode(&h).unwrap();
    assert_eq!(
        b,
        [
            0, 1, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 3, 0, 0, 0, b'a', b'b', 0
        ]
    );
    // A float64 after the header's 19 body bytes is aligned to 8 counted after the 4-byte
    // encapsulation (Odometry: header "ab", child "c", then the pose's float64s).
    let o = Odometry {
        header: h.clone(),
        child_frame_id: "c".into(),
        ..Default::default()
    };
    let ob = rosmsg::encode(&o).unwrap();
    // Body: the header 15 bytes (padded to 16), the child 4 + 2 (22, padded to 24), then
    // 7 + 36 + 6 + 36 float64s.
    assert_eq!(ob.len(), 4 + 24 + 8 * (7 + 36 + 6 + 36));
    assert_eq!(rosmsg::decode::<Odometry>(&ob).unwrap(), o);
    // The schema text: the type, then each dependency after a line of 80 '='.
    let text = Odometry::schema_text();
    assert!(text.starts_with("std_msgs/Header header\n"));
    let sep = format!("\n{}\nMSG: ", "=".repeat(80));
    for dep in [
        "std_msgs/Header",
        "builtin_interfaces/Time",
        "geometry_msgs/PoseWithCovariance",
        "geometry_msgs/Pose",
        "geometry_msgs/Point",
        "geometry_msgs/Quaternion",
        "geometry_msgs/TwistWithCovariance",
        "geometry_msgs/Twist",
        "geometry_msgs/Vector3",
    ] {
        assert_eq!(
            text.matches(&format!("{sep}{dep}\n")).count(),
            1,
            "{dep} in\n{text}"
        );
    }
    assert_eq!(Odometry::schema_name(), "nav_msgs/msg/Odometry");
    let q = pose_rotation(&Default::default());
    assert_eq!(q, glam::DQuat::IDENTITY);
}

#[test]
fn run_mcap_counts_are_rates_times_duration_and_odometry_is_trajectory_csv() {
    let (sc, r, bytes, csv) = recorded_with_csv();
    // The run went to its end (the scenario's timeout is its duration).
    assert!((r.summary.sim_time_s - sc.duration).abs() < 1e-9);
    let msgs = by_topic(&bytes);
    // Every output interval from 0 to the end, both included: 1 s / 10 ms + 1.
    let per_sample = (sc.duration / sc.output_interval).round() as usize + 1;
    assert_eq!(per_sample, 101);
    for topic in [
        "/clock",
        "/tf",
        "/odom",
        "/ground_truth/odom",
        "/joint_states",
        "/tracks",
    ] {
        assert_eq!(msgs[topic].len(), per_sample, "{topic}");
    }
    // Every sensor at its rate: a reading at 0 and then every 1 / rate s up to the end.
    for m in &sc.vehicle.sensors {
        let expected = (m.rate_hz * sc.duration + 1e-6).floor() as usize + 1;
        let topic = format!("/{}", m.name);
        assert_eq!(msgs[&topic].len(), expected, "{topic} at {} Hz", m.rate_hz);
        let times: Vec<u64> = msgs[&topic].iter().map(|(t, _)| *t).collect();
        for w in times.windows(2) {
            let dt = (w[1] - w[0]) as f64 * 1e-9;
            assert!((dt - 1.0 / m.rate_hz).abs() < 1.5e-3, "{topic}: {dt} s");
        }
    }
    // /clock carries the log time.
    for (t, d) in &msgs["/clock"] {
        assert_eq!(
            rosmsg::decode::<rosmsg::Clock>(d).unwrap().clock.nanos(),
            *t
        );
    }
    // /odom and /ground_truth/odom against trajectory.csv's columns (written to 1e-6).
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).expect(name);
    let cols = [
        "t_s",
        "odom_x_m",
        "odom_y_m",
        "odom_yaw_rad",
        "x_m",
        "y_m",
        "z_m",
        "yaw_rad",
    ]
    .map(col);
    let rows: Vec<Vec<f64>> = lines
        .map(|l| {
            let cells: Vec<&str> = l.split(',').collect();
            cols.iter().map(|&c| cells[c].parse().unwrap()).collect()
        })
        .collect();
    let odom: Vec<Odometry> = decoded(&msgs["/odom"]);
    let truth: Vec<Odometry> = decoded(&msgs["/ground_truth/odom"]);
    assert_eq!(rows.len(), odom.len());
    let yaw = |q: &rosmsg::Quaternion| {
        glam::DQuat::from_xyzw(q.x, q.y, q.z, q.w)
            .to_euler(glam::EulerRot::ZYX)
            .0
    };
    let close = |a: f64, b: f64| (a - b).abs() <= 5.1e-7;
    for ((row, o), g) in rows.iter().zip(&odom).zip(&truth) {
        let t = o.header.stamp.nanos() as f64 * 1e-9;
        assert!(close(t, row[0]), "{t} {}", row[0]);
        let p = o.pose.pose.position;
        assert!(close(p.x, row[1]) && close(p.y, row[2]), "{p:?} {row:?}");
        assert!(close(yaw(&o.pose.pose.orientation), row[3]), "{row:?}");
        let q = g.pose.pose.position;
        assert!(close(q.x, row[4]) && close(q.y, row[5]) && close(q.z, row[6]));
        assert!(close(yaw(&g.pose.pose.orientation), row[7]), "{row:?}");
    }
    // The encoders' odometry is not the truth (it sees the belts, slip included), but it
    // advances with the robot.
    let (o, g) = (odom.last().unwrap(), truth.last().unwrap());
    assert!(o.pose.pose.position.x > 0.1 && g.pose.pose.position.x > 0.1);
}

/// `[output] mcap = true` in a scenario file: every front end's outputs include `run.mcap`
/// (here those of `sweep`, which asks for neither replay nor plots); a misspelt key is refused.
#[test]
fn output_key_of_a_scenario_records_mcap_for_every_front_end() {
    let root = common::root();
    let text = std::fs::read_to_string(root.join("scenarios/packbot_flat.toml"))
        .unwrap()
        .replace(
            "../vehicles/",
            &format!("{}/", root.join("vehicles").display()),
        );
    let dir = std::env::temp_dir().join(format!("tracksim-i27-key-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("s.toml");
    std::fs::write(&file, format!("{text}\n[output]\nmcap = true\n")).unwrap();
    let sc = tracksim::load_scenario_with(
        &file,
        &tracksim::Overrides {
            duration_s: Some(0.2),
            ..Default::default()
        },
    )
    .unwrap();
    assert!(sc.record_mcap);
    let r = tracksim::run_scenario(&sc, |_, _| {}).unwrap();
    let none = tracksim::output::Outputs {
        replay: false,
        plots: false,
        mcap: false,
        raw_images: false,
    };
    let out = dir.join("out");
    let written = tracksim::output::write_outputs(&sc, &r, &out, none).unwrap();
    assert!(written.contains(&out.join(MCAP_FILE)), "{written:?}");
    let bytes = std::fs::read(out.join(MCAP_FILE)).unwrap();
    assert_eq!(by_topic(&bytes)["/odom"].len(), r.samples.len());
    // Without the key: no run.mcap, as before.
    let plain = tracksim::load_scenario(&root.join("scenarios/packbot_flat.toml")).unwrap();
    assert!(!plain.record_mcap);
    std::fs::write(&file, format!("{text}\n[output]\nmcpa = true\n")).unwrap();
    let e = tracksim::load_scenario(&file).unwrap_err().to_string();
    assert!(e.contains("mcpa") && e.contains("mcap"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The `.msg` file of the ROS 2 package `ros/tracksim_msgs` is the schema text of `/tracks`.
#[test]
fn track_states_msg_file_is_the_schema() {
    let file =
        std::fs::read_to_string(common::root().join("ros/tracksim_msgs/msg/TrackStates.msg"))
            .unwrap();
    assert_eq!(file, TrackStates::DEF.text);
    let schema = TrackStates::schema_text();
    assert!(schema.starts_with(file.trim_end()));
    assert!(schema.ends_with("\nMSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n"));
    let cmake =
        std::fs::read_to_string(common::root().join("ros/tracksim_msgs/CMakeLists.txt")).unwrap();
    assert!(cmake.contains("\"msg/TrackStates.msg\""));
}

/// A lidar of several scan lines is an organised `PointCloud2` (rows of elevation, columns of
/// azimuth, x y z float32 in the sensor's frame): the stream's points, bit for bit in f32.
#[test]
fn a_3d_lidar_is_an_organised_point_cloud_of_its_points() {
    let sc = common::file_with(
        "scenarios/packbot_sensors.toml",
        |s| s.simulation.duration_s = 0.3,
        |v| {
            let scan = v.sensors.iter_mut().find(|m| m.name == "scan").unwrap();
            let tracksim::model::SensorKind::Lidar(p) = &mut scan.kind else {
                panic!("scan is a lidar")
            };
            p.azimuth_rays = 90;
            p.elevation_rays = 4;
            p.elevation_fov = 30f64.to_radians();
        },
    );
    let r = tracksim::run_scenario(&sc, |_, _| {}).unwrap();
    let bytes = tracksim::output::mcap::mcap_bytes(&sc, &r).unwrap();
    let msgs = by_topic(&bytes);
    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    let ch = summary
        .channels
        .values()
        .find(|c| c.topic == "/scan")
        .unwrap();
    assert_eq!(
        ch.schema.as_ref().unwrap().name,
        "sensor_msgs/msg/PointCloud2"
    );
    let stream = r.sensors.iter().find(|s| s.name == "scan").unwrap();
    let clouds: Vec<rosmsg::PointCloud2> = decoded(&msgs["/scan"]);
    assert_eq!(clouds.len(), stream.len());
    let points = stream
        .channels
        .iter()
        .position(|c| c.name == "points")
        .unwrap();
    let n = stream.channels[points].data.len();
    assert_eq!(n, 4 * 90 * 3);
    let values: Vec<f32> = match stream.channel_log(points) {
        tracksim::sensors::LogData::F64(v) => v.iter().map(|x| *x as f32).collect(),
        tracksim::sensors::LogData::F32(v) => v,
        tracksim::sensors::LogData::Png(_) => panic!("a lidar's points are numbers"),
    };
    for (k, c) in clouds.iter().enumerate() {
        assert_eq!(
            (c.height, c.width, c.point_step, c.row_step),
            (4, 90, 12, 12 * 90)
        );
        assert_eq!(c.header.frame_id, "scan_link");
        let got: Vec<f32> = c
            .data
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        let want = &values[k * n..(k + 1) * n];
        assert!(
            got.iter()
                .zip(want)
                .all(|(a, b)| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()))
        );
        assert_eq!(c.is_dense, want.iter().all(|v| v.is_finite()));
    }
}
