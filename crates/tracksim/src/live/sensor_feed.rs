//! The sensor readings a live state carries (`"sensors"` of the state message): each lidar's
//! and depth camera's latest reading, sent once, in the first state published after it was
//! taken (a state without a new reading has none; the page keeps drawing the last one). A slow
//! client that drops states (the hub keeps only the newest) may miss a reading and see the
//! next one.
//!
//! Entries (JSON):
//! - lidar: `{"name", "kind": "lidar", "t": s, "hits": N, "points": [x, y, z, ...]}`: the
//!   returns of the scan (finite ranges) as world-frame points, m, rounded to the millimetre,
//!   every k-th return (k = ceil(hits / [`MAX_LIDAR_POINTS`])) so that at most
//!   [`MAX_LIDAR_POINTS`] are sent; `hits` counts the returns before that decimation;
//! - depth camera: `{"name", "kind": "depth_camera", "t": s, "width": W, "height": H,
//!   "stride": k, "max_range_m": R, "position": [x, y, z], "orientation": [x, y, z, w],
//!   "depth_mm": [...]}`: the image row-major (row 0 at the top, column 0 at the left), every
//!   k-th pixel of every k-th row so that W <= [`MAX_DEPTH_WIDTH`] and H <=
//!   [`MAX_DEPTH_HEIGHT`], as whole millimetres along the optical axis (0: no return, nearer
//!   than the minimum or beyond the maximum range); the camera's world pose (m, quaternion)
//!   at the reading.

use crate::model::SensorKind;
use crate::run::RunView;
use crate::sensors::Channel;
use glam::{DQuat, DVec3};
use serde_json::{Value, json};

/// Most lidar points in one state message.
pub const MAX_LIDAR_POINTS: usize = 2000;
/// Widest depth image in a state message, pixels.
pub const MAX_DEPTH_WIDTH: usize = 64;
/// Tallest depth image in a state message, pixels.
pub const MAX_DEPTH_HEIGHT: usize = 48;

/// Which readings have been sent.
#[derive(Default)]
pub struct SensorFeed {
    /// Time of the last reading sent, per sensor (NaN: none yet).
    sent: Vec<f64>,
}

fn channel<'a>(chs: &'a [Channel], name: &str) -> Option<&'a Channel> {
    chs.iter().find(|c| c.name == name)
}

/// The world pose of a reading (its `position` and `orientation` channels).
fn pose(chs: &[Channel]) -> Option<(DVec3, DQuat)> {
    let p = &channel(chs, "position")?.data;
    let q = &channel(chs, "orientation")?.data;
    Some((
        DVec3::new(p[0], p[1], p[2]),
        DQuat::from_xyzw(q[0], q[1], q[2], q[3]),
    ))
}

/// Millimetre rounding (keeps the JSON short).
fn mm(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

fn lidar_entry(chs: &[Channel]) -> Option<Value> {
    let (origin, rot) = pose(chs)?;
    let pts = &channel(chs, "points")?.data;
    let hits: Vec<DVec3> = pts
        .chunks_exact(3)
        .filter(|p| p.iter().all(|x| x.is_finite()))
        .map(|p| DVec3::new(p[0], p[1], p[2]))
        .collect();
    let k = hits.len().div_ceil(MAX_LIDAR_POINTS).max(1);
    let points: Vec<f64> = hits
        .iter()
        .step_by(k)
        .flat_map(|p| (origin + rot * *p).to_array().map(mm))
        .collect();
    Some(json!({ "kind": "lidar", "hits": hits.len(), "points": points }))
}

fn depth_entry(chs: &[Channel], max_range: f64) -> Option<Value> {
    let (origin, rot) = pose(chs)?;
    let depth = channel(chs, "depth")?;
    let (h, w) = (depth.shape[0], depth.shape[1]);
    let k = w
        .div_ceil(MAX_DEPTH_WIDTH)
        .max(h.div_ceil(MAX_DEPTH_HEIGHT))
        .max(1);
    let mut out = Vec::with_capacity(w.div_ceil(k) * h.div_ceil(k));
    for v in (0..h).step_by(k) {
        for u in (0..w).step_by(k) {
            let d = depth.data[v * w + u];
            out.push(if d.is_finite() {
                (d * 1000.0).round().max(1.0) as u32
            } else {
                0
            });
        }
    }
    Some(json!({
        "kind": "depth_camera",
        "width": w.div_ceil(k),
        "height": h.div_ceil(k),
        "stride": k,
        "max_range_m": max_range,
        "position": origin.to_array(),
        "orientation": [rot.x, rot.y, rot.z, rot.w],
        "depth_mm": out,
    }))
}

impl SensorFeed {
    /// The lidar and depth camera readings of robot `run` taken since the last call (see the
    /// module's text for the entries).
    pub fn new_readings(&mut self, run: &RunView) -> Vec<Value> {
        let set = run.sensors;
        self.sent.resize(set.len(), f64::NAN);
        let mut out = Vec::new();
        for i in 0..set.len() {
            let t = set.reading_time(i);
            // `!=`: a reset starts the readings again from t = 0.
            if t == self.sent[i] {
                continue;
            }
            let s = set.sensor(i);
            let entry = match s.model().kind {
                SensorKind::Lidar(_) => lidar_entry(s.channels()),
                SensorKind::DepthCamera(p) => depth_entry(s.channels(), p.max_range),
                _ => None,
            };
            self.sent[i] = t;
            if let Some(Value::Object(mut e)) = entry {
                e.insert("name".into(), json!(s.model().name));
                e.insert("t".into(), json!(t));
                out.push(Value::Object(e));
            }
        }
        out
    }
}
