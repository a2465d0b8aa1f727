//! A session's attempts (issue 43): a reset ends an attempt and starts the next inside the same
//! session; every attempt is kept as a run of its own. [`AttemptRecord`] is one line of the
//! session's `summary.json` `attempts` list.

use super::RunResult;
use serde::Serialize;

/// Folder of attempt `n` (from 1) inside a session's folder.
pub fn attempt_folder(n: usize) -> String {
    format!("attempts/{n}")
}

/// One attempt of a session, as the session's `summary.json` lists it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AttemptRecord {
    /// Its number, from 1.
    pub attempt: usize,
    /// Its run folder relative to the session's (`attempts/N`; `.` for the last attempt,
    /// which is the session's folder itself).
    pub folder: String,
    /// How long it lasted, s of simulated time.
    pub duration_s: f64,
    /// What ended it: `reset` (the driver or the instructor) or the session's end.
    pub ended_by: String,
    /// Its outcome's name and reason.
    pub outcome: String,
    /// Why.
    pub outcome_reason: String,
    /// The course's status (`completed`, `time_limit`, `not_completed`), on a course.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub course_status: Option<&'static str>,
    /// The course's score time (time plus penalties), s, on a course.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub score_s: Option<f64>,
}

impl AttemptRecord {
    /// Attempt `attempt` (from 1) kept in `folder`, ended by `ended_by`, of run `r`.
    pub fn of(attempt: usize, folder: String, ended_by: &str, r: &RunResult) -> Self {
        let course = r.summary.course.as_ref();
        AttemptRecord {
            attempt,
            folder,
            // From its first sample: 0 s, or a reset of one robot of several (world time).
            duration_s: r.samples.last().map_or(0.0, |s| s.t)
                - r.samples.first().map_or(0.0, |s| s.t),
            ended_by: ended_by.to_string(),
            outcome: r.summary.outcome.clone(),
            outcome_reason: r.summary.outcome_reason.clone(),
            course_status: course.map(|c| c.status),
            score_s: course.map(|c| c.score.score_s),
        }
    }
}
