//! A scenario file's `[[commands]]` as one source of controls: each command holds from its
//! `t_s` until the next.

use crate::model::{Command, Controls};

/// The commands of a scenario in time order, handed out as they fall due.
#[derive(Clone, Debug)]
pub struct Timeline {
    commands: Vec<Command>,
    next: usize,
}

impl Timeline {
    /// A timeline of `commands` (sorted by time, as compiled scenarios hold them).
    pub fn new(commands: &[Command]) -> Self {
        Timeline {
            commands: commands.to_vec(),
            next: 0,
        }
    }

    /// The controls of every command whose time has come by `t` s and that was not handed out
    /// yet, in order (usually none or one).
    pub fn due(&mut self, t: f64) -> Vec<Controls> {
        let mut out = Vec::new();
        while self.next < self.commands.len() && self.commands[self.next].t <= t + 1e-9 {
            out.push(self.commands[self.next].controls.clone());
            self.next += 1;
        }
        out
    }

    /// Starts again from the first command.
    pub fn rewind(&mut self) {
        self.next = 0;
    }
}
