//! A scored course on ROS 2 topics: `/course` (`tracksim_msgs/CourseStatus`, the score at every
//! sample) and `/course/events` (`tracksim_msgs/CourseEvent`, each event once), as the node
//! publishes them, and `run.mcap`'s record of them. Without DDS: the same functions build the
//! node's messages (`output::ros_course`); the node itself on DDS is exercised by
//! `python/tests/test_ros_dds.py` (`test_course_score_on_ros_topics`).

use crate::common::{self, decoded, mcap_messages as by_topic};

use std::collections::BTreeMap;
use tracksim::model::{Scenario, load_vehicle};
use tracksim::output::ros_course::{EventCursor, course_event, course_status};
use tracksim::output::ros_names::Namespace;
use tracksim::rosmsg::{self, CourseEvent, CourseStatus, RosMessage, Time};
use tracksim::run::{CourseScore, End, Runner};

/// The recorded `/course/events` and `/course` of one robot (namespace `ns`) against the
/// score `c` of its summary, and the run's last sample time `end` s.
fn check_recorded(
    msgs: &BTreeMap<String, Vec<(u64, Vec<u8>)>>,
    ns: &Namespace,
    c: &CourseScore,
    end: f64,
) {
    let ev = &msgs[&ns.topic("/course/events")];
    let events: Vec<CourseEvent> = decoded(ev);
    assert_eq!(events.len(), c.events.len(), "every event once");
    for (((log, _), m), e) in ev.iter().zip(&events).zip(&c.events) {
        assert_eq!(*log, Time::from_secs(e.t_s).nanos(), "at its time");
        assert_eq!(m, &course_event(e));
        assert_eq!(
            (m.kind.as_str(), m.detail.as_str()),
            (e.kind, e.detail.as_str())
        );
        assert_eq!(m.header.frame_id, "map");
        assert_eq!(m.fault, e.fault.unwrap_or(""));
    }
    let st: Vec<CourseStatus> = decoded(&msgs[&ns.topic("/course")]);
    assert_eq!(st.len(), 1, "the final score once");
    let s = &st[0];
    assert_eq!(s, &course_status(end, c));
    assert_eq!(s.header.stamp, Time::from_secs(end));
    assert_eq!(s.status, c.status);
    assert_eq!(s.score, c.score.score_s);
    assert_eq!(s.repetition_times, c.rep_times_s);
}

/// The .msg files of the ROS 2 package are the schemas the node and the recording declare.
#[test]
fn course_msg_files_are_the_schemas() {
    for (file, def) in [
        ("CourseStatus.msg", CourseStatus::DEF),
        ("CourseEvent.msg", CourseEvent::DEF),
    ] {
        let text = std::fs::read_to_string(common::root().join("ros/tracksim_msgs/msg").join(file))
            .unwrap();
        assert_eq!(text, def.text, "{file}");
        let schema = def.schema_text();
        assert!(schema.starts_with(text.trim_end()));
        assert!(schema.contains("\nMSG: std_msgs/Header\n"), "{schema}");
        let cmake =
            std::fs::read_to_string(common::root().join("ros/tracksim_msgs/CMakeLists.txt"))
                .unwrap();
        assert!(
            cmake.contains(&format!("\"msg/{file}\"")),
            "{file} in CMakeLists.txt"
        );
    }
}

/// The bundled stairs course run to its end (it ends when the course is completed), recorded:
/// `/course/events` has each of the summary's events at its time, `/course` the final score;
/// the score adds up (trial time + penalties, every gate of every repetition passed).
#[test]
fn the_bundled_course_is_recorded_to_its_end() {
    let sc = tracksim::load_scenario(&common::root().join("scenarios/course_stairs.toml")).unwrap();
    let r = tracksim::run_scenario(&sc, |_, _| {}).expect("runs");
    let c = r.summary.course.clone().expect("a course");
    assert_eq!(c.status, "completed", "{c:?}");
    assert!(c.finished);
    assert_eq!(
        c.gates_passed as usize,
        c.gates_total * c.repetitions_required as usize
    );
    assert_eq!(c.rep_times_s.len() as u32, c.repetitions_required);
    let end = r.samples.last().unwrap().t;
    assert!(
        (end - c.score.time_s).abs() < 1e-9,
        "the run ends at the finish"
    );
    let bytes = tracksim::output::mcap::mcap_bytes(&sc, &r).unwrap();
    let msgs = by_topic(&bytes);
    check_recorded(&msgs, &Namespace::none(), &c, end);
    let s = course_status(end, &c);
    assert_eq!(s.score, s.trial_time + s.penalty);
    assert_eq!(
        s.time_limit,
        sc.course.as_ref().unwrap().time_limit.unwrap_or(0.0)
    );
    // CDR there and back.
    let back: CourseStatus = rosmsg::decode(&rosmsg::encode(&s).unwrap()).unwrap();
    assert_eq!(back, s);

    // A run without a course records neither topic.
    let flat = common::load_for("scenarios/packbot_flat.toml", 0.05);
    let r = tracksim::run_scenario(&flat, |_, _| {}).unwrap();
    let msgs = by_topic(&tracksim::output::mcap::mcap_bytes(&flat, &r).unwrap());
    assert!(
        !msgs.keys().any(|t| t.starts_with("/course")),
        "{:?}",
        msgs.keys()
    );
}

