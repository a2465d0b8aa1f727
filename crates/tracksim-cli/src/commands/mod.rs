//! One file per command: its clap `Args` and the function that runs it. What they share:
//! [`Failure`] (mapped to exit codes in `main.rs`), flag checks, the stop flag of Ctrl-C and
//! SIGTERM, and scenario files found by path or by bundled name.

pub mod bench;
pub mod check;
pub mod compare;
pub mod debrief;
pub mod drive;
pub mod export;
pub mod import;
pub mod list;
pub mod merge;
pub mod ros;
pub mod run;
pub mod sessions;
pub mod setting;
pub mod sweep;
pub mod validate;
pub mod video;
pub mod view;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use tracksim::{Error, Method};

/// Why a command failed, mapped to an exit code.
pub enum Failure {
    /// The scenario's outcome was failure (`--strict`) or a validation case failed; exit 1.
    Outcome,
    /// Stopped by Ctrl-C or SIGTERM (what was simulated is written); exit 130.
    Interrupted,
    /// Already reported on standard output (by `check`); exit 2.
    Reported,
    /// An error of the library.
    Sim(Error),
    /// The world stopped (a blow-up, robots too far apart) and what was simulated up to there
    /// is written; exit 3 (the message says why and where).
    Stopped(String),
}

/// A run or session whose world stopped before its end (`why`: `Summary::stopped`, or a team
/// result's `stopped`): said on standard error with where its outputs are, exit 3; `Ok`
/// otherwise (issue 59).
pub fn world_stopped(why: Option<&str>, out: &std::path::Path) -> Result<(), Failure> {
    match why {
        Some(why) => Err(Failure::Stopped(format!(
            "{why}\nwrote what was simulated up to there, every robot's, into {}",
            out.display()
        ))),
        None => Ok(()),
    }
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        Failure::Sim(e)
    }
}

/// A refused command-line value: `arg` names the flag.
pub fn bad_arg(arg: &str, message: String) -> Failure {
    Failure::Sim(Error::Invalid {
        path: arg.into(),
        issues: vec![tracksim::SpecIssue::new("", message)],
    })
}

/// Parses one track method name given to `flag`.
pub fn parse_method(flag: &str, name: &str) -> Result<Method, Failure> {
    Method::parse("", name).map_err(|i| bad_arg(flag, i.message))
}

/// Parses a `--methods` list; empty means every compared method.
pub fn parse_methods(names: &[String]) -> Result<Vec<Method>, Failure> {
    if names.is_empty() {
        return Ok(Method::COMPARED.to_vec());
    }
    names.iter().map(|m| parse_method("--methods", m)).collect()
}

/// The overrides of `--method`, `--duration` and `--commands`.
pub fn overrides(
    method: Option<&str>,
    duration: Option<f64>,
    commands: Option<&Path>,
) -> Result<tracksim::Overrides, Failure> {
    Ok(tracksim::Overrides {
        method: method.map(|m| parse_method("--method", m)).transpose()?,
        duration_s: duration,
        commands: commands.map(Path::to_path_buf),
        ..Default::default()
    })
}

/// A scenario (or vehicle) file given on the command line: the path if it exists, else the
/// bundled file of that name (`packbot_flat`, `classic/packbot_drawbar`), extracted.
pub fn scenario_file(given: &Path) -> Result<PathBuf, Failure> {
    if given.exists() {
        return Ok(given.to_path_buf());
    }
    match tracksim::bundled::resolve(&given.to_string_lossy())? {
        Some(p) => Ok(p),
        // The loader names the missing file.
        None => Ok(given.to_path_buf()),
    }
}

/// The folder holding `vehicles/` and `scenarios/` for the named cases of `bench` and
/// `validate`: the current folder if it has them (a clone), else the bundle extracted.
pub fn data_root() -> Result<PathBuf, Failure> {
    let here = PathBuf::from(".");
    if here.join("scenarios").is_dir() && here.join("vehicles").is_dir() {
        Ok(here)
    } else {
        Ok(tracksim::bundled::extracted()?)
    }
}

/// Set by Ctrl-C or SIGTERM: a run stops at its next step and writes what it simulated.
pub static STOP: AtomicBool = AtomicBool::new(false);

/// Exit code of a command stopped by Ctrl-C or SIGTERM (128 + SIGINT, as shells report it).
pub const EXIT_INTERRUPTED: u8 = 130;

