//! The instructor's seat of a live session (issue 43): a page opened with the instructor's
//! own token (`/?instructor=TOKEN`, printed by `tracksim drive`, never served by
//! `/session.json`) that pauses and resumes the session, resets a robot (a new attempt), ends
//! the session and injects faults. Its page shows everything; a trainee's page shows what the
//! trainee would see (the onboard video frozen with "no signal" while it is dropped).
//!
//! Protocol (JSON text frames, instructor to server; an error text comes back for a message
//! refused): `{"type":"pause"}`, `{"type":"resume"}`, `{"type":"end"}`,
//! `{"type":"reset","robot":NAME?}`, `{"type":"fault","robot":NAME?,"fault":{...}}` with the
//! `fault` table of a `[[commands]]` entry ([`crate::spec::FaultSpec`]: `track`, `flipper`,
//! `latency_s`, `video`, `patch`), checked against the scenario before it is queued.
//!
//! The session takes the queued actions at each sample boundary (`Desk::take`): a pause
//! holds the loop (simulated time stands still; the pacing clock is moved on by the pause),
//! a reset ends the attempt (in a session of several robots, the named robot's alone: its
//! `reset = true` entry, `Desk::take_reset_of`; `robot` is required there), an end ends the session, a fault goes into the robot's next
//! `[[commands]]` entry (applied and recorded like any control, so `commands.toml` replays
//! it). Every action is an event of the attempt it happened in (`summary.json` `events`).

use crate::run::events::RunEvent;
use crate::spec::FaultSpec;
use crate::world::Simulation;
use serde_json::{Map, Value, json};

/// An instructor's action, queued by the hub for the session.
#[derive(Clone, Debug, PartialEq)]
pub enum InstructorAction {
    /// Hold the session: simulated time stops.
    Pause,
    /// Go on after a pause.
    Resume,
    /// End the session (its outputs are written).
    End,
    /// Reset robot `k`: its attempt ends, a new one begins.
    Reset(usize),
    /// Set or clear faults on robot `k`.
    Fault(usize, FaultSpec),
}

/// The session's side of the instructor's seat: the pause, a pending reset and end, each
/// robot's faults not yet applied, its latency and video state, and the events of the
/// attempt under way.
#[derive(Debug, Default)]
pub(super) struct Desk {
    paused: bool,
    /// Each robot's reset asked since it was last taken.
    resets: Vec<bool>,
    ended: bool,
    /// Each robot's faults to apply at its next control (merged when several came).
    pending: Vec<Option<FaultSpec>>,
    /// Each robot's added command latency, s.
    latency_s: Vec<f64>,
    /// Whether each robot's onboard video is dropped.
    video_dropped: Vec<bool>,
    /// The instructor's actions (and the driver's resets) in the attempt under way.
    events: Vec<RunEvent>,
}

impl Desk {
    /// A desk for `robots` robots, nothing in force.
    pub(super) fn new(robots: usize) -> Desk {
        Desk {
            resets: vec![false; robots],
            pending: vec![None; robots],
            latency_s: vec![0.0; robots],
            video_dropped: vec![false; robots],
            ..Desk::default()
        }
    }

    /// Takes the instructor's queued `actions` (`Hub::take_actions`) at simulated time `t` s
    /// (the robots named `names`), recording each as an event.
    pub(super) fn take(&mut self, actions: Vec<InstructorAction>, t: f64, names: &[String]) {
        for a in actions {
            let (kind, detail) = match a {
                InstructorAction::Pause if !self.paused => {
                    self.paused = true;
                    ("pause", "the instructor paused the session".to_string())
                }
                InstructorAction::Resume if self.paused => {
                    self.paused = false;
                    ("resume", "the instructor resumed the session".to_string())
                }
                InstructorAction::Pause | InstructorAction::Resume => continue,
                InstructorAction::End => {
                    self.ended = true;
                    ("end", "the instructor ended the session".to_string())
                }
                InstructorAction::Reset(k) => {
                    if let Some(r) = self.resets.get_mut(k) {
                        *r = true;
                    }
                    let who = names.get(k).map_or("the robot", String::as_str);
                    (
                        "reset",
                        format!("the instructor reset {who}: a new attempt begins"),
                    )
                }
                InstructorAction::Fault(k, f) => {
                    let detail = fault_words(&f);
                    let slot = &mut self.pending[k];
                    *slot = Some(match slot.take() {
                        None => f,
                        Some(mut p) => {
                            p.track.extend(f.track);
                            p.flipper.extend(f.flipper);
                            p.latency_s = f.latency_s.or(p.latency_s);
                            p.video = f.video.or(p.video);
                            p.patch = f.patch.or(p.patch);
                            p
                        }
                    });
                    let who = names.get(k).map_or("", String::as_str);
                    (
                        "fault",
                        format!("the instructor injected on {who}: {detail}"),
                    )
                }
            };
            self.event(t, kind, detail);
        }
    }

    /// Robot `k`'s own driver reset it at simulated time `t` s (a session of several robots,
    /// the robots named `names`): as the instructor's reset of it, recorded as the driver's.
    pub(super) fn driver_reset(&mut self, k: usize, t: f64, names: &[String]) {
        if let Some(r) = self.resets.get_mut(k) {
            *r = true;
        }
        let who = names.get(k).map_or("the robot", String::as_str);
        self.event(
            t,
            "reset",
            format!("{who}'s driver reset: a new attempt begins"),
        );
    }

