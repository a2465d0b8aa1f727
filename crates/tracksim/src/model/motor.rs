//! A track's drive motor (issue 14.1): a DC motor (stall torque and no-load speed: the linear
//! torque-speed line), a gearbox (ratio and efficiency) and the sprocket's pitch radius, behind
//! a speed controller with a torque limit, as real motor drivers are. The controller holds the
//! commanded belt speed while the motor can; the belt force it can deliver at belt speed `v` is
//! `F_max(v) = min(T_stall (1 - w / w_0), T_limit) G eta / r` with `w = d v G / r` the motor
//! speed in the direction `d` it drives (the sign of the command); beyond it the belt slows: the
//! belt speed becomes a result of the motor, the ground and the vehicle. Back-driven (`w < 0`,
//! e.g. sliding back down a slope) a DC motor gives more than its stall torque; the driver's
//! current limit (`T_limit`, else the stall torque) caps it. Held (a zero speed command) the
//! motor holds up to that limit too.
//!
//! The gearbox loses power in the direction the power flows (issue 23.5): motoring (belt force
//! and belt speed in one direction) the motor gives `T = F r / (G eta)` for a belt force `F`,
//! so the belt gets eta of the shaft power; back-driven (braking, holding) it sees only
//! `T = F r eta / G`, so at most eta of the belt's power reaches the motor, and a torque `T`
//! holds a belt force up to `T G / (eta r)` (the gear's friction helps).
//!
//! A measured torque-speed curve (`torque_speed`) can replace the line. With `voltage_v` and
//! `stall_current_a` (and `no_load_current_a`) the motor also has the DC motor's electrical
//! model, with one motor constant `k` (N m/A = V s/rad: torque per amp and back-EMF per rad/s
//! are the same constant, or the motor would create energy) and a resistance `R`, both taken
//! from the line and the supply: stall `T_stall = k (V / R - I_0)`, no load `V = I_0 R + k w_0`,
//! i.e. `T_stall w_0 R = (V - I_0 R)^2`. At torque `T` and speed `w` the current is
//! `I = T / k + I_0 sgn(w)`, the terminal voltage `u = I R + k w` and the electrical power `u I`
//! (negative when the motor brakes and the driver regenerates), and `u I - T w = I^2 R +
//! k I_0 |w|` is never negative. The stall current the file gives must agree with `V / R` within 10 % (a datasheet
//! whose torque constant exceeds its back-EMF constant, issue 23.5, is refused).

use crate::check::Checker;
use crate::spec::MotorSpec;

/// A drive motor command other than a speed set-point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MotorCommand {
    /// Duty cycle in [-1, 1]: the DC motor's torque-speed line scaled by it
    /// (`T = T_stall (d - w / w_0)`), towards the no-load speed times `d`.
    Duty(f64),
    /// Motor shaft torque, N m (signed: positive drives forwards), delivered within the
    /// torque-speed curve and the driver's limit.
    Torque(f64),
}

/// The DC motor's electrical constants, derived from its supply voltage, stall and no-load
/// currents and its torque-speed line.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MotorElectrics {
    /// Supply voltage, V.
    pub voltage: f64,
    /// No-load current, A.
    pub no_load_current: f64,
    /// Torque constant, N m / A.
    pub torque_constant: f64,
    /// Winding resistance, ohm.
    pub resistance: f64,
    /// Back-EMF constant, V s / rad.
    pub back_emf_constant: f64,
}

/// The motor's electrical state at one instant.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ElectricalState {
    /// Current, A (signed: positive drives the belt forwards).
    pub current: f64,
    /// Terminal voltage, V (signed).
    pub voltage: f64,
    /// Electrical power drawn from the supply, W (negative: regenerating).
    pub power: f64,
}

impl MotorElectrics {
    /// The electrical state at motor torque `torque` N m and motor speed `speed` rad/s (both
    /// signed in the belt's forward sense).
    pub fn state(&self, torque: f64, speed: f64) -> ElectricalState {
        let sign = if torque != 0.0 {
            torque.signum()
        } else if speed != 0.0 {
            speed.signum()
        } else {
            0.0
        };
        // The no-load current overcomes the motor's own friction, which opposes its motion:
        // it follows the speed (the torque only at standstill).
        let sign = if speed != 0.0 { speed.signum() } else { sign };
        let current = torque / self.torque_constant + self.no_load_current * sign;
        let voltage = current * self.resistance + self.back_emf_constant * speed;
        ElectricalState {
            current,
            voltage,
            power: voltage * current,
        }
    }
}