/// Installs the handler of Ctrl-C and SIGTERM (containers, systemd and `timeout` send it):
/// the first sets [`STOP`] and calls `also`; a second ends the program at once.
pub fn on_stop(also: impl Fn() + Send + 'static) {
    if let Err(e) = ctrlc::set_handler(move || {
        if STOP.swap(true, Ordering::SeqCst) {
            std::process::exit(i32::from(EXIT_INTERRUPTED));
        }
        also();
    }) {
        eprintln!("warning: Ctrl-C and SIGTERM will not write the outputs of a stopped run: {e}");
    }
}

/// Whether Ctrl-C or SIGTERM came.
pub fn stopped() -> bool {
    STOP.load(Ordering::SeqCst)
}

/// Checks a `--duration` value, s, for steps of `dt` s (the limits of `simulation.duration_s`).
pub fn check_duration(d: f64, dt: f64) -> Result<f64, Failure> {
    match tracksim::model::duration_problem(d, dt) {
        None => Ok(d),
        Some(m) => Err(bad_arg("--duration", m)),
    }
}

/// The first lines a paced session (`drive`, `ros`) prints when it ends: simulated and wall
/// time with both real-time factors, and the outcome.
pub fn session_report(s: &tracksim::Summary) {
    out!(
        "simulated  {:.3} s in {:.3} s wall ({:.2} x real time paced, stepping alone {:.1} x)",
        s.sim_time_s,
        s.elapsed_time_s,
        s.paced_real_time_factor,
        s.real_time_factor
    );
    out!("outcome    {}: {}", s.outcome, s.outcome_reason);
    if let Some(c) = &s.course {
        out!("{}", tracksim::output::report::course_line(c));
    }
}

/// The address to listen on: loopback unless `--bind` says otherwise (then with a warning).
pub fn bind_address(bind: Option<std::net::IpAddr>) -> std::net::IpAddr {
    match bind {
        Some(a) if !a.is_loopback() => {
            eprintln!(
                "warning: listening on {a}, not loopback: anyone who can reach this machine can \
                 open the page and watch; driving needs the session's token, which the page \
                 served here reads (so anyone who can open it can drive)"
            );
            a
        }
        Some(a) => a,
        None => tracksim::live::DEFAULT_BIND,
    }
}

/// Who else may use the page's server (`drive`, `view`): besides its own loopback names.
#[derive(clap::Args, Debug, Default)]
pub struct AccessArgs {
    /// Also answer requests for this host name or IP address (the `Host` a browser sends when
    /// it opens http://NAME:PORT/; e.g. the machine's name on the lab network). Repeatable.
    /// By default only 127.0.0.1, localhost and [::1] (and a non-loopback --bind address).
    #[arg(long = "allow-host", value_name = "NAME")]
    pub allow_host: Vec<String>,
    /// Also accept pages of this origin (http://NAME:PORT or https://NAME, as its address
    /// bar shows it): their WebSocket may watch, and drive with the session's token.
    /// Repeatable. By default only the server's own pages.
    #[arg(long = "allow-origin", value_name = "URL")]
    pub allow_origin: Vec<String>,
}

/// The server's [`tracksim::live::Access`] from `--allow-host` and `--allow-origin`.
pub fn access(a: &AccessArgs) -> Result<tracksim::live::Access, Failure> {
    let mut access = tracksim::live::Access::loopback();
    for h in &a.allow_host {
        access = access
            .allow_host(h)
            .map_err(|m| bad_arg("--allow-host", m))?;
    }
    for o in &a.allow_origin {
        access = access
            .allow_origin(o)
            .map_err(|m| bad_arg("--allow-origin", m))?;
    }
    Ok(access)
}

/// Most characters of a `--trainee` name.
pub const MAX_TRAINEE_CHARS: usize = 100;

/// A `--trainee` name checked: 1 to [`MAX_TRAINEE_CHARS`] characters, no control characters.
pub fn trainee(name: Option<&str>) -> Result<Option<String>, Failure> {
    let Some(n) = name else {
        return Ok(None);
    };
    let count = n.chars().count();
    if n.trim().is_empty() || count > MAX_TRAINEE_CHARS || n.chars().any(char::is_control) {
        return Err(bad_arg(
            "--trainee",
            format!(
                "must be 1 to {MAX_TRAINEE_CHARS} characters without control characters, got \
                 {count} characters"
            ),
        ));
    }
    Ok(Some(n.trim().to_string()))
}