    /// Records an event of the attempt under way.
    pub(super) fn event(&mut self, t: f64, kind: &'static str, detail: String) {
        self.events.push(RunEvent {
            t_s: t,
            t_end_s: None,
            kind,
            detail,
        });
    }

    /// Whether the session is held paused.
    pub(super) fn paused(&self) -> bool {
        self.paused
    }

    /// Whether the instructor ended the session.
    pub(super) fn ended(&self) -> bool {
        self.ended
    }

    /// Whether the instructor asked for a reset (of any robot) since the last call.
    pub(super) fn take_reset(&mut self) -> bool {
        let any = self.resets.iter().any(|r| *r);
        self.resets.iter_mut().for_each(|r| *r = false);
        any
    }

    /// Whether the instructor asked for a reset of robot `k` since the last call; if so, the
    /// robot's faults, latency and video state are cleared (it starts again as built; a
    /// session of several robots, where the others go on).
    pub(super) fn take_reset_of(&mut self, k: usize) -> bool {
        if !self.resets.get_mut(k).is_some_and(std::mem::take) {
            return false;
        }
        self.latency_s[k] = 0.0;
        self.video_dropped[k] = false;
        self.pending[k] = None;
        true
    }

    /// Robot `k`'s faults to apply now, if any; its latency and video state take them on.
    pub(super) fn take_fault(&mut self, k: usize) -> Option<FaultSpec> {
        let f = self.pending.get_mut(k)?.take()?;
        if let Some(l) = f.latency_s {
            self.latency_s[k] = l;
        }
        if let Some(v) = &f.video {
            self.video_dropped[k] = v == "dropped";
        }
        Some(f)
    }

    /// Robot `k`'s added command latency, s.
    pub(super) fn latency_s(&self, k: usize) -> f64 {
        self.latency_s.get(k).copied().unwrap_or(0.0)
    }

    /// The attempt under way ends (a reset): its events; the next attempt starts with a new
    /// world, so no fault stays in force (the pause does).
    pub(super) fn next_attempt(&mut self) -> Vec<RunEvent> {
        self.latency_s.iter_mut().for_each(|l| *l = 0.0);
        self.video_dropped.iter_mut().for_each(|v| *v = false);
        self.pending.iter_mut().for_each(|p| *p = None);
        std::mem::take(&mut self.events)
    }

    /// The events of the attempt under way.
    pub(super) fn take_events(&mut self) -> Vec<RunEvent> {
        std::mem::take(&mut self.events)
    }

    /// What a state of robot `k` carries of the instructor's seat: `paused`, and `faults`
    /// (`track`: each track's `ok`, `stopped` or `unpowered`; `flipper`: each flipper's `ok` or
    /// `jammed`; `latency_s`; `video`: `ok` or `dropped`; `patch`: the low-friction patch on
    /// the ground, `centre_m`, `size_m`, `friction`, or null) read from `sim` (robot `k`
    /// selected).
    pub(super) fn fields(&self, k: usize, sim: &Simulation) -> Map<String, Value> {
        let tracks: Vec<&str> = (0..sim.track_names().len())
            .map(|i| sim.track_fault(i).name())
            .collect();
        let flippers: Vec<&str> = (0..sim.flipper_names().len())
            .map(|i| {
                if sim.flipper_jammed(i) {
                    "jammed"
                } else {
                    "ok"
                }
            })
            .collect();
        let video = if self.video_dropped.get(k).copied().unwrap_or(false) {
            "dropped"
        } else {
            "ok"
        };
        let patch = sim
            .friction_patch()
            .map(|p| json!({"centre_m": p.centre, "size_m": p.size, "friction": p.friction}));
        let mut m = Map::new();
        m.insert("paused".into(), json!(self.paused));
        m.insert(
            "faults".into(),
            json!({
                "track": tracks, "flipper": flippers,
                "latency_s": self.latency_s(k), "video": video, "patch": patch,
            }),
        );
        m
    }
}

/// A fault table in words (`track left stopped, latency 0.5 s`).
pub fn fault_words(f: &FaultSpec) -> String {
    let mut parts: Vec<String> = Vec::new();
    parts.extend(f.track.iter().map(|(n, k)| format!("track {n} {k}")));
    parts.extend(f.flipper.iter().map(|(n, k)| format!("flipper {n} {k}")));
    if let Some(l) = f.latency_s {
        parts.push(format!("command latency {l} s"));
    }
    if let Some(v) = &f.video {
        parts.push(format!("video {v}"));
    }
    match &f.patch {
        Some(crate::spec::PatchSpec::Area(a)) => parts.push(format!(
            "low-friction patch (friction {}) of {} m x {} m at x {} m, y {} m",
            a.friction, a.size_m[0], a.size_m[1], a.centre_m[0], a.centre_m[1]
        )),
        Some(crate::spec::PatchSpec::Word(w)) => parts.push(format!("patch {w}")),
        None => {}
    }
    if parts.is_empty() {
        "nothing".into()
    } else {
        parts.join(", ")
    }
}
