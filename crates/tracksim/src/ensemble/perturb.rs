//! The ensemble's perturbation model ([`Perturbations`], [`Member`]): what is perturbed, by how
//! much, from which seed. docs/ENSEMBLE.md says why these and these sizes.

use crate::error::{Error, Result, SpecIssue};
use crate::model::{MAX_ORDER_SALT, Overrides, Scenario, ScenarioTemplate, StartOffset};
use rand_core::SeedableRng;
use rand_distr::{Distribution, Uniform};

/// Most members of one ensemble.
pub const MAX_MEMBERS: usize = 1024;

/// The sizes of the perturbations every member but the nominal one draws.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Perturbations {
    /// Half-width of the uniform start offset in x and in y (each drawn), m. Default 1 mm:
    /// less than anyone places a real robot, far more than f32 rounding at a few metres.
    pub start_m: f64,
    /// Half-width of the uniform start yaw offset, degrees (a key in degrees, as in files).
    /// Default 0.05 deg: 0.4 mm at the end of a 0.5 m track.
    pub yaw_deg: f64,
    /// Whether members also change the solver's order (`simulation.order_salt` = member
    /// index): inert colliders that touch nothing but reorder Rapier's contact constraints.
    pub solver_order: bool,
}

impl Default for Perturbations {
    fn default() -> Self {
        Perturbations {
            start_m: 1e-3,
            yaw_deg: 0.05,
            solver_order: true,
        }
    }
}

/// One robot's start offset in a member of an ensemble of several robots.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RobotOffset {
    /// Start offset in x, m.
    pub dx_m: f64,
    /// Start offset in y, m.
    pub dy_m: f64,
    /// Start yaw offset, degrees.
    pub dyaw_deg: f64,
}

/// One member's perturbation. Member 0 is the scenario as written (all zero).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Member {
    /// Index in the ensemble, from 0.
    pub index: usize,
    /// Start offset in x, m.
    pub dx_m: f64,
    /// Start offset in y, m.
    pub dy_m: f64,
    /// Start yaw offset, degrees.
    pub dyaw_deg: f64,
    /// `simulation.order_salt` of the member.
    pub order_salt: usize,
    /// In a world of several robots, each robot's start offset by its index in the file
    /// (robot 0's is `dx_m`, `dy_m`, `dyaw_deg`; the others draw their own); empty for one
    /// robot.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub robots: Vec<RobotOffset>,
}

impl Perturbations {
    /// Refuses sizes that are not small perturbations: negative, not finite, or larger than
    /// 0.1 m / 5 deg (an ensemble measures sensitivity, it is not a sweep).
    pub fn check(&self, members: usize) -> Result<()> {
        let mut issues = Vec::new();
        if !(2..=MAX_MEMBERS).contains(&members) {
            issues.push(SpecIssue::new(
                "--ensemble",
                format!("must be from 2 to {MAX_MEMBERS} members, got {members}"),
            ));
        }
        if !(self.start_m.is_finite() && (0.0..=0.1).contains(&self.start_m)) {
            issues.push(SpecIssue::new(
                "--ensemble-start-mm",
                format!(
                    "must be from 0 to 100 mm (a perturbation, not a sweep: use `tracksim sweep` for wider ranges), got {} mm",
                    self.start_m * 1e3
                ),
            ));
        }
        if !(self.yaw_deg.is_finite() && (0.0..=5.0).contains(&self.yaw_deg)) {
            issues.push(SpecIssue::new(
                "--ensemble-yaw-deg",
                format!(
                    "must be from 0 to 5 deg (a perturbation, not a sweep), got {}",
                    self.yaw_deg
                ),
            ));
        }
        if issues.is_empty() {
            Ok(())
        } else {
            Err(Error::Settings {
                what: "ensemble settings".into(),
                issues,
            })
        }
    }

    /// Member `k` of the ensemble seeded `seed`: member 0 is unperturbed; member k >= 1 draws
    /// its offsets uniformly from a PCG stream of its own (`seed`, k), so adding members never
    /// changes the earlier ones.
    pub fn member(&self, seed: u64, k: usize) -> Member {
        if k == 0 {
            return Member {
                index: 0,
                dx_m: 0.0,
                dy_m: 0.0,
                dyaw_deg: 0.0,
                order_salt: 0,
                robots: Vec::new(),
            };
        }
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(
            seed ^ (k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15),
        );
        let mut draw = |half: f64| {
            if half > 0.0 {
                Uniform::new_inclusive(-half, half).map_or(0.0, |u| u.sample(&mut rng))
            } else {
                0.0
            }
        };
        let dx_m = draw(self.start_m);
        let dy_m = draw(self.start_m);
        let dyaw_deg = draw(self.yaw_deg);
        Member {
            index: k,
            dx_m,
            dy_m,
            dyaw_deg,
            order_salt: if self.solver_order {
                k % (MAX_ORDER_SALT + 1)
            } else {
                0
            },
            robots: Vec::new(),
        }
    }