/// A compiled drive motor, SI units at the motor shaft unless said otherwise.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DriveMotor {
    /// Stall torque, N m (the curve's torque at speed 0).
    pub stall_torque: f64,
    /// No-load speed, rad/s (where the curve reaches 0).
    pub no_load_speed: f64,
    /// A measured torque-speed curve, `[speed rad/s, torque N m]` from 0 to the no-load speed
    /// (None: the straight line between the stall and no-load points).
    pub curve: Option<Vec<[f64; 2]>>,
    /// Gear ratio G (motor turns per sprocket turn).
    pub gear_ratio: f64,
    /// Gearbox efficiency eta, in (0, 1].
    pub efficiency: f64,
    /// Sprocket pitch radius r, m.
    pub sprocket_radius: f64,
    /// The driver's torque (current) limit, N m (None: the stall torque).
    pub torque_limit: Option<f64>,
    /// The electrical model (None: torques and mechanical power only).
    pub electrics: Option<MotorElectrics>,
}

impl DriveMotor {
    /// Motor shaft speed at belt speed `v` m/s, rad/s.
    pub fn motor_speed(&self, v: f64) -> f64 {
        v.abs() * self.gear_ratio / self.sprocket_radius
    }

    /// The torque-speed curve at motor speed `w` >= 0 rad/s, N m (0 from the no-load speed).
    pub fn curve_torque(&self, w: f64) -> f64 {
        let Some(pts) = &self.curve else {
            return self.stall_torque * (1.0 - w / self.no_load_speed);
        };
        if w <= 0.0 {
            return pts[0][1];
        }
        for p in pts.windows(2) {
            let ([w0, t0], [w1, t1]) = (p[0], p[1]);
            if w <= w1 {
                return t0 + (t1 - t0) * (w - w0) / (w1 - w0);
            }
        }
        0.0
    }

    /// Largest motor torque at belt speed `v` m/s when driving towards the command `cmd` m/s,
    /// N m: the torque-speed curve at the motor speed in the driving direction (the stall torque
    /// for a held belt), capped by the driver's limit (else the stall torque), never negative.
    pub fn max_motor_torque(&self, v: f64, cmd: f64) -> f64 {
        let w = cmd.signum() * v * self.gear_ratio / self.sprocket_radius;
        let w = if cmd == 0.0 { 0.0 } else { w };
        let limit = self.torque_limit.unwrap_or(self.stall_torque);
        if w < 0.0 {
            return limit;
        }
        self.curve_torque(w).clamp(0.0, limit)
    }

    /// Largest belt force at belt speed `v` m/s towards the command `cmd` m/s, N: motoring
    /// (the belt runs the command's way or stands) the torque-speed curve through the gear
    /// (`T G eta / r`); back-driven (the belt runs against the command) or held (`cmd` = 0)
    /// the driver's torque limit through the gear the other way (`T G / (eta r)`).
    pub fn max_belt_force(&self, v: f64, cmd: f64) -> f64 {
        let motoring = cmd != 0.0 && v * cmd >= 0.0;
        self.belt_force_of_torque(self.max_motor_torque(v, cmd), motoring)
    }

    /// Belt force that motor torque `torque` N m (>= 0) holds or drives, N: `T G eta / r`
    /// when motoring, `T G / (eta r)` when back-driven.
    pub fn belt_force_of_torque(&self, torque: f64, motoring: bool) -> f64 {
        let gear = if motoring {
            self.efficiency
        } else {
            1.0 / self.efficiency
        };
        torque * self.gear_ratio * gear / self.sprocket_radius
    }

    /// Belt speed at the motor's no-load speed, m/s.
    pub fn no_load_belt_speed(&self) -> f64 {
        self.no_load_speed * self.sprocket_radius / self.gear_ratio
    }

    /// The belt speed a duty or torque command drives towards, m/s: the no-load belt speed
    /// times the duty, or in the torque's direction.
    pub fn command_target(&self, cmd: MotorCommand) -> f64 {
        match cmd {
            MotorCommand::Duty(d) => d * self.no_load_belt_speed(),
            MotorCommand::Torque(t) => t.signum() * self.no_load_belt_speed(),
        }
    }

