//! What the robot's own encoders would report (issue 14.3): the measured belt speeds of the
//! left and right tracks integrated with
//! the skid-steer model, `v = (v_l + v_r) / 2`, `w = (v_r - v_l) / B`, with `v_l`, `v_r` the
//! mean belt speed of each side and `B` the effective track separation (`[odometry]
//! track_separation_m` of the vehicle file; by default the distance between the mean left and
//! mean right mid-planes). The encoders counted are the chassis tracks' when the chassis has
//! tracks on both sides (a PackBot's main tracks, as its own odometry does), else every
//! track's, wherever it rides (issue 42: four tracks on flippers, a robot's track on a
//! flipper link). A robot whose tracks are not on both sides (one track on the mid-plane)
//! measures forward speed only: `v` the mean belt speed, `w = 0`. The pose lives in an `odom` frame (ROS REP 105) that
//! coincides with the world frame at the start, so it compares directly with the ground truth;
//! it is planar (x, y, yaw), as a wheel-odometry node publishes it.

use crate::model::{Parent, VehicleModel, side_of, side_separation};

/// Planar odometry state, integrated every physics step.
#[derive(Clone, Debug, PartialEq)]
pub struct Odometry {
    /// Track indices on the chassis's left (+y) side.
    left: Vec<usize>,
    /// Track indices on the chassis's right (-y) side.
    right: Vec<usize>,
    /// Every counted track's index (for the forward speed without both sides).
    all: Vec<usize>,
    /// Effective track separation B, m.
    separation: f64,
    /// x in the odom frame, m.
    pub x: f64,
    /// y in the odom frame, m.
    pub y: f64,
    /// Yaw in the odom frame, rad (unwrapped).
    pub yaw: f64,
}

impl Odometry {
    /// Odometry over the tracks at lateral offsets `offsets` (m, chassis frame; `None` for
    /// tracks not counted), with separation `separation` m, starting at (x, y, yaw).
    pub fn new(offsets: &[Option<f64>], separation: f64, x: f64, y: f64, yaw: f64) -> Self {
        let side = |s: f64| -> Vec<usize> {
            offsets
                .iter()
                .enumerate()
                .filter_map(|(i, o)| o.filter(|&y| side_of(y) == s).map(|_| i))
                .collect()
        };
        Odometry {
            left: side(1.0),
            right: side(-1.0),
            all: (0..offsets.len())
                .filter(|&i| offsets[i].is_some())
                .collect(),
            separation,
            x,
            y,
            yaw,
        }
    }

    /// The encoders of `v` (see the module: the chassis tracks when they are on both sides,
    /// else every track), with the vehicle's `[odometry]` separation or the geometric one,
    /// starting at (x, y, yaw).
    pub fn of_vehicle(v: &VehicleModel, x: f64, y: f64, yaw: f64) -> Self {
        let offsets = Odometry::counted_offsets(v);
        let b = v
            .odometry_separation
            .unwrap_or_else(|| Odometry::geometric_separation(&offsets));
        Odometry::new(&offsets, b, x, y, yaw)
    }

    /// Each track's lateral offset, m, `None` for a track the encoders do not count.
    pub fn counted_offsets(v: &VehicleModel) -> Vec<Option<f64>> {
        let on_body: Vec<Option<f64>> = v
            .tracks
            .iter()
            .map(|t| (t.parent == Parent::Body).then(|| t.lateral_offset()))
            .collect();
        let sides = |s: f64| on_body.iter().flatten().any(|&y| side_of(y) == s);
        if sides(1.0) && sides(-1.0) {
            on_body
        } else {
            v.track_offsets().into_iter().map(Some).collect()
        }
    }

    /// Default effective separation, m: the distance between the mean left and mean right
    /// mid-planes of the counted tracks (0 if a side has none).
    pub fn geometric_separation(offsets: &[Option<f64>]) -> f64 {
        let counted: Vec<f64> = offsets.iter().flatten().copied().collect();
        side_separation(&counted)
    }

