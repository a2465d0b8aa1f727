//! A scored course's ROS 2 messages (`[course]`, docs/COURSES.md): its score at a sample
//! ([`course_status`], `tracksim_msgs/CourseStatus` on `/course`) and each of its events
//! ([`course_event`], `tracksim_msgs/CourseEvent` on `/course/events`). The ROS 2 node
//! publishes them live and `run.mcap` records the events, built by these functions in both.

use super::ros_sensors::MAP_FRAME;
use crate::rosmsg::{self, Header};
use crate::run::{CourseEvent, CourseScore};

/// `/course` at sample time `t` s: the score `c` so far.
pub fn course_status(t: f64, c: &CourseScore) -> rosmsg::CourseStatus {
    rosmsg::CourseStatus {
        header: Header::new(t, MAP_FRAME),
        name: c.name.clone(),
        status: c.status.to_string(),
        finished: c.finished,
        next_gate: c.next_gate as u32,
        gates_passed: c.gates_passed,
        gates_total: c.gates_total as u32,
        repetition: c.repetition,
        repetitions_done: c.repetitions_done,
        repetitions_required: c.repetitions_required,
        repetition_times: c.rep_times_s.clone(),
        elapsed: c.elapsed_s,
        time_limit: c.time_limit_s.unwrap_or(0.0),
        resets: c.faults.reset,
        tip_overs: c.faults.tip_over,
        touches: c.faults.touch,
        penalty: c.penalty_s,
        trial_time: c.score.time_s,
        score: c.score.score_s,
    }
}

/// `/course/events`: event `e`, stamped with its time.
pub fn course_event(e: &CourseEvent) -> rosmsg::CourseEvent {
    rosmsg::CourseEvent {
        header: Header::new(e.t_s, MAP_FRAME),
        kind: e.kind.to_string(),
        detail: e.detail.clone(),
        fault: e.fault.unwrap_or("").to_string(),
        penalty: e.penalty_s.unwrap_or(0.0),
    }
}

/// Which of a course's events have been published: a live node asks it at every sample for the
/// events new since the last one. A reset restarts a score's list of events (its first entry
/// is the reset's fault), which the cursor sees by the count of resets.
#[derive(Clone, Debug, Default)]
pub struct EventCursor {
    published: usize,
    resets: u32,
}

impl EventCursor {
    /// The events of `c` not yet published, in order; from now on they count as published.
    pub fn new_events<'c>(&mut self, c: &'c CourseScore) -> &'c [CourseEvent] {
        if c.faults.reset != self.resets {
            self.resets = c.faults.reset;
            self.published = 0;
        }
        let from = self.published.min(c.events.len());
        self.published = c.events.len();
        &c.events[from..]
    }
}
