//! Samples of the selected robot on `Simulation` (`Simulation::sample`).

use super::Simulation;
use super::sample::{DriveSample, ICR_MIN_RATE_RAD_S, PoseRpy, Sample, slip_ratio};
use crate::check::f;
use crate::model::Parent;
use crate::tracks::WORLD_GROUP;
use glam::DVec3;
use rapier3d::prelude::*;

impl Simulation {
    /// Height of the terrain surface below the world point (x, y), m, by a downward ray that
    /// sees only the terrain; `None` if there is no terrain there (off the edge).
    pub fn terrain_below(&self, x: f64, y: f64) -> Option<f64> {
        self.terrain_below_local(x - self.origin.x, y - self.origin.y)
            .map(|z| z + self.origin.z)
    }

    /// [`Simulation::terrain_below`] of every point (`xs[i]`, `ys[i]`), m: NaN where there is
    /// no terrain. `xs` and `ys` must have the same length (keys `xs`, `ys` in the refusal).
    pub fn terrain_heights(&self, xs: &[f64], ys: &[f64]) -> crate::error::Result<Vec<f64>> {
        if xs.len() != ys.len() {
            return Err(crate::error::Error::setting(
                "terrain_heights",
                "ys",
                format!(
                    "expected one y per x: xs has {} entries, ys {}",
                    xs.len(),
                    ys.len()
                ),
            ));
        }
        Ok(xs
            .iter()
            .zip(ys)
            .map(|(x, y)| self.terrain_below(*x, *y).unwrap_or(f64::NAN))
            .collect())
    }

    /// [`Simulation::terrain_below`] for a point in the Rapier world's coordinates, m.
    pub(crate) fn terrain_below_local(&self, x: f64, y: f64) -> Option<f64> {
        let top = 1000.0f32;
        let ray = Ray::new(Vector::new(x as f32, y as f32, top), Vector::NEG_Z);
        let filter = QueryFilter::default().groups(InteractionGroups::new(
            Group::ALL,
            WORLD_GROUP,
            InteractionTestMode::And,
        ));
        self.world
            .cast_ray(&ray, 2.0 * top, true, filter)
            .map(|(_, toi)| (top - toi) as f64)
    }

    /// Pose of the chassis in world coordinates.
    pub fn body_pose(&self) -> PoseRpy {
        let mut p = PoseRpy::from_pose(self.world.bodies[self.robots[self.focus].body].position());
        p.x += self.origin.x;
        p.y += self.origin.y;
        p.z += self.origin.z;
        p
    }

    /// Number of active solver contact points in the world.
    pub fn contact_count(&self) -> usize {
        self.world
            .narrow_phase
            .contact_pairs()
            .flat_map(|p| p.solver_manifolds())
            .map(|m| m.data.solver_contacts.len())
            .sum()
    }

    /// Active solver contact points per touching contact pair: (the shape type of the pair's
    /// vehicle collider, or of collider 1 if neither is terrain, and its number of points), in
    /// the narrow phase's order. For checking what a collider representation costs
    /// (`okada2020_line_tips`: 3 points per tip capsule on the flat-ground tile, 4 per box).
    pub fn contact_points_per_pair(&self) -> Vec<(ShapeType, usize)> {
        let cs = &self.world.colliders;
        let terrain = |c: &Collider| c.collision_groups().memberships.contains(WORLD_GROUP);
        self.world
            .narrow_phase
            .contact_pairs()
            .filter_map(|p| {
                let n: usize = p
                    .solver_manifolds()
                    .iter()
                    .map(|m| m.data.solver_contacts.len())
                    .sum();
                let (c1, c2) = (cs.get(p.collider1)?, cs.get(p.collider2)?);
                let vehicle = if terrain(c1) { c2 } else { c1 };
                (n > 0).then(|| (vehicle.shape().shape_type(), n))
            })
            .collect()
    }