    /// The effective track separation B, m, when the encoders measure yaw (tracks on both
    /// sides and B > 0).
    pub fn yaw_separation(&self) -> Option<f64> {
        (!self.left.is_empty() && !self.right.is_empty() && self.separation > 0.0)
            .then_some(self.separation)
    }

    /// The mean left and mean right belt speeds, m/s, for belt speeds `belt` (`None` without
    /// tracks on both sides).
    pub fn side_speeds(&self, belt: &[f64]) -> Option<(f64, f64)> {
        let mean = |ix: &[usize]| ix.iter().map(|&i| belt[i]).sum::<f64>() / ix.len() as f64;
        self.yaw_separation()?;
        Some((mean(&self.left), mean(&self.right)))
    }

    /// Forward speed (m/s) and yaw rate (rad/s) the encoders imply for belt speeds `belt` m/s.
    pub fn twist(&self, belt: &[f64]) -> (f64, f64) {
        self.twist_of(|i| belt[i])
    }

    /// [`Odometry::twist`] with track `i`'s belt speed given by `belt(i)`, m/s.
    fn twist_of(&self, belt: impl Fn(usize) -> f64) -> (f64, f64) {
        let mean = |ix: &[usize]| ix.iter().map(|&i| belt(i)).sum::<f64>() / ix.len() as f64;
        if self.all.is_empty() {
            return (0.0, 0.0);
        }
        if self.left.is_empty() || self.right.is_empty() || self.separation <= 0.0 {
            // No yaw from the encoders: one track, or tracks on one side only.
            return (mean(&self.all), 0.0);
        }
        let (l, r) = (mean(&self.left), mean(&self.right));
        (0.5 * (l + r), (r - l) / self.separation)
    }

    /// Integrates one step of `dt` s with measured belt speeds `belt` m/s (midpoint heading).
    pub fn update(&mut self, belt: &[f64], dt: f64) {
        self.update_with(|i| belt[i], dt);
    }

    /// [`Odometry::update`] with track `i`'s belt speed given by `belt(i)` (no allocation on
    /// the step's hot path).
    pub fn update_with(&mut self, belt: impl Fn(usize) -> f64, dt: f64) {
        let (v, w) = self.twist_of(belt);
        let heading = self.yaw + 0.5 * w * dt;
        self.x += v * heading.cos() * dt;
        self.y += v * heading.sin() * dt;
        self.yaw += w * dt;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_differential_turn_integrates_to_the_circle_it_describes() {
        // Left 0.2 m/s, right 0.4 m/s, B = 0.5 m: v = 0.3 m/s, w = 0.4 rad/s, radius 0.75 m.
        let offsets = [Some(0.25), Some(-0.25)];
        assert_eq!(Odometry::geometric_separation(&offsets), 0.5);
        let mut o = Odometry::new(&offsets, 0.5, 0.0, 0.0, 0.0);
        let t = std::f64::consts::PI / 0.4; // half a turn
        let n = 100_000;
        for _ in 0..n {
            o.update(&[0.2, 0.4], t / n as f64);
        }
        assert!((o.yaw - std::f64::consts::PI).abs() < 1e-9);
        assert!(o.x.abs() < 1e-6 && (o.y - 1.5).abs() < 1e-6, "{o:?}");
    }

    #[test]
    fn one_track_on_the_mid_plane_measures_forward_speed_and_no_yaw() {
        let o = Odometry::new(&[Some(0.0)], 0.0, 0.0, 0.0, 0.0);
        assert_eq!(o.twist(&[0.25]), (0.25, 0.0));
        // Flipper tracks count with their side: left 0.1, 0.3 and right 0.2, 0.4 m/s.
        let offsets = [Some(0.2), Some(0.3), Some(-0.2), Some(-0.3)];
        let o = Odometry::new(&offsets, 0.5, 0.0, 0.0, 0.0);
        let (v, w) = o.twist(&[0.1, 0.3, 0.2, 0.4]);
        assert!(
            (v - 0.25).abs() < 1e-12 && (w - 0.2).abs() < 1e-12,
            "{v} {w}"
        );
    }
}
