//! Insertion of a compiled terrain into a Rapier world ([`TerrainModel::insert_into`]), and the
//! flat-ground tile kept under the vehicle ([`GROUND_TILE_HALF_M`],
//! [`TerrainModel::recentre_ground_tile`]).

use super::{HeightFieldModel, TerrainModel};
use crate::check::{f, q};
use crate::render::Rgb;
use glam::{DQuat, DVec3};
use rapier3d::parry::shape::TriMeshFlags;
use rapier3d::prelude::*;

/// Half-extent (x and y) of the flat-ground tile a simulation uses for `[terrain.ground]`, m.
///
/// An infinite plane (Rapier's half-space) has an infinite bounding box, so every collider of
/// the vehicle, the top runs' grousers included, is paired with it and goes through the narrow
/// phase every step. A finite box under the vehicle, re-centred as it drives (see
/// [`GROUND_RECENTRE_M`]), is the same flat surface for the vehicle and pairs only with what
/// is near it: measured +25 % real-time factor on the Table II case (BENCHMARKS.md). The tile
/// is kept small because the box-box contact loses f32 precision with large boxes (a 1 km
/// tile gave metre-deep spurious penetrations).
pub const GROUND_TILE_HALF_M: f64 = 10.0;
/// The ground tile is moved under the vehicle when the vehicle is this far (in x or y) from
/// the tile's centre, m: the vehicle always stays at least 6 m inside the tile.
pub const GROUND_RECENTRE_M: f64 = 4.0;
/// Thickness of the ground tile, m.
const GROUND_TILE_THICKNESS_M: f64 = 1.0;

/// What [`TerrainModel::insert_into`] put in the world.
#[derive(Clone, Debug)]
pub struct InsertedTerrain {
    /// The flat-ground tile's body, if one was asked for and the terrain has ground.
    pub ground_tile: Option<RigidBodyHandle>,
    /// Every collider inserted, with its colour in camera images.
    pub colors: Vec<(ColliderHandle, Rgb)>,
}

