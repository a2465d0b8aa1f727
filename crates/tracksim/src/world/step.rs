//! One step of the world, as named stages: keep the ground tile under the vehicle, step the
//! physics with the contact hook, the tracks' after-step work, and the stability check.

use super::at_rest::{REST_REANCHOR_M, STICK_RATE_RAD_S, STICK_SPEED_MPS};
use super::contacts::ContactHooks;
use super::{MAX_ANGULAR_SPEED_RAD_S, MAX_SPEED_MPS, Simulation};
use crate::error::{Error, Result};

impl Simulation {
    /// Advances the simulation by one time step with the controls set so far (every robot).
    pub fn step(&mut self) -> Result<()> {
        let focus = self.focus;
        let shifted = self.scenario.solver.floating_origin && self.follow_origin();
        self.recentre_ground_tile();
        let mut held_all = true;
        let mut held_on_motors = false;
        for i in 0..self.order.len() {
            let k = self.order[i];
            self.focus = k;
            self.apply_drawbar();
            let held = self.braked_at_rest();
            held_all &= held;
            held_on_motors |= held && self.robots[k].has_motors;
        }
        self.focus = focus;
        self.keep_momenta();
        self.world.integration_parameters.friction_in_bias_pass =
            self.held_friction_in_bias_pass && held_all;
        let hooks = ContactHooks {
            slop: self.slop,
            robots: &self.robots,
            springs: &self.springs,
            dt: self.dt as f32,
            soil: self.soil.as_ref(),
            origin: self.origin,
            patch: self.friction_patch.as_ref(),
            cull: self.cull.mode(),
        };
        // After an origin shift no pair may keep contacts frozen at the old place. Held at
        // rest on motors neither: their held belt position moves by the solver's residual, the
        // links' recycled contacts (anchors and normal frozen in world space) then slid the
        // robot down 20 deg at 0.9 mm/s; with fresh contacts 0.017 mm/s. Held without motors
        // the links come back to the same pose every step and recycling holds them exactly
        // (0.23 mm/s of creep with fresh contacts), so it stays on.
        let recycling = self.world.integration_parameters.contact_recycling;
        // Coming to rest on held belts after moving, the contacts are made afresh where the
        // robot stands: recycled, their anchors were where they began, before the skid to a
        // stop, and the bias pass's friction then pulled a PackBot stopped from 0.3 m/s back
        // 7.4 mm over 2 s, rocking at 11 mm/s across the at-rest threshold (issue 43's red slip
        // bars at rest). A robot standing still crosses that threshold many times a second
        // (landing, solver noise) without moving: only a return to rest at least
        // `REST_REANCHOR_M` from the last rest counts, else its anchors would be renewed as it
        // creeps and it would creep on (2.6 mm in 20 s, against 0.02 mm).
        let coming_to_rest = held_all && !self.held_at_rest && self.moved_since_rest();
        self.held_at_rest = held_all;
        if held_all {
            // In place: no allocation in the steps a robot stands.
            self.rest_positions
                .resize(self.robots.len(), Default::default());
            for (p, r) in self.rest_positions.iter_mut().zip(&self.robots) {
                *p = self.world.bodies[r.body].translation();
            }
        }
        // Soil contacts change every step (the allowance follows the load and the ruts): a
        // recycled contact would skip the hook.
        self.world.integration_parameters.contact_recycling =
            recycling && !shifted && !held_on_motors && !coming_to_rest && self.soil.is_none();
        self.world.step_with_events(&hooks, &());
        self.world.integration_parameters.contact_recycling = recycling;
        // A robot put back at its start (`reset_robot`): its colliders asked for the hook for
        // this step only, so that none of its pairs kept contacts frozen at its old place.
        for (c, h) in self.fresh_pairs.drain(..) {
            if let Some(c) = self.world.colliders.get_mut(c) {
                c.set_active_hooks(h);
            }
        }
        self.steps += 1;
        self.time = self.steps as f64 * self.dt;
        for k in 0..self.robots.len() {
            self.focus = k;
            self.record_track_loads();
        }
        self.focus = focus;
        self.soil_after_step();
        let dt = self.dt;
        for &k in &self.order {
            for t in &mut self.robots[k].tracks {
                t.after_step(&mut self.world, dt);
            }
        }
        self.conveyors.after_step(&mut self.world, self.dt);
        for r in &mut self.robots {
            let tracks = &r.tracks;
            r.odometry
                .update_with(|i| tracks[i].measured_belt_speed(), dt);
        }
        for k in 0..self.robots.len() {
            self.check_stability(k)?;
        }
        self.check_spread()
    }

