//! The covariances of `/odom` (issue 42): what a skid-steer encoder odometry would state about
//! its own error, so that a fusing node (robot_localization's `ekf_node`, Nav2) weighs it
//! rather than take it as exact. `/ground_truth/odom` keeps a tiny covariance
//! ([`TRUTH_VARIANCE`]): a simulator's truth.
//!
//! The model (every parameter a constant here, listed in `docs/ROS2.md`):
//! - each side's travel is a random walk: a side that rolled `|d|` metres adds
//!   [`SIDE_VARIANCE_PER_M`]` * |d|` m^2 to the variance of its travel (belt-speed noise and
//!   slip);
//! - the effective separation `B` of a skid-steered vehicle is uncertain (it changes with the
//!   slip): each radian turned adds `(`[`SEPARATION_REL_SD`]`)^2 * |dyaw|` rad^2 to the yaw
//!   variance;
//! - the pose covariance (x, y, yaw) is propagated between samples as an EKF does, from the
//!   sample's odometry increment: `P <- F P F^T + G diag(var_l, var_r) G^T + q_B`, with
//!   `ds = (d_l + d_r) / 2`, `dyaw = (d_r - d_l) / B`, `F` the Jacobian of the planar motion
//!   and `G` that of the side travels; it starts at [`START_VARIANCE`] on x, y and yaw;
//! - z, roll and pitch are not measured by a planar odometry: [`UNMEASURED_VARIANCE`];
//! - the twist covariance comes from the belt-speed noise of each side, standard deviation
//!   [`SPEED_SD_MPS`]` + `[`SLIP_SD_FRACTION`]` * |v_side|`: `var(v) = (s_l^2 + s_r^2) / 4`,
//!   `var(w) = (s_l^2 + s_r^2) / B^2 + (`[`SEPARATION_REL_SD`]` * w)^2`, `cov(v, w) =
//!   (s_r^2 - s_l^2) / (2 B)`; the lateral speed gets `var(v)` (a skid-steered robot slides a
//!   little sideways), the other components [`UNMEASURED_VARIANCE`].
//!
//! A robot whose encoders measure no yaw (its tracks not on both sides) reports its yaw as
//! unknown: [`UNMEASURED_VARIANCE`] for the yaw and the yaw rate.

use crate::world::{Odometry as EncoderOdometry, Sample};

/// Variance added to a side's travel per metre it rolls, m^2/m (standard deviation 0.1 m after
/// the first metre, 0.32 m after 10 m).
pub const SIDE_VARIANCE_PER_M: f64 = 0.01;
/// Relative standard deviation of the effective track separation `B` (skid steering: `B`
/// grows with the slip of a turn).
pub const SEPARATION_REL_SD: f64 = 0.2;
/// Standard deviation of a belt-speed reading at rest, m/s.
pub const SPEED_SD_MPS: f64 = 0.01;
/// Standard deviation of a belt-speed reading per m/s of its speed (slip).
pub const SLIP_SD_FRACTION: f64 = 0.1;
/// The variance of x, y (m^2) and yaw (rad^2) at the start (the odometry's origin is where
/// the robot starts; this keeps the matrix positive definite).
pub const START_VARIANCE: f64 = 1e-6;
/// The variance of what the planar odometry does not measure (z, roll, pitch and their
/// rates), as ROS drivers state an unknown.
pub const UNMEASURED_VARIANCE: f64 = 1e6;
/// The variance of every component of `/ground_truth/odom`: exact but for a tiny value.
pub const TRUTH_VARIANCE: f64 = 1e-12;

type M3 = [[f64; 3]; 3];

fn mul(a: &M3, b: &M3) -> M3 {
    let mut c = [[0.0; 3]; 3];
    for (i, row) in c.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    c
}

fn transpose(a: &M3) -> M3 {
    let mut c = [[0.0; 3]; 3];
    for (i, row) in c.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = a[j][i];
        }
    }
    c
}

/// The (x, y, yaw) covariance of the encoder odometry, propagated sample by sample.
#[derive(Clone, Debug, PartialEq)]
pub struct OdomCovariance {
    /// Effective separation B, m (`None`: the encoders measure no yaw).
    separation: Option<f64>,
    /// Covariance of (x, y, yaw).
    p: M3,
    /// The last sample's time, s, and odometry pose.
    last: Option<(f64, [f64; 3])>,
}

