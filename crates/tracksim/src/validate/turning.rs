//! Skid steering: PackBot 510 spinning on the spot (`turning/spin`) and driving straight
//! (`turning/straight`) on flat ground.

use super::compile::compile;
use super::jobs::{Jobs, Ran, Runs, pose_at};
use super::limits::{PACKBOT_SPEED_MPS, STRAIGHT_SLIP_LIMIT, TURN_RATIO_BAND};
use super::options::SolverSetting;
use super::report::{Case, PlotJob, ValidationReport};
use crate::error::Result;
use crate::geometry::Segment;
use crate::model::Method as TrackMethod;
use crate::model::{Scenario, VehicleModel};
use crate::run::RunResult;
use std::path::Path;

const TURN_SETTLE_S: f64 = 2.0;
const TURN_DURATION_S: f64 = 6.0;

/// Case name of the spin on the spot (belts at +-v).
const SPIN: &str = "turning/spin";
/// Case name of the straight line (both belts at +v).
const STRAIGHT: &str = "turning/straight";

/// Adds the spin and the straight line.
pub(super) fn add_jobs(
    jobs: &mut Jobs,
    packbot: &VehicleModel,
    method: TrackMethod,
    root: &Path,
    setting: SolverSetting,
) -> Result<()> {
    let flat = |v| flat_scenario(packbot, method, root, TURN_DURATION_S, v, setting);
    jobs.add(SPIN, flat(-PACKBOT_SPEED_MPS)?)?;
    jobs.add(STRAIGHT, flat(PACKBOT_SPEED_MPS)?)
}

/// Adds the spin and straight-line cases (and their plots) to `report`.
pub(super) fn assemble(
    report: &mut ValidationReport,
    runs: &mut Runs,
    packbot: &VehicleModel,
    method: TrackMethod,
) {
    for (case, plot) in [
        spin_case(runs.take(SPIN), packbot, method),
        straight_case(runs.take(STRAIGHT), method),
    ] {
        report.cases.push(case);
        report.plots.extend(plot);
    }
}

/// The spin on the spot: yaw rate against the no-slip 2v/B and the Coulomb estimate.
fn spin_case(ran: Ran, packbot: &VehicleModel, method: TrackMethod) -> (Case, Option<PlotJob>) {
    let name = "PackBot spin (belts +-v)";
    let r = match ran.result {
        Ok(r) => r,
        Err(e) => return (Case::error("turning", name, SPIN, &e), None),
    };
    let gauge = track_gauge(packbot);
    let patch = contact_length(packbot);
    let w0 = 2.0 * PACKBOT_SPEED_MPS / gauge;
    let theory = spin_ratio_coulomb(gauge / 2.0, patch / 2.0);
    let y1 = unwrapped_yaw_at(&r, TURN_SETTLE_S);
    let y2 = unwrapped_yaw_at(&r, TURN_DURATION_S);
    let w = (y2 - y1) / (TURN_DURATION_S - TURN_SETTLE_S);
    let ratio = w / w0;
    let case = Case {
        group: "turning".into(),
        name: name.into(),
        runs: vec![SPIN.into()],
        outcome: r.outcome.name().into(),
        measured: format!("yaw rate {w:.3} rad/s = {ratio:.2} x no-slip"),
        expected: format!(
            "ratio in [{:.1}, {:.1}]; Coulomb estimate {theory:.2} (no-slip 2v/B = {w0:.3} rad/s)",
            TURN_RATIO_BAND.0, TURN_RATIO_BAND.1
        ),
        passed: ratio >= TURN_RATIO_BAND.0 && ratio <= TURN_RATIO_BAND.1,
        note: format!(
            "Left belt -{v} m/s, right +{v} m/s on flat ground (friction 0.6), track gauge B = {gauge:.3} m; mean yaw rate from {TURN_SETTLE_S:.0} s to {TURN_DURATION_S:.0} s. A skid-steered vehicle must slide its tracks sideways to turn, so the yaw rate is below the no-slip 2v/B (ratio < 1). For uniform ground pressure and isotropic Coulomb friction on a rigid floor, the moment balance over the two {patch:.2} m contact patches gives a ratio of {theory:.2} (independent of mu); the band 0.3..1.0 accepts the pressure distributions the grousers and pulleys actually make (end-loaded patches turn more easily, centre-loaded less) while rejecting a vehicle that turns without slipping (> 1 is impossible) or barely turns.",
            v = PACKBOT_SPEED_MPS
        ),
        plot: "turning_spin".into(),
    };
    let plot = PlotJob::bare(
        "turning_spin",
        format!("PackBot 510 spinning on the spot: {ratio:.2} x the no-slip yaw rate"),
        vec![(method.name(), r)],
    );
    (case, Some(plot))
}

