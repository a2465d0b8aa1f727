//! The inputs of one step ([`Controls`]) and a scenario file's timed [`Command`]s, by track and
//! flipper index.

use super::VehicleModel;
use super::motor::MotorCommand;
use crate::error::{Error, Result, SpecIssue};

/// Checks that `values` holds one finite number per name of `names` (`key` names the array in
/// the message, `unit` its unit).
fn one_each(what: &str, key: &str, values: &[f64], names: &[&str], unit: &str) -> Result<()> {
    let mut issues = Vec::new();
    if values.len() != names.len() {
        let per = if key == "belt_speeds" {
            "track"
        } else {
            "flipper"
        };
        issues.push(SpecIssue::new(
            key,
            format!(
                "expected {} {} (one per {per}: {}), got {}",
                names.len(),
                key.replace('_', " "),
                names.join(", "),
                values.len()
            ),
        ));
    }
    for (i, v) in values.iter().enumerate() {
        if !v.is_finite() {
            issues.push(SpecIssue::new(
                format!("{key}[{i}]"),
                format!("must be a finite number of {unit}, got {v}"),
            ));
        }
    }
    if issues.is_empty() {
        Ok(())
    } else {
        Err(Error::Settings {
            what: what.into(),
            issues,
        })
    }
}

/// The inputs of one step, by track and flipper index (a controller's output, or one entry of a
/// file's `[[commands]]`); `None` keeps the previous value.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Controls {
    /// Belt speed per track index, m/s (positive drives forwards).
    pub belt_speed: Vec<Option<f64>>,
    /// Flipper target angle per flipper index, rad.
    pub flipper_angle: Vec<Option<f64>>,
    /// A duty or torque command per track index (tracks with a drive motor); replaces the
    /// track's belt speed set-point until a belt speed is given again. May be empty.
    pub motor: Vec<Option<MotorCommand>>,
    /// Faults set or cleared (a command's `fault` table; issue 43), applied before the rest.
    pub faults: super::Faults,
    /// Put the robot back at its start first (a command's `reset = true`; issue 43). The run
    /// layer does it (`Simulation::reset_robot`, which can fail); [`Controls`] applied to a
    /// `Simulation` directly do not.
    pub reset: bool,
}

impl Controls {
    /// Controls that change nothing, sized for `v`.
    pub fn keep(v: &VehicleModel) -> Self {
        Controls {
            belt_speed: vec![None; v.tracks.len()],
            flipper_angle: vec![None; v.flippers.len()],
            motor: vec![None; v.tracks.len()],
            faults: super::Faults::default(),
            reset: false,
        }
    }

    /// Every belt at `speed` m/s.
    pub fn belts(v: &VehicleModel, speed: f64) -> Self {
        Controls {
            belt_speed: vec![Some(speed); v.tracks.len()],
            ..Controls::keep(v)
        }
    }

    /// Body-level skid steering without slip: forward speed `forward` m/s and yaw rate
    /// `yaw_rate` rad/s (REP 103, positive turns left) about the body origin; each belt runs at
    /// `forward - yaw_rate * y` for its track's mid-plane at lateral offset `y` m, or, with
    /// one speed per side ([`super::Steering`]), at `forward -+ yaw_rate * B / 2`.
    pub fn twist(v: &VehicleModel, forward: f64, yaw_rate: f64) -> Self {
        Controls {
            belt_speed: (0..v.tracks.len())
                .map(|i| Some(v.twist_belt_speed(i, forward, yaw_rate)))
                .collect(),
            ..Controls::keep(v)
        }
    }

    /// Every belt at its own speed, m/s: `speeds` holds one finite number per track of `v`, in
    /// track order (key `belt_speeds` in the refusal).
    pub fn belt_speeds(v: &VehicleModel, speeds: &[f64]) -> Result<Self> {
        let names: Vec<&str> = v.tracks.iter().map(|t| t.name.as_str()).collect();
        one_each("set_belt_speeds", "belt_speeds", speeds, &names, "m/s")?;
        Ok(Controls {
            belt_speed: speeds.iter().map(|s| Some(*s)).collect(),
            ..Controls::keep(v)
        })
    }

    /// Every flipper to its own target angle, rad: `angles` holds one finite number per
    /// flipper of `v`, in flipper order (key `flipper_angles` in the refusal).
    pub fn flipper_angles(v: &VehicleModel, angles: &[f64]) -> Result<Self> {
        let names: Vec<&str> = v.flippers.iter().map(|f| f.name.as_str()).collect();
        one_each(
            "set_flipper_angles",
            "flipper_angles",
            angles,
            &names,
            "rad",
        )?;
        Ok(Controls {
            flipper_angle: angles.iter().map(|a| Some(*a)).collect(),
            ..Controls::keep(v)
        })
    }

    /// Sets flipper `i`'s target angle, rad.
    pub fn with_flipper(mut self, i: usize, angle: f64) -> Self {
        if let Some(a) = self.flipper_angle.get_mut(i) {
            *a = Some(angle);
        }
        self
    }
}

/// One timed command of a scenario file, resolved to track and flipper indices.
#[derive(Clone, Debug, PartialEq)]
pub struct Command {
    /// Start time, s.
    pub t: f64,
    /// What it sets.
    pub controls: Controls,
}
