//! The ROS 2 messages of a run's sample, in one place: what `run.mcap`
//! ([`super::mcap`]) records and what the ROS 2 node (`crate::ros`) publishes are built by the
//! same functions, so the two cannot disagree. Frames (REP 103 axes, REP 105 names) and topics
//! are listed in [`super::mcap`]'s documentation.

use super::odom_covariance::{OdomCovariance, truth_covariance};
use super::ros_sensors::{MAP_FRAME, link_frame, message_frame};
use crate::model::{Scenario, SensorKind};
use crate::rosmsg::{
    self, Clock, Header, JointState, Odometry, PoseWithCovariance, Quaternion, TFMessage, Time,
    TrackStates, Transform, TransformStamped, Twist, TwistWithCovariance, Vector3,
};
use crate::world::{Odometry as EncoderOdometry, PoseRpy, Sample};
use glam::{DMat3, DQuat, DVec3, EulerRot};

/// The odometry frame (REP 105): `/odom` and `/tf`'s `odom -> base_link` are the encoders'
/// estimate in it; `map -> odom` is where that estimate drifted from the truth.
pub const ODOM_FRAME: &str = "odom";
/// The chassis frame.
pub const BASE_FRAME: &str = "base_link";

/// The frame of flipper `name`.
pub fn flipper_frame(name: &str) -> String {
    format!("{name}_flipper_link")
}

/// The joint name of track `name`'s belt in `/joint_states`.
pub fn belt_joint(name: &str) -> String {
    format!("{name}_belt")
}

fn vec3(v: DVec3) -> Vector3 {
    Vector3 {
        x: v.x,
        y: v.y,
        z: v.z,
    }
}

fn quat(q: DQuat) -> Quaternion {
    Quaternion {
        x: q.x,
        y: q.y,
        z: q.z,
        w: q.w,
    }
}

/// The rotation of a REP 103 roll/pitch/yaw pose.
pub fn pose_rotation(p: &PoseRpy) -> DQuat {
    DQuat::from_euler(EulerRot::ZYX, p.yaw, p.pitch, p.roll)
}

/// The transform `parent -> child` at `t` s: `child`'s origin `at` (m) and rotation `rot` in
/// `parent`.
pub fn transform(t: f64, parent: &str, child: &str, at: DVec3, rot: DQuat) -> TransformStamped {
    TransformStamped {
        header: Header::new(t, parent),
        child_frame_id: child.to_string(),
        transform: Transform {
            translation: vec3(at),
            rotation: quat(rot),
        },
    }
}

/// A robot's encoder odometry as `/odom` states it: the skid-steer model of its tracks (for
/// the twist) and the covariance it has gathered ([`OdomCovariance`]), sample by sample.
#[derive(Clone, Debug)]
pub struct EncoderOdom {
    /// The skid-steer model of the tracks.
    pub model: EncoderOdometry,
    /// The covariance so far.
    pub covariance: OdomCovariance,
}

/// The encoder odometry of `sc`'s tracks, at the start.
pub fn encoder_model(sc: &Scenario) -> EncoderOdom {
    let model = EncoderOdometry::of_vehicle(&sc.vehicle, 0.0, 0.0, 0.0);
    EncoderOdom {
        covariance: OdomCovariance::new(&model),
        model,
    }
}

/// The encoder odometry of sample `s` (frame `odom`, child `base_link`), its covariances from
/// the encoder model ([`super::odom_covariance`]) propagated to `s` (call it with every sample
/// in order; a sample again changes nothing).
pub fn encoder_odometry(s: &Sample, enc: &mut EncoderOdom) -> Odometry {
    enc.covariance.update(s);
    let (v, w) = enc.model.twist(&s.belt_speed);
    let [x, y, yaw] = s.odom;
    let mut pose = PoseWithCovariance::default();
    pose.pose.position = rosmsg::Point { x, y, z: 0.0 };
    pose.pose.orientation = quat(DQuat::from_rotation_z(yaw));
    pose.covariance = enc.covariance.pose();
    let twist = TwistWithCovariance {
        twist: Twist {
            linear: Vector3 {
                x: v,
                y: 0.0,
                z: 0.0,
            },
            angular: Vector3 {
                x: 0.0,
                y: 0.0,
                z: w,
            },
        },
        covariance: enc
            .covariance
            .twist(enc.model.side_speeds(&s.belt_speed), v, w),
    };
    Odometry {
        header: Header::new(s.t, ODOM_FRAME),
        child_frame_id: BASE_FRAME.into(),
        pose,
        twist,
    }
}

