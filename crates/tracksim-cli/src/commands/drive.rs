//! `tracksim drive`: a live session from the 3-D page, recorded as a run.

use super::{
    AccessArgs, Failure, access, bad_arg, bind_address, check_duration, overrides, scenario_file,
};
use std::path::PathBuf;

/// Drive a scenario live from a 3-D page in the browser (prints its URL); the session is
/// a run: on stop (stop button, Ctrl-C, SIGTERM, --duration, or no page back within the
/// reconnect grace) its outputs go to --out.
#[derive(clap::Args)]
pub struct DriveArgs {
    /// Scenario file (TOML), or the name of a bundled scenario.
    pub file: PathBuf,
    /// Output folder (as `run`, plus commands.toml and controls.csv).
    #[arg(long, default_value = "out/drive")]
    pub out: PathBuf,
    /// Simulated seconds per wall-clock second (0.5 slower, 2 faster than real time).
    #[arg(long, default_value_t = 1.0)]
    pub speed: f64,
    /// TCP port of the page (0: any free port).
    #[arg(long, default_value_t = tracksim::live::DEFAULT_PORT)]
    pub port: u16,
    /// Address to listen on (default loopback only; any other is reachable by others).
    #[arg(long)]
    pub bind: Option<std::net::IpAddr>,
    /// End the session at this simulated time, s (default: when the operator stops).
    #[arg(long)]
    pub duration: Option<f64>,
    /// Track method, overriding the scenario's `simulation.method`.
    #[arg(long)]
    pub method: Option<String>,
    /// Do not write the plot files.
    #[arg(long)]
    pub no_plot: bool,
    /// Start simulating only once a page has connected (the clock starts then).
    #[arg(long)]
    pub wait_for_page: bool,
    /// How long a dropped driver's page (a reload, a network hiccup) may take to reconnect
    /// and drive on, s; the robot stops meanwhile. With no page connected after it, the
    /// session ends.
    #[arg(long, default_value_t = tracksim::live::DEFAULT_RECONNECT_GRACE_S)]
    pub reconnect_grace: f64,
    /// The trainee (operator) driving, recorded in summary.json (`tracksim sessions` lists it).
    /// A session of several robots has a trainee per seat: `--trainee ROBOT=NAME`, once per
    /// robot (recorded in that robot's summary.json and in team.json).
    #[arg(long)]
    pub trainee: Vec<String>,
    /// Who else may use the page (docs/LIVE.md, security).
    #[command(flatten)]
    pub access: AccessArgs,
}

/// `tracksim drive`.
pub fn drive(a: DriveArgs) -> Result<(), Failure> {
    use tracksim::live::{DriveOptions, Hub, Mode, Server};
    let file = scenario_file(&a.file)?;
    let sc = tracksim::load_scenario_with(&file, &overrides(a.method.as_deref(), None, None)?)?;
    if sc.team.is_none() && a.trainee.len() > 1 {
        return Err(bad_arg(
            "--trainee",
            format!(
                "one robot has one trainee, got {}: give --trainee once",
                a.trainee.len()
            ),
        ));
    }
    let trainee = match sc.team {
        None => super::trainee(a.trainee.first().map(String::as_str))?,
        Some(_) => None,
    };
    if !(a.speed.is_finite() && a.speed > 0.0) {
        return Err(bad_arg(
            "--speed",
            format!("must be a number > 0 (1 = real time), got {}", a.speed),
        ));
    }
    let max_time = a
        .duration
        .map(|d| check_duration(d, sc.solver.dt))
        .transpose()?;
    if !(a.reconnect_grace.is_finite() && (0.0..=86_400.0).contains(&a.reconnect_grace)) {
        return Err(bad_arg(
            "--reconnect-grace",
            format!(
                "must be a number of seconds in [0, 86400] (default {}), got {}",
                tracksim::live::DEFAULT_RECONNECT_GRACE_S,
                a.reconnect_grace
            ),
        ));
    }
    let opts = DriveOptions {
        speed: a.speed,
        max_time,
        wait_for_page: a.wait_for_page,
        interrupt: Some(&super::STOP),
    };
    if sc.team.is_some() {
        return drive_team(&a, &file, &sc, opts);
    }
    let hub = Hub::with_grace(a.reconnect_grace);
    let scene_json = vec![tracksim::output::Scene::new(&sc).to_json()];
    let mode = Mode::Drive {
        hub: hub.clone(),
        scene_json,
    };
    let mut server = Server::start_with(bind_address(a.bind), a.port, mode, access(&a.access)?)?;
    let h = hub.clone();
    super::on_stop(move || h.request_stop());
    out!(
        "drive      open {} in a browser (the first page to connect drives)",
        server.url()
    );
    out!(
        "           stop: the page's stop button, Ctrl-C or SIGTERM; a dropped page may \
         reconnect within {} s (the robot stops meanwhile)",
        a.reconnect_grace
    );
    session_token(&hub, &server.url());
    tracksim::output::incomplete::mark_incomplete(&a.out)?;
    let session = tracksim::live::run_session(&sc, &hub, opts);
    hub.request_stop();
    server.shutdown();
    let mut session = session?;
    session.set_trainee(trainee);
    if !session.attempts.is_empty() {
        out!(
            "attempts   {} (each reset kept: {}/attempts/1 .. {}; the last is the session's \
             folder)",
            session.attempts.len() + 1,
            a.out.display(),
            session.attempts.len()
        );
    }
    let written = session.write(&sc, &file, &a.out, !a.no_plot)?;
    tracksim::output::incomplete::mark_complete(&a.out)?;
    super::session_report(&session.result.summary);
    finish(
        &a,
        &file,
        &written,
        session.duration(),
        &session.result.outcome,
    )?;
    super::world_stopped(session.result.summary.stopped.as_deref(), &a.out)
}

