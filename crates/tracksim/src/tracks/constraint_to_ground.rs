//! Constraint to ground (Pecka et al., IROS 2017; Gazebo's TrackController; paper Sec. II-C):
//! one rigid outline per track (the convex hull of the loop swept across the belt width) fixed
//! to its parent, whose contacts get the belt's surface velocity. No grousers.
//!
//! Friction: the outline gets [`SURFACE_TRACK_FRICTION`]. Gazebo's TrackController example
//! gives the track mu2 = 150 along the belt ("set a very high mu for the track links" instead
//! of grousers); Rapier's friction is isotropic, and with the min rule the other surface
//! decides.

use super::common::track_tag;
use super::track::{BuildContext, Track, TrackContact};
use crate::check::f;
use crate::error::{Error, Result};
use crate::model::TrackModel;
use glam::DVec3;
use rapier3d::prelude::*;

/// Friction of the constraint-to-ground track outline (see the module docs).
pub const SURFACE_TRACK_FRICTION: f64 = 150.0;

/// A constraint-to-ground track.
#[derive(Debug)]
pub struct ConstraintToGround {
    /// Lateral axis of the loop in the parent frame.
    lateral: DVec3,
    position: f64,
    speed_cmd: f64,
}

impl ConstraintToGround {
    /// Builds the outline of `track` on `ctx.parent`, tagged so its contacts come back to
    /// [`Track::modify_contacts`].
    pub fn build(ctx: &mut BuildContext, track: &TrackModel) -> Result<Self> {
        let world = &mut *ctx.world;
        let axis = track.path.axis();
        let mut pts = Vec::new();
        for s in track.path.segments() {
            let n = if s.is_straight() { 1 } else { 48 };
            for i in 0..=n {
                let p = s.point_tangent(s.length() * i as f64 / n as f64).0;
                pts.push(f(p + axis * (track.width / 2.0)));
                pts.push(f(p - axis * (track.width / 2.0)));
            }
        }
        let c = ColliderBuilder::convex_hull(&pts)
            .ok_or_else(|| {
                Error::Build(format!("track {}: could not build its outline", track.name))
            })?
            .density(0.0)
            .friction(SURFACE_TRACK_FRICTION as f32)
            .friction_combine_rule(track.combine)
            .collision_groups(ctx.groups)
            .active_hooks(ActiveHooks::MODIFY_SOLVER_CONTACTS)
            .user_data(track_tag(ctx.index));
        world
            .colliders
            .insert_with_parent(c, ctx.parent, &mut world.bodies);
        Ok(ConstraintToGround {
            lateral: axis,
            position: 0.0,
            speed_cmd: 0.0,
        })
    }
}

impl Track for ConstraintToGround {
    fn set_belt_speed(&mut self, _world: &mut PhysicsWorld, v: f64) {
        self.speed_cmd = v;
    }

    fn commanded_belt_speed(&self) -> f64 {
        self.speed_cmd
    }

    fn after_step(&mut self, _world: &mut PhysicsWorld, dt: f64) {
        self.position += self.speed_cmd * dt;
    }

    fn belt_position(&self) -> f64 {
        self.position
    }

    fn belt_phase(&self) -> f64 {
        0.0
    }

    /// The belt is a surface velocity: it runs exactly as commanded.
    fn measured_belt_speed(&self) -> f64 {
        self.speed_cmd
    }

    fn bodies(&self) -> Vec<RigidBodyHandle> {
        Vec::new()
    }

    /// Every contact of the outline gets a target sliding velocity equal to the belt velocity
    /// there, along the belt's tangent (lateral axis x outward normal), so the rounded ends
    /// push along their curve.
    fn modify_contacts(&self, ctx: &mut ContactModificationContext, contact: TrackContact) {
        let Some(body) = ctx.colliders[contact.collider].parent() else {
            return;
        };
        let lateral_w = ctx.bodies[body].rotation() * f(self.lateral);
        let sign = contact.sign;
        let Some(m) = ctx.rigid_mut() else {
            return;
        };
        // The manifold normal points from collider 1 to collider 2: outward for the track when
        // it is collider 1.
        let n_out = *m.normal * sign;
        let t = lateral_w.cross(n_out).normalize_or_zero();
        // The solver drives (v1 - v2).t to -tangent_velocity.t; the track surface must move at
        // the belt velocity relative to its body.
        let u = t * (self.speed_cmd as f32) * sign;
        for c in m.solver_contacts.iter_mut() {
            c.tangent_velocity = u;
        }
    }
}
