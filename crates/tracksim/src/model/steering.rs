//! How a twist command (forward speed, yaw rate) becomes belt speeds ([`Steering`],
//! `[steering]` of a vehicle file): per track, each belt at `v - w y` for its own mid-plane at
//! lateral offset `y` (tracksim's default), or per side as Gazebo's `TrackedVehicle` does,
//! every track on a side at one speed `v -+ w B / 2` (the default when a URDF or SDF plugin
//! names the sides), so a flipper track and the main track of one side never fight.

/// Tracks closer than this to the chassis' mid-plane (m) belong to neither side.
pub const SIDE_EPSILON_M: f64 = 1e-6;

/// Which side of the chassis a track at lateral offset `y` m rides on: +1 left (+y), -1
/// right, 0 on the mid-plane.
pub fn side_of(y: f64) -> f64 {
    if y > SIDE_EPSILON_M {
        1.0
    } else if y < -SIDE_EPSILON_M {
        -1.0
    } else {
        0.0
    }
}

/// The twist-to-belts rule of a vehicle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Steering {
    /// One speed per side (Gazebo's rule) instead of one per track.
    pub per_side: bool,
    /// The separation B of the sides' speeds in the per-side rule, m (unused per track).
    pub separation: f64,
}

impl Steering {
    /// Each belt at `v - w y` (the default).
    pub const PER_TRACK: Steering = Steering {
        per_side: false,
        separation: 0.0,
    };

    /// The belt speed, m/s, of a track at lateral offset `y` m (chassis frame) for forward
    /// speed `forward` m/s and yaw rate `yaw_rate` rad/s (REP 103, positive left).
    pub fn belt_speed(&self, y: f64, forward: f64, yaw_rate: f64) -> f64 {
        if self.per_side {
            forward - yaw_rate * side_of(y) * 0.5 * self.separation
        } else {
            forward - yaw_rate * y
        }
    }
}

/// The distance between the mean left and mean right mid-planes of tracks at lateral offsets
/// `offsets` m (0 if a side has none).
pub fn side_separation(offsets: &[f64]) -> f64 {
    let mean = |s: f64| {
        let v: Vec<f64> = offsets
            .iter()
            .copied()
            .filter(|&y| side_of(y) == s)
            .collect();
        (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
    };
    match (mean(1.0), mean(-1.0)) {
        (Some(l), Some(r)) => l - r,
        _ => 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn per_side_gives_every_track_of_a_side_one_speed() {
        let s = Steering {
            per_side: true,
            separation: 0.4,
        };
        // A spin at 0.5 rad/s: every left track at -0.1 m/s, every right one at +0.1.
        for y in [0.2, 0.3, 0.05] {
            assert!((s.belt_speed(y, 0.0, 0.5) + 0.1).abs() < 1e-12);
            assert!((s.belt_speed(-y, 0.0, 0.5) - 0.1).abs() < 1e-12);
        }
        assert_eq!(s.belt_speed(0.0, 0.3, 0.5), 0.3);
        let t = Steering::PER_TRACK;
        assert!((t.belt_speed(0.3, 0.0, 0.5) + 0.15).abs() < 1e-12);
        assert!((side_separation(&[0.2, 0.3, -0.2, -0.3, 0.0]) - 0.5).abs() < 1e-12);
        assert_eq!(side_separation(&[0.2]), 0.0);
    }
}
