//! The race or team score of several robots on one course ([`Standings`]): each robot's
//! course score ([`CourseScore`]) ranked, and the team's by the world's rule.
//!
//! Ranking (the course's own scoring, lower `score_s` = time + penalties is better): robots
//! that completed every repetition first, by `score_s` (then by time); then the others by
//! progress (repetitions done, then gates passed of the repetition under way, more is better),
//! then by `score_s`; ties keep the file's order. A race (`outcome.team = "first"`) is won by
//! rank 1 if it completed; a team (`"all"`) has completed when every robot has, its score the sum
//! of the robots' `score_s` and its time the last robot's.

use super::course::CourseScore;
use crate::model::TeamRule;
use serde::Serialize;

/// A robot's line in the standings.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Standing {
    /// 1 for the best.
    pub rank: usize,
    /// The robot's name.
    pub name: String,
    /// `running`, `completed`, `time_limit` or `not_completed` (the course's status).
    pub status: &'static str,
    /// Repetitions completed.
    pub repetitions: u32,
    /// Gates passed of the repetition under way.
    pub gates_passed: usize,
    /// Time of the trial, s.
    pub time_s: f64,
    /// Faults of every kind.
    pub faults: u32,
    /// Penalty time, s.
    pub penalty_s: f64,
    /// `time_s + penalty_s`, s.
    pub score_s: f64,
}

/// Several robots' scores on one course, ranked, and the team's.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Standings {
    /// The course's name.
    pub course: String,
    /// The world's rule (`all`: a team; `first`: a race).
    pub rule: &'static str,
    /// Every robot, best first.
    pub robots: Vec<Standing>,
    /// Robots that completed the course.
    pub completed: usize,
    /// A race's winner (rank 1, once it completed).
    pub winner: Option<String>,
    /// A team's score once every robot completed: the sum of their `score_s`, s.
    pub team_score_s: Option<f64>,
    /// A team's time once every robot completed: the last robot's `time_s`, s.
    pub team_time_s: Option<f64>,
}

impl Standings {
    /// The standings of `scores` (robot name, its course score; `None`: no course) under
    /// `rule`; `None` when no robot has a course.
    pub fn of(rule: TeamRule, scores: &[(String, Option<CourseScore>)]) -> Option<Standings> {
        let course = scores.iter().find_map(|(_, c)| c.as_ref())?.name.clone();
        let mut lines: Vec<(usize, Standing)> = scores
            .iter()
            .enumerate()
            .filter_map(|(i, (name, c))| {
                let c = c.as_ref()?;
                Some((
                    i,
                    Standing {
                        rank: 0,
                        name: name.clone(),
                        status: c.status,
                        repetitions: c.repetitions_done,
                        gates_passed: if c.status == "completed" {
                            c.gates_total
                        } else {
                            c.next_gate
                        },
                        time_s: c.score.time_s,
                        faults: c.score.faults,
                        penalty_s: c.score.penalty_s,
                        score_s: c.score.score_s,
                    },
                ))
            })
            .collect();
        let done = |s: &Standing| s.status == "completed";
        lines.sort_by(|(i, a), (j, b)| {
            done(b)
                .cmp(&done(a))
                .then_with(|| {
                    if done(a) {
                        std::cmp::Ordering::Equal
                    } else {
                        (b.repetitions, b.gates_passed).cmp(&(a.repetitions, a.gates_passed))
                    }
                })
                .then(a.score_s.total_cmp(&b.score_s))
                .then(a.time_s.total_cmp(&b.time_s))
                .then(i.cmp(j))
        });
        let robots: Vec<Standing> = lines
            .into_iter()
            .enumerate()
            .map(|(r, (_, s))| Standing { rank: r + 1, ..s })
            .collect();
        let completed = robots.iter().filter(|s| done(s)).count();
        let all = completed == robots.len();
        Some(Standings {
            course,
            rule: rule.name(),
            winner: robots
                .first()
                .filter(|s| rule == TeamRule::First && done(s))
                .map(|s| s.name.clone()),
            team_score_s: (rule == TeamRule::All && all)
                .then(|| robots.iter().map(|s| s.score_s).sum()),
            team_time_s: (rule == TeamRule::All && all)
                .then(|| robots.iter().map(|s| s.time_s).fold(0.0, f64::max)),
            completed,
            robots,
        })
    }

