//! The contact hook's last stage (issue 44): a speculative contact manifold that cannot act in
//! this step is not sent to the solver.
//!
//! Rapier gives the solver every contact point within the prediction distance (2 cm) of the
//! other shape. A point `dist` apart is a one-sided constraint "close the gap by at most
//! `dist` in this step": it pushes only if the bodies would close more than `dist` within
//! the step, i.e. if their closing speed exceeds `dist / dt` (1 m/s per mm at dt = 1 ms). A
//! grouser hovering 5 mm above a stair's tread at belt speed costs the solver as much as one
//! carrying the robot, and gives nothing. On the bundled stairs about a third of the
//! vehicle's manifolds are such; the solver is ~75 % of a step.
//!
//! A manifold between a vehicle part and the fixed ground is dropped when, for every one of
//! its solver contacts,
//! - the gap exceeds [`CULL_MARGIN_M`] plus twice what the contact closes in a step at the
//!   closing speed the bodies have when the hook runs: the margin covers what the step's other
//!   impulses can add to that speed (3 mm: 3 m/s at dt = 1 ms);
//! - and the contact carries no impulse from earlier steps (its normal, friction and twist
//!   impulses stored for the warm start are all zero), so dropping it leaves no stale warm
//!   start behind: a contact that pushed in the last step is solved once more (to zero, as it
//!   opens) before it may be dropped.
//!
//! Such a constraint's impulse is zero: so are its friction's (bounded by the friction
//! coefficient times the normal impulse). The check mode
//! (`Simulation::set_cull_check`, `world/cull_check.rs`) keeps every manifold and
//! records the ones the cull would drop, to prove after the step that the solver gave them
//! nothing (`tests/suite/issue_44_cull.rs`: none of 1.4 million over whole runs up and down
//! the stairs, the stairs course and a ramp course). Dropping them still changes the solver's
//! order of visits, so trajectories part at f32 rounding; a verdict that is a coin toss can
//! then fall the other way (the bollards task got over its first row in 3 of 8 perturbed
//! starts without the cull, 0 of 8 with it). Hence `simulation.cull_speculative_contacts` is
//! off by default, and the bundled stairs, whose climb holds in 16 of 16 perturbed starts
//! either way, turn it on (docs/DESIGN.md).
//!
//! Only pairs that ask for the contact hook pass through it: vehicles with a contact slop
//! (the bundled stairs), compliance, a friction patch. Not soil: its after-step update reads
//! the manifolds it let sink (with the cull, line-tip grousers on sand drove at 0.145 m/s
//! instead of 0.265). Asking for the hook costs a pair Rapier's contact recycling: hooking
//! the belts for the cull alone made the PackBot's flat-ground step 4 % cheaper, every vehicle
//! collider 2 % dearer, so nothing is hooked for the cull alone.

use rapier3d::geometry::NEW_CONTACT_BIT;
use rapier3d::prelude::*;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};

/// Gap beyond which a contact that is not closing cannot act within a step, m: what one step
/// of 1 ms closes at 3 m/s, the most the step's other impulses are taken to add to a contact
/// point's closing speed. At 1 mm one manifold of 244,000 the cull would have dropped on the
/// way down the stairs (a landing, whose impacts turn the chassis within the step) got
/// 0.38 N s from the solver; at 3 mm none of 1.4 million did on the stairs and ramp courses.
pub const CULL_MARGIN_M: f32 = 0.003;

/// A manifold the cull would have dropped (check mode): its pair and the sub-shapes of a
/// composite shape (0 for a single shape).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CullMark {
    /// The pair's first collider.
    pub collider1: ColliderHandle,
    /// The pair's second collider.
    pub collider2: ColliderHandle,
    /// The sub-shape of the first collider.
    pub subshape1: u32,
    /// The sub-shape of the second collider.
    pub subshape2: u32,
}

