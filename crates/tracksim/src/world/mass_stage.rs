//! The mass stage on `Simulation`: the link-mass floor taken back from the chassis, and the mass
//! report.

use super::Simulation;
use super::mass::{MIN_PARENT_MASS_FRACTION, MassReport, PartMass};
use crate::error::{Error, Result};
use crate::model::{Parent, Scenario, TrackModel};
use glam::DVec3;
use rapier3d::prelude::*;

impl Simulation {
    /// Takes the mass the track methods added back from the tracks' parents (see the module
    /// docs).
    pub(crate) fn conserve_mass(&mut self, sc: &Scenario) -> Result<()> {
        super::build::refresh_queries(&mut self.world);
        let parents: Vec<RigidBodyHandle> = std::iter::once(self.robots[self.focus].body)
            .chain(self.robots[self.focus].flippers.iter().map(|f| f.body))
            .collect();
        // Flippers first: their tracks' excess is carried to the chassis.
        let (mut carry, mut carry_moment) = (0.0, DVec3::ZERO);
        for (pi, &ph) in parents.iter().enumerate().rev() {
            let (mut excess, mut excess_moment) = (carry, carry_moment);
            (carry, carry_moment) = (0.0, DVec3::ZERO);
            let parent_pose = *self.world.bodies[ph].position();
            for (ti, t) in sc.vehicle.tracks.iter().enumerate() {
                let on_this = match t.parent {
                    Parent::Body => pi == 0,
                    Parent::Flipper(i) => pi == i + 1,
                };
                if !on_this {
                    continue;
                }
                let (m, moment) =
                    mass_moment(&self.world, &self.robots[self.focus].tracks[ti].bodies());
                let file_c = parent_pose.transform_point(crate::check::f(belt_centroid(t)));
                let file_c = DVec3::new(file_c.x as f64, file_c.y as f64, file_c.z as f64);
                // A method without bodies of its own (constraint to ground) gets a negative
                // excess: the parent takes the belt's mass at the belt's centre.
                excess += m - t.belt_mass;
                excess_moment += moment - file_c * t.belt_mass;
            }
            if excess.abs() < 1e-12 {
                continue;
            }
            if pi > 0 {
                // The chassis pays for its flippers' tracks (see the module docs).
                (carry, carry_moment) = (excess, excess_moment);
                continue;
            }
            self.give_back(ph, excess, excess_moment, sc)?;
        }
        Ok(())
    }

    /// Removes `excess` kg with world moment `excess_moment` kg m from the chassis `ph`.
    fn give_back(
        &mut self,
        ph: RigidBodyHandle,
        excess: f64,
        excess_moment: DVec3,
        sc: &Scenario,
    ) -> Result<()> {
        let (file_mass, file_inertia) = (sc.vehicle.body.mass, sc.vehicle.body.inertia);
        let b = &self.world.bodies[ph];
        let m = b.mass() as f64;
        let c = b.center_of_mass();
        let c = DVec3::new(c.x as f64, c.y as f64, c.z as f64);
        let m_new = m - excess;
        if m_new < MIN_PARENT_MASS_FRACTION * file_mass {
            return Err(Error::Invalid {
                path: sc.source.clone().unwrap_or_default(),
                issues: vec![crate::error::SpecIssue::new(
                    "simulation.min_link_mass_kg",
                    format!(
                        "the floor {} kg adds {excess:.3} kg to the tracks, more than {:.0} % of the body's {file_mass} kg can give back; lower min_link_mass_kg or raise the belts' belt_mass_kg",
                        sc.solver.min_link_mass,
                        100.0 * (1.0 - MIN_PARENT_MASS_FRACTION)
                    ),
                )],
            });
        }
        // The chassis's new centre of mass keeps the vehicle's where the file puts it.
        let c_new = (c * m - excess_moment) / m_new;
        let pose = *b.position();
        let local = pose.inverse_transform_point(crate::check::f(c_new));
        let inertia = file_inertia * (m_new / file_mass);
        let props = MassProperties::new(local, m_new as f32, crate::check::f(inertia));
        self.world.bodies[ph].set_additional_mass_properties(props, true);
        Ok(())
    }

    /// Simulated and file masses of every part and in all, kg.
    pub fn mass_report(&self) -> MassReport {
        let v = &self.rb().view.vehicle;
        let mass = |h: RigidBodyHandle| self.world.bodies[h].mass() as f64;
        let mut parts = vec![PartMass {
            part: "body".into(),
            file_kg: v.body.mass,
            simulated_kg: mass(self.robots[self.focus].body),
        }];
        for (f, rt) in v.flippers.iter().zip(&self.robots[self.focus].flippers) {
            parts.push(PartMass {
                part: format!("flipper {}", f.name),
                file_kg: f.mass,
                simulated_kg: mass(rt.body),
            });
        }
        for (t, rt) in v.tracks.iter().zip(&self.robots[self.focus].tracks) {
            parts.push(PartMass {
                part: format!("track {}", t.name),
                file_kg: t.belt_mass,
                // `+ 0.0`: an empty sum is -0.0.
                simulated_kg: rt.bodies().into_iter().map(mass).sum::<f64>() + 0.0,
            });
        }
        let (m, moment) = mass_moment(&self.world, &self.vehicle_bodies());
        let c = moment / m.max(1e-12);
        let local = self.world.bodies[self.robots[self.focus].body]
            .position()
            .inverse_transform_point(crate::check::f(c));
        MassReport {
            centre_of_mass_body_m: [local.x as f64, local.y as f64, local.z as f64],
            total_file_kg: parts.iter().map(|p| p.file_kg).sum(),
            total_simulated_kg: parts.iter().map(|p| p.simulated_kg).sum(),
            parts,
        }
    }
}

/// Mass, kg, and mass-weighted sum of world centres of mass, kg m, of `bodies`.
fn mass_moment(world: &PhysicsWorld, bodies: &[RigidBodyHandle]) -> (f64, DVec3) {
    bodies.iter().fold((0.0, DVec3::ZERO), |(m, s), h| {
        let b = &world.bodies[*h];
        let c = b.center_of_mass();
        let mb = b.mass() as f64;
        (
            m + mb,
            s + DVec3::new(c.x as f64, c.y as f64, c.z as f64) * mb,
        )
    })
}

/// Centre of the belt's mass as the file distributes it (evenly along the loop), parent frame.
fn belt_centroid(t: &TrackModel) -> DVec3 {
    let n = 512;
    let l = t.path.length();
    (0..n)
        .map(|i| t.path.frame_at(l * (i as f64 + 0.5) / n as f64).origin)
        .sum::<DVec3>()
        / n as f64
}
