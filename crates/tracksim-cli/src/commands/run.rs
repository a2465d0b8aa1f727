//! `tracksim run`: a scenario run to its end; its outputs written, its report printed.

use super::{EXIT_INTERRUPTED, Failure, on_stop, overrides, scenario_file};
use std::io::IsTerminal;
use std::path::PathBuf;
use tracksim::{Outcome, RunOptions};

/// Run a scenario file; write summary.json, trajectory.csv and plots into --out.
#[derive(clap::Args)]
pub struct RunArgs {
    /// Scenario file (TOML), or the name of a bundled scenario (see `tracksim list`).
    pub file: PathBuf,
    /// Output folder.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Print nothing but errors (no progress bar, no summary).
    #[arg(long)]
    pub quiet: bool,
    /// Print the summary as JSON on standard output.
    #[arg(long)]
    pub json: bool,
    /// Pace the simulation to the wall clock (for watching or driving it live).
    #[arg(long)]
    pub realtime: bool,
    /// Exit with code 1 when the scenario's outcome is failure.
    #[arg(long)]
    pub strict: bool,
    /// Track method, overriding the scenario's `simulation.method`.
    #[arg(long)]
    pub method: Option<String>,
    /// Override the simulated duration, s.
    #[arg(long)]
    pub duration: Option<f64>,
    /// Do not write the plot files.
    #[arg(long)]
    pub no_plot: bool,
    /// Also write run.mcap: the run as a ROS 2 recording (cdr messages, ros2msg schemas:
    /// /tf, /tf_static, /odom, /ground_truth/odom, /joint_states, /tracks, /clock, sensors),
    /// for Foxglove and the ROS 2 bag tools.
    #[arg(long)]
    pub mcap: bool,
    /// Replace the scenario's `[[commands]]` by those of this file (e.g. the
    /// `commands.toml` a `tracksim drive` session wrote: the run reproduces the session).
    #[arg(long)]
    pub commands: Option<PathBuf>,
    /// The trainee (operator) of the run, recorded in summary.json (`tracksim sessions`).
    #[arg(long)]
    pub trainee: Option<String>,
}

fn progress_bar(show: bool) -> Option<indicatif::ProgressBar> {
    show.then(|| {
        let b = indicatif::ProgressBar::new(1000);
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "{bar:40} {msg} (elapsed {elapsed}, eta {eta})",
            )
            .expect("valid template"),
        );
        b
    })
}

/// `tracksim run`.
pub fn run(a: RunArgs) -> Result<(), Failure> {
    let file = scenario_file(&a.file)?;
    let o = overrides(a.method.as_deref(), a.duration, a.commands.as_deref())?;
    let sc = tracksim::load_scenario_with(&file, &o)?;
    let trainee = super::trainee(a.trainee.as_deref())?;
    let bar = progress_bar(!a.quiet && !a.json && std::io::stderr().is_terminal());
    on_stop(|| {});
    let wall = std::time::Instant::now();
    let opts = RunOptions {
        realtime: a.realtime,
        stop: Some(&super::STOP),
    };
    let result = tracksim::run_scenario_with(&sc, opts, |t, total| {
        if let Some(b) = &bar {
            b.set_position((1000.0 * t / total) as u64);
            b.set_message(format!(
                "t = {t:.2} / {total:.2} s, {:.1} x real time",
                t / wall.elapsed().as_secs_f64().max(1e-9)
            ));
        }
    });
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let mut result = result?;
    result.summary.trainee = trainee;
    let which = tracksim::output::Outputs {
        replay: true,
        plots: !a.no_plot,
        mcap: a.mcap,
    };
    let written = tracksim::output::write_outputs(&sc, &result, &a.out, which)?;
    if a.json {
        out!(
            "{}",
            serde_json::to_string_pretty(&result.summary).expect("summary serialises")
        );
    } else if !a.quiet {
        out!(
            "{}",
            tracksim::output::run_report(&file, &sc, &result, &written)
        );
    }
    if matches!(result.outcome, Outcome::Interrupted(_)) {
        eprintln!(
            "interrupted: wrote what was simulated into {} (exit {EXIT_INTERRUPTED})",
            a.out.display()
        );
        return Err(Failure::Interrupted);
    }
    if a.strict && matches!(result.outcome, Outcome::Failure(_)) {
        return Err(Failure::Outcome);
    }
    Ok(())
}
