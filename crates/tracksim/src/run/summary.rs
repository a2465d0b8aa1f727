//! The numbers `summary.json` holds, computed from a finished run.

use super::outcome::Outcome;
use crate::model::Scenario;
use crate::world::{PoseRpy, Sample, Simulation};
use serde::Serialize;

/// The numbers `summary.json` holds.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// Scenario file, if any.
    pub scenario: Option<String>,
    /// Vehicle name.
    pub vehicle: String,
    /// Track method.
    pub method: String,
    /// Time step, s.
    pub dt_s: f64,
    /// Steps taken.
    pub steps: u64,
    /// Simulated time, s.
    pub sim_time_s: f64,
    /// Wall-clock time spent stepping (computing), s.
    pub wall_time_s: f64,
    /// Compute speed: sim_time_s / wall_time_s (how much faster than real time the stepping
    /// alone runs).
    pub real_time_factor: f64,
    /// Wall-clock time of the whole run, waiting included, s.
    pub elapsed_time_s: f64,
    /// Paced speed: sim_time_s / elapsed_time_s (1.0 when paced to the wall clock).
    pub paced_real_time_factor: f64,
    /// Whether the run was paced to the wall clock (`--realtime`).
    pub paced: bool,
    /// Displacement along the start heading divided by simulated time, m/s.
    pub mean_speed_mps: f64,
    /// Horizontal path length of the body, m, counted in steps of at least
    /// [`PATH_RESOLUTION_M`] so that jitter of a stalled robot does not add up.
    pub distance_m: f64,
    /// Horizontal straight-line distance from the start to the end, m.
    pub net_displacement_m: f64,
    /// Progress along the start heading, m (negative: backwards).
    pub progress_m: f64,
    /// Pose at the start (after placement).
    pub initial_pose: PoseRpy,
    /// Pose at the end.
    pub final_pose: PoseRpy,
    /// "success", "failure" or "completed" (no success condition was set and nothing failed).
    pub outcome: String,
    /// Why.
    pub outcome_reason: String,
    /// When the outcome was decided, s.
    pub outcome_time_s: f64,
    /// Solver settings that change the physics.
    pub solver: SolverSummary,
    /// Seed of the run.
    pub seed: u64,
    /// Largest link deviation from its exact pose after a physics step (joint error), m.
    pub max_link_error_m: f64,
    /// Same, as an angle, rad.
    pub max_link_error_rad: f64,
    /// Deepest contact penetration seen in the trajectory rows, m (how far grousers sank).
    pub max_penetration_m: f64,
    /// Simulated and file mass of every part, the totals, and the centre of mass.
    pub mass: crate::world::MassReport,
    /// Every track: belt speeds, slip, traction, normal load, contacts.
    pub tracks: Vec<super::TrackSummary>,
    /// Odometry against the ground truth at the end.
    pub odometry: super::OdometrySummary,
    /// The steady drawbar pull and slip (`[drawbar]` runs only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drawbar: Option<super::DrawbarSummary>,
    /// Sinkage, soil thrust and the rut grid's memory (runs on soil only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub soil: Option<super::SoilSummary>,
    /// Every stretch of constant belt commands that asks for a turn, commanded against
    /// achieved (left out when there is none).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub turns: Vec<super::TurnSummary>,
    /// The values drawn for the scenario's `[randomize]` parameters, by name (left out of
    /// `summary.json` for a scenario without `[randomize]`).
    #[serde(skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub randomized: std::collections::BTreeMap<String, f64>,
    /// Every sensor: kind, file, rate, readings, cost (left out for a vehicle without
    /// `[[sensors]]`).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub sensors: Vec<SensorSummary>,
    /// Moments to jump to in a review, in time order: each stall, the largest tilt, the
    /// outcome ([`super::events::run_events`]).
    pub events: Vec<super::events::RunEvent>,
    /// The trainee (operator) of the session, as the front end was told (`--trainee`);
    /// `null` when not given.
    pub trainee: Option<String>,
    /// Wall-clock date and time the run started (or was last reset), UTC, ISO 8601
    /// (`2026-12-03T12:27:37Z`).
    pub started_utc: String,
    /// The course's score (`[course]` scenarios only; docs/COURSES.md).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub course: Option<super::CourseScore>,
    /// A live session's attempts, in order (a reset starts the next; issue 43); left out of
    /// a run without resets.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub attempts: Vec<super::AttemptRecord>,
    /// How close the run came to its limits: peak pitch and roll against the tip limit, each
    /// track's smallest normal load, largest slip and motor load (issue 62).
    pub margins: super::Margins,
    /// Why the world stopped before its end, when it did (a blow-up, or robots further apart
    /// than one world holds; issue 59): the run holds what was simulated up to there. Left
    /// out of `summary.json` when the run ended as it should.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stopped: Option<String>,
}

