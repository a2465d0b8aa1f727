//! Outputs of runs: `trajectory.csv`, `summary.json` and the plots, written from a
//! [`RunResult`] (the run layer writes nothing).
//!
//! - [`plot`]: side view over the terrain, top view, attitude (PNG + SVG);
//! - [`replay`]: what the 3-D view needs to replay a run (`scene.json`, `belts.csv`);
//! - [`side_line`]: the side view's polyline;
//! - [`report`]: a finished run in words;
//! - [`plot_files`]: the plot files of runs and comparisons, with the terrain drawn under them;
//! - [`signals`]: position, speed, yaw, flipper angles, slip and traction against time;
//! - [`mod@mcap`]: `run.mcap`, the run as a ROS 2 recording (topics, types and frames there);
//! - [`team`]: a world with several robots: each robot's outputs in its folder, `team.json`,
//!   the robots in one plot, the run in words;
//! - [`ros_messages`]: the ROS 2 messages of a sample, which `run.mcap` records and the ROS 2
//!   node publishes;
//! - [`kept_attempts`]: a run folder's earlier attempts (`attempts/N/`), read back;
//! - [`ros_course`]: a scored course's score and events as ROS 2 messages (`/course`,
//!   `/course/events`);
//! - [`odom_covariance`]: the covariances of `/odom` from a skid-steer encoder model;
//! - [`foxglove_scene`]: `run.mcap`'s `/scene` (`foxglove.SceneUpdate`: terrain and robot)
//!   and `/soil`;
//! - [`urdf_export`]: `/robot_description`, the URDF file's text or one generated from the
//!   vehicle model;
//! - [`ros_names`]: a robot's topics and frames namespaced in a world of several robots;
//! - [`debrief`]: `debrief.html`, a run's printable debrief (score, events, the path on the
//!   course map: [`debrief_map`], key plots: [`debrief_plots`]), read back from its folder;

pub mod debrief;
pub mod debrief_map;
pub mod debrief_plots;
pub mod foxglove_scene;
pub mod incomplete;
pub mod kept_attempts;
pub mod mcap;
pub mod odom_covariance;
pub mod plot;
pub mod plot_files;
pub mod replay;
pub mod report;
pub mod ros_course;
pub mod ros_messages;
pub mod ros_names;
pub mod ros_sensors;
pub mod sensors;
pub mod side_line;
pub mod signals;
pub mod team;
pub mod urdf_export;
pub mod vehicle_outline;

pub use plot_files::{
    SideLine, side_view_terrain, write_compare_plots, write_run_plots, write_team_plots,
};
pub use replay::{Scene, write_replay};
pub use report::run_report;
pub use team::{TeamSummary, team_report, write_team, write_team_session};

use crate::error::{Error, Result};
use crate::run::RunResult;
use crate::world::Sample;
use std::path::Path;

