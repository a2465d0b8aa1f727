//! Contact compliance of the tracks' rubber (`[tracks.compliance]`, issue 11.6): the build
//! stage that tags grouser and belt colliders with their spring, and the contact modification
//! that makes a tagged contact a spring and damper.
//!
//! Rapier's solver is velocity-level and its contact softness is global (one natural frequency
//! for every contact), so a stiffness per part is made in the contact hook, with the mechanism
//! the contact slop uses: the solver contacts of a manifold (one grouser or belt link against
//! one terrain piece) are told that the part may sink `d = F_f / k` into the terrain, and the
//! solver only pushes back what is deeper. `F_f` is the manifold's normal force (the impulses
//! the solver applied in the previous step, divided by dt), low-pass filtered with the time
//! constant `tau = c / k` and kept in the manifold's `user_data` (the bits of an `f32`).
//! While the solver holds the part at `d` (its own regularisation in series), the filter
//! `tau F_f' = F - F_f` gives `F = F_f + tau F_f' = k d + c d'`: a Kelvin-Voigt element of
//! stiffness `k` and damping `c` (stable for any `tau >= dt`; a shorter `tau` acts as `dt`).

use crate::model::{ContactSpring, TrackModel};
use crate::tracks::{Track, compliance_tag};
use rapier3d::prelude::*;

/// A contact spring in the solver's units.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SolverSpring {
    /// Stiffness, N/m.
    stiffness: f32,
    /// Filter gain per step, `dt / tau` capped at 1.
    gain: f32,
}

impl SolverSpring {
    fn new(s: ContactSpring, dt: f64) -> Self {
        let tau = s.relaxation_time();
        SolverSpring {
            stiffness: s.stiffness as f32,
            gain: if tau > dt { (dt / tau) as f32 } else { 1.0 },
        }
    }
}

/// Compliance stage: tags every grouser and belt collider of a track with a compliance with
/// its spring (user data [`compliance_tag`], the contact hook on), appending the springs to
/// the world's table `springs` (a tag's index is its place there: every robot's in one table). Colliders a track tagged for itself keep their tag (and stay rigid).
pub(crate) fn tag_compliance(
    world: &mut PhysicsWorld,
    models: &[TrackModel],
    tracks: &[Box<dyn Track>],
    dt: f64,
    springs: &mut Vec<SolverSpring>,
) {
    for (model, track) in models.iter().zip(tracks) {
        let c = model.compliance;
        if c.is_rigid() {
            continue;
        }
        let grousers = track.grouser_colliders();
        let mut index = |s: Option<ContactSpring>| {
            s.map(|s| {
                springs.push(SolverSpring::new(s, dt));
                springs.len() - 1
            })
        };
        let (gi, bi) = (index(c.grousers), index(c.belt));
        for body in track.bodies() {
            let colliders: Vec<ColliderHandle> = world.bodies[body].colliders().to_vec();
            for h in colliders {
                let i = if grousers.contains(&h) { gi } else { bi };
                let col = &mut world.colliders[h];
                if let (Some(i), 0) = (i, col.user_data) {
                    col.user_data = compliance_tag(i);
                    col.set_active_hooks(ActiveHooks::MODIFY_SOLVER_CONTACTS);
                }
            }
        }
    }
}

/// Lets the manifold's part sink by its spring's deflection under the filtered normal force
/// (see the module docs). `dt` in s.
pub(crate) fn apply_compliance(ctx: &mut ContactModificationContext, s: SolverSpring, dt: f32) {
    let Some(m) = ctx.rigid_mut() else {
        return;
    };
    // The impulses the solver applied last step to the points still in the manifold.
    let impulse: f32 = m.manifold.points.iter().map(|p| p.data.impulse).sum();
    let force = (impulse / dt).max(0.0);
    let previous = f32::from_bits(*m.user_data);
    let previous = if previous.is_finite() { previous } else { 0.0 };
    let filtered = previous + s.gain * (force - previous);
    *m.user_data = filtered.to_bits();
    let deflection = filtered / s.stiffness;
    for c in m.solver_contacts.iter_mut() {
        c.dist += deflection;
    }
}