    /// The selected robot's belts are all commanded to 0 m/s and its chassis is at rest (below
    /// [`STICK_SPEED_MPS`] and [`STICK_RATE_RAD_S`]): static friction holds it. A braked
    /// vehicle that slides (beyond the friction cone) leaves this state within milliseconds and
    /// slides with Rapier's plain friction.
    /// Whether a robot's chassis is at least [`REST_REANCHOR_M`] from where it was last at rest
    /// (or none was yet).
    fn moved_since_rest(&self) -> bool {
        self.rest_positions.len() != self.robots.len()
            || self.robots.iter().zip(&self.rest_positions).any(|(r, p)| {
                (self.world.bodies[r.body].translation() - *p).length() >= REST_REANCHOR_M
            })
    }

    fn braked_at_rest(&self) -> bool {
        let b = &self.world.bodies[self.rb().body];
        self.rb().tracks.iter().all(|t| t.holds_belt())
            && b.linvel().length() < STICK_SPEED_MPS
            && b.angvel().length() < STICK_RATE_RAD_S
    }

    /// Moves the flat-ground tile under the robots (`terrain::GROUND_RECENTRE_M`): under their
    /// chassis' centre.
    fn recentre_ground_tile(&mut self) {
        if let Some(tile) = self.ground_tile {
            let (x, y) = self.chassis_centre_local();
            crate::terrain::TerrainModel::recentre_ground_tile(&mut self.world, tile, x, y);
        }
    }

    /// Stops a world whose robots have spread further apart than it holds exactly
    /// ([`crate::model::MAX_ROBOT_SPREAD_M`]).
    fn check_spread(&self) -> Result<()> {
        if self.robots.len() < 2 {
            return Ok(());
        }
        let (lo, hi) = self.chassis_extent_local();
        let spread = (hi.0 - lo.0).max(hi.1 - lo.1);
        if spread <= crate::model::MAX_ROBOT_SPREAD_M {
            return Ok(());
        }
        Err(Error::Limit {
            time_s: self.time,
            what: format!(
                "the robots ({}) are {spread:.2} m apart in x or y, more than the {} m one world \
                 holds exactly (Rapier's f32 around one floating origin): keep the robots \
                 closer, or run them in separate scenarios",
                self.robot_names().join(", "),
                crate::model::MAX_ROBOT_SPREAD_M
            ),
        })
    }

    /// Stops a run that blew up: NaN, a body of robot `k` flung off, or one that left the
    /// world.
    fn check_stability(&self, k: usize) -> Result<()> {
        // Names are only formatted when something is wrong: this runs every step.
        let r = &self.robots[k];
        let handles = std::iter::once(r.body).chain(r.flippers.iter().map(|f| f.body));
        for (i, h) in handles.enumerate() {
            let b = &self.world.bodies[h];
            let p = b.position();
            let v = b.linvel();
            let bad = if !p.is_finite() || !v.is_finite() || !b.angvel().is_finite() {
                Some("has a non-finite position or velocity (NaN)".to_string())
            } else if v.length() > MAX_SPEED_MPS {
                Some(format!(
                    "moves at {:.1} m/s (limit {MAX_SPEED_MPS} m/s): it was flung off",
                    v.length()
                ))
            } else if b.angvel().length() > MAX_ANGULAR_SPEED_RAD_S {
                Some(format!(
                    "spins at {:.1} rad/s (limit {MAX_ANGULAR_SPEED_RAD_S} rad/s): the solver \
                     made energy (a time step or solver iterations too coarse for this load: \
                     `tracksim validate --accuracy` with the file's setting tells)",
                    b.angvel().length()
                ))
            } else if p.translation.z < -100.0 {
                Some("fell below z = -100 m: it left the world".to_string())
            } else {
                None
            };
            if let Some(what) = bad {
                let part = match i {
                    0 => "body".to_string(),
                    _ => format!("flipper {}", r.flipper_names[i - 1]),
                };
                return Err(Error::Unstable {
                    time_s: self.time,
                    body: if self.robots.len() > 1 {
                        format!("{} of robot `{}`", part, r.name)
                    } else {
                        part
                    },
                    what,
                });
            }
        }
        Ok(())
    }
}