impl OdomCovariance {
    /// The covariance at the start, for encoders `model`.
    pub fn new(model: &EncoderOdometry) -> Self {
        let separation = model.yaw_separation();
        let yaw = match separation {
            Some(_) => START_VARIANCE,
            None => UNMEASURED_VARIANCE,
        };
        OdomCovariance {
            separation,
            p: [
                [START_VARIANCE, 0.0, 0.0],
                [0.0, START_VARIANCE, 0.0],
                [0.0, 0.0, yaw],
            ],
            last: None,
        }
    }

    /// Propagates to sample `s` (a sample at or before the last one changes nothing).
    pub fn update(&mut self, s: &Sample) {
        let now = s.odom;
        let Some((t0, before)) = self.last else {
            self.last = Some((s.t, now));
            return;
        };
        if s.t <= t0 {
            return;
        }
        self.last = Some((s.t, now));
        let dyaw = now[2] - before[2];
        let mid = before[2] + 0.5 * dyaw;
        let (sin, cos) = mid.sin_cos();
        let ds = (now[0] - before[0]) * cos + (now[1] - before[1]) * sin;
        let f = [[1.0, 0.0, -ds * sin], [0.0, 1.0, ds * cos], [0.0, 0.0, 1.0]];
        let mut p = mul(&mul(&f, &self.p), &transpose(&f));
        match self.separation {
            Some(b) => {
                let (dl, dr) = (ds - 0.5 * b * dyaw, ds + 0.5 * b * dyaw);
                let (vl, vr) = (
                    SIDE_VARIANCE_PER_M * dl.abs(),
                    SIDE_VARIANCE_PER_M * dr.abs(),
                );
                // G = [[c/2, c/2], [s/2, s/2], [-1/B, 1/B]].
                let g = [
                    [0.5 * cos, 0.5 * cos],
                    [0.5 * sin, 0.5 * sin],
                    [-1.0 / b, 1.0 / b],
                ];
                for (i, row) in p.iter_mut().enumerate() {
                    for (j, x) in row.iter_mut().enumerate() {
                        *x += g[i][0] * vl * g[j][0] + g[i][1] * vr * g[j][1];
                    }
                }
                p[2][2] += SEPARATION_REL_SD * SEPARATION_REL_SD * dyaw.abs();
            }
            None => {
                let v = SIDE_VARIANCE_PER_M * ds.abs() / 2.0;
                p[0][0] += cos * cos * v;
                p[0][1] += cos * sin * v;
                p[1][0] += cos * sin * v;
                p[1][1] += sin * sin * v;
                p[2] = [0.0, 0.0, UNMEASURED_VARIANCE];
                p[0][2] = 0.0;
                p[1][2] = 0.0;
            }
        }
        self.p = p;
    }

    /// The pose covariance of `nav_msgs/Odometry` (6 x 6, row-major over x, y, z, roll, pitch,
    /// yaw).
    pub fn pose(&self) -> [f64; 36] {
        let mut c = [0.0; 36];
        let ix = [0, 1, 5];
        for (i, &a) in ix.iter().enumerate() {
            for (j, &b) in ix.iter().enumerate() {
                c[6 * a + b] = self.p[i][j];
            }
        }
        for k in [2, 3, 4] {
            c[7 * k] = UNMEASURED_VARIANCE;
        }
        c
    }

    /// The twist covariance (6 x 6, row-major over vx, vy, vz, wx, wy, wz) for the side belt
    /// speeds `sides` (m/s; `None` without both sides, then `forward` m/s is the mean belt speed)
    /// and yaw rate `w` rad/s.
    pub fn twist(&self, sides: Option<(f64, f64)>, forward: f64, w: f64) -> [f64; 36] {
        let sd = |v: f64| SPEED_SD_MPS + SLIP_SD_FRACTION * v.abs();
        let mut c = [0.0; 36];
        match (sides, self.separation) {
            (Some((l, r)), Some(b)) => {
                let (sl, sr) = (sd(l).powi(2), sd(r).powi(2));
                let var_v = (sl + sr) / 4.0;
                c[0] = var_v;
                c[7] = var_v;
                c[35] = (sl + sr) / (b * b) + (SEPARATION_REL_SD * w).powi(2);
                c[5] = (sr - sl) / (2.0 * b);
                c[30] = c[5];
            }
            _ => {
                let var_v = sd(forward).powi(2);
                c[0] = var_v;
                c[7] = var_v;
                c[35] = UNMEASURED_VARIANCE;
            }
        }
        for k in [2, 3, 4] {
            c[7 * k] = UNMEASURED_VARIANCE;
        }
        c
    }
}