    /// The standings in words, a line each (for the run report).
    pub fn lines(&self) -> Vec<String> {
        let mut l = vec![format!(
            "standings  {} ({}): {} of {} completed{}",
            self.course,
            if self.rule == "first" { "race" } else { "team" },
            self.completed,
            self.robots.len(),
            match (&self.winner, self.team_score_s, self.team_time_s) {
                (Some(w), ..) => format!("; won by {w}"),
                (None, Some(s), Some(t)) => format!("; team score {s:.2} s (last in at {t:.2} s)"),
                _ => String::new(),
            }
        )];
        for s in &self.robots {
            l.push(format!(
                "  {:>2}. {:<12} {:<13} reps {} gates {} time {:.2} s + penalties {:.1} s ({} faults) = {:.2} s",
                s.rank, s.name, s.status, s.repetitions, s.gates_passed, s.time_s, s.penalty_s, s.faults, s.score_s
            ));
        }
        l
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::course::{FaultCounts, ScoreSummary};

    fn score(
        status: &'static str,
        reps: u32,
        next_gate: usize,
        time: f64,
        pen: f64,
    ) -> CourseScore {
        CourseScore {
            name: "c".into(),
            next_gate,
            gates_passed: 0,
            gates_total: 3,
            repetition: reps + 1,
            repetitions_done: reps,
            repetitions_required: 1,
            rep_times_s: Vec::new(),
            elapsed_s: time,
            time_limit_s: None,
            faults: FaultCounts::default(),
            penalty_s: pen,
            finished: status != "running",
            status,
            score: ScoreSummary {
                repetitions: reps,
                time_s: time,
                faults: u32::from(pen > 0.0),
                penalty_s: pen,
                score_s: time + pen,
            },
            events: Vec::new(),
        }
    }

    #[test]
    fn completed_rank_by_score_then_the_rest_by_progress() {
        let scores = vec![
            (
                "slow".to_string(),
                Some(score("completed", 1, 0, 30.0, 0.0)),
            ),
            (
                "fast_but_penalised".into(),
                Some(score("completed", 1, 0, 20.0, 15.0)),
            ),
            (
                "behind".into(),
                Some(score("not_completed", 0, 1, 40.0, 0.0)),
            ),
            (
                "further".into(),
                Some(score("not_completed", 0, 2, 40.0, 5.0)),
            ),
            ("no_course".into(), None),
        ];
        let race = Standings::of(TeamRule::First, &scores).unwrap();
        let order: Vec<&str> = race.robots.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(order, ["slow", "fast_but_penalised", "further", "behind"]);
        assert_eq!(race.robots[3].rank, 4);
        assert_eq!(race.winner.as_deref(), Some("slow"));
        assert_eq!((race.completed, race.team_score_s), (2, None));
        let team = Standings::of(TeamRule::All, &scores).unwrap();
        assert_eq!(
            (team.winner, team.team_score_s),
            (None, None),
            "not all completed"
        );
        let both = vec![
            ("a".to_string(), Some(score("completed", 1, 0, 30.0, 5.0))),
            ("b".into(), Some(score("completed", 1, 0, 32.0, 0.0))),
        ];
        let team = Standings::of(TeamRule::All, &both).unwrap();
        assert_eq!(team.team_score_s, Some(67.0));
        assert_eq!(team.team_time_s, Some(32.0));
        assert!(Standings::of(TeamRule::All, &[("x".into(), None)]).is_none());
    }
}