/// The CSV header of `trajectory.csv`.
pub fn csv_header(result: &RunResult) -> Vec<String> {
    let mut h: Vec<String> = [
        "t_s",
        "x_m",
        "y_m",
        "z_m",
        "roll_rad",
        "pitch_rad",
        "yaw_rad",
        "vx_mps",
        "vy_mps",
        "vz_mps",
        "wx_rad_s",
        "wy_rad_s",
        "wz_rad_s",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    for n in &result.track_names {
        h.push(format!("belt_speed_{n}_mps"));
    }
    for n in &result.track_names {
        h.push(format!("belt_phase_{n}_m"));
    }
    for n in &result.flipper_names {
        h.push(format!("flipper_{n}_rad"));
    }
    h.push("contacts".into());
    h.push("penetration_m".into());
    for n in &result.track_names {
        h.extend([
            format!("belt_cmd_{n}_mps"),
            format!("slip_{n}"),
            format!("traction_{n}_n"),
            format!("friction_traction_{n}_n"),
            format!("reaction_{n}_n"),
            format!("normal_load_{n}_n"),
            format!("contacts_{n}"),
        ]);
    }
    for c in ["odom_x_m", "odom_y_m", "odom_yaw_rad", "icr_x_m", "icr_y_m"] {
        h.push(c.into());
    }
    if let Some(s) = result.samples.first() {
        for (n, d) in result.track_names.iter().zip(&s.drive) {
            if d.is_some() {
                h.extend([
                    format!("belt_force_{n}_n"),
                    format!("max_belt_force_{n}_n"),
                    format!("sprocket_torque_{n}_nm"),
                    format!("motor_torque_{n}_nm"),
                    format!("power_{n}_w"),
                ]);
            }
            if d.as_ref().is_some_and(|d| d.electrical.is_some()) {
                h.extend([
                    format!("current_{n}_a"),
                    format!("voltage_{n}_v"),
                    format!("electrical_power_{n}_w"),
                ]);
            }
        }
        if s.drawbar_n.is_some() {
            h.push("drawbar_n".into());
        }
        if !s.soil.is_empty() {
            for n in &result.track_names {
                h.extend([
                    format!("sinkage_{n}_m"),
                    format!("max_sinkage_{n}_m"),
                    format!("soil_normal_{n}_n"),
                    format!("soil_thrust_{n}_n"),
                    format!("compaction_{n}_n"),
                    format!("soil_contact_area_{n}_m2"),
                    format!("soil_contact_length_{n}_m"),
                ]);
            }
        }
    }
    h
}

/// The per-track, odometry and centre-of-rotation cells of a row (after `penetration_m`);
/// the centre of rotation is empty while the chassis does not turn.
fn track_cells(s: &Sample) -> String {
    let mut line = String::new();
    for (i, l) in s.loads.iter().enumerate() {
        line.push_str(&format!(
            ",{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{}",
            s.belt_cmd[i],
            s.slip[i],
            l.traction_n,
            l.friction_traction_n,
            l.reaction_n,
            l.normal_n,
            l.contacts
        ));
    }
    let [x, y, yaw] = s.odom;
    line.push_str(&format!(",{x:.6},{y:.6},{yaw:.6}"));
    match s.icr {
        Some([ix, iy]) => line.push_str(&format!(",{ix:.6},{iy:.6}")),
        None => line.push_str(",,"),
    }
    for d in s.drive.iter().flatten() {
        line.push_str(&format!(
            ",{:.6},{:.6},{:.6},{:.6},{:.6}",
            d.belt_force_n, d.max_belt_force_n, d.sprocket_torque_nm, d.motor_torque_nm, d.power_w
        ));
        if let Some(e) = d.electrical {
            line.push_str(&format!(
                ",{:.6},{:.6},{:.6}",
                e.current, e.voltage, e.power
            ));
        }
    }
    if let Some(p) = s.drawbar_n {
        line.push_str(&format!(",{p:.6}"));
    }
    for g in &s.soil {
        line.push_str(&format!(
            ",{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6}",
            g.sinkage_m,
            g.max_sinkage_m,
            g.normal_n,
            g.thrust_n,
            g.compaction_n,
            g.contact_area_m2,
            g.contact_length_m
        ));
    }
    line
}

/// The text of `trajectory.csv`: a header, then one row per sample (6 decimals, SI units).
/// (In memory: for tests and short runs; [`write_run`] streams the rows to the file.)
pub fn trajectory_csv(result: &RunResult) -> String {
    let mut text = csv_header(result).join(",");
    text.push('\n');
    for s in result.samples.iter() {
        text.push_str(&trajectory_row(&s));
    }
    text
}

/// One row of `trajectory.csv` (with its newline).
fn trajectory_row(s: &Sample) -> String {
    let p = &s.pose;
    let mut row = vec![
        s.t,
        p.x,
        p.y,
        p.z,
        p.roll,
        p.pitch,
        p.yaw,
        s.linvel[0],
        s.linvel[1],
        s.linvel[2],
        s.angvel[0],
        s.angvel[1],
        s.angvel[2],
    ];
    row.extend(&s.belt_speed);
    row.extend(&s.belt_phase);
    row.extend(&s.flipper_angle);
    let mut line = row
        .iter()
        .map(|v| format!("{v:.6}"))
        .collect::<Vec<_>>()
        .join(",");
    line.push_str(&format!(",{},{:.6}", s.contacts, s.penetration));
    line.push_str(&track_cells(s));
    line.push('\n');
    line
}

/// Refuses a trajectory row with a non-finite value (NaN or infinite) in any cell: such a run
/// is reported as unstable (exit code 3), never written as a result.
fn check_finite_row(header: &[String], line: &str) -> Result<()> {
    let line = line.trim_end();
    for (i, cell) in line.split(',').enumerate() {
        let lower = cell.to_ascii_lowercase();
        if lower.contains("nan") || lower.contains("inf") {
            return Err(Error::Unstable {
                time_s: line
                    .split(',')
                    .next()
                    .and_then(|t| t.parse().ok())
                    .unwrap_or(0.0),
                body: "the trajectory".into(),
                what: format!(
                    "has a non-finite value ({cell}) in column {}",
                    header.get(i).map_or("?", String::as_str)
                ),
            });
        }
    }
    Ok(())
}

/// Refuses a summary with a non-finite number (serde writes it as `null`; the only optional
/// fields are `scenario` and `trainee`), as [`check_finite_row`] does for the trajectory.
fn check_finite_summary(result: &RunResult) -> Result<()> {
    fn null_at(v: &serde_json::Value, at: &str) -> Option<String> {
        match v {
            serde_json::Value::Null => Some(at.to_string()),
            serde_json::Value::Array(a) => a
                .iter()
                .enumerate()
                .find_map(|(i, x)| null_at(x, &format!("{at}[{i}]"))),
            serde_json::Value::Object(m) => m
                .iter()
                .filter(|(k, _)| !(at.is_empty() && ["scenario", "trainee"].contains(&k.as_str())))
                .find_map(|(k, x)| {
                    null_at(
                        x,
                        &if at.is_empty() {
                            k.clone()
                        } else {
                            format!("{at}.{k}")
                        },
                    )
                }),
            _ => None,
        }
    }
    let v = serde_json::to_value(&result.summary).expect("summary serialises");
    match null_at(&v, "") {
        None => Ok(()),
        Some(key) => Err(Error::Unstable {
            time_s: result.summary.sim_time_s,
            body: "the summary".into(),
            what: format!("has a non-finite value at {key}"),
        }),
    }
}

/// Writes `summary.json` and `trajectory.csv` into `dir` (created if needed), each atomically
/// (a temporary file renamed into place); a trajectory with a non-finite value is refused
/// ([`Error::Unstable`]) and nothing is written.
pub fn write_run(result: &RunResult, dir: &Path) -> Result<()> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| Error::Io { path, source }
    };
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    check_finite_summary(result)?;
    // The rows streamed to the file one by one (the samples may be on disk: issue 45), each
    // checked; a non-finite one stops the writing and nothing is left.
    let header = csv_header(result);
    let mut unstable = None;
    let tp = dir.join("trajectory.csv");
    let written = crate::files::write_atomic_with(&tp, |w| {
        writeln!(w, "{}", header.join(","))?;
        for s in result.samples.iter() {
            let row = trajectory_row(&s);
            if let Err(e) = check_finite_row(&header, &row) {
                unstable = Some(e);
                return Err(std::io::Error::other("a non-finite value"));
            }
            w.write_all(row.as_bytes())?;
        }
        Ok(())
    });
    if let Some(e) = unstable {
        return Err(e);
    }
    written?;
    let sp = dir.join("summary.json");
    let json = serde_json::to_string_pretty(&result.summary).expect("summary serialises");
    crate::files::write_atomic(&sp, (json + "\n").as_bytes())?;
    Ok(())
}