/// The straight line: longitudinal slip 1 - v_body / v_belt.
fn straight_case(ran: Ran, method: TrackMethod) -> (Case, Option<PlotJob>) {
    let name = "PackBot straight-line slip";
    let r = match ran.result {
        Ok(r) => r,
        Err(e) => return (Case::error("turning", name, STRAIGHT, &e), None),
    };
    let p1 = pose_at(&r, TURN_SETTLE_S);
    let p2 = pose_at(&r, TURN_DURATION_S);
    let v =
        ((p2.x - p1.x).powi(2) + (p2.y - p1.y).powi(2)).sqrt() / (TURN_DURATION_S - TURN_SETTLE_S);
    let slip = 1.0 - v / PACKBOT_SPEED_MPS;
    let case = Case {
        group: "turning".into(),
        name: name.into(),
        runs: vec![STRAIGHT.into()],
        outcome: r.outcome.name().into(),
        measured: format!("v_body {v:.4} m/s, slip {:+.2} %", slip * 100.0),
        expected: format!("abs(slip) < {:.0} %", STRAIGHT_SLIP_LIMIT * 100.0),
        passed: slip.abs() < STRAIGHT_SLIP_LIMIT,
        note: format!(
            "Both belts at {PACKBOT_SPEED_MPS} m/s on flat ground (friction 0.6); body speed from {TURN_SETTLE_S:.0} s to {TURN_DURATION_S:.0} s. On level ground the only resistance is the solver's rolling losses, far below the friction limit, so the belts should not slip."
        ),
        plot: "turning_straight".into(),
    };
    let plot = PlotJob::bare(
        "turning_straight",
        format!("PackBot 510 driving straight: slip {:+.2} %", slip * 100.0),
        vec![(method.name(), r)],
    );
    (case, Some(plot))
}

/// PackBot 510 on flat ground (friction 0.6): right belts at `PACKBOT_SPEED_MPS`, left
/// belts at `left` m/s.
fn flat_scenario(
    packbot: &VehicleModel,
    method: TrackMethod,
    root: &Path,
    duration: f64,
    left: f64,
    setting: SolverSetting,
) -> Result<Scenario> {
    let speeds: Vec<String> = packbot
        .tracks
        .iter()
        .map(|t| {
            let v = if t.lateral_offset() > 0.0 {
                left
            } else {
                PACKBOT_SPEED_MPS
            };
            format!("{} = {v}", t.name)
        })
        .collect();
    let text = format!(
        r#"
description = "PackBot 510 on flat ground, left belts {left} m/s, right {PACKBOT_SPEED_MPS} m/s"
[vehicle]
file = "../vehicles/packbot510.toml"
[terrain.ground]
friction = 0.6
[simulation]
duration_s = {duration}
method = "{m}"
[[commands]]
t_s = 0.0
belt_speed_mps = {{ {s} }}
"#,
        m = method.name(),
        s = speeds.join(", "),
    );
    compile(&text, packbot.clone(), root, setting)
}

/// Distance between the outermost left and right body tracks' mid-planes, m.
fn track_gauge(v: &VehicleModel) -> f64 {
    let ys: Vec<f64> = v
        .tracks
        .iter()
        .filter(|t| t.parent == crate::model::Parent::Body)
        .map(|t| t.lateral_offset())
        .collect();
    let hi = ys.iter().copied().fold(f64::MIN, f64::max);
    let lo = ys.iter().copied().fold(f64::MAX, f64::min);
    hi - lo
}

/// Length of the lowest straight run of the first body track (the flat-ground contact patch), m.
fn contact_length(v: &VehicleModel) -> f64 {
    v.tracks
        .iter()
        .find(|t| t.parent == crate::model::Parent::Body)
        .and_then(|t| {
            t.path
                .segments()
                .iter()
                .filter_map(|s| match s {
                    Segment::Straight { start, length, .. } => Some((start.z, *length)),
                    _ => None,
                })
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .map(|(_, l)| l)
        })
        .unwrap_or(0.0)
}

/// Yaw-rate ratio (measured / no-slip 2v/B) of a vehicle spinning on the spot with belts at
/// +-v, for two straight contact patches of half-length `a` at +-`b` with uniform pressure
/// and isotropic Coulomb friction: the yaw rate w at which the friction moments about the
/// centre balance. The slip velocity of a belt point at x is (v - w b, w x); the moment
/// balance is b (v - w b) * int dx / |s| = w * int x^2 dx / |s|, independent of mu.
pub fn spin_ratio_coulomb(b: f64, a: f64) -> f64 {
    if b <= 0.0 || a <= 0.0 {
        return f64::NAN;
    }
    let v = 1.0;
    let n = 2000;
    let f = |w: f64| {
        let u = v - w * b;
        let (mut s1, mut s2) = (0.0, 0.0);
        for i in 0..n {
            let x = -a + 2.0 * a * (i as f64 + 0.5) / n as f64;
            let s = u.hypot(w * x);
            s1 += 1.0 / s;
            s2 += x * x / s;
        }
        b * u * s1 - w * s2
    };
    let (mut lo, mut hi) = (0.0, v / b);
    for _ in 0..60 {
        let m = 0.5 * (lo + hi);
        if f(m) > 0.0 {
            lo = m;
        } else {
            hi = m;
        }
    }
    lo * b / v
}

/// Yaw at time `t`, unwrapped from the start, rad.
fn unwrapped_yaw_at(r: &RunResult, t: f64) -> f64 {
    let mut total = 0.0;
    let mut prev = match r.samples.first() {
        Some(s) => s.pose.yaw,
        None => return 0.0,
    };
    for s in r.samples.iter() {
        let mut d = s.pose.yaw - prev;
        while d > std::f64::consts::PI {
            d -= std::f64::consts::TAU;
        }
        while d < -std::f64::consts::PI {
            d += std::f64::consts::TAU;
        }
        total += d;
        prev = s.pose.yaw;
        if s.t >= t - 1e-6 {
            break;
        }
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coulomb_spin_ratio_is_between_zero_and_one() {
        let r = spin_ratio_coulomb(0.1625, 0.255);
        assert!(r > 0.55 && r < 0.7, "{r}");
        // A very short patch turns almost without slip, a very long one hardly turns.
        assert!(spin_ratio_coulomb(0.1625, 0.001) > 0.99);
        assert!(spin_ratio_coulomb(0.1625, 5.0) < 0.1);
    }
}
