//! The drawbar's pull on the chassis, on `Simulation`.

use super::Simulation;
use super::drawbar::DrawbarState;
use crate::check::f;
use crate::model::Drawbar;
use glam::DVec3;

impl Simulation {
    /// The drawbar of the scenario at the placed start pose (None without `[drawbar]`).
    pub(crate) fn start_drawbar(&self) -> Option<DrawbarState> {
        let model = self.rb().view.drawbar.clone()?;
        let (s, c) = self.rb().view.start_yaw.sin_cos();
        Some(DrawbarState {
            anchor: self.hitch_world(&model),
            heading: DVec3::new(c, s, 0.0),
            model,
            pull: 0.0,
        })
    }

    /// The hitch point in the world frame, m.
    fn hitch_world(&self, d: &Drawbar) -> DVec3 {
        let b = &self.world.bodies[self.robots[self.focus].body];
        let p = b.position().transform_point(f(d.hitch));
        self.origin() + DVec3::new(p.x as f64, p.y as f64, p.z as f64)
    }

    /// Sets the drawbar's force on the chassis for the coming step (at time `self.time`).
    pub(crate) fn apply_drawbar(&mut self) {
        let Some(state) = &self.robots[self.focus].drawbar else {
            return;
        };
        let hitch = self.hitch_world(&state.model);
        let forward = (hitch - state.anchor).dot(state.heading);
        let pull = state.model.pull(self.time, forward);
        let force = f(-state.heading * pull);
        let point = f(hitch - self.origin());
        let b = &mut self.world.bodies[self.robots[self.focus].body];
        b.reset_forces(false);
        b.add_force_at_point(force, point, false);
        if let Some(s) = &mut self.robots[self.focus].drawbar {
            s.pull = pull;
        }
    }

    /// The drawbar's pull in the last step, N (None without a drawbar).
    pub fn drawbar_pull(&self) -> Option<f64> {
        self.robots[self.focus].drawbar.as_ref().map(|d| d.pull)
    }
}