    /// Number of active solver contact points in the world and the deepest penetration (m, 0 if
    /// none) of any touching vehicle-terrain collider pair, measured from the colliders' current poses (the
    /// narrow phase's stored distances can be frames old for recycled pairs, and the contact
    /// slop hook rewrites the solver's).
    pub fn contact_stats(&self) -> (usize, f64) {
        let mut n = 0;
        let mut deepest = 0.0f32;
        let cs = &self.world.colliders;
        for p in self.world.narrow_phase.contact_pairs() {
            let active: usize = p
                .solver_manifolds()
                .iter()
                .map(|m| m.data.solver_contacts.len())
                .sum();
            if active == 0 {
                continue;
            }
            n += active;
            let (Some(c1), Some(c2)) = (cs.get(p.collider1), cs.get(p.collider2)) else {
                continue;
            };
            // Penetration counts vehicle-terrain pairs only (not, e.g., plates on their wheels).
            let terrain = |c: &Collider| c.collision_groups().memberships.contains(WORLD_GROUP);
            if !(terrain(c1) || terrain(c2)) {
                continue;
            }
            if let Some(d) = self.tile_depth(c1, c2).or_else(|| self.tile_depth(c2, c1)) {
                deepest = deepest.max(d);
            } else if let Ok(Some(c)) = rapier3d::parry::query::contact(
                c1.position(),
                c1.shape(),
                c2.position(),
                c2.shape(),
                0.0,
            ) {
                deepest = deepest.max(-c.dist);
            }
        }
        (n, deepest as f64)
    }

    /// Depth, m, of `other`'s lowest point below the top of the flat-ground tile when `tile` is
    /// the tile's collider: exact for the convex shapes of a vehicle. (parry's box-box query
    /// against the 20 m tile returned a tilted normal and 78 mm for a plate whose manifold
    /// said 1 mm.)
    fn tile_depth(&self, tile: &Collider, other: &Collider) -> Option<f32> {
        if tile.parent() != self.ground_tile || self.ground_tile.is_none() {
            return None;
        }
        let top = tile.position().translation.z + tile.shape().as_cuboid()?.half_extents.z;
        let sm = other.shape().as_support_map()?;
        let pose = other.position();
        let dir = pose.rotation.inverse() * Vector::NEG_Z;
        let low = pose.transform_point(sm.local_support_point(dir));
        Some((top - low.z).max(0.0))
    }

    /// Angle of flipper `i` relative to the body, rad.
    pub fn flipper_angle(&self, i: usize) -> f64 {
        let fl = &self.robots[self.focus].flippers[i];
        let pb = self.world.bodies[self.robots[self.focus].body].position();
        let pf = self.world.bodies[fl.body].position();
        let r = (pb.rotation.inverse() * pf.rotation).normalize();
        let v = DVec3::new(r.x as f64, r.y as f64, r.z as f64);
        2.0 * v.dot(fl.axis).atan2(r.w as f64)
    }

    /// The selected robot's chassis velocity (world frame): linear m/s, angular rad/s.
    pub fn body_velocity(&self) -> ([f64; 3], [f64; 3]) {
        let b = &self.world.bodies[self.robots[self.focus].body];
        let (lv, av) = (b.linvel(), b.angvel());
        (
            [lv.x as f64, lv.y as f64, lv.z as f64],
            [av.x as f64, av.y as f64, av.z as f64],
        )
    }