impl TerrainModel {
    /// Inserts the terrain as colliders on one fixed body of `world`, in collision `groups`,
    /// in coordinates relative to `origin` (the world point, m, that is the Rapier world's
    /// origin: every position is taken relative to it in f64 before it becomes f32, so terrain
    /// far from the world origin keeps its precision near `origin`).
    /// `[terrain.ground]` becomes an infinite half-space, or, with `ground_tile`, a
    /// [`GROUND_TILE_HALF_M`] box on its own fixed body centred at (x, y) = `ground_tile`
    /// (Rapier coordinates), whose handle is returned (move it with
    /// [`Self::recentre_ground_tile`]) with the colour of every collider inserted.
    pub fn insert_into(
        &self,
        world: &mut PhysicsWorld,
        groups: InteractionGroups,
        ground_tile: Option<(f64, f64)>,
        origin: DVec3,
    ) -> InsertedTerrain {
        let mut colors = Vec::new();
        let fixed = world.bodies.insert(RigidBodyBuilder::fixed());
        let mut tile = None;
        if let Some((z, mu)) = self.ground {
            let c = match ground_tile {
                None => ColliderBuilder::new(SharedShape::halfspace(Vector::Z))
                    .translation(Vector::new(0.0, 0.0, (z - origin.z) as f32)),
                Some(_) => ColliderBuilder::cuboid(
                    GROUND_TILE_HALF_M as f32,
                    GROUND_TILE_HALF_M as f32,
                    (GROUND_TILE_THICKNESS_M / 2.0) as f32,
                )
                .translation(Vector::new(
                    0.0,
                    0.0,
                    (z - origin.z - GROUND_TILE_THICKNESS_M / 2.0) as f32,
                )),
            }
            .friction(mu as f32)
            .collision_groups(groups);
            let c = with_soil(c, self.ground_soil);
            let parent = match ground_tile {
                None => fixed,
                Some((x, y)) => {
                    let h = world.bodies.insert(
                        RigidBodyBuilder::fixed().translation(Vector::new(x as f32, y as f32, 0.0)),
                    );
                    tile = Some(h);
                    h
                }
            };
            let h = world
                .colliders
                .insert_with_parent(c, parent, &mut world.bodies);
            colors.push((h, self.ground_color));
        }
        let mut add = |c: ColliderBuilder, friction: f64, soil: Option<usize>, color: Rgb| {
            let c = with_soil(c, soil);
            let c = c.friction(friction as f32).collision_groups(groups);
            let h = world
                .colliders
                .insert_with_parent(c, fixed, &mut world.bodies);
            colors.push((h, color));
        };
        for b in &self.boxes {
            add(
                ColliderBuilder::cuboid(b.half.x as f32, b.half.y as f32, b.half.z as f32)
                    .position(Pose::from_parts(f(b.centre - origin), q(b.rotation()))),
                b.friction,
                b.soil,
                b.color,
            );
        }
        for cy in &self.cylinders {
            // Rapier's cylinder axis is its local y.
            add(
                ColliderBuilder::cylinder(cy.half_length as f32, cy.radius as f32).position(
                    Pose::from_parts(f(cy.centre - origin), q(DQuat::from_rotation_z(cy.yaw))),
                ),
                cy.friction,
                None,
                cy.color,
            );
        }
        for h in &self.heightfields {
            // Rapier's grid is column-major, indexed [row (its z)][column (its x)].
            let mut data = vec![0.0f32; h.rows * h.cols];
            for r in 0..h.rows {
                for col in 0..h.cols {
                    data[r + col * h.rows] = h.heights[r * h.cols + col] as f32;
                }
            }
            add(
                ColliderBuilder::heightfield_with_flags(
                    Array2::new(h.rows, h.cols, data),
                    Vector::new(h.size_x as f32, 1.0, h.size_y as f32),
                    HeightFieldFlags::FIX_INTERNAL_EDGES,
                )
                .position(Pose::from_parts(f(h.centre - origin), q(h.pose()))),
                h.friction,
                None,
                h.color,
            );
        }
        for m in &self.meshes {
            let verts = m.vertices.iter().map(|v| f(*v - origin)).collect();
            // Cannot fail: compile_terrain keeps only meshes with triangles.
            if let Ok(b) = ColliderBuilder::trimesh_with_flags(
                verts,
                m.triangles.clone(),
                TriMeshFlags::FIX_INTERNAL_EDGES | TriMeshFlags::MERGE_DUPLICATE_VERTICES,
            ) {
                add(b, m.friction, None, m.color);
            }
        }
        InsertedTerrain {
            ground_tile: tile,
            colors,
        }
    }

    /// Moves the ground tile of [`Self::insert_into`] under (x, y) when that point is more than
    /// [`GROUND_RECENTRE_M`] from the tile's centre. The surface the vehicle touches does not
    /// change: same plane, same friction.
    pub fn recentre_ground_tile(world: &mut PhysicsWorld, tile: RigidBodyHandle, x: f64, y: f64) {
        let b = &world.bodies[tile];
        let c = b.translation();
        if (x - c.x as f64).abs() > GROUND_RECENTRE_M || (y - c.y as f64).abs() > GROUND_RECENTRE_M
        {
            let to = Vector::new(x.round() as f32, y.round() as f32, c.z);
            world.bodies[tile].set_translation(to, false);
        }
    }
}

/// A soil surface carries its tag ([`super::soil_tag`]) and turns the contact hook on.
fn with_soil(c: ColliderBuilder, soil: Option<usize>) -> ColliderBuilder {
    match soil {
        Some(i) => c
            .user_data(super::soil_tag(i))
            .active_hooks(ActiveHooks::MODIFY_SOLVER_CONTACTS),
        None => c,
    }
}

impl HeightFieldModel {
    /// Rapier's pose for this field: Rapier height fields are y-up with rows along their z,
    /// so a +90 degree rotation about x takes their (x, height, z) to our (x, -z, height).
    fn pose(&self) -> DQuat {
        DQuat::from_rotation_z(self.yaw) * DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2)
    }
}
