//! Unit tests of the track-path geometry.

use super::*;
use glam::DVec3;
use std::f64::consts::PI;

fn oval(a: f64, r: f64) -> TrackPath {
    TrackPath::from_pulleys(
        &[
            Pulley {
                x: -a / 2.0,
                z: 0.0,
                radius: r,
            },
            Pulley {
                x: a / 2.0,
                z: 0.0,
                radius: r,
            },
        ],
        0.0,
    )
    .unwrap()
}

#[test]
fn oval_length_is_exact() {
    let p = oval(0.51, 0.082);
    let expected = 2.0 * 0.51 + 2.0 * PI * 0.082;
    assert!((p.length() - expected).abs() < 1e-12, "{}", p.length());
    assert_eq!(p.segments().len(), 4);
    // Lower run moves backwards so a positive belt speed drives forwards.
    let lower = p.frame_at(p.segment_start(2) + 0.1);
    assert!((lower.tangent - DVec3::NEG_X).length() < 1e-12);
    assert!((lower.normal - DVec3::NEG_Z).length() < 1e-12);
    assert!((lower.origin.z + 0.082).abs() < 1e-12);
    assert!((p.axis() - DVec3::Y).length() < 1e-12);
}
