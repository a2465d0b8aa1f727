//! `tracksim_msgs/CourseStatus` and `tracksim_msgs/CourseEvent`: the live score of a scored
//! course (`[course]`, docs/COURSES.md) on `/course` and its events on `/course/events`. Their
//! `.msg` texts ([`COURSE_STATUS`], [`COURSE_EVENT`], fields with their units) are also the
//! files `ros/tracksim_msgs/msg/CourseStatus.msg` and `CourseEvent.msg` of the ROS 2 package
//! (`tests/suite/issue_27_mcap.rs` keeps them equal).

use super::builtin::{HEADER, Header};
use super::schema::{MsgDef, RosMessage};
use serde::{Deserialize, Serialize};

/// `tracksim_msgs/CourseStatus`: a course's score at a sample.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CourseStatus {
    /// The sample's time; frame `map` (gates and obstacles are in it).
    pub header: Header,
    /// The course's name.
    pub name: String,
    /// `running`, `completed`, `time_limit` or `not_completed`.
    pub status: String,
    /// Whether the course is finished (completed or out of time).
    pub finished: bool,
    /// Index of the gate to pass next (0-based).
    pub next_gate: u32,
    /// Gates passed since the start (or the last reset), every repetition's.
    pub gates_passed: u32,
    /// Gates of one repetition.
    pub gates_total: u32,
    /// The repetition under way (1-based; the last one once finished).
    pub repetition: u32,
    /// Repetitions completed.
    pub repetitions_done: u32,
    /// Repetitions to complete.
    pub repetitions_required: u32,
    /// Time of each completed repetition, s.
    pub repetition_times: Vec<f64>,
    /// Simulated time since the start (or the last reset), s.
    pub elapsed: f64,
    /// The time limit, s (0: none).
    pub time_limit: f64,
    /// Resets by the operator.
    pub resets: u32,
    /// Tip-overs.
    pub tip_overs: u32,
    /// Touches of marked obstacles.
    pub touches: u32,
    /// Penalty time of the faults, s.
    pub penalty: f64,
    /// Time of the trial, s: to the end of the last repetition once completed, else elapsed.
    pub trial_time: f64,
    /// `trial_time + penalty`, s (lower is better).
    pub score: f64,
}

/// `tracksim_msgs/CourseStatus`.
pub const COURSE_STATUS: MsgDef = MsgDef {
    name: "tracksim_msgs/CourseStatus",
    text: "# The score of a tracksim course (topic /course) at every output sample of a run whose
# scenario has a [course] (docs/COURSES.md). SI units; times are simulated seconds.
std_msgs/Header header          # sample time; frame map
string name                     # the course's name
string status                   # running, completed, time_limit or not_completed
bool finished                   # completed or out of time
uint32 next_gate                # index of the gate to pass next, 0-based
uint32 gates_passed             # since the start or the last reset, every repetition's
uint32 gates_total              # gates of one repetition
uint32 repetition               # the repetition under way, 1-based
uint32 repetitions_done         # repetitions completed
uint32 repetitions_required     # repetitions to complete
float64[] repetition_times      # time of each completed repetition, s
float64 elapsed                 # since the start or the last reset, s
float64 time_limit              # s; 0 when the course has none
uint32 resets                   # faults: resets by the operator
uint32 tip_overs                # faults: tip-overs
uint32 touches                  # faults: touches of marked obstacles
float64 penalty                 # penalty time of the faults, s
float64 trial_time              # time of the trial, s (to the last repetition's end once completed)
float64 score                   # trial_time + penalty, s; lower is better
",
    deps: &[&HEADER],
};

impl RosMessage for CourseStatus {
    const DEF: &'static MsgDef = &COURSE_STATUS;
}

/// `tracksim_msgs/CourseEvent`: something that happened on a course.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CourseEvent {
    /// The time of the sample it was seen at; frame `map`.
    pub header: Header,
    /// `gate`, `repetition`, `fault` or `finished`.
    pub kind: String,
    /// In words (which gate, the repetition's time, which fault).
    pub detail: String,
    /// A fault's kind: `reset`, `tip_over` or `touch` (empty for other events).
    pub fault: String,
    /// A fault's penalty, s (0 for other events).
    pub penalty: f64,
}

/// `tracksim_msgs/CourseEvent`.
pub const COURSE_EVENT: MsgDef = MsgDef {
    name: "tracksim_msgs/CourseEvent",
    text:
        "# Something that happened on a tracksim course (topic /course/events), once, as it happens.
std_msgs/Header header          # time of the sample it was seen at; frame map
string kind                     # gate, repetition, fault or finished
string detail                   # in words: which gate, the repetition's time, which fault
string fault                    # a fault's kind: reset, tip_over or touch; empty for other kinds
float64 penalty                 # a fault's penalty, s; 0 for other kinds
",
    deps: &[&HEADER],
};

impl RosMessage for CourseEvent {
    const DEF: &'static MsgDef = &COURSE_EVENT;
}