/// Prints the session's token: what a client other than the page (which reads it itself)
/// presents to drive (`/ws?session=TOKEN`); and the instructor's URL (its own token, never
/// served to a page).
fn session_token(hub: &tracksim::live::Hub, url: &str) {
    if let Some(t) = hub.session_token() {
        out!(
            "           session token {t} (the page has it; another client presents \
             /ws?session=TOKEN to drive)"
        );
    }
    if let Some(t) = hub.instructor_token() {
        out!(
            "instructor open {url}?instructor={t} (pause, reset, end, faults; keep this URL \
             to the instructor)"
        );
    }
}

/// Lists what a session wrote and how to replay it; an interrupted session fails.
fn finish(
    a: &DriveArgs,
    file: &std::path::Path,
    written: &[PathBuf],
    duration: f64,
    outcome: &tracksim::Outcome,
) -> Result<(), Failure> {
    for w in written {
        out!("wrote      {}", w.display());
    }
    out!(
        "replay     tracksim view {}   (or reproduce: {})",
        a.out.display(),
        tracksim::run::command_log::reproduce_command(file, &a.out.join("commands.toml"), duration)
    );
    if matches!(outcome, tracksim::Outcome::Interrupted(_)) {
        return Err(Failure::Interrupted);
    }
    Ok(())
}

/// `tracksim drive` of a file with several robots: a seat per robot.
fn drive_team(
    a: &DriveArgs,
    file: &std::path::Path,
    sc: &tracksim::Scenario,
    opts: tracksim::live::DriveOptions,
) -> Result<(), Failure> {
    use tracksim::live::{Hub, Mode, Server};
    let names = sc.robot_names();
    let trainees = seat_trainees(&a.trainee, &names)?;
    let hub = Hub::team(names.clone(), a.reconnect_grace);
    let scene_json = (0..names.len())
        .map(|k| tracksim::output::Scene::new(&sc.robot_view(k)).to_json())
        .collect();
    let mode = Mode::Drive {
        hub: hub.clone(),
        scene_json,
    };
    let mut server = Server::start_with(bind_address(a.bind), a.port, mode, access(&a.access)?)?;
    let h = hub.clone();
    super::on_stop(move || h.request_stop());
    out!(
        "drive      {} robots, a seat each: open {} in a browser per trainee (each page takes \
         the first free seat), or pick one:",
        names.len(),
        server.url()
    );
    for n in &names {
        out!("           {n}: {}?robot={n}", server.url());
    }
    out!(
        "           watch any robot: {}?watch=1&robot=NAME",
        server.url()
    );
    session_token(&hub, &server.url());
    out!(
        "           a driver's stop closes their seat; the session ends when every seat taken \
         has stopped, on Ctrl-C or SIGTERM; a dropped page may reconnect within {} s",
        a.reconnect_grace
    );
    tracksim::output::incomplete::mark_incomplete(&a.out)?;
    let session = tracksim::live::run_team_session(sc, &hub, opts);
    hub.request_stop();
    server.shutdown();
    let mut session = session?;
    for name in &names {
        session.set_trainee(name, trainees.get(name).cloned());
    }
    let written = session.write(sc, file, &a.out, !a.no_plot)?;
    tracksim::output::incomplete::mark_complete(&a.out)?;
    for (name, run) in &session.result.robots {
        let who = run
            .summary
            .trainee
            .as_ref()
            .map_or_else(String::new, |t| format!(" ({t})"));
        let score = run.summary.course.as_ref().map_or_else(String::new, |c| {
            format!(", course {}: score {:.2} s", c.status, c.score.score_s)
        });
        out!(
            "{name:<10} {}: {}{who}{score}",
            run.summary.outcome,
            run.summary.outcome_reason
        );
    }
    let o = session.outcome();
    out!("outcome    {}: {}", o.name(), o.reason());
    finish(a, file, &written, session.duration(), o)?;
    super::world_stopped(session.result.stopped.as_deref(), &a.out)
}

/// The trainee of each seat from `--trainee ROBOT=NAME` (each robot at most once, every name
/// checked as a one-robot session's).
fn seat_trainees(
    given: &[String],
    robots: &[String],
) -> Result<std::collections::BTreeMap<String, String>, Failure> {
    let mut out = std::collections::BTreeMap::new();
    for g in given {
        let Some((robot, name)) = g.split_once('=') else {
            return Err(bad_arg(
                "--trainee",
                format!(
                    "a session of several robots has a trainee per seat: give --trainee \
                     ROBOT=NAME for each (robots: {}), got {g:?}",
                    robots.join(", ")
                ),
            ));
        };
        let robot = robot.trim();
        if !robots.iter().any(|r| r == robot) {
            return Err(bad_arg(
                "--trainee",
                format!(
                    "no robot {robot:?} in this file (robots: {})",
                    robots.join(", ")
                ),
            ));
        }
        let name = super::trainee(Some(name))?.unwrap_or_default();
        if out.insert(robot.to_string(), name).is_some() {
            return Err(bad_arg(
                "--trainee",
                format!("robot {robot:?} is given a trainee twice: one per seat"),
            ));
        }
    }
    Ok(out)
}