/// The true odometry of sample `s`: pose in `map`, velocities in `base_link` axes, a tiny
/// covariance (a simulator's truth: [`super::odom_covariance::TRUTH_VARIANCE`]).
pub fn true_odometry(s: &Sample) -> Odometry {
    let r = pose_rotation(&s.pose);
    let inv = r.inverse();
    let mut pose = PoseWithCovariance::default();
    pose.pose.position = rosmsg::Point {
        x: s.pose.x,
        y: s.pose.y,
        z: s.pose.z,
    };
    pose.pose.orientation = quat(r);
    pose.covariance = truth_covariance();
    let twist = TwistWithCovariance {
        twist: Twist {
            linear: vec3(inv * DVec3::from_array(s.linvel)),
            angular: vec3(inv * DVec3::from_array(s.angvel)),
        },
        covariance: truth_covariance(),
    };
    Odometry {
        header: Header::new(s.t, MAP_FRAME),
        child_frame_id: BASE_FRAME.into(),
        pose,
        twist,
    }
}

/// The pose of an odometry message: its position (m) and rotation.
fn pose_of(o: &Odometry) -> (DVec3, DQuat) {
    let p = &o.pose.pose;
    let q = &p.orientation;
    (
        DVec3::new(p.position.x, p.position.y, p.position.z),
        DQuat::from_xyzw(q.x, q.y, q.z, q.w),
    )
}

/// `/tf` of sample `s` (REP 105): `odom -> base_link` from the encoder odometry `odom` (what
/// `/odom` says: planar, slip included), `base_link -> <flipper>_flipper_link` (origin at
/// the pivot, turned by the flipper angle about its axis), and with `with_map` also
/// `map -> odom`, the encoders' drift from the true pose (a perfect localisation: `map ->
/// base_link` is the truth, so sensor data lands where it was taken). A URDF vehicle's links
/// that move with a flipper are there too under the URDF's names (`<parent link> -> <child
/// link>`, the joint's origin turned by the flipper's angle; the fixed ones are on
/// `/tf_static`, [`tf_static`]).
pub fn tf_of_sample(sc: &Scenario, s: &Sample, odom: &Odometry, with_map: bool) -> TFMessage {
    let (at, rot) = pose_of(odom);
    let mut transforms = vec![transform(s.t, ODOM_FRAME, BASE_FRAME, at, rot)];
    for (f, angle) in sc.vehicle.flippers.iter().zip(&s.flipper_angle) {
        transforms.push(transform(
            s.t,
            BASE_FRAME,
            &flipper_frame(&f.name),
            f.pivot,
            DQuat::from_axis_angle(f.axis.normalize(), *angle),
        ));
    }
    for (j, angle) in urdf_arms(sc, &s.flipper_angle) {
        transforms.push(transform(
            s.t,
            &j.parent,
            &j.child,
            j.origin,
            j.rotation * DQuat::from_axis_angle(j.axis, angle),
        ));
    }
    if with_map {
        // map->odom = (map->base_link) * (odom->base_link)^-1.
        let r = (pose_rotation(&s.pose) * rot.inverse()).normalize();
        let t = DVec3::new(s.pose.x, s.pose.y, s.pose.z) - r * at;
        transforms.push(transform(s.t, MAP_FRAME, ODOM_FRAME, t, r));
    }
    TFMessage { transforms }
}

/// The per-track message of sample `s`.
pub fn track_states(s: &Sample, names: &[String]) -> TrackStates {
    let motors = s.drive.iter().any(|d| d.is_some());
    let motor = |f: fn(&crate::world::DriveSample) -> f64| -> Vec<f64> {
        if motors {
            s.drive
                .iter()
                .map(|d| d.as_ref().map_or(f64::NAN, f))
                .collect()
        } else {
            Vec::new()
        }
    };
    TrackStates {
        header: Header::new(s.t, BASE_FRAME),
        name: names.to_vec(),
        slip: s.slip.clone(),
        belt_speed: s.belt_speed.clone(),
        belt_command: s.belt_cmd.clone(),
        belt_position: s.belt_position.clone(),
        traction: s.loads.iter().map(|l| l.traction_n).collect(),
        friction_traction: s.loads.iter().map(|l| l.friction_traction_n).collect(),
        normal_load: s.loads.iter().map(|l| l.normal_n).collect(),
        contacts: s.loads.iter().map(|l| l.contacts as u32).collect(),
        belt_force: motor(|d| d.belt_force_n),
        motor_torque: motor(|d| d.motor_torque_nm),
    }
}

/// The rotation from a depth camera's frame (x forward, y left, z up) to its optical frame
/// (z forward, x right, y down).
pub fn optical_rotation() -> DQuat {
    let q = DQuat::from_mat3(&DMat3::from_cols(
        DVec3::new(0.0, -1.0, 0.0),
        DVec3::new(0.0, 0.0, -1.0),
        DVec3::new(1.0, 0.0, 0.0),
    ));
    if q.w < 0.0 { -q } else { q }
}

