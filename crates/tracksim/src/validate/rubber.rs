//! The rubber of the Table IV column "compliant grousers, rigid terrain, no slop" (issue 11.6):
//! Quince's grousers and belts given the contact compliance that a stated track rubber and
//! their dimensions imply, instead of the paper simulator's 10 mm contact slop.

use super::limits::STEP_SPEED_MPS;
use super::report::RubberNote;
use crate::model::{
    Compliance, ContactSpring, GrouserShape, TrackModel, VehicleModel, belt_compression_stiffness,
    lug_tip_stiffness,
};

/// Young's modulus of the track rubber, Pa: 5 MPa, a Shore A hardness of about 70 (the usual
/// range of moulded track and grouser rubber, Shore 60-80A, is about 3.5-9 MPa by Gent's
/// relation between Shore A and modulus).
pub const TRACK_RUBBER_YOUNGS_MODULUS_PA: f64 = 5.0e6;
/// Poisson's ratio of rubber (nearly incompressible).
pub const TRACK_RUBBER_POISSON: f64 = 0.5;
/// Loss factor of the track rubber at low frequency (filled natural rubber / SBR at room
/// temperature: 0.1-0.3).
pub const TRACK_RUBBER_LOSS_FACTOR: f64 = 0.2;

/// The contact compliance of track `t` made of the rubber above: each grouser a tapered
/// cantilever lug loaded across its tip (bending and shear, [`lug_tip_stiffness`]: the lug's
/// softest mode, the one that lets a grouser tip pressed against a riser bend up over the
/// corner), each belt link the belt's thickness compressed over one grouser pitch of its width
/// ([`belt_compression_stiffness`]); damping from the loss factor at the frequency grousers
/// meet the ground at the test speed (`v / pitch`).
pub fn rubber_compliance(t: &TrackModel) -> Compliance {
    rubber_compliance_with(t, TRACK_RUBBER_YOUNGS_MODULUS_PA)
}

/// [`rubber_compliance`] for a rubber of Young's modulus `e` Pa.
pub fn rubber_compliance_with(t: &TrackModel, e: f64) -> Compliance {
    let Some(g) = &t.grousers else {
        return Compliance {
            grousers: None,
            belt: None,
        };
    };
    let pitch = t.path.length() / g.layout.count as f64;
    let hz = STEP_SPEED_MPS / pitch;
    let spring = |k: f64| ContactSpring::from_loss_factor(k, TRACK_RUBBER_LOSS_FACTOR, hz);
    let (root, tip, width) = lug_dimensions(&g.shapes[0], g.height, t.width);
    Compliance {
        grousers: Some(spring(lug_tip_stiffness(
            e,
            TRACK_RUBBER_POISSON,
            width,
            g.height,
            root,
            tip,
        ))),
        belt: Some(spring(belt_compression_stiffness(
            e,
            t.width,
            pitch,
            t.belt_thickness,
        ))),
    }
}

/// Thickness along the belt at the root and at the tip, and width across, m, of a grouser
/// shape `height` m high (footprint frame: x along the belt, y across, z outwards).
fn lug_dimensions(shape: &GrouserShape, height: f64, track_width: f64) -> (f64, f64, f64) {
    match shape {
        GrouserShape::Box { half, .. } => (2.0 * half.x, 2.0 * half.x, 2.0 * half.y),
        GrouserShape::Convex(points) => {
            let extent = |pick: &dyn Fn(&glam::DVec3) -> bool, axis: usize| {
                let v: Vec<f64> = points.iter().filter(|p| pick(p)).map(|p| p[axis]).collect();
                let max = v.iter().copied().fold(f64::MIN, f64::max);
                let min = v.iter().copied().fold(f64::MAX, f64::min);
                if v.is_empty() { 0.0 } else { max - min }
            };
            let z0 = points.iter().map(|p| p.z).fold(f64::MAX, f64::min);
            let root = extent(&|p| (p.z - z0).abs() < 1e-6, 0);
            let tip = extent(&|p| (p.z - z0 - height).abs() < 1e-6, 0);
            let width = extent(&|_| true, 1);
            (root, tip, if width > 0.0 { width } else { track_width })
        }
    }
}

/// The springs a rubber of modulus `e` Pa gives each of `v`'s tracks, for the report.
pub(super) fn note(v: &VehicleModel, e: f64) -> RubberNote {
    let pair = |s: Option<ContactSpring>| s.map_or((0.0, 0.0), |s| (s.stiffness, s.damping));
    RubberNote {
        youngs_modulus_pa: e,
        loss_factor: TRACK_RUBBER_LOSS_FACTOR,
        springs: v
            .tracks
            .iter()
            .map(|t| {
                let c = rubber_compliance_with(t, e);
                let ((kg, cg), (kb, cb)) = (pair(c.grousers), pair(c.belt));
                (t.name.clone(), kg, cg, kb, cb)
            })
            .collect(),
    }
}

/// `quince` with every track given [`rubber_compliance`].
pub fn with_rubber(quince: &VehicleModel) -> VehicleModel {
    with_rubber_of(quince, TRACK_RUBBER_YOUNGS_MODULUS_PA)
}

/// `quince` with every track given [`rubber_compliance_with`] a rubber of modulus `e` Pa.
pub fn with_rubber_of(quince: &VehicleModel, e: f64) -> VehicleModel {
    let mut v = quince.clone();
    for t in &mut v.tracks {
        t.compliance = rubber_compliance_with(t, e);
    }
    v
}
