//! What is recorded of the running state: the body's pose and velocities, belts, flippers and
//! contacts ([`Sample`]), and the queries behind it.

use super::TrackLoad;
use rapier3d::prelude::*;

/// Pose of a body as REP 103 position and roll/pitch/yaw (Z-Y-X), m and rad.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PoseRpy {
    /// m.
    pub x: f64,
    /// m.
    pub y: f64,
    /// m.
    pub z: f64,
    /// rad, about x.
    pub roll: f64,
    /// rad, about y.
    pub pitch: f64,
    /// rad, about z.
    pub yaw: f64,
}

impl PoseRpy {
    /// Converts a Rapier pose.
    pub fn from_pose(p: &Pose) -> Self {
        let r = p.rotation;
        let (w, x, y, z) = (r.w as f64, r.x as f64, r.y as f64, r.z as f64);
        PoseRpy {
            x: p.translation.x as f64,
            y: p.translation.y as f64,
            z: p.translation.z as f64,
            roll: (2.0 * (w * x + y * z)).atan2(1.0 - 2.0 * (x * x + y * y)),
            pitch: (2.0 * (w * y - z * x)).clamp(-1.0, 1.0).asin(),
            yaw: (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z)),
        }
    }
}

/// One recorded instant of the vehicle's state.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Sample {
    /// Simulated time, s.
    pub t: f64,
    /// Body pose.
    pub pose: PoseRpy,
    /// Body linear velocity (world), m/s.
    pub linvel: [f64; 3],
    /// Body angular velocity (world), rad/s.
    pub angvel: [f64; 3],
    /// Measured belt speed per track, m/s.
    pub belt_speed: Vec<f64>,
    /// Belt phase per track, m.
    pub belt_phase: Vec<f64>,
    /// Unwrapped belt position per track, m (how far the belt has run; the 3-D view draws the
    /// grousers at this arc length along the path, so the rollback does not show).
    pub belt_position: Vec<f64>,
    /// Flipper angle per flipper, rad.
    pub flipper_angle: Vec<f64>,
    /// Active contact points in the world.
    pub contacts: usize,
    /// Deepest geometric penetration among the vehicle-terrain contact points (0 if none), m.
    pub penetration: f64,
    /// Commanded belt speed per track, m/s.
    pub belt_cmd: Vec<f64>,
    /// Slip ratio per track: (belt - ground) / max(|belt|, |ground|), 0 when both are below
    /// [`SLIP_MIN_SPEED_MPS`] (5 mm/s); ground is the parent's velocity at the track's centre along its forward axis
    /// (positive: the belt runs faster than the track moves over the ground, as when driving).
    pub slip: Vec<f64>,
    /// The terrain's force on each track over the last step.
    pub loads: Vec<TrackLoad>,
    /// Odometry pose (x m, y m, yaw rad) in the odom frame (REP 105; the world frame at start).
    pub odom: [f64; 3],
    /// Drive of each track with a motor model (`None` without).
    pub drive: Vec<Option<DriveSample>>,
    /// Instantaneous centre of rotation of the chassis's planar motion in its own frame
    /// (x m, y m), `None` while it turns slower than [`ICR_MIN_RATE_RAD_S`].
    pub icr: Option<[f64; 2]>,
    /// The drawbar's pull on the chassis, N (`None` without `[drawbar]`).
    pub drawbar_n: Option<f64>,
    /// Unwrapped belt position of every conveyor, m (`[[terrain.conveyors]]`; for the replay).
    pub conveyor_position: Vec<f64>,
    /// Pose of every loose box, world frame (`[[terrain.loose_boxes]]`; for the replay).
    pub loose_poses: Vec<PoseRpy>,
    /// Each track's sinkage, soil thrust and compaction over the last step (empty when the
    /// terrain has no soil).
    pub soil: Vec<super::TrackSoil>,
}

/// What a track's drive motor does (`[tracks.motor]`).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct DriveSample {
    /// Belt force, N: the motor's limit while it is saturated (the belt slower than
    /// commanded), else the track's traction (the belt force in steady state, the links'
    /// inertia neglected) within that limit.
    pub belt_force_n: f64,
    /// Torque at the sprocket, N m.
    pub sprocket_torque_nm: f64,
    /// Torque at the motor shaft, N m.
    pub motor_torque_nm: f64,
    /// Largest belt force the motor could deliver at this speed, N.
    pub max_belt_force_n: f64,
    /// Mechanical power into the belt (force times measured belt speed), W.
    pub power_w: f64,
    /// The motor's current, terminal voltage and electrical power (with the electrical
    /// model of `[tracks.motor]`: `voltage_v`, `stall_current_a`).
    pub electrical: Option<crate::model::ElectricalState>,
}

/// Yaw rate below which the instantaneous centre of rotation is not reported, rad/s.
pub const ICR_MIN_RATE_RAD_S: f64 = 1e-3;

/// Speed below which neither a belt nor the ground under it is taken to move, m/s: the slip
/// ratio is reported as 0 there (issue 43: the ratio of two speeds near zero read as slips of
/// 0.6-1.0 on the HUD while a robot stood). A held PackBot at rest moves at 0.4 mm/s, its
/// belts at 0.3 mm/s (rigid ground, after a stop from 0.3 m/s); 5 mm/s is more than ten times
/// that, and a tenth of a slow drive's 0.05 m/s. Slower driving reads no slip.
pub const SLIP_MIN_SPEED_MPS: f64 = 0.005;

/// Slip ratio of a belt running at `belt` m/s over ground it moves along at `ground` m/s:
/// (belt - ground) / the larger of the two, 0 while neither reaches [`SLIP_MIN_SPEED_MPS`].
pub fn slip_ratio(belt: f64, ground: f64) -> f64 {
    let scale = belt.abs().max(ground.abs());
    if scale < SLIP_MIN_SPEED_MPS {
        0.0
    } else {
        (belt - ground) / scale
    }
}