/// Which files [`write_outputs`] writes besides `summary.json` and `trajectory.csv`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Outputs {
    /// The replay data of the 3-D page: `scene.json`, `belts.csv`.
    pub replay: bool,
    /// The plots (PNG and SVG).
    pub plots: bool,
    /// `run.mcap`, the run as a ROS 2 recording ([`mod@mcap`]).
    pub mcap: bool,
    /// Colour cameras' raw `sensor_msgs/Image` in `run.mcap` besides their compressed ones
    /// ([`mcap::McapOptions::raw_images`]; off by default: 57.6 kB per 160 x 120 frame,
    /// against 3 to 37 kB of PNG in docs/MCAP.md's measurements).
    pub raw_images: bool,
}

impl Outputs {
    /// What `tracksim run` writes by default (everything but `run.mcap`, written on request).
    pub const ALL: Outputs = Outputs {
        replay: true,
        plots: true,
        mcap: false,
        raw_images: false,
    };

    /// The data only, no plots and no `run.mcap`: `summary.json`, `trajectory.csv` and, with
    /// `replay`, the replay data (what an ensemble's member writes).
    pub const fn data(replay: bool) -> Outputs {
        Outputs {
            replay,
            plots: false,
            mcap: false,
            raw_images: false,
        }
    }
}

/// Writes a session's run folder: what [`write_outputs`] writes (`which`) and the session's
/// controls as `commands.toml` (`log` under `header`; its replay command runs
/// `scenario_file` for the run's duration). Returns the paths written. `drive`, `ros` and the
/// env's recorder write through here.
pub fn write_session(
    sc: &crate::model::Scenario,
    result: &RunResult,
    (log, header): (&crate::run::CommandLog, crate::run::LogHeader),
    scenario_file: &Path,
    dir: &Path,
    which: Outputs,
) -> Result<Vec<std::path::PathBuf>> {
    let mut written = write_outputs(sc, result, dir, which)?;
    let duration = result.samples.last().map_or(0.0, |s| s.t);
    written.push(log.write(header, scenario_file, dir, duration)?);
    Ok(written)
}

/// Writes every output of a run of `sc` into `dir` (`summary.json`, `trajectory.csv`, and
/// what `which` selects; `run.mcap` also when the scenario's `[output] mcap` is true; with the
/// replay data, `debrief.html` when the scenario has a `[course]`);
/// returns the paths written. `run`, `drive`, `compare` and every
/// other front end write through here.
pub fn write_outputs(
    sc: &crate::model::Scenario,
    result: &RunResult,
    dir: &Path,
    which: Outputs,
) -> Result<Vec<std::path::PathBuf>> {
    write_run(result, dir)?;
    let mut written = vec![dir.join("summary.json"), dir.join("trajectory.csv")];
    written.extend(sensors::write_sensor_streams(&result.sensors, dir)?);
    if which.replay {
        written.extend(write_replay(sc, result, dir)?);
    }
    if which.plots {
        written.extend(write_run_plots(sc, result, dir)?);
    }
    if which.mcap || sc.record_mcap {
        let opts = mcap::McapOptions {
            raw_images: which.raw_images,
        };
        written.push(mcap::write_mcap(sc, result, dir, opts)?);
    }
    if which.replay && sc.course.is_some() {
        written.push(debrief::write_debrief(dir)?);
    }
    Ok(written)
}
