//! The soil parts of a vehicle: how a collider loads the soil (`Part`), the patch of ground it owns
//! (`Patch`: its cells) and a load on it (`Load`).

use super::EDGE_MARGIN_M;
use crate::terrain::SoilModel;
use glam::{DVec2, DVec3};
use rapier3d::prelude::*;

/// How a vehicle collider loads the soil.
#[derive(Clone, Copy, Debug)]
pub(super) struct Part {
    /// The track it belongs to, if any.
    pub(super) track: Option<usize>,
    /// A grouser: half the pitch (along its x) and half the track width (its y), m; otherwise
    /// the patch is its bounding box.
    pub(super) grouser: Option<(f64, f64)>,
    /// Grouser height, m (0 for other parts).
    pub(super) height: f64,
    /// Grouser thickness along the track, m (its tip bears the load until it is embedded).
    pub(super) thickness: f64,
    /// The belt surface of a track with grousers: its soil contacts are dropped.
    pub(super) drop: bool,
}

/// What shares one pressure: a track, or a body that is not part of a track.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum Footprint {
    Track(usize),
    Body(RigidBodyHandle),
}

impl Part {
    pub(super) fn footprint(&self, body: RigidBodyHandle) -> Footprint {
        match self.track {
            Some(t) => Footprint::Track(t),
            None => Footprint::Body(body),
        }
    }
}

/// A patch of ground a part loads, in Rapier coordinates.
#[derive(Clone, Copy, Debug)]
pub(super) struct Patch {
    pub(super) centre: DVec2,
    /// Unit vector of the patch's length.
    pub(super) along: DVec2,
    pub(super) half_len: f64,
    pub(super) half_width: f64,
}

impl Patch {
    pub(super) fn area(&self) -> f64 {
        4.0 * self.half_len * self.half_width
    }
    /// Bekker's `b`: the smaller side, m.
    pub(super) fn b(&self) -> f64 {
        2.0 * self.half_len.min(self.half_width)
    }
    /// Calls `f` with the world indices of every cell whose centre lies in the patch (the cell
    /// under the centre when none does).
    pub(super) fn cells(&self, per_m: i64, origin_cells: (i64, i64), mut f: impl FnMut(i64, i64)) {
        let pm = per_m as f64;
        let across = DVec2::new(-self.along.y, self.along.x);
        let ex = self.along.x.abs() * self.half_len + across.x.abs() * self.half_width;
        let ey = self.along.y.abs() * self.half_len + across.y.abs() * self.half_width;
        let (x0, x1) = (
            ((self.centre.x - ex) * pm).floor() as i64,
            ((self.centre.x + ex) * pm).floor() as i64,
        );
        let (y0, y1) = (
            ((self.centre.y - ey) * pm).floor() as i64,
            ((self.centre.y + ey) * pm).floor() as i64,
        );
        let mut any = false;
        for iy in y0..=y1 {
            for ix in x0..=x1 {
                let c = DVec2::new((ix as f64 + 0.5) / pm, (iy as f64 + 0.5) / pm) - self.centre;
                // A cell centre on the patch's edge (a 75 mm track is 7.5 cells of 1 cm) is
                // left out on both sides alike: without the margin, f32 rounding of the track's
                // position (y = +-0.1625 m) took the edge cell on the left and not on the right,
                // and turns on sand did not mirror.
                if c.dot(self.along).abs() <= self.half_len - EDGE_MARGIN_M
                    && c.dot(across).abs() <= self.half_width - EDGE_MARGIN_M
                {
                    any = true;
                    f(ix + origin_cells.0, iy + origin_cells.1);
                }
            }
        }
        if !any {
            f(
                (self.centre.x * pm).floor() as i64 + origin_cells.0,
                (self.centre.y * pm).floor() as i64 + origin_cells.1,
            );
        }
    }
}

/// A manifold's load on the soil this step, for the after-step update.
#[derive(Clone, Copy, Debug)]
pub(super) struct Load {
    pub(super) soil: usize,
    pub(super) track: Option<usize>,
    pub(super) footprint: Footprint,
    pub(super) patch: Patch,
    /// The sinkage the solver was told (belt level, without the grouser height), m.
    pub(super) z: f64,
    /// Bekker's sinkage at the patch's pressure on virgin soil (0 while the grousers' tips
    /// bear), m: what a cell loaded now is pressed to at least. (The patch's `z` follows the
    /// mean memory of its cells; a fresh cell does not inherit its neighbours' depth.)
    pub(super) z_virgin: f64,
    /// Bekker's b, m.
    pub(super) b: f64,
    /// The patch's shear limit, mobilised, N.
    pub(super) limit: f64,
    /// The filtered normal force, N.
    pub(super) force: f64,
    pub(super) body: RigidBodyHandle,
    pub(super) part: ColliderHandle,
    pub(super) ground: ColliderHandle,
    /// Soil surface normal (Rapier frame, pointing out of the soil).
    pub(super) normal: Vector,
}

/// The floating origin in whole cells of `soil`. On soil the origin is on whole metres
/// (`world/build.rs` `start_origin`, then whole-metre shifts).
pub(super) fn origin_cells(soil: &SoilModel, origin: DVec3) -> (i64, i64) {
    debug_assert!(
        origin.x.fract() == 0.0 && origin.y.fract() == 0.0,
        "the floating origin on soil must be on whole metres: {origin}"
    );
    let per_m = soil.cells_per_m();
    (
        origin.x.round() as i64 * per_m,
        origin.y.round() as i64 * per_m,
    )
}

/// The patch part `p` of collider `c` loads.
pub(super) fn patch_of(p: &Part, c: &Collider) -> Patch {
    let pos = c.position();
    let t = pos.translation;
    let centre = DVec2::new(t.x as f64, t.y as f64);
    match p.grouser {
        Some((half_len, half_width)) => {
            let x = pos.rotation * Vector::X;
            let along = DVec2::new(x.x as f64, x.y as f64)
                .try_normalize()
                .unwrap_or(DVec2::X);
            Patch {
                centre,
                along,
                half_len,
                half_width,
            }
        }
        None => {
            let a = c.compute_aabb();
            let (lo, hi) = (a.mins, a.maxs);
            Patch {
                centre: DVec2::new(0.5 * (lo.x + hi.x) as f64, 0.5 * (lo.y + hi.y) as f64),
                along: DVec2::X,
                half_len: (0.5 * (hi.x - lo.x) as f64).max(1e-3),
                half_width: (0.5 * (hi.y - lo.y) as f64).max(1e-3),
            }
        }
    }
}