    /// Largest belt force, N, under a duty or torque command at belt speed `v` m/s: for a duty
    /// `d` the line scaled by it, `|T_stall (d - w / w_0)|` (it brakes above `d w_0`); for a
    /// torque `t` its magnitude within the torque-speed curve in its direction; both within the
    /// driver's limit.
    pub fn commanded_belt_force(&self, cmd: MotorCommand, v: f64) -> f64 {
        let limit = self.torque_limit.unwrap_or(self.stall_torque);
        let (torque, motoring) = match cmd {
            MotorCommand::Duty(d) => {
                let w = v * self.gear_ratio / self.sprocket_radius;
                let t = self.stall_torque * (d - w / self.no_load_speed);
                // Motoring while the torque pushes the way the belt runs (or starts it).
                (t.abs(), t * v > 0.0 || (v == 0.0 && t != 0.0))
            }
            MotorCommand::Torque(t) => (
                t.abs()
                    .min(self.max_motor_torque(v, self.command_target(cmd))),
                t * v >= 0.0,
            ),
        };
        self.belt_force_of_torque(torque.min(limit), motoring)
    }

    /// Motor torque at belt force `force` N and belt speed `v` m/s, N m: motoring (`F v > 0`,
    /// or standing) the gearbox losses on top (`F r / (G eta)`), back-driven (`F v < 0`) taken
    /// off (`F r eta / G`).
    pub fn motor_torque(&self, force: f64, v: f64) -> f64 {
        let gear = if force * v < 0.0 {
            self.efficiency
        } else {
            1.0 / self.efficiency
        };
        force * self.sprocket_radius * gear / self.gear_ratio
    }

