//! A track's drive motor (issue 14.1): a DC motor (stall torque and no-load speed: the linear
//! torque-speed line), a gearbox (ratio and efficiency) and the sprocket's pitch radius, behind
//! a speed controller with a torque limit, as real motor drivers are. The controller holds the
//! commanded belt speed while the motor can; the belt force it can deliver at belt speed `v` is
//! `F_max(v) = min(T_stall (1 - w / w_0), T_limit) G eta / r` with `w = d v G / r` the motor
//! speed in the direction `d` it drives (the sign of the command); beyond it the belt slows: the
//! belt speed becomes a result of the motor, the ground and the vehicle. Back-driven (`w < 0`,
//! e.g. sliding back down a slope) a DC motor gives more than its stall torque; the driver's
//! current limit (`T_limit`, else the stall torque) caps it.

use crate::check::Checker;
use crate::spec::MotorSpec;

/// A compiled drive motor, SI units at the motor shaft unless said otherwise.
#[derive(Clone, Debug, PartialEq)]
pub struct DriveMotor {
    /// Stall torque, N m.
    pub stall_torque: f64,
    /// No-load speed, rad/s.
    pub no_load_speed: f64,
    /// Gear ratio G (motor turns per sprocket turn).
    pub gear_ratio: f64,
    /// Gearbox efficiency eta, in (0, 1].
    pub efficiency: f64,
    /// Sprocket pitch radius r, m.
    pub sprocket_radius: f64,
    /// The driver's torque (current) limit, N m (None: the stall torque).
    pub torque_limit: Option<f64>,
}

impl DriveMotor {
    /// Motor shaft speed at belt speed `v` m/s, rad/s.
    pub fn motor_speed(&self, v: f64) -> f64 {
        v.abs() * self.gear_ratio / self.sprocket_radius
    }

    /// Largest motor torque at belt speed `v` m/s when driving towards the command `cmd` m/s,
    /// N m: the torque-speed line at the motor speed in the driving direction (the stall torque
    /// for a held belt), capped by the driver's limit (else the stall torque), never negative.
    pub fn max_motor_torque(&self, v: f64, cmd: f64) -> f64 {
        let w = cmd.signum() * v * self.gear_ratio / self.sprocket_radius;
        let w = if cmd == 0.0 { 0.0 } else { w };
        let line = self.stall_torque * (1.0 - w / self.no_load_speed);
        line.clamp(0.0, self.torque_limit.unwrap_or(self.stall_torque))
    }

    /// Largest belt force at belt speed `v` m/s towards the command `cmd` m/s, N.
    pub fn max_belt_force(&self, v: f64, cmd: f64) -> f64 {
        self.max_motor_torque(v, cmd) * self.gear_ratio * self.efficiency / self.sprocket_radius
    }

    /// Motor torque that delivers belt force `force` N, N m.
    pub fn motor_torque(&self, force: f64) -> f64 {
        force * self.sprocket_radius / (self.gear_ratio * self.efficiency)
    }
}

/// Checks and compiles `[tracks.motor]` at key `k`; `sprocket` is the track's
/// `sprocket_pitch_radius_m`.
pub(crate) fn compile_motor(
    c: &mut Checker,
    k: &str,
    m: &MotorSpec,
    sprocket: Option<f64>,
) -> Option<DriveMotor> {
    c.positive(&format!("{k}.stall_torque_nm"), m.stall_torque_nm, "N m");
    c.positive(
        &format!("{k}.no_load_speed_rad_s"),
        m.no_load_speed_rad_s,
        "rad/s",
    );
    c.positive(&format!("{k}.gear_ratio"), m.gear_ratio, "");
    if !(m.efficiency.is_finite() && m.efficiency > 0.0 && m.efficiency <= 1.0) {
        c.push(
            format!("{k}.efficiency"),
            format!("must be in (0, 1], got {}", m.efficiency),
        );
    }
    if let Some(l) = m.torque_limit_nm {
        c.positive(&format!("{k}.torque_limit_nm"), l, "N m");
    }
    let Some(r) = sprocket else {
        c.push(
            k.to_string(),
            "a motor needs the track's `sprocket_pitch_radius_m` (the radius its torque acts at)",
        );
        return None;
    };
    Some(DriveMotor {
        stall_torque: m.stall_torque_nm,
        no_load_speed: m.no_load_speed_rad_s,
        gear_ratio: m.gear_ratio,
        efficiency: m.efficiency,
        sprocket_radius: r,
        torque_limit: m.torque_limit_nm,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn torque_speed_line_and_limit() {
        let m = DriveMotor {
            stall_torque: 1.0,
            no_load_speed: 100.0,
            gear_ratio: 10.0,
            efficiency: 0.5,
            sprocket_radius: 0.1,
            torque_limit: Some(0.8),
        };
        // At rest: the driver's limit 0.8 N m -> 0.8 * 10 * 0.5 / 0.1 = 40 N.
        assert!((m.max_belt_force(0.0, 0.3) - 40.0).abs() < 1e-12);
        // 0.5 m/s in the driving direction (either way): 50 rad/s, the line gives 0.5 N m -> 25 N.
        assert!((m.max_belt_force(0.5, 0.6) - 25.0).abs() < 1e-12);
        assert!((m.max_belt_force(-0.5, -0.6) - 25.0).abs() < 1e-12);
        // Back-driven (moving against the command): the driver's limit.
        assert!((m.max_belt_force(-0.5, 0.6) - 40.0).abs() < 1e-12);
        // Held belt: the limit both ways.
        assert!((m.max_belt_force(0.2, 0.0) - 40.0).abs() < 1e-12);
        // At and past the no-load speed (1 m/s): nothing.
        assert_eq!(m.max_belt_force(1.0, 1.0), 0.0);
        assert_eq!(m.max_belt_force(2.0, 1.0), 0.0);
        assert!((m.motor_torque(25.0) - 0.5).abs() < 1e-12);
    }
}
