//! Issue 43, honest gauges: the slip ratio is reported only where a belt or the ground moves
//! ([`tracksim::world::SLIP_MIN_SPEED_MPS`], 5 mm/s), and a braked robot stands where it
//! stopped. PackBot drives at 0.3 m/s for 2 s on flat ground (friction 0.6) and its belts are
//! then held: while it drives its belts do not slip, while it skids to a stop (7.5 mm) the held
//! belts read the full slip of -1, and from then on it stands and reads 0. Before, the brake's
//! recycled contacts kept their anchors from before the skid: the bias pass's friction pulled
//! the robot back 7.4 mm over 2 s, rocking at up to 11 mm/s across the at-rest threshold with
//! its belts at 2.9 mm/s, and the ratio of those speeds read 0.6-1.0.

use crate::common::packbot;
use tracksim::spec::{CommandSpec, PerTrack};
use tracksim::world::SLIP_MIN_SPEED_MPS;

#[test]
fn a_held_robot_at_rest_reads_no_slip_and_a_skidding_one_reads_its_slip() {
    let sc = packbot(
        |s| {
            s.simulation.duration_s = 6.0;
            s.expect = Default::default();
            s.commands.push(CommandSpec {
                t_s: 2.0,
                belt_speed_mps: Some(PerTrack::All(0.0)),
                ..Default::default()
            });
        },
        |_| {},
    );
    let r = tracksim::run_scenario(&sc, |_, _| {}).unwrap();
    let at = |t0: f64, t1: f64| r.samples.iter().filter(move |s| s.t > t0 && s.t < t1);
    // Driving: the belts grip (no-slip within 5 %).
    for s in at(0.5, 2.0) {
        assert!(
            s.slip.iter().all(|x| x.abs() < 0.05),
            "t {}: {:?}",
            s.t,
            s.slip
        );
    }
    // Skidding to a stop on held belts, while the ground still moves past 20 mm/s: slip -1.
    let skid: Vec<_> = at(2.0, 2.2)
        .filter(|s| s.linvel[0] > SLIP_MIN_SPEED_MPS)
        .collect();
    assert!(skid.len() >= 3, "{} samples of the stop", skid.len());
    for s in &skid {
        assert!(s.slip.iter().all(|x| *x < -0.9), "t {}: {:?}", s.t, s.slip);
    }
    // Standing: it stays where the skid ended, and every speed is far below the threshold.
    let rest: Vec<_> = at(2.2, 6.01).collect();
    let fastest = rest.iter().map(|s| s.linvel[0].abs()).fold(0.0, f64::max);
    assert!(fastest < 1e-3, "the robot moved at {fastest} m/s");
    let (x0, x1) = (rest[0].pose.x, rest.last().unwrap().pose.x);
    assert!(
        (x1 - x0).abs() < 1e-4,
        "it moved {} mm while braked",
        1e3 * (x1 - x0)
    );
    for s in &rest {
        assert_eq!(s.slip, vec![0.0; s.slip.len()], "t {}", s.t);
    }
}
