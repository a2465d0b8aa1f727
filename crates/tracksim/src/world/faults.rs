//! `impl Simulation`: faults applied to the selected robot (issue 43): a track stopped (its
//! belt held at 0 m/s whatever is commanded) or unpowered (its drive lets go: the belt
//! free-wheels), a flipper jammed (held at the angle it has), each cleared by `"ok"`, after
//! which the latest command applies again; and the world's low-friction patch (the contact
//! hook's stage in `friction_patch.rs`). The setters of `simulation.rs` consult the state
//! (`fault_state.rs`); a robot without faults steps exactly as before.

use super::Simulation;
use super::fault_state::BeltCommand;
use crate::model::{Faults, FrictionPatch, TrackFault};

impl Simulation {
    /// Sets or clears the faults `f` names on the selected robot.
    pub fn apply_faults(&mut self, f: &Faults) {
        for (i, t) in f.track.iter().enumerate() {
            if let Some(t) = t {
                self.set_track_fault(i, *t);
            }
        }
        for (i, j) in f.flipper_jammed.iter().enumerate() {
            if let Some(j) = j {
                self.set_flipper_jammed(i, *j);
            }
        }
        if let Some(p) = f.patch {
            self.set_friction_patch(p);
        }
    }

    /// Puts a low-friction patch on the ground (replacing the one before) or removes it
    /// (`None`): the world's, whichever robot is selected. Ground contacts of every robot whose
    /// contact point lies inside it take its friction coefficient from the next step on.
    pub fn set_friction_patch(&mut self, patch: Option<FrictionPatch>) {
        if patch.is_some() && !self.ground_hooked {
            super::friction_patch::hook_the_ground(&mut self.world);
            self.ground_hooked = true;
        }
        self.friction_patch = patch;
        self.patch_log.push(super::PatchChange {
            t: self.time,
            patch,
        });
    }

    /// Every change of the low-friction patch since the world was built (or reset), in
    /// order: the run's patch timeline (`scene.json` `patches`).
    pub fn patch_changes(&self) -> &[super::PatchChange] {
        &self.patch_log
    }

    /// The low-friction patch on the ground, if one is in force.
    pub fn friction_patch(&self) -> Option<FrictionPatch> {
        self.friction_patch
    }

    /// The fault of the selected robot's track `i`.
    pub fn track_fault(&self, i: usize) -> TrackFault {
        self.rb().faults.track[i]
    }

    /// Whether the selected robot's flipper `i` is jammed.
    pub fn flipper_jammed(&self, i: usize) -> bool {
        self.rb().faults.jammed[i]
    }

    /// Sets track `i`'s fault: stopped holds its belt at 0, unpowered lets its drive go, ok
    /// gives it back its latest command.
    pub fn set_track_fault(&mut self, i: usize, fault: TrackFault) {
        let k = self.focus;
        let rb = &mut self.robots[k];
        rb.faults.track[i] = fault;
        let unpowered = fault == TrackFault::Unpowered;
        rb.tracks[i].set_unpowered(&mut self.world, unpowered);
        if fault == TrackFault::Stopped {
            rb.tracks[i].set_belt_speed(&mut self.world, 0.0);
        } else {
            match rb.faults.wanted[i] {
                BeltCommand::Speed(v) => rb.tracks[i].set_belt_speed(&mut self.world, v),
                BeltCommand::Motor(m) => rb.tracks[i].set_motor_command(&mut self.world, m),
            }
        }
    }

    /// Jams flipper `i` at the angle it has now (its motor holds it there; targets given
    /// meanwhile are kept for later), or frees it (its latest target applies again).
    pub fn set_flipper_jammed(&mut self, i: usize, jammed: bool) {
        let k = self.focus;
        if jammed == self.robots[k].faults.jammed[i] {
            return;
        }
        let hold = if jammed {
            let now = self.flipper_angle(i);
            let fl = &self.robots[k].flippers[i];
            self.robots[k].faults.wanted_flipper[i] = fl.target;
            now
        } else {
            self.robots[k].faults.wanted_flipper[i]
        };
        self.robots[k].faults.jammed[i] = false;
        self.set_flipper_angle(i, hold);
        self.robots[k].faults.jammed[i] = jammed;
    }
}
