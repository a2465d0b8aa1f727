//! Line-tip grousers (`okada2020_line_tips`, issue 16.2): the paper's segment links with every
//! grouser as two colliders, so that flat ground meets a line instead of a face.
//!
//! A grouser tip on flat ground touches it along a line across the belt; Rapier's box-box
//! manifold gives 4 contact points per grouser where two at the line's ends carry every force
//! and torque the jointed link can feel (each solver point costs about the same). So each
//! grouser gets:
//! - its **exact hull** (the vehicle file's box or convex shape, as `okada2020` has it), which
//!   touches every terrain piece but the flat-ground tile: steps, boxes, ramps, height fields
//!   and meshes meet the grouser's real edges and flanks;
//! - a **tip capsule** across the belt at the grouser's outer face (radius half the tip's
//!   length along the belt, ends at the grouser's sides, outermost point at the tip), which
//!   touches only the flat-ground tile: a segment against a face, 3 contact points on the box
//!   tile (parry clips the segment to 2 and adds the rounded shapes' deepest point; 2 against
//!   a half-space) instead of the box grouser's 4.
//!
//! Only the flat ground sees the rounded tip (up to ~1 mm of the tip's corners rounded off
//! where a grouser meets the ground tilted, on the pulleys). One grouser shape per track.

use super::common::{RELIEF_GROUP, VEHICLE_GROUP};
use crate::check::f;
use crate::error::{Error, Result};
use crate::model::{GrouserShape, TrackModel};
use glam::DVec3;
use rapier3d::prelude::*;

/// Smallest tip capsule radius, m (a grouser whose tip is a sharp ridge).
pub const MIN_TIP_RADIUS_M: f64 = 0.0005;

/// Collision groups of a grouser's exact hull: the vehicle's, seeing terrain other than the
/// flat-ground tile.
pub fn hull_groups() -> InteractionGroups {
    InteractionGroups::new(VEHICLE_GROUP, RELIEF_GROUP, InteractionTestMode::And)
}

/// Collision groups of a grouser's tip capsule: the vehicle's, seeing the flat-ground tile only.
pub fn tip_groups() -> InteractionGroups {
    InteractionGroups::new(
        VEHICLE_GROUP,
        super::common::FLAT_GROUND_GROUP,
        InteractionTestMode::And,
    )
}

/// The tip capsule of a grouser shape, in the frame of its collider (the box's centre, or the
/// footprint frame of a convex shape: x along the belt, y across, z outwards).
pub fn tip_shape(shape: &GrouserShape) -> Option<SharedShape> {
    let (x_c, x_half, y_min, y_max, z_top) = match shape {
        GrouserShape::Box { half, .. } => (0.0, half.x.min(half.z), -half.y, half.y, half.z),
        GrouserShape::Convex(pts) => {
            let z_top = pts.iter().map(|p| p.z).fold(f64::NEG_INFINITY, f64::max);
            let tip: Vec<&DVec3> = pts.iter().filter(|p| p.z > z_top - 1e-6).collect();
            let x_min = tip.iter().map(|p| p.x).fold(f64::INFINITY, f64::min);
            let x_max = tip.iter().map(|p| p.x).fold(f64::NEG_INFINITY, f64::max);
            let y_min = pts.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
            let y_max = pts.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max);
            (
                (x_min + x_max) / 2.0,
                (x_max - x_min) / 2.0,
                y_min,
                y_max,
                z_top,
            )
        }
    };
    let r = x_half.max(MIN_TIP_RADIUS_M);
    let (a, b) = (y_min + r, y_max - r);
    if !(a < b && r.is_finite()) {
        return None;
    }
    let z = z_top - r;
    Some(SharedShape::capsule(
        f(DVec3::new(x_c, a, z)),
        f(DVec3::new(x_c, b, z)),
        r as f32,
    ))
}

/// The tip capsule of `t`'s grouser shape (empty without grousers), or why there is none.
pub fn tip_shapes(t: &TrackModel) -> Result<Vec<SharedShape>> {
    let Some(g) = &t.grousers else {
        return Ok(Vec::new());
    };
    if g.shapes.len() != 1 {
        return Err(Error::Build(format!(
            "track {}: the okada2020_line_tips method takes one grouser shape per track, the \
             vehicle file gives {} in turn; use okada2020",
            t.name,
            g.shapes.len()
        )));
    }
    tip_shape(&g.shapes[0]).map(|s| vec![s]).ok_or_else(|| {
        Error::Build(format!(
            "track {}: the grouser is narrower across the belt than its tip is long; use \
             okada2020",
            t.name
        ))
    })
}