/// `t` as an ISO 8601 UTC date and time to the second (`2026-12-03T12:27:37Z`); a time before
/// 1970 is given as 1970-01-01T00:00:00Z.
pub fn iso8601_utc(t: std::time::SystemTime) -> String {
    let secs = t
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let (days, rem) = ((secs / 86_400) as i64, secs % 86_400);
    // Civil date from days since 1970-01-01 (H. Hinnant's algorithm, proleptic Gregorian).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}Z",
        rem / 3600,
        rem / 60 % 60,
        rem % 60
    )
}

/// A sensor's line in `summary.json`.
#[derive(Clone, Debug, Serialize)]
pub struct SensorSummary {
    /// Name.
    pub name: String,
    /// Kind.
    pub kind: String,
    /// Its stream, relative to the run folder (`sensors/NAME.csv` or `.npz`).
    pub file: String,
    /// Rate, Hz.
    pub rate_hz: f64,
    /// Readings taken (the first at t = 0).
    pub readings: usize,
    /// Mean wall time of an update, us.
    pub cost_us_per_update: f64,
}

impl SensorSummary {
    /// The line of `stream`.
    pub fn of(stream: &crate::sensors::SensorStream) -> Self {
        SensorSummary {
            name: stream.name.clone(),
            kind: stream.kind.to_string(),
            file: stream.file_name(),
            rate_hz: stream.rate_hz,
            readings: stream.len(),
            cost_us_per_update: stream.mean_cost_us,
        }
    }
}

/// Solver settings reported with every run.
#[derive(Clone, Debug, Serialize)]
pub struct SolverSummary {
    /// Time step, s.
    pub dt_s: f64,
    /// Solver iterations.
    pub iterations: usize,
    /// Position-correction passes per solver iteration.
    pub stabilization_iterations: usize,
    /// Contact clustering.
    pub contact_clustering: bool,
    /// Smallest segment link mass, kg.
    pub min_link_mass_kg: f64,
    /// Speculative contact distance, m.
    pub prediction_distance_m: f64,
    /// Uncorrected vehicle-terrain penetration (ODE's `min_depth`), m; 0 = rigid contact.
    pub contact_slop_m: f64,
    /// Friction in Rapier's position-correction pass while every belt is held.
    pub held_friction_in_bias_pass: bool,
    /// `simulation.contact_recycling`.
    pub contact_recycling: bool,
    /// `simulation.floating_origin`.
    pub floating_origin: bool,
    /// `simulation.order_salt` (0 unless an ensemble member's).
    pub order_salt: usize,
}

impl SolverSummary {
    /// The solver settings of a scenario.
    pub fn of(sc: &Scenario) -> Self {
        SolverSummary {
            dt_s: sc.solver.dt,
            iterations: sc.solver.iterations,
            stabilization_iterations: sc.solver.stabilization_iterations,
            contact_clustering: sc.solver.contact_clustering,
            min_link_mass_kg: sc.solver.min_link_mass,
            prediction_distance_m: sc.solver.prediction_distance,
            contact_slop_m: sc.solver.contact_slop,
            held_friction_in_bias_pass: sc.solver.held_friction_in_bias_pass,
            contact_recycling: sc.solver.contact_recycling,
            floating_origin: sc.solver.floating_origin,
            order_salt: sc.solver.order_salt,
        }
    }
}

/// Smallest horizontal move, m, that the path length counts: the body's position is taken as
/// a new point of the path only once it is this far from the last one (a stalled robot that
/// jitters by millimetres adds nothing; a driving one loses at most this much per turn).
pub const PATH_RESOLUTION_M: f64 = 0.01;