/// The cull's state in a world: whether it is on, what it dropped, its check mode.
pub(crate) struct CullState {
    /// `simulation.cull_speculative_contacts`.
    on: bool,
    /// Manifolds culled since the start.
    pub(super) culled: AtomicU64,
    /// The check mode (`Simulation::set_cull_check`, `world/cull_check.rs`):
    /// what the cull would have dropped since the marks were last taken.
    pub(super) check: Option<Mutex<Vec<CullMark>>>,
}

impl CullState {
    /// The state of a world whose file turns the cull on (`on`) or not.
    pub(crate) fn new(on: bool) -> Self {
        CullState {
            on,
            culled: AtomicU64::new(0),
            check: None,
        }
    }

    /// What the hook's stage does in the coming step.
    pub(crate) fn mode(&self) -> CullMode<'_> {
        match (&self.check, self.on) {
            (Some(marks), _) => CullMode::Check(marks),
            (None, true) => CullMode::On(&self.culled),
            (None, false) => CullMode::Off,
        }
    }
}

/// What the stage does with a manifold that cannot act.
pub(crate) enum CullMode<'a> {
    /// Keep it (`simulation.cull_speculative_contacts = false`).
    Off,
    /// Drop it, counting the drops.
    On(&'a AtomicU64),
    /// Keep it and record it (the check mode).
    Check(&'a Mutex<Vec<CullMark>>),
}

/// Whether the body `b` of a pair (`None`: a collider without a body) is fixed.
fn fixed(bodies: &RigidBodySet, b: Option<RigidBodyHandle>) -> bool {
    b.is_none_or(|b| bodies[b].is_fixed())
}

/// Whether the manifold of `ctx` (a pair of a moving body and the fixed ground) cannot act in
/// this step of `dt` s, see the module's documentation.
fn cannot_act(ctx: &mut ContactModificationContext, dt: f32) -> bool {
    let bodies: &RigidBodySet = ctx.bodies;
    let (b1, b2) = (ctx.rigid_body1, ctx.rigid_body2);
    if fixed(bodies, b1) == fixed(bodies, b2) {
        return false;
    }
    let Some(m) = ctx.rigid_mut() else {
        return false;
    };
    if m.solver_contacts.is_empty() {
        return false;
    }
    let n = *m.normal;
    let velocity = |b: Option<RigidBodyHandle>, p: Vector| {
        b.filter(|b| !bodies[*b].is_fixed())
            .map_or(Vector::ZERO, |b| bodies[b].velocity_at_point(p))
    };
    m.solver_contacts.iter().all(|c| {
        let id = (c.contact_id[0] & !NEW_CONTACT_BIT) as usize;
        let rested = m.manifold.points.get(id).is_some_and(|p| {
            p.data.impulse == 0.0
                && p.data.warmstart_impulse == 0.0
                && p.data.warmstart_twist_impulse == 0.0
                && p.data.warmstart_tangent_world == Vector::ZERO
        });
        let closing = (velocity(b1, c.anchor1) - velocity(b2, c.anchor2)).dot(n);
        rested && c.dist > CULL_MARGIN_M + 2.0 * dt * closing.max(0.0)
    })
}

/// The stage: drops (or, checking, records) the manifold of `ctx` if it cannot act.
pub(crate) fn cull_speculative(ctx: &mut ContactModificationContext, mode: &CullMode, dt: f32) {
    if matches!(mode, CullMode::Off) || !cannot_act(ctx, dt) {
        return;
    }
    let (collider1, collider2) = (ctx.collider1, ctx.collider2);
    let Some(m) = ctx.rigid_mut() else {
        return;
    };
    match mode {
        CullMode::Off => {}
        CullMode::On(count) => {
            m.solver_contacts.clear();
            count.fetch_add(1, Ordering::Relaxed);
        }
        CullMode::Check(marks) => {
            let mark = CullMark {
                collider1,
                collider2,
                subshape1: m.manifold.subshape1,
                subshape2: m.manifold.subshape2,
            };
            if let Ok(mut marks) = marks.lock() {
                marks.push(mark);
            }
        }
    }
}
