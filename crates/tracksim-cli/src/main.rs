//! The `tracksim` command: a thin layer over the `tracksim` library, one file per command in
//! `commands/` (its clap `Args` and the function that runs it).
//!
//! Exit codes: 0 success, 1 the scenario's outcome was failure (with `--strict`) or a
//! validation case failed, 2 bad input, 3 the simulation went unstable, 130 stopped by Ctrl-C or
//! SIGTERM (what was simulated is written, with the outcome "interrupted").

#![warn(clippy::too_many_lines)]

use clap::{Parser, Subcommand};
use std::process::ExitCode;
use tracksim::Error;

/// Prints a line on standard output; a closed standard output (`tracksim ... | head`) ends the
/// program quietly with exit code 0 instead of a panic.
macro_rules! out {
    () => {
        out!("")
    };
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = writeln!(std::io::stdout().lock(), $($arg)*) {
            if e.kind() == std::io::ErrorKind::BrokenPipe {
                std::process::exit(0);
            }
            eprintln!("error: cannot write to standard output: {e}");
            std::process::exit(2);
        }
    }};
}

mod commands;

use commands::{Failure, *};

/// Real-time simulation of tracked robots with grousers (Okada et al., ICRA 2020) on Rapier.
#[derive(Parser)]
#[command(name = "tracksim", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    Run(run::RunArgs),
    Compare(compare::CompareArgs),
    Bench(bench::BenchArgs),
    Validate(validate::ValidateArgs),
    Drive(drive::DriveArgs),
    View(view::ViewArgs),
    Video(video::VideoArgs),
    Ros(ros::RosArgs),
    Check(check::CheckArgs),
    /// Run a randomised scenario many times (a dataset): one folder per run and a manifest
    /// (one JSON line per run), sharded for job arrays, resumable.
    Sweep(sweep::SweepArgs),
    Merge(merge::MergeArgs),
    List(list::ListArgs),
    Sessions(sessions::SessionsArgs),
    Debrief(debrief::DebriefArgs),
    Export(export::ExportArgs),
    Import(import::ImportArgs),
}

fn main() -> ExitCode {
    let r = match Cli::parse().command {
        Cmd::Run(a) => run::run(a),
        Cmd::Compare(a) => compare::compare(a),
        Cmd::Bench(a) => bench::bench(a),
        Cmd::Validate(a) => validate::validate(a),
        Cmd::Drive(a) => drive::drive(a),
        Cmd::View(a) => view::view(a),
        Cmd::Video(a) => video::video(a),
        Cmd::Ros(a) => ros::ros(a),
        Cmd::Check(a) => check::check(a),
        Cmd::Sweep(a) => sweep::sweep(a),
        Cmd::Merge(a) => merge::merge(a),
        Cmd::List(a) => list::list(a),
        Cmd::Sessions(a) => sessions::sessions(a),
        Cmd::Debrief(a) => debrief::debrief(a),
        Cmd::Export(a) => export::export(a),
        Cmd::Import(a) => import::import(a),
    };
    match r {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Outcome) => ExitCode::from(1),
        Err(Failure::Interrupted) => ExitCode::from(EXIT_INTERRUPTED),
        Err(Failure::Reported) => ExitCode::from(2),
        Err(Failure::Stopped(why)) => {
            eprintln!("error: {why}");
            ExitCode::from(3)
        }
        Err(Failure::Sim(e)) => {
            eprintln!("error: {e}");
            ExitCode::from(match e {
                Error::Unstable { .. } | Error::Limit { .. } => 3,
                _ => 2,
            })
        }
    }
}