    /// The electrical state delivering belt force `force` N at belt speed `v` m/s (None without
    /// the electrical model).
    pub fn electrical(&self, force: f64, v: f64) -> Option<ElectricalState> {
        let e = self.electrics?;
        Some(e.state(
            self.motor_torque(force, v),
            v * self.gear_ratio / self.sprocket_radius,
        ))
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
    let (stall, no_load, curve) = torque_curve(c, k, m)?;
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
    let electrics = electrics(c, k, m, stall, no_load, curve.is_some());
    let Some(r) = sprocket else {
        c.push(
            k.to_string(),
            "a motor needs the track's `sprocket_pitch_radius_m` (the radius its torque acts at)",
        );
        return None;
    };
    Some(DriveMotor {
        stall_torque: stall,
        no_load_speed: no_load,
        curve,
        gear_ratio: m.gear_ratio,
        efficiency: m.efficiency,
        sprocket_radius: r,
        torque_limit: m.torque_limit_nm,
        electrics,
    })
}

/// Points of a torque-speed curve, `[speed rad/s, torque N m]`.
type Curve = Vec<[f64; 2]>;

/// The torque-speed curve: the line of `stall_torque_nm` and `no_load_speed_rad_s`, or the
/// `torque_speed` points (from speed 0, speeds increasing, torques >= 0, ending at torque 0).
fn torque_curve(c: &mut Checker, k: &str, m: &MotorSpec) -> Option<(f64, f64, Option<Curve>)> {
    match (m.stall_torque_nm, m.no_load_speed_rad_s, &m.torque_speed) {
        (Some(t), Some(w), None) => {
            c.positive(&format!("{k}.stall_torque_nm"), t, "N m");
            c.positive(&format!("{k}.no_load_speed_rad_s"), w, "rad/s");
            Some((t, w, None))
        }
        (None, None, Some(pts)) => {
            let key = format!("{k}.torque_speed");
            let ok = pts.len() >= 2
                && pts[0][0] == 0.0
                && pts
                    .iter()
                    .all(|p| p[0].is_finite() && p[1].is_finite() && p[1] >= 0.0)
                && pts.windows(2).all(|p| p[1][0] > p[0][0])
                && pts[0][1] > 0.0
                && pts[pts.len() - 1][1] == 0.0;
            if !ok {
                c.push(
                    key,
                    "must be [speed rad/s, torque N m] points from speed 0 (torque > 0, the stall \
                     torque) with increasing speeds and torques >= 0, the last at torque 0 (the \
                     no-load speed), e.g. [[0, 1.2], [300, 0.9], [500, 0]]",
                );
                return None;
            }
            Some((pts[0][1], pts[pts.len() - 1][0], Some(pts.clone())))
        }
        _ => {
            c.push(
                k.to_string(),
                "give either `stall_torque_nm` and `no_load_speed_rad_s` (the DC motor's line) or \
                 `torque_speed` (a measured curve), not both",
            );
            None
        }
    }
}

/// The electrical model from `voltage_v`, `stall_current_a`, `no_load_current_a`.
fn electrics(
    c: &mut Checker,
    k: &str,
    m: &MotorSpec,
    stall: f64,
    no_load: f64,
    has_curve: bool,
) -> Option<MotorElectrics> {
    let (v, i_s) = match (m.voltage_v, m.stall_current_a) {
        (None, None) => {
            if m.no_load_current_a.is_some() {
                c.push(
                    format!("{k}.no_load_current_a"),
                    "needs `voltage_v` and `stall_current_a` (the electrical model)",
                );
            }
            return None;
        }
        (Some(v), Some(i)) => (v, i),
        _ => {
            c.push(
                k.to_string(),
                "the electrical model needs both `voltage_v` and `stall_current_a`",
            );
            return None;
        }
    };
    if has_curve {
        c.push(
            k.to_string(),
            "the electrical model is the DC motor's: give `stall_torque_nm` and \
             `no_load_speed_rad_s` rather than `torque_speed`",
        );
        return None;
    }
    c.positive(&format!("{k}.voltage_v"), v, "V");
    c.positive(&format!("{k}.stall_current_a"), i_s, "A");
    let i_0 = m.no_load_current_a.unwrap_or(0.0);
    if !(i_0.is_finite() && i_0 >= 0.0 && i_0 < i_s) {
        c.push(
            format!("{k}.no_load_current_a"),
            format!("must be >= 0 A and below the stall current {i_s} A, got {i_0}"),
        );
        return None;
    }
    // One motor constant for torque and back-EMF: R from T_s w_0 R = (V - I_0 R)^2 (the
    // smaller root, which tends to V^2 / (T_s w_0) as I_0 -> 0), then k = (V - I_0 R) / w_0.
    let b = 2.0 * v * i_0 + stall * no_load;
    let resistance = if i_0 > 0.0 {
        (b - (b * b - 4.0 * i_0 * i_0 * v * v).max(0.0).sqrt()) / (2.0 * i_0 * i_0)
    } else {
        v * v / (stall * no_load)
    };
    let k_m = (v - i_0 * resistance) / no_load;
    let i_stall = v / resistance;
    if (i_s - i_stall).abs() > 0.1 * i_stall {
        c.push(
            format!("{k}.stall_current_a"),
            format!(
                "a DC motor of {stall} N m stall torque and {no_load} rad/s no-load speed at {v} V \
                 (no-load current {i_0} A) draws {i_stall:.3} A at stall; got {i_s} A, more than \
                 10 % off (its torque per amp and back-EMF per rad/s would differ and the motor \
                 would create energy): give {i_stall:.3} A or check the datasheet"
            ),
        );
        return None;
    }
    Some(MotorElectrics {
        voltage: v,
        no_load_current: i_0,
        torque_constant: k_m,
        resistance,
        back_emf_constant: k_m,
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
            ..Default::default()
        };
        // At rest: the driver's limit 0.8 N m -> 0.8 * 10 * 0.5 / 0.1 = 40 N.
        assert!((m.max_belt_force(0.0, 0.3) - 40.0).abs() < 1e-12);
        // 0.5 m/s in the driving direction (either way): 50 rad/s, the line gives 0.5 N m -> 25 N.
        assert!((m.max_belt_force(0.5, 0.6) - 25.0).abs() < 1e-12);
        assert!((m.max_belt_force(-0.5, -0.6) - 25.0).abs() < 1e-12);
        // Back-driven (moving against the command): the driver's limit, the gear's friction
        // helping: 0.8 * 10 / (0.5 * 0.1) = 160 N.
        assert!((m.max_belt_force(-0.5, 0.6) - 160.0).abs() < 1e-12);
        // Held belt: the limit both ways.
        assert!((m.max_belt_force(0.2, 0.0) - 160.0).abs() < 1e-12);
        assert!((m.max_belt_force(0.0, 0.0) - 160.0).abs() < 1e-12);
        // At and past the no-load speed (1 m/s): nothing.
        assert_eq!(m.max_belt_force(1.0, 1.0), 0.0);
        assert_eq!(m.max_belt_force(2.0, 1.0), 0.0);
        // Motoring: the gear's losses on top; braking: taken off.
        assert!((m.motor_torque(25.0, 0.5) - 0.5).abs() < 1e-12);
        assert!((m.motor_torque(-25.0, 0.5) + 0.125).abs() < 1e-12);
    }

    /// The motor and its gearbox create no energy (issue 23.5): motoring, the supply gives at
    /// least the belt's power; braking, it gets back at most eta of what the belt absorbs; a
    /// back-driven gear passes at most eta of the power to the motor shaft.
    #[test]
    fn electrical_power_bounds_the_belt_power_both_ways() {
        for (stall, w0, v_s, i_s, i_0, eta) in [
            (0.07, 600.0, 24.0, 2.04, 0.15, 0.8), // packbot510_motors
            (0.07, 600.0, 24.0, 2.04, 0.15, 0.5),
            (2.0, 400.0, 24.0, 34.0, 0.5, 0.9),
        ] {
            let spec = MotorSpec {
                stall_torque_nm: Some(stall),
                no_load_speed_rad_s: Some(w0),
                torque_speed: None,
                gear_ratio: 50.0,
                efficiency: eta,
                torque_limit_nm: None,
                voltage_v: Some(v_s),
                stall_current_a: Some(i_s),
                no_load_current_a: Some(i_0),
            };
            let mut c = Checker::default();
            let m = compile_motor(&mut c, "m", &spec, Some(0.082)).unwrap();
            let v_max = m.no_load_belt_speed();
            for i in -10..=10 {
                let v = v_max * i as f64 / 10.0;
                // Motoring within the torque-speed line (the supply's voltage reaches no
                // further), braking up to the stall torque.
                let w = v.abs() * m.gear_ratio / m.sprocket_radius;
                let line = m.curve_torque(w).max(0.0);
                for j in -10..=10 {
                    let t = if j > 0 { line } else { stall } * j as f64 / 10.0;
                    let force = m.belt_force_of_torque(t.abs(), j > 0) * t.signum() * v.signum();
                    let belt = force * v;
                    let shaft = m.motor_torque(force, v) * v * m.gear_ratio / m.sprocket_radius;
                    let e = m.electrical(force, v).unwrap();
                    if belt > 0.0 {
                        assert!(shaft >= belt - 1e-9, "{shaft} < {belt}");
                        assert!(e.power >= belt - 1e-9, "motoring {} < {belt}", e.power);
                    } else if belt < 0.0 {
                        assert!(-shaft <= eta * -belt + 1e-9, "{shaft} vs {belt}");
                        assert!(-e.power <= eta * -belt + 1e-9, "regen {} > {belt}", e.power);
                    }
                }
            }
        }
    }

    #[test]
    fn a_measured_curve_is_interpolated_and_ends_at_the_no_load_speed() {
        let m = DriveMotor {
            stall_torque: 1.2,
            no_load_speed: 500.0,
            curve: Some(vec![[0.0, 1.2], [300.0, 0.9], [500.0, 0.0]]),
            gear_ratio: 1.0,
            efficiency: 1.0,
            sprocket_radius: 1.0,
            ..Default::default()
        };
        assert!((m.curve_torque(150.0) - 1.05).abs() < 1e-12);
        assert!((m.curve_torque(400.0) - 0.45).abs() < 1e-12);
        assert_eq!(m.curve_torque(600.0), 0.0);
        assert!((m.max_motor_torque(0.0, 1.0) - 1.2).abs() < 1e-12);
    }

    #[test]
    fn the_electrical_model_passes_through_the_datasheet_points() {
        // 24 V, stall 2 N m, no load 400 rad/s at 0.5 A: R from 800 R = (24 - 0.5 R)^2,
        // 0.69918 ohm, stall current 34.326 A.
        let spec = MotorSpec {
            stall_torque_nm: Some(2.0),
            no_load_speed_rad_s: Some(400.0),
            torque_speed: None,
            gear_ratio: 1.0,
            efficiency: 1.0,
            torque_limit_nm: None,
            voltage_v: Some(24.0),
            stall_current_a: Some(34.0),
            no_load_current_a: Some(0.5),
        };
        let mut c = Checker::default();
        let m = compile_motor(&mut c, "tracks[0].motor", &spec, Some(1.0)).unwrap();
        assert!(c.issues.is_empty());
        let e = m.electrics.unwrap();
        assert_eq!(e.torque_constant, e.back_emf_constant);
        let stall = e.state(2.0, 0.0);
        assert!((stall.voltage - 24.0).abs() < 1e-9, "{stall:?}");
        assert!((stall.current - 24.0 / e.resistance).abs() < 1e-9);
        let free = e.state(0.0, 400.0);
        assert!((free.current - 0.5).abs() < 1e-9 && (free.voltage - 24.0).abs() < 1e-9);
        // Half way along the line (1 N m at 200 rad/s) it still runs at the supply voltage.
        let mid = e.state(1.0, 200.0);
        assert!((mid.voltage - 24.0).abs() < 1e-9, "{mid:?}");
        // A stall current far from the one the line and the supply imply is refused.
        let bad = MotorSpec {
            stall_current_a: Some(20.0),
            ..spec
        };
        let mut c = Checker::default();
        let _ = compile_motor(&mut c, "tracks[0].motor", &bad, Some(1.0));
        assert_eq!(c.issues.len(), 1, "{:?}", c.issues);
        assert!(
            c.issues[0]
                .to_string()
                .contains("tracks[0].motor.stall_current_a")
        );
        assert!(
            c.issues[0].to_string().contains("34.326 A"),
            "{:?}",
            c.issues
        );
    }
}
