//! A robot of a scenario seen as the one robot of its world ([`Scenario::robot_view`]), and
//! the robot part of a compiled one-robot scenario ([`RobotModel::of`]).

use super::DEFAULT_ROBOT_NAME;
use super::scenario::{Scenario, ScenarioData};
use super::team::RobotModel;

impl RobotModel {
    /// The robot part of a compiled one-robot scenario, under `name`.
    pub(crate) fn of(name: &str, sc: &Scenario) -> Self {
        RobotModel {
            name: name.to_string(),
            vehicle: sc.vehicle.clone(),
            start_xy: sc.start_xy,
            start_z: sc.start_z,
            start_yaw: sc.start_yaw,
            start_pitch: sc.start_pitch,
            commands: sc.commands.clone(),
            outcome: sc.outcome.clone(),
            drawbar: sc.drawbar.clone(),
            expect: sc.expect.clone(),
        }
    }
}

impl Scenario {
    /// Robots in the world (1 for a one-robot file).
    pub fn robot_count(&self) -> usize {
        self.team.as_ref().map_or(1, |t| t.robots.len())
    }

    /// The robots' names, in file order ([`DEFAULT_ROBOT_NAME`] for a one-robot file).
    pub fn robot_names(&self) -> Vec<String> {
        match &self.team {
            Some(t) => t.robots.iter().map(|r| r.name.clone()).collect(),
            None => vec![DEFAULT_ROBOT_NAME.to_string()],
        }
    }

    /// Robot `k`'s own scenario: this world with robot `k` as its one robot (its vehicle, start,
    /// commands, outcome, drawbar and `[expect]`), what every one-robot layer reads. For a
    /// one-robot file (k = 0) a copy of the scenario. Panics if `k` is out of range.
    pub fn robot_view(&self, k: usize) -> Scenario {
        let Some(team) = &self.team else {
            assert_eq!(k, 0, "a one-robot scenario has robot 0 only");
            return self.clone();
        };
        let r = &team.robots[k];
        Scenario(ScenarioData {
            vehicle: r.vehicle.clone(),
            start_xy: r.start_xy,
            start_z: r.start_z,
            start_yaw: r.start_yaw,
            start_pitch: r.start_pitch,
            commands: r.commands.clone(),
            outcome: r.outcome.clone(),
            drawbar: r.drawbar.clone(),
            expect: r.expect.clone(),
            team: None,
            ..self.clone_world()
        })
    }

    /// The scenario without its team (cheap enough: the world's parts are cloned once per robot
    /// view, never per step).
    fn clone_world(&self) -> ScenarioData {
        ScenarioData {
            team: None,
            ..self.0.clone()
        }
    }
}