/// Window over which the body's position is averaged before the path length is measured, s:
/// chatter faster than 2 Hz (a stalled robot rattling against a step or wall by centimetres)
/// adds nothing, a drive is unchanged (the means of a straight stretch lie on it; on a 0.5 m
/// radius arc at 0.3 m/s the chords shorten the path by 0.4 %).
pub const PATH_WINDOW_S: f64 = 0.5;

/// Horizontal path length of the samples, m: the start, the mean positions over consecutive
/// [`PATH_WINDOW_S`] windows and the end, counted at [`PATH_RESOLUTION_M`], the last partial
/// stretch to the final sample included.
pub fn path_length<S: std::borrow::Borrow<Sample>>(samples: impl IntoIterator<Item = S>) -> f64 {
    let d = |a: (f64, f64), b: (f64, f64)| ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
    // The points of the path, taken one by one as their windows close (one pass: the samples
    // may be on disk): `last` the last point counted, `total` the length to it.
    let mut samples = samples.into_iter();
    let Some(first) = samples.next() else {
        return 0.0;
    };
    let first = first.borrow();
    let mut last = (first.pose.x, first.pose.y);
    let mut total = 0.0;
    let mut take = |p: (f64, f64)| {
        let step = d(last, p);
        if step >= PATH_RESOLUTION_M {
            total += step;
            last = p;
        }
    };
    let mut end = (first.pose.x, first.pose.y);
    let (mut sx, mut sy, mut n, mut t0) = (0.0 + first.pose.x, 0.0 + first.pose.y, 1.0, first.t);
    for s in samples {
        let s = s.borrow();
        if s.t - t0 >= PATH_WINDOW_S && n > 0.0 {
            take((sx / n, sy / n));
            (sx, sy, n, t0) = (0.0, 0.0, 0.0, s.t);
        }
        sx += s.pose.x;
        sy += s.pose.y;
        n += 1.0;
        end = (s.pose.x, s.pose.y);
    }
    take(end);
    total + d(last, end)
}

/// Wall-clock times of a run, s.
#[derive(Clone, Copy, Debug, Default)]
pub struct WallTimes {
    /// Spent stepping.
    pub stepping: f64,
    /// The whole run, waiting included.
    pub elapsed: f64,
    /// Whether it was paced to the wall clock.
    pub paced: bool,
    /// Wall-clock date of the start (`None`: now).
    pub started: Option<std::time::SystemTime>,
}