/// `/joint_states` of sample `s`: flipper angles (rad; velocity by backward difference from
/// `prev`, 0 without it), belt travel (m) and measured belt speed (m/s).
pub fn joint_state(names: &[String], s: &Sample, prev: Option<&Sample>) -> JointState {
    let mut position = s.flipper_angle.clone();
    position.extend(&s.belt_position);
    let mut velocity: Vec<f64> = match prev {
        Some(p) if s.t > p.t => s
            .flipper_angle
            .iter()
            .zip(&p.flipper_angle)
            .map(|(a, b)| (a - b) / (s.t - p.t))
            .collect(),
        _ => vec![0.0; s.flipper_angle.len()],
    };
    velocity.extend(&s.belt_speed);
    JointState {
        header: Header::new(s.t, ""),
        name: names.to_vec(),
        position,
        velocity,
        effort: Vec::new(),
    }
}

/// The frames tracksim names itself for `sc`'s vehicle (a URDF link of the same name is not
/// published again: a frame has one parent).
fn own_frames(sc: &Scenario) -> Vec<String> {
    let v = &sc.vehicle;
    let mut f = vec![
        BASE_FRAME.to_string(),
        ODOM_FRAME.to_string(),
        MAP_FRAME.to_string(),
    ];
    f.extend(v.flippers.iter().map(|x| flipper_frame(&x.name)));
    for m in &v.sensors {
        f.push(link_frame(m));
        f.push(message_frame(m));
    }
    f
}

/// A URDF vehicle's joints that move with a flipper (the flipper named as the joint), each with
/// the flipper's angle in `angles` (rad), as `/tf` carries them under the URDF's link names.
fn urdf_arms<'a>(
    sc: &'a Scenario,
    angles: &'a [f64],
) -> impl Iterator<Item = (&'a crate::urdf::JointFrame, f64)> + 'a {
    let own = sc
        .vehicle
        .urdf
        .as_ref()
        .map(|_| own_frames(sc))
        .unwrap_or_default();
    sc.vehicle
        .urdf
        .iter()
        .flat_map(|u| u.joints.iter())
        .filter(move |j| j.moving && !own.contains(&j.child))
        .filter_map(move |j| {
            let i = sc.vehicle.flipper_index(&j.name)?;
            Some((j, angles.get(i).copied().unwrap_or(0.0)))
        })
}

/// A URDF vehicle's fixed links (and joints that do not move with a flipper, at their held
/// angle) under their own names, and `base_link -> <root link>` (identity: the chassis frame
/// is the root link's) when the root is not called `base_link`.
fn urdf_static(sc: &Scenario) -> Vec<TransformStamped> {
    let Some(u) = &sc.vehicle.urdf else {
        return Vec::new();
    };
    let own = own_frames(sc);
    let mut out = Vec::new();
    if !u.root.is_empty() && u.root != BASE_FRAME {
        out.push(transform(
            0.0,
            BASE_FRAME,
            &u.root,
            DVec3::ZERO,
            DQuat::IDENTITY,
        ));
    }
    for j in &u.joints {
        let arm = j.moving && sc.vehicle.flipper_index(&j.name).is_some();
        if arm || own.contains(&j.child) || j.child == u.root {
            continue;
        }
        out.push(transform(
            0.0,
            &j.parent,
            &j.child,
            j.origin,
            j.rotation * DQuat::from_axis_angle(j.axis, j.locked_angle),
        ));
    }
    out
}

/// `/tf_static`: each sensor's frame on its mount (`base_link` or the flipper's link) and the
/// cameras' (depth and colour) optical frames (encoders have no frame).
pub fn tf_static(sc: &Scenario) -> TFMessage {
    let mut transforms = urdf_static(sc);
    for m in &sc.vehicle.sensors {
        if matches!(m.kind, SensorKind::Encoders(_)) {
            continue;
        }
        let (parent, at) = match m.mount {
            crate::model::Mount::Body => (BASE_FRAME.to_string(), m.position),
            crate::model::Mount::Flipper(i) => {
                let f = &sc.vehicle.flippers[i];
                (flipper_frame(&f.name), m.position - f.pivot)
            }
        };
        let frame = link_frame(m);
        transforms.push(transform(0.0, &parent, &frame, at, m.rotation));
        if matches!(
            m.kind,
            SensorKind::DepthCamera(_) | SensorKind::RgbCamera(_)
        ) {
            transforms.push(transform(
                0.0,
                &frame,
                &message_frame(m),
                DVec3::ZERO,
                optical_rotation(),
            ));
        }
    }
    TFMessage { transforms }
}

/// `/clock` at `t` s of simulated time.
pub fn clock(t: f64) -> Clock {
    Clock {
        clock: Time::from_secs(t),
    }
}

/// The joint names of `/joint_states` for `sc`'s vehicle: the flippers (revolute, rad), then
/// each track's belt as the continuous joint `<track>_belt` (its travel, m).
pub fn joint_names(sc: &Scenario) -> Vec<String> {
    let mut names: Vec<String> = sc.vehicle.flippers.iter().map(|f| f.name.clone()).collect();
    names.extend(sc.vehicle.tracks.iter().map(|t| belt_joint(&t.name)));
    names
}