/// A straight drive over two waypoints with a reset after 1 s, scored live as the node does
/// at every sample: each event is sent once, the reset's fault after the first attempt's gate,
/// and every status is the score at its sample.
#[test]
fn a_live_session_sends_each_event_once_across_a_reset() {
    let vehicle = load_vehicle(&common::root().join("vehicles/packbot510.toml")).unwrap();
    let text = "[vehicle]\nfile = \"x\"\n[terrain.ground]\nfriction = 0.6\n[simulation]\n\
                duration_s = 10.0\n[[commands]]\nt_s = 0.0\nbelt_speed_mps = 0.3\n";
    let spec: tracksim::spec::ScenarioSpec = tracksim::toml::from_str(text).unwrap();
    let plain = tracksim::compile_scenario(&spec, vehicle.clone(), &common::root()).unwrap();
    let x0 = plain.start_xy.0;
    let course = format!(
        "[course]\n[[course.gates]]\nx_m = {:?}\ny_m = 0.0\nradius_m = 0.05\n\
         [[course.gates]]\nx_m = {:?}\ny_m = 0.0\nradius_m = 0.05\n[course.penalty_s]\nreset = 30.0\n",
        x0 + 0.15,
        x0 + 5.0
    );
    let spec: tracksim::spec::ScenarioSpec =
        tracksim::toml::from_str(&format!("{text}{course}")).unwrap();
    let sc: Scenario = tracksim::compile_scenario(&spec, vehicle, &common::root()).unwrap();

    let mut r = Runner::new(&sc).unwrap().without_sensors();
    let mut cursor = EventCursor::default();
    let mut sent: Vec<rosmsg::CourseEvent> = Vec::new();
    let mut statuses: Vec<CourseStatus> = Vec::new();
    let mut attempt_statuses = 0;
    let mut live = |r: &Runner, sent: &mut Vec<_>, statuses: &mut Vec<CourseStatus>| {
        let c = r.course().unwrap();
        sent.extend(cursor.new_events(&c).iter().map(course_event));
        statuses.push(course_status(r.time(), &c));
    };
    for attempt in 0..2 {
        while r.time() < 1.0 - 1e-9 {
            r.step().unwrap();
            if r.at_sample() {
                live(&r, &mut sent, &mut statuses);
            }
        }
        let s = statuses.last().unwrap();
        assert_eq!(
            (s.next_gate, s.gates_passed, s.resets),
            (1, 1, attempt),
            "{s:?}"
        );
        if attempt == 0 {
            attempt_statuses = statuses.len();
            r.reset(None).unwrap();
        }
    }
    let kinds: Vec<(&str, &str)> = sent
        .iter()
        .map(|e| (e.kind.as_str(), e.fault.as_str()))
        .collect();
    assert_eq!(
        kinds,
        [("gate", ""), ("fault", "reset"), ("gate", "")],
        "{sent:?}"
    );
    assert_eq!(sent[1].penalty, 30.0);
    assert!(sent[0].header.stamp.nanos() < Time::from_secs(1.0).nanos());
    // Each status is the score at its sample: the elapsed time restarts with the attempt.
    for (k, s) in statuses.iter().enumerate() {
        let t = s.header.stamp.nanos() as f64 * 1e-9;
        assert!((s.elapsed - t).abs() < 1e-6, "sample {k}: {s:?}");
        assert_eq!(s.penalty, if k < attempt_statuses { 0.0 } else { 30.0 });
        assert_eq!(s.score, s.trial_time + s.penalty);
        assert_eq!(s.status, "running");
    }
    // The run written since the reset holds the second attempt's events, as sent after it.
    let res = r.finish(End::ByOperator);
    let c = res.summary.course.unwrap();
    let after: Vec<_> = c.events.iter().map(course_event).collect();
    assert_eq!(after, sent[1..]);
}

/// Each robot of a race records its own course under its name.
#[test]
fn each_robot_of_a_race_records_its_course_under_its_name() {
    let sc =
        tracksim::load_scenario(&common::root().join("scenarios/team/race_step.toml")).unwrap();
    let r = tracksim::run::run_team(&sc, Default::default()).unwrap();
    let msgs = by_topic(&tracksim::output::mcap::team_mcap_bytes(&sc, &r).unwrap());
    assert!(!msgs.contains_key("/course"));
    for (name, run) in &r.robots {
        let c = run.summary.course.as_ref().expect("each robot scored");
        assert_eq!(c.status, "completed", "{name}: {c:?}");
        let end = run.samples.last().unwrap().t;
        check_recorded(&msgs, &Namespace::robot(name), c, end);
    }
}

/// A sensor publishes on `/<name>`: one named after a topic of the robot's own (`course`,
/// `odom`, ...) is refused with its key and the fix; its neighbours' names are fine.
#[test]
fn a_sensor_named_after_a_topic_of_the_robots_own_is_refused() {
    #[derive(serde::Deserialize)]
    struct File {
        sensors: Vec<tracksim::spec::SensorSpec>,
    }
    let imu = |name: &str| format!("[[sensors]]\nname = \"{name}\"\nkind = \"imu\"\n");
    let text: String = ["imu", "course", "odom", "tf-static", "course_sensor"]
        .map(imu)
        .concat();
    let mut spec: tracksim::spec::VehicleSpec =
        tracksim::model::read_toml(&common::root().join("vehicles/packbot510.toml")).unwrap();
    spec.sensors = tracksim::toml::from_str::<File>(&text).unwrap().sensors;
    let issues = tracksim::model::compile_vehicle(&spec).expect_err("refused");
    let all: Vec<String> = issues.iter().map(|i| i.to_string()).collect();
    for (k, name) in [(1, "course"), (2, "odom"), (3, "tf-static")] {
        assert!(
            all.iter().any(|m| m.contains(&format!("sensors[{k}].name"))
                && m.contains(&format!("\"{name}\" is a topic of the robot's own"))
                && m.contains("rename the sensor")),
            "{all:#?}"
        );
    }
    assert_eq!(all.len(), 3, "{all:#?}");
}