impl Summary {
    /// Summarises a finished run of `sim` (built from `sc`) with its `samples`.
    pub fn new(
        sc: &Scenario,
        sim: &Simulation,
        samples: &super::SampleLog,
        outcome: (&Outcome, f64),
        wall: WallTimes,
    ) -> Self {
        let first = samples.first().expect("a run has its first sample").pose;
        let last = samples.last().map(|s| s.pose).unwrap_or(first);
        let (c, s) = (first.yaw.cos(), first.yaw.sin());
        let forward = (last.x - first.x) * c + (last.y - first.y) * s;
        let distance = path_length(samples.iter());
        let (err_m, err_rad) = sim.max_link_error();
        let sim_time = sim.time();
        Summary {
            scenario: sc.source.as_ref().map(|p| p.display().to_string()),
            vehicle: sc.vehicle.name.clone(),
            method: sim.method().name(),
            dt_s: sc.solver.dt,
            steps: sim.steps(),
            sim_time_s: sim_time,
            wall_time_s: wall.stepping,
            real_time_factor: sim_time / wall.stepping.max(1e-12),
            elapsed_time_s: wall.elapsed,
            paced_real_time_factor: sim_time / wall.elapsed.max(1e-12),
            paced: wall.paced,
            mean_speed_mps: forward / sim_time,
            distance_m: distance,
            net_displacement_m: ((last.x - first.x).powi(2) + (last.y - first.y).powi(2)).sqrt(),
            progress_m: forward,
            initial_pose: first,
            final_pose: last,
            outcome: outcome.0.name().to_string(),
            outcome_reason: outcome.0.reason(),
            outcome_time_s: outcome.1,
            solver: SolverSummary::of(sc),
            seed: sim.seed(),
            max_link_error_m: err_m,
            max_link_error_rad: err_rad,
            max_penetration_m: samples.iter().map(|s| s.penetration).fold(0.0, f64::max),
            mass: sim.mass_report(),
            tracks: super::track_summaries(sim.track_names(), samples),
            odometry: super::odometry_summary(samples),
            drawbar: super::drawbar_summary(sc, samples),
            soil: super::soil_summary(sim, samples),
            turns: super::turn_summaries(&sc.vehicle, samples),
            randomized: sc.randomized.clone(),
            sensors: Vec::new(),
            events: super::events::run_events(samples, sc.outcome.max_tilt, outcome),
            trainee: None,
            started_utc: iso8601_utc(wall.started.unwrap_or_else(std::time::SystemTime::now)),
            course: None,
            attempts: Vec::new(),
            margins: super::Margins::of(samples, sim.track_names(), sc.outcome.max_tilt),
            stopped: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(t: f64, x: f64, y: f64) -> Sample {
        Sample {
            t,
            pose: PoseRpy {
                x,
                y,
                ..Default::default()
            },
            linvel: [0.0; 3],
            angvel: [0.0; 3],
            belt_speed: Vec::new(),
            belt_phase: Vec::new(),
            belt_position: Vec::new(),
            flipper_angle: Vec::new(),
            ..Default::default()
        }
    }

    /// Issue 11.3: a robot stalled at a step that jittered by millimetres reported 1.96 m of
    /// path for 0.18 m of progress. Jitter of +-3 mm (x and y) every 10 ms for 10 s adds nothing; a
    /// straight drive of 1 m in 3 mm samples counts 1 m.
    /// Known dates: the epoch, a leap day, the end of a century year that is not a leap year.
    #[test]
    fn iso8601_dates() {
        let at = |s: u64| iso8601_utc(std::time::UNIX_EPOCH + std::time::Duration::from_secs(s));
        assert_eq!(at(0), "1970-01-01T00:00:00Z");
        assert_eq!(at(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(at(4_107_542_399), "2100-02-28T23:59:59Z");
        assert_eq!(at(1_796_301_257), "2026-12-03T12:34:17Z");
    }

    #[test]
    fn path_length_ignores_jitter_and_counts_driving() {
        let jitter: Vec<Sample> = (0..1000)
            .map(|i| {
                let s = if i % 2 == 0 { 0.003 } else { -0.003 };
                at(i as f64 * 0.01, 0.5 + s, s)
            })
            .collect();
        let naive: f64 = jitter
            .windows(2)
            .map(|w| {
                ((w[1].pose.x - w[0].pose.x).powi(2) + (w[1].pose.y - w[0].pose.y).powi(2)).sqrt()
            })
            .sum();
        assert!(naive > 8.0, "{naive}");
        assert!(
            path_length(&jitter) < PATH_RESOLUTION_M,
            "{}",
            path_length(&jitter)
        );
        let drive: Vec<Sample> = (0..=333)
            .map(|i| at(i as f64 * 0.01, i as f64 * 0.003, 0.0))
            .collect();
        assert!(
            (path_length(&drive) - 0.999).abs() < 1e-9,
            "{}",
            path_length(&drive)
        );
    }

    /// Issue 23.7: a robot stalled at x = 0.45 m in `compare`'s table reported 2.39 m of path:
    /// it rattled by more than the 1 cm resolution. Chatter of +-2 cm at 10 Hz for 10 s (4 m
    /// of naive path) now adds under 2 cm; a drive with that chatter on top keeps its length.
    #[test]
    fn path_length_ignores_centimetre_chatter() {
        let chatter = |v: f64| -> Vec<Sample> {
            (0..1000)
                .map(|i| {
                    let t = i as f64 * 0.01;
                    let s = 0.02 * (std::f64::consts::TAU * 10.0 * t).sin();
                    at(t, 0.45 + v * t + s, 0.0)
                })
                .collect()
        };
        let stalled = path_length(chatter(0.0));
        assert!(stalled < 0.02, "{stalled}");
        let driving = path_length(chatter(0.3));
        assert!((driving - 0.3 * 9.99).abs() < 0.03, "{driving}");
    }
}