    /// Member `k` of the ensemble seeded `seed` of a world of `robots` robots: each robot's
    /// start moved and turned on its own (robot 0 by [`Perturbations::member`]'s draws, robot
    /// r >= 1 from a PCG stream of its own (`seed`, k, r)), so that what the robots do to each
    /// other is perturbed too; a shift of the whole world would change nothing (translation).
    /// Member 0 is unperturbed.
    pub fn team_member(&self, seed: u64, k: usize, robots: usize) -> Member {
        let mut m = self.member(seed, k);
        m.robots = (0..robots)
            .map(|r| {
                if r == 0 || k == 0 {
                    return RobotOffset {
                        dx_m: m.dx_m,
                        dy_m: m.dy_m,
                        dyaw_deg: m.dyaw_deg,
                    };
                }
                let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(
                    seed ^ (k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
                        ^ (r as u64).wrapping_mul(0xD1B5_4A32_D192_ED03),
                );
                let mut draw = |half: f64| {
                    if half > 0.0 {
                        Uniform::new_inclusive(-half, half).map_or(0.0, |u| u.sample(&mut rng))
                    } else {
                        0.0
                    }
                };
                RobotOffset {
                    dx_m: draw(self.start_m),
                    dy_m: draw(self.start_m),
                    dyaw_deg: draw(self.yaw_deg),
                }
            })
            .collect();
        m
    }
}

impl Member {
    /// This member's perturbation of `base` as overrides of the file's keys: the start moved
    /// and turned (`vehicle.x_m`, `y_m`, `yaw_deg`) and `simulation.order_salt`, each left out
    /// where it changes nothing (member 0 has none).
    pub fn overrides(&self, base: &Scenario) -> Overrides {
        let moved = self.dx_m != 0.0 || self.dy_m != 0.0 || self.dyaw_deg != 0.0;
        let team = !self.robots.is_empty();
        let robots_moved = self
            .robots
            .iter()
            .any(|o| o.dx_m != 0.0 || o.dy_m != 0.0 || o.dyaw_deg != 0.0);
        Overrides {
            start_offset: (moved && !team).then_some(StartOffset {
                x_m: self.dx_m,
                y_m: self.dy_m,
                yaw_deg: self.dyaw_deg,
            }),
            robot_offsets: if robots_moved {
                self.robots
                    .iter()
                    .map(|o| StartOffset {
                        x_m: o.dx_m,
                        y_m: o.dy_m,
                        yaw_deg: o.dyaw_deg,
                    })
                    .collect()
            } else {
                Vec::new()
            },
            order_salt: (self.order_salt != base.solver.order_salt).then_some(self.order_salt),
            ..Overrides::default()
        }
    }

    /// The scenario of this member: `base` (the template's scenario for `base.seed`) compiled
    /// again from the template with [`Member::overrides`], every key checked as the file's.
    pub fn scenario(
        &self,
        t: &ScenarioTemplate,
        base: &Scenario,
    ) -> crate::error::Result<Scenario> {
        t.instantiate_overridden(base.seed, &self.overrides(base))
    }

    /// The file keys that reproduce this member with `tracksim run` (added to the scenario's
    /// own values): `vehicle.x_m`, `vehicle.y_m`, `vehicle.yaw_deg`, `simulation.order_salt`.
    pub fn keys(&self, sc: &Scenario) -> Vec<(String, f64)> {
        if !self.robots.is_empty() {
            let mut keys = Vec::new();
            for (r, o) in self.robots.iter().enumerate() {
                let v = sc.robot_view(r);
                keys.push((format!("vehicles[{r}].vehicle.x_m"), v.start_xy.0 + o.dx_m));
                keys.push((format!("vehicles[{r}].vehicle.y_m"), v.start_xy.1 + o.dy_m));
                keys.push((
                    format!("vehicles[{r}].vehicle.yaw_deg"),
                    v.start_yaw.to_degrees() + o.dyaw_deg,
                ));
            }
            keys.push(("simulation.order_salt".into(), self.order_salt as f64));
            return keys;
        }
        vec![
            ("vehicle.x_m".into(), sc.start_xy.0 + self.dx_m),
            ("vehicle.y_m".into(), sc.start_xy.1 + self.dy_m),
            (
                "vehicle.yaw_deg".into(),
                sc.start_yaw.to_degrees() + self.dyaw_deg,
            ),
            ("simulation.order_salt".into(), self.order_salt as f64),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn members_are_seeded_bounded_and_independent_of_the_count() {
        let p = Perturbations::default();
        assert_eq!(p.member(7, 0).dx_m, 0.0);
        let a: Vec<Member> = (0..16).map(|k| p.member(7, k)).collect();
        let b: Vec<Member> = (0..16).map(|k| p.member(7, k)).collect();
        assert_eq!(a, b);
        for m in &a[1..] {
            assert!(m.dx_m.abs() <= 1e-3 && m.dy_m.abs() <= 1e-3 && m.dyaw_deg.abs() <= 0.05);
        }
        // Not all alike, and a different seed gives different members.
        assert!(a[1].dx_m != a[2].dx_m);
        assert!(p.member(8, 1).dx_m != a[1].dx_m);
        // They spread over the interval: the 15 draws of x reach past half of it both ways.
        let max = a[1..].iter().map(|m| m.dx_m).fold(f64::MIN, f64::max);
        let min = a[1..].iter().map(|m| m.dx_m).fold(f64::MAX, f64::min);
        assert!(max > 0.5e-3 && min < -0.5e-3, "{min} {max}");
    }

    #[test]
    fn bad_sizes_are_refused_naming_the_flag() {
        let p = Perturbations {
            start_m: -1.0,
            ..Default::default()
        };
        let e = p.check(8).unwrap_err().to_string();
        assert!(e.contains("--ensemble-start-mm"), "{e}");
        let e = Perturbations::default().check(1).unwrap_err().to_string();
        assert!(e.contains("--ensemble"), "{e}");
    }
}
