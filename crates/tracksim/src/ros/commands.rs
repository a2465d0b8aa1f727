//! The commands in force: what the subscriptions delivered (already sanitised), turned into
//! the vehicle's [`Controls`] at each sample boundary, and the watchdog that stops a robot
//! whose commands went silent.
//!
//! - `/cmd_vel` sets every track's belt speed by skid steering (`v - w y` for the track's
//!   lateral offset `y`, [`Controls::twist`]); a per-track speed command then sets that track
//!   alone, until the next `/cmd_vel`.
//! - Watchdog: a track whose last speed command (either kind) is older than
//!   [`WATCHDOG_TIMEOUT_S`] of simulated time is commanded 0 m/s, as ROS base controllers do
//!   (`cmd_vel_timeout`). Flipper targets are positions and hold until changed.

use crate::model::{Controls, VehicleModel};

/// How long a belt speed command holds without a new one, s of simulated time (the node's
/// clock: `/clock`); then the track is commanded to stop.
pub const WATCHDOG_TIMEOUT_S: f64 = 0.5;

/// A command, sanitised ([`super::sanitize`]).
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// `/cmd_vel`: forward speed m/s and yaw rate rad/s.
    Twist {
        /// Forward speed, m/s.
        forward_mps: f64,
        /// Yaw rate, rad/s (positive turns left).
        yaw_rate_rad_s: f64,
    },
    /// One track's belt speed, m/s.
    BeltSpeed {
        /// Track index.
        track: usize,
        /// Belt speed, m/s.
        mps: f64,
    },
    /// One flipper's target angle, rad.
    Flipper {
        /// Flipper index.
        flipper: usize,
        /// Target, rad.
        rad: f64,
    },
}

/// The set-points in force and when each belt's was last commanded.
#[derive(Clone, Debug)]
pub struct CommandState {
    /// Belt speed per track, m/s, and the simulated time it was commanded at, s.
    belts: Vec<(f64, f64)>,
    /// Flipper target per flipper, rad (`None`: not commanded yet).
    flippers: Vec<Option<f64>>,
    /// Whether the watchdog has stopped each track (reported once per silence).
    stopped: Vec<bool>,
    /// The controls last handed to the physics (belt speeds, flipper targets).
    applied: Option<(Vec<f64>, Vec<Option<f64>>)>,
}

impl CommandState {
    /// Nothing commanded: every belt at rest, flippers where the vehicle file puts them.
    pub fn new(v: &VehicleModel) -> Self {
        CommandState {
            belts: vec![(0.0, f64::NEG_INFINITY); v.tracks.len()],
            flippers: vec![None; v.flippers.len()],
            stopped: vec![true; v.tracks.len()],
            applied: None,
        }
    }

    /// Takes in command `c` received at simulated time `t` s.
    pub fn take(&mut self, v: &VehicleModel, c: &Command, t: f64) {
        match *c {
            Command::Twist {
                forward_mps,
                yaw_rate_rad_s,
            } => {
                let tw = Controls::twist(v, forward_mps, yaw_rate_rad_s);
                for (b, s) in self.belts.iter_mut().zip(tw.belt_speed) {
                    *b = (s.unwrap_or(0.0), t);
                }
                self.stopped.iter_mut().for_each(|s| *s = false);
            }
            Command::BeltSpeed { track, mps } => {
                if let Some(b) = self.belts.get_mut(track) {
                    *b = (mps, t);
                    self.stopped[track] = false;
                }
            }
            Command::Flipper { flipper, rad } => {
                if let Some(f) = self.flippers.get_mut(flipper) {
                    *f = Some(rad);
                }
            }
        }
    }

    /// Applies the watchdog at simulated time `t` s: tracks silent for longer than
    /// [`WATCHDOG_TIMEOUT_S`] are set to 0 m/s. Returns the tracks it stopped just now.
    pub fn watchdog(&mut self, t: f64) -> Vec<usize> {
        let mut now_stopped = Vec::new();
        for (i, b) in self.belts.iter_mut().enumerate() {
            if t - b.1 > WATCHDOG_TIMEOUT_S && !self.stopped[i] {
                b.0 = 0.0;
                self.stopped[i] = true;
                now_stopped.push(i);
            }
        }
        now_stopped
    }

    /// Belt speed set-points, m/s, by track.
    pub fn belt_speeds(&self) -> Vec<f64> {
        self.belts.iter().map(|b| b.0).collect()
    }

    /// Flipper targets, rad, by flipper (`None`: not commanded).
    pub fn flipper_targets(&self) -> &[Option<f64>] {
        &self.flippers
    }

    /// The controls to apply now, if they differ from the last ones applied (then they count
    /// as applied).
    pub fn changed_controls(&mut self, v: &VehicleModel) -> Option<Controls> {
        let now = (self.belt_speeds(), self.flippers.clone());
        if self.applied.as_ref() == Some(&now) {
            return None;
        }
        let c = Controls {
            belt_speed: now.0.iter().map(|s| Some(*s)).collect(),
            flipper_angle: now.1.clone(),
            ..Controls::keep(v)
        };
        self.applied = Some(now);
        Some(c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vehicle() -> VehicleModel {
        let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenarios/packbot_stairs.toml");
        crate::load_scenario(&p).unwrap().vehicle.clone()
    }

    #[test]
    fn cmd_vel_sets_every_belt_and_a_track_command_one() {
        let v = vehicle();
        let mut s = CommandState::new(&v);
        s.take(
            &v,
            &Command::Twist {
                forward_mps: 0.4,
                yaw_rate_rad_s: 1.0,
            },
            0.0,
        );
        let want: Vec<f64> = v.tracks.iter().map(|t| 0.4 - t.lateral_offset()).collect();
        assert_eq!(s.belt_speeds(), want);
        s.take(
            &v,
            &Command::BeltSpeed {
                track: 0,
                mps: -0.1,
            },
            0.1,
        );
        assert_eq!(s.belt_speeds()[0], -0.1);
        assert_eq!(s.belt_speeds()[1..], want[1..]);
        let c = s.changed_controls(&v).unwrap();
        assert_eq!(c.belt_speed[0], Some(-0.1));
        assert!(
            s.changed_controls(&v).is_none(),
            "unchanged: nothing to apply"
        );
        s.take(
            &v,
            &Command::Flipper {
                flipper: 0,
                rad: 0.3,
            },
            0.2,
        );
        assert_eq!(s.changed_controls(&v).unwrap().flipper_angle[0], Some(0.3));
    }

    #[test]
    fn the_watchdog_stops_silent_tracks_once() {
        let v = vehicle();
        let mut s = CommandState::new(&v);
        assert!(
            s.watchdog(10.0).is_empty(),
            "never commanded: nothing to stop"
        );
        let go = Command::Twist {
            forward_mps: 0.3,
            yaw_rate_rad_s: 0.0,
        };
        s.take(&v, &go, 1.0);
        assert!(s.watchdog(1.0 + WATCHDOG_TIMEOUT_S - 0.01).is_empty());
        assert!(s.belt_speeds().iter().all(|&b| b == 0.3));
        let stopped = s.watchdog(1.0 + WATCHDOG_TIMEOUT_S + 0.01);
        assert_eq!(stopped.len(), v.tracks.len());
        assert!(s.belt_speeds().iter().all(|&b| b == 0.0));
        assert!(s.watchdog(5.0).is_empty(), "reported once");
        s.take(&v, &Command::BeltSpeed { track: 1, mps: 0.2 }, 5.0);
        assert_eq!(s.watchdog(5.0 + WATCHDOG_TIMEOUT_S + 0.01), vec![1]);
    }
}
