//! What the robot's own encoders would report (issue 14.3): the measured belt speeds of the
//! chassis's left and right tracks integrated with the skid-steer model,
//! `v = (v_l + v_r) / 2`, `w = (v_r - v_l) / B`, with `B` the effective track separation
//! (`[odometry] track_separation_m` of the vehicle file; by default the distance between the
//! left and right tracks' mid-planes). The pose lives in an `odom` frame (ROS REP 105) that
//! coincides with the world frame at the start, so it compares directly with the ground truth;
//! it is planar (x, y, yaw), as a wheel-odometry node publishes it.

/// Planar odometry state, integrated every physics step.
#[derive(Clone, Debug, PartialEq)]
pub struct Odometry {
    /// Track indices on the chassis's left (+y) side.
    left: Vec<usize>,
    /// Track indices on the chassis's right (-y) side.
    right: Vec<usize>,
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
    /// Odometry over the chassis tracks at lateral offsets `offsets` (m, `None` for tracks not
    /// on the chassis), with separation `separation` m, starting at (x, y, yaw).
    pub fn new(offsets: &[Option<f64>], separation: f64, x: f64, y: f64, yaw: f64) -> Self {
        let side = |pick: fn(f64) -> bool| -> Vec<usize> {
            offsets
                .iter()
                .enumerate()
                .filter_map(|(i, o)| o.filter(|&y| pick(y)).map(|_| i))
                .collect()
        };
        Odometry {
            left: side(|y| y > 0.0),
            right: side(|y| y < 0.0),
            separation,
            x,
            y,
            yaw,
        }
    }

    /// Default effective separation, m: the distance between the mean left and mean right
    /// mid-planes of the chassis tracks (0 if a side has none).
    pub fn geometric_separation(offsets: &[Option<f64>]) -> f64 {
        let mean = |pick: fn(f64) -> bool| {
            let v: Vec<f64> = offsets
                .iter()
                .flatten()
                .copied()
                .filter(|&y| pick(y))
                .collect();
            (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
        };
        match (mean(|y| y > 0.0), mean(|y| y < 0.0)) {
            (Some(l), Some(r)) => l - r,
            _ => 0.0,
        }
    }

    /// Forward speed (m/s) and yaw rate (rad/s) the encoders imply for belt speeds `belt` m/s.
    pub fn twist(&self, belt: &[f64]) -> (f64, f64) {
        self.twist_of(|i| belt[i])
    }

    /// [`Odometry::twist`] with track `i`'s belt speed given by `belt(i)`, m/s.
    fn twist_of(&self, belt: impl Fn(usize) -> f64) -> (f64, f64) {
        let mean = |ix: &[usize]| ix.iter().map(|&i| belt(i)).sum::<f64>() / ix.len() as f64;
        if self.left.is_empty() || self.right.is_empty() || self.separation <= 0.0 {
            return (0.0, 0.0);
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
}
