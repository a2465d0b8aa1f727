//! Questions about a compiled terrain: its extent ([`TerrainModel::bounds`]) and the height of
//! its surface ([`TerrainModel::height_at`], [`TerrainModel::heights_at`]).

use super::TerrainModel;
use crate::check::f;
use glam::{DQuat, DVec3};
use rapier3d::prelude::*;

impl TerrainModel {
    /// The extent of all finite surfaces: (min corner, max corner), m. x and y bound every
    /// box, cylinder, height field and mesh; z spans their lowest to highest points. `None`
    /// when there is an infinite ground plane (the terrain has no edge) or nothing at all.
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        if self.ground.is_some() {
            return None;
        }
        self.finite_extent()
    }

    /// The extent of the finite surfaces (everything but the ground plane), m.
    fn finite_extent(&self) -> Option<(DVec3, DVec3)> {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        let mut grow = |p: DVec3| {
            lo = lo.min(p);
            hi = hi.max(p);
        };
        for b in &self.boxes {
            let rot = b.rotation();
            for i in 0..8 {
                let s = DVec3::new(
                    if i & 1 == 0 { -1.0 } else { 1.0 },
                    if i & 2 == 0 { -1.0 } else { 1.0 },
                    if i & 4 == 0 { -1.0 } else { 1.0 },
                );
                grow(b.centre + rot * (b.half * s));
            }
        }
        for cy in &self.cylinders {
            let axis = DQuat::from_rotation_z(cy.yaw) * DVec3::Y * cy.half_length;
            for e in [cy.centre + axis, cy.centre - axis] {
                grow(e - DVec3::splat(cy.radius));
                grow(e + DVec3::splat(cy.radius));
            }
        }
        for h in &self.heightfields {
            let (zmin, zmax) = h
                .heights
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), z| {
                    (a.min(*z), b.max(*z))
                });
            for (r, col) in [
                (0, 0),
                (0, h.cols - 1),
                (h.rows - 1, 0),
                (h.rows - 1, h.cols - 1),
            ] {
                let v = h.vertex(r, col);
                grow(DVec3::new(v.x, v.y, zmin));
                grow(DVec3::new(v.x, v.y, zmax));
            }
        }
        for m in &self.meshes {
            for t in &m.triangles {
                for i in t {
                    grow(m.vertices[*i as usize]);
                }
            }
        }
        lo.is_finite().then_some((lo, hi))
    }

    /// Height of the highest terrain surface at (x, y), m, found by a downward ray from just
    /// above the highest surface; `None` where there is nothing (off the terrain).
    pub fn height_at(&self, x: f64, y: f64) -> Option<f64> {
        self.heights_at(&[(x, y)])[0]
    }

    /// [`Self::height_at`] for many points at once (builds the terrain once), m.
    pub fn heights_at(&self, points: &[(f64, f64)]) -> Vec<Option<f64>> {
        let mut world = PhysicsWorld::new();
        self.insert_into(
            &mut world,
            InteractionGroups::all(),
            None,
            glam::DVec3::ZERO,
        );
        world.step_with_events(&(), &()); // no dynamic bodies: only updates the query structures
        // Rays start just above the highest surface: from far above, f32 rounding of the
        // shapes' rotations would be magnified by the distance.
        let (mut lo, mut hi) = self
            .finite_extent()
            .map_or((f64::INFINITY, f64::NEG_INFINITY), |(l, h)| (l.z, h.z));
        if let Some((z, _)) = self.ground {
            (lo, hi) = (lo.min(z), hi.max(z));
        }
        if !(lo.is_finite() && hi.is_finite()) {
            return vec![None; points.len()];
        }
        let top = hi + 1.0;
        let reach = (top - lo + 1.0) as f32;
        points
            .iter()
            .map(|&(x, y)| {
                let ray = Ray::new(f(DVec3::new(x, y, top)), Vector::NEG_Z);
                world
                    .cast_ray(&ray, reach, true, QueryFilter::default())
                    .map(|(_, toi)| top - toi as f64)
            })
            .collect()
    }
}