    /// Current state as a sample.
    pub fn sample(&self) -> Sample {
        let (linvel, angvel) = self.body_velocity();
        // Before the first step the narrow phase still holds the placement's trial contacts.
        let (contacts, penetration) = if self.steps() == 0 {
            (0, 0.0)
        } else {
            self.contact_stats()
        };
        Sample {
            t: self.time,
            pose: self.body_pose(),
            linvel,
            angvel,
            belt_speed: self
                .rb()
                .tracks
                .iter()
                .map(|t| t.measured_belt_speed())
                .collect(),
            belt_phase: self.robots[self.focus]
                .tracks
                .iter()
                .map(|t| t.belt_phase())
                .collect(),
            belt_position: self.robots[self.focus]
                .tracks
                .iter()
                .map(|t| t.belt_position())
                .collect(),
            flipper_angle: (0..self.robots[self.focus].flippers.len())
                .map(|i| self.flipper_angle(i))
                .collect(),
            contacts,
            penetration,
            belt_cmd: self
                .rb()
                .tracks
                .iter()
                .map(|t| t.commanded_belt_speed())
                .collect(),
            slip: self.slip(),
            loads: self.track_loads(),
            odom: [
                self.robots[self.focus].odometry.x,
                self.robots[self.focus].odometry.y,
                self.robots[self.focus].odometry.yaw,
            ],
            icr: self.icr(),
            drawbar_n: self.drawbar_pull(),
            drive: self.drive(),
            conveyor_position: self.conveyor_belts().iter().map(|b| b.0).collect(),
            loose_poses: self.loose_box_poses(),
            soil: self.track_soil(),
        }
    }

    /// [`Sample::drive`].
    fn drive(&self) -> Vec<Option<DriveSample>> {
        self.rb()
            .view
            .vehicle
            .tracks
            .iter()
            .zip(&self.robots[self.focus].tracks)
            .zip(self.track_loads())
            .map(|((m, t), load)| {
                let motor = m.motor.as_ref()?;
                let v = t.measured_belt_speed();
                let max = t
                    .belt_force_limit()
                    .unwrap_or_else(|| motor.max_belt_force(v, t.commanded_belt_speed()));
                // Saturated (the belt runs more than 1 mm/s slower than commanded): the link
                // motors deliver exactly their cap. Otherwise the controller holds the speed and
                // the belt force is the terrain's pull on the belt (steady state, the links'
                // inertia neglected), within the cap.
                let cmd = t.commanded_belt_speed();
                let saturated = cmd != 0.0 && (v - cmd) * cmd.signum() < -1e-3;
                let force = if saturated {
                    max * cmd.signum()
                } else {
                    load.traction_n.clamp(-max, max)
                };
                Some(DriveSample {
                    belt_force_n: force,
                    sprocket_torque_nm: force * motor.sprocket_radius,
                    motor_torque_nm: motor.motor_torque(force, v),
                    max_belt_force_n: max,
                    power_w: force * v,
                    electrical: motor.electrical(force, v),
                })
            })
            .collect()
    }

    /// Slip ratio of every track ([`Sample::slip`]).
    fn slip(&self) -> Vec<f64> {
        let mut out = vec![0.0; self.robots[self.focus].tracks.len()];
        self.slip_into(&mut out);
        out
    }

    /// The slip ratio of every track ([`Sample::slip`], [`slip_ratio`]) into `out` (one per
    /// track, in track order), without allocating.
    pub fn slip_into(&self, out: &mut [f64]) {
        let tracks = self.rb().view.vehicle.tracks.iter().zip(&self.rb().tracks);
        for (o, (m, t)) in out.iter_mut().zip(tracks) {
            let parent = match m.parent {
                Parent::Body => self.robots[self.focus].body,
                Parent::Flipper(i) => self.robots[self.focus].flippers[i].body,
            };
            let b = &self.world.bodies[parent];
            let segs = m.path.segments();
            let c = segs.iter().map(|s| s.start()).sum::<DVec3>() / segs.len() as f64;
            let v = b.velocity_at_point(b.position() * f(c));
            let ground = v.dot(b.rotation() * Vector::X) as f64;
            *o = slip_ratio(t.measured_belt_speed(), ground);
        }
    }

    /// Instantaneous centre of rotation in the chassis frame ([`Sample::icr`]).
    fn icr(&self) -> Option<[f64; 2]> {
        let b = &self.world.bodies[self.robots[self.focus].body];
        let r = b.rotation().inverse();
        // Velocity of the chassis frame's origin (not of its centre of mass), body frame.
        let (v, w) = (r * b.velocity_at_point(b.translation()), r * b.angvel());
        let wz = w.z as f64;
        (wz.abs() >= ICR_MIN_RATE_RAD_S).then(|| [-(v.y as f64) / wz, v.x as f64 / wz])
    }
}
