//! The node's ROS names: node `/tracksim`, its topics (absolute names; on DDS `rt/<name>`,
//! types `pkg::msg::dds_::Type_`) and the per-track and per-flipper command topics.
//! Track and flipper names may hold `-`, which ROS names do not: it becomes `_`.

/// The node's name.
pub const NODE_NAME: &str = "tracksim";
/// Body twist command (`geometry_msgs/Twist`).
pub const CMD_VEL: &str = "/cmd_vel";
/// Simulated clock (`rosgraph_msgs/Clock`).
pub const CLOCK: &str = "/clock";
/// Encoder odometry (`nav_msgs/Odometry`).
pub const ODOM: &str = "/odom";
/// True pose and velocity (`nav_msgs/Odometry`).
pub const GROUND_TRUTH: &str = "/ground_truth/odom";
/// Transforms (`tf2_msgs/TFMessage`).
pub const TF: &str = "/tf";
/// Fixed transforms, latched (`tf2_msgs/TFMessage`).
pub const TF_STATIC: &str = "/tf_static";
/// Flipper angles and belt travel (`sensor_msgs/JointState`).
pub const JOINT_STATES: &str = "/joint_states";
/// Per-track figures (`tracksim_msgs/TrackStates`).
pub const TRACKS: &str = "/tracks";
/// A scored course's score at every sample (`tracksim_msgs/CourseStatus`).
pub const COURSE: &str = "/course";
/// A scored course's events, each once (`tracksim_msgs/CourseEvent`).
pub const COURSE_EVENTS: &str = "/course/events";
/// The robot's URDF (`std_msgs/String`, transient local: late joiners get it).
pub const ROBOT_DESCRIPTION: &str = "/robot_description";
/// Every flipper's target by name in one message (`sensor_msgs/JointState`, rad).
pub const FLIPPER_POSITIONS: &str = "/flippers/cmd_positions";

/// A track or flipper name as a ROS name token (`-` to `_`).
pub fn token(name: &str) -> String {
    name.replace('-', "_")
}

/// The belt speed command topic of track `name` (`std_msgs/Float64`, m/s).
pub fn track_speed(name: &str) -> String {
    format!("/tracks/{}/cmd_speed", token(name))
}

/// The target angle command topic of flipper `name` (`std_msgs/Float64`, rad).
pub fn flipper_position(name: &str) -> String {
    format!("/flippers/{}/cmd_position", token(name))
}

/// The topic of sensor `name`.
pub fn sensor(name: &str) -> String {
    format!("/{}", token(name))
}

/// Every topic of one robot of vehicle `v` in namespace `ns`, as the node creates them: its
/// command topics (`/cmd_vel`, `/flippers/cmd_positions`, each track's speed and each
/// flipper's target), its state (`/odom`, `/ground_truth/odom`, `/joint_states`, `/tracks`),
/// its course's (`/course`, `/course/events`, when `course`) and its sensors (a colour camera's
/// `compressed` and `camera_info` topics). The world's `/clock`, `/tf`, `/tf_static` and
/// `/rosout` are not a robot's.
pub fn robot_topics(
    v: &crate::model::VehicleModel,
    course: bool,
    ns: &crate::output::ros_names::Namespace,
) -> Vec<String> {
    let mut t: Vec<String> = [
        CMD_VEL,
        FLIPPER_POSITIONS,
        ODOM,
        GROUND_TRUTH,
        JOINT_STATES,
        TRACKS,
        ROBOT_DESCRIPTION,
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    if course {
        t.extend([COURSE, COURSE_EVENTS].map(String::from));
    }
    t.extend(v.tracks.iter().map(|x| track_speed(&x.name)));
    t.extend(v.flippers.iter().map(|x| flipper_position(&x.name)));
    for x in &v.sensors {
        let s = sensor(&x.name);
        if matches!(x.kind, crate::model::SensorKind::RgbCamera(_)) {
            // The raw image topic is there only with `raw_images`.
            t.push(crate::output::ros_sensors::compressed_topic(&s));
            t.push(crate::output::ros_sensors::camera_info_topic(&s));
        } else {
            t.push(s);
        }
    }
    t.iter().map(|x| ns.topic(x)).collect()
}