/// The covariance of `/ground_truth/odom` (pose or twist): [`TRUTH_VARIANCE`] on the diagonal.
pub fn truth_covariance() -> [f64; 36] {
    let mut c = [0.0; 36];
    for k in 0..6 {
        c[7 * k] = TRUTH_VARIANCE;
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(t: f64, odom: [f64; 3]) -> Sample {
        Sample {
            t,
            odom,
            ..Sample::default()
        }
    }

    #[test]
    fn the_pose_variance_grows_with_the_distance_and_the_yaw_with_the_turns() {
        let model = EncoderOdometry::new(&[Some(0.25), Some(-0.25)], 0.5, 0.0, 0.0, 0.0);
        let mut c = OdomCovariance::new(&model);
        c.update(&sample(0.0, [0.0; 3]));
        let start = c.pose();
        assert_eq!(start[0], START_VARIANCE);
        assert_eq!(start[14], UNMEASURED_VARIANCE);
        // 10 m straight ahead in 1 cm steps.
        for k in 1..=1000 {
            c.update(&sample(k as f64 * 0.01, [k as f64 * 0.01, 0.0, 0.0]));
        }
        let p = c.pose();
        // Along x: each side's 10 m random walk, halved: 0.01 * 10 / 2 = 0.05 m^2.
        assert!((p[0] - 0.05).abs() < 1e-5, "{}", p[0]);
        // Yaw: 2 * 0.01 * 10 / B^2 = 0.8 rad^2; y grows with the yaw error times the distance.
        assert!((p[35] - 0.8).abs() < 1e-3, "{}", p[35]);
        assert!(p[7] > 1.0 && p[11] > 0.0, "{p:?}");
        // Symmetric.
        for i in 0..6 {
            for j in 0..6 {
                assert_eq!(p[6 * i + j], p[6 * j + i]);
            }
        }
        // A turn on the spot (pi rad) adds the separation term and the sides' travel.
        let before = p[35];
        for k in 1..=100 {
            let yaw = std::f64::consts::PI * k as f64 / 100.0;
            c.update(&sample(10.0 + k as f64 * 0.01, [10.0, 0.0, yaw]));
        }
        let turned = c.pose()[35] - before;
        let expect = SEPARATION_REL_SD.powi(2) * std::f64::consts::PI
            + 2.0 * SIDE_VARIANCE_PER_M * 0.25 * std::f64::consts::PI / 0.25;
        assert!((turned - expect).abs() < 1e-9, "{turned} {expect}");
        // The same sample again changes nothing.
        let p = c.pose();
        c.update(&sample(11.0, [10.0, 0.0, std::f64::consts::PI]));
        assert_eq!(c.pose(), p);
    }

    #[test]
    fn the_twist_covariance_follows_the_belt_speed_noise() {
        let model = EncoderOdometry::new(&[Some(0.25), Some(-0.25)], 0.5, 0.0, 0.0, 0.0);
        let c = OdomCovariance::new(&model);
        let t = c.twist(Some((0.0, 0.0)), 0.0, 0.0);
        assert!((t[0] - 0.01f64.powi(2) / 2.0).abs() < 1e-15);
        assert!((t[35] - 2.0 * 0.01f64.powi(2) / 0.25).abs() < 1e-15);
        let fast = c.twist(Some((1.0, 1.0)), 1.0, 0.0);
        assert!(fast[0] > 20.0 * t[0]);
        // Without both sides, the yaw is unknown.
        let one = OdomCovariance::new(&EncoderOdometry::new(&[Some(0.0)], 0.0, 0.0, 0.0, 0.0));
        assert_eq!(one.pose()[35], UNMEASURED_VARIANCE);
        assert_eq!(one.twist(None, 0.3, 0.0)[35], UNMEASURED_VARIANCE);
    }
}
