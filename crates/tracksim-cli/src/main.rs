//! The `tracksim` command: a thin layer over the `tracksim` library.

use anyhow::Result;
use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

/// Real-time simulation of tracked robots with grousers (Okada et al., ICRA 2020) on Rapier.
#[derive(Parser)]
#[command(name = "tracksim", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Run a scenario file; write summary.json and trajectory.csv into --out.
    Run {
        /// Scenario file (TOML).
        file: PathBuf,
        /// Output folder.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Print nothing but errors.
        #[arg(long)]
        quiet: bool,
        /// Print the summary as JSON on standard output.
        #[arg(long)]
        json: bool,
    },
}

fn run(file: PathBuf, out: PathBuf, quiet: bool, json: bool) -> Result<(), tracksim::Error> {
    let sc = tracksim::load_scenario(&file)?;
    let result = tracksim::run_scenario(&sc, |_, _| {})?;
    result.write(&out)?;
    let s = &result.summary;
    if json {
        println!(
            "{}",
            serde_json::to_string_pretty(s).expect("summary serialises")
        );
    } else if !quiet {
        let p = &s.final_pose;
        println!("scenario   {}", file.display());
        println!("vehicle    {}", s.vehicle);
        println!(
            "simulated  {:.3} s in {:.3} s wall: real-time factor {:.1}",
            s.sim_time_s, s.wall_time_s, s.real_time_factor
        );
        println!(
            "mean speed {:.4} m/s, distance {:.3} m",
            s.mean_speed_mps, s.distance_m
        );
        println!(
            "final pose x {:.4} y {:.4} z {:.4} m, roll {:.2} pitch {:.2} yaw {:.2} deg",
            p.x,
            p.y,
            p.z,
            p.roll.to_degrees(),
            p.pitch.to_degrees(),
            p.yaw.to_degrees()
        );
        println!("outputs    {}", out.display());
    }
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let r = match cli.command {
        Cmd::Run {
            file,
            out,
            quiet,
            json,
        } => run(file, out, quiet, json),
    };
    match r {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(match e {
                tracksim::Error::Unstable { .. } => 3,
                _ => 2,
            })
        }
    }
}
