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
    /// The solver setting (overrides the file's; the file's `[expect]` is then not checked).
    #[command(flatten)]
    pub setting: super::setting::SettingArgs,
    /// Do not write the plot files.
    #[arg(long)]
    pub no_plot: bool,
    /// Also write run.mcap: the run as a ROS 2 recording (cdr messages, ros2msg schemas:
    /// /tf, /tf_static, /odom, /ground_truth/odom, /joint_states, /tracks, /clock, sensors),
    /// for Foxglove and the ROS 2 bag tools.
    #[arg(long)]
    pub mcap: bool,
    /// With --mcap, also record colour cameras' raw sensor_msgs/Image (rgb8) on /<camera>,
    /// besides their CompressedImage (PNG) on /<camera>/compressed and CameraInfo (57.6 kB a
    /// 160 x 120 frame against a few kB of PNG; Foxglove shows the compressed topic).
    #[arg(long)]
    pub raw_images: bool,
    /// Replace the scenario's `[[commands]]` by those of this file (e.g. the
    /// `commands.toml` a `tracksim drive` session wrote: the run reproduces the session).
    #[arg(long)]
    pub commands: Option<PathBuf>,
    /// Run on past the decided outcome to the duration (the scenario's `outcome.stop` set to
    /// false), as a live session goes on after its course is completed: the reproduce command a
    /// `drive` or `ros` session prints carries it.
    #[arg(long)]
    pub keep_running: bool,
    /// The trainee (operator) of the run, recorded in summary.json (`tracksim sessions`).
    #[arg(long)]
    pub trainee: Option<String>,
    /// Seed of the run instead of the file's `simulation.seed`: a randomised file's
    /// `[randomize]` values are drawn from it, as an environment's episode of that seed drew
    /// them (a recorded episode's folder `seed<S>-ep<K>` names it; with its `commands.toml` the
    /// run replays the episode byte for byte).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Run an ensemble of N members instead of one run: member 0 as written, the others with
    /// seeded perturbations of the start (x, y, yaw; each robot's of a file of several) and of
    /// the solver's order, on every core (docs/ENSEMBLE.md). Writes --out/member-NNN/ and ensemble.json / ensemble.csv, prints
    /// the verdict ("S 16/16", "marginal 9/16") and checks the file's [expect] ensemble bounds.
    #[arg(long, value_name = "N")]
    pub ensemble: Option<usize>,
    /// Seed of the ensemble's perturbations.
    #[arg(long, default_value_t = 0, requires = "ensemble")]
    pub ensemble_seed: u64,
    /// Half-width of the ensemble's start offset in x and in y, mm (in a file of several
    /// robots, each robot's own).
    #[arg(long, default_value_t = 1.0, requires = "ensemble")]
    pub ensemble_start_mm: f64,
    /// Half-width of the ensemble's start yaw offset, degrees.
    #[arg(long, default_value_t = 0.05, requires = "ensemble")]
    pub ensemble_yaw_deg: f64,
    /// Keep the solver's order in every member (perturb only the start).
    #[arg(long, requires = "ensemble")]
    pub ensemble_keep_order: bool,
    /// Threads of the ensemble (default: every core).
    #[arg(long, requires = "ensemble")]
    pub jobs: Option<usize>,
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
    let mut o = overrides(a.method.as_deref(), a.duration, a.commands.as_deref())?;
    a.setting.apply(&mut o);
    if a.keep_running {
        o.stop_at_outcome = Some(false);
    }
    let template = tracksim::ScenarioTemplate::load_with(&file, &o)?;
    let sc = match a.seed {
        Some(seed) => template.instantiate(seed)?,
        None => template.file_scenario()?,
    };
    if a.seed.is_some() && a.ensemble.is_some() {
        return Err(super::bad_arg(
            "--seed",
            "an ensemble perturbs the file's own scenario (--ensemble-seed seeds its \
             perturbations): leave out --seed, or run one member with it"
                .into(),
        ));
    }
    if let Some(n) = a.ensemble {
        return run_ensemble(&a, &template, &sc, n);
    }
    if sc.robot_count() > 1 {
        return run_team(&a, &file, &sc);
    }
    let trainee = super::trainee(a.trainee.as_deref())?;
    tracksim::output::incomplete::mark_incomplete(&a.out)?;
    let bar = progress_bar(!a.quiet && !a.json && std::io::stderr().is_terminal());
    on_stop(|| {});
    let wall = std::time::Instant::now();
    let opts = RunOptions {
        realtime: a.realtime,
        stop: Some(&super::STOP),
    };
    let kept = tracksim::run::run_scenario_kept(&sc, opts, |t, total| {
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
    let (mut result, _) = kept?;
    result.summary.trainee = trainee;
    let which = tracksim::output::Outputs {
        replay: true,
        plots: !a.no_plot,
        mcap: a.mcap,
        raw_images: a.raw_images,
    };
    let written = tracksim::output::write_outputs(&sc, &result, &a.out, which)?;
    tracksim::output::incomplete::mark_complete(&a.out)?;
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
    // What was simulated up to a blow-up is written; the run still fails (exit 3).
    super::world_stopped(result.summary.stopped.as_deref(), &a.out)?;
    if a.strict && matches!(result.outcome, Outcome::Failure(_)) {
        return Err(Failure::Outcome);
    }
    Ok(())
}

/// `tracksim run` of a file with several robots (`[[vehicles]]`).
fn run_team(a: &RunArgs, file: &std::path::Path, sc: &tracksim::Scenario) -> Result<(), Failure> {
    if a.trainee.is_some() {
        return Err(super::bad_arg(
            "--trainee",
            "names the operator of one robot; this file has several ([[vehicles]]): leave it out"
                .into(),
        ));
    }
    on_stop(|| {});
    let opts = RunOptions {
        realtime: a.realtime,
        stop: Some(&super::STOP),
    };
    tracksim::output::incomplete::mark_incomplete(&a.out)?;
    let (result, _) = tracksim::run::run_team_kept(sc, opts)?;
    // With --mcap each robot's folder holds its run.mcap (its own topics and frames).
    let which = tracksim::output::Outputs {
        replay: true,
        plots: !a.no_plot,
        mcap: a.mcap,
        raw_images: a.raw_images,
    };
    tracksim::output::write_team(sc, &result, &a.out, which)?;
    tracksim::output::incomplete::mark_complete(&a.out)?;
    if a.json {
        out!(
            "{}",
            serde_json::to_string_pretty(&tracksim::output::team::TeamSummary::of(sc, &result))
                .expect("team serialises")
        );
    } else if !a.quiet {
        out!(
            "{}",
            tracksim::output::team_report(file, sc, &result, &a.out)
        );
    }
    if matches!(result.outcome, Outcome::Interrupted(_)) {
        return Err(Failure::Interrupted);
    }
    super::world_stopped(result.stopped.as_deref(), &a.out)?;
    if a.strict && matches!(result.outcome, Outcome::Failure(_)) {
        return Err(Failure::Outcome);
    }
    Ok(())
}

/// `tracksim run --ensemble N`.
fn run_ensemble(
    a: &RunArgs,
    template: &tracksim::ScenarioTemplate,
    sc: &tracksim::Scenario,
    n: usize,
) -> Result<(), Failure> {
    use tracksim::ensemble::{EnsembleOptions, Perturbations, check_ensemble, run_ensemble};
    if a.realtime || a.mcap || a.trainee.is_some() {
        return Err(Failure::Sim(tracksim::Error::Build(
            "--ensemble runs its members as fast as possible without recordings: leave out \
             --realtime and --mcap (and --trainee)"
                .into(),
        )));
    }
    let opts = EnsembleOptions {
        members: n,
        seed: a.ensemble_seed,
        perturbations: Perturbations {
            start_m: a.ensemble_start_mm * 1e-3,
            yaw_deg: a.ensemble_yaw_deg,
            solver_order: !a.ensemble_keep_order,
        },
        jobs: a.jobs.unwrap_or(0),
        out: Some(a.out.clone()),
        replay: true,
        stop: Some(&super::STOP),
        shard: None,
    };
    on_stop(|| {});
    let show = !a.quiet && !a.json && std::io::stderr().is_terminal();
    let report = run_ensemble(template, &opts, |done, total| {
        if show {
            eprint!("\r{done}/{total} members");
        }
    })?;
    if show {
        eprintln!();
    }
    let misses = sc
        .expect
        .ensemble
        .as_ref()
        .map(|e| check_ensemble(e, &report))
        .unwrap_or_default();
    if a.json {
        out!("{}", report.to_json()?);
    } else if !a.quiet {
        out!("{}", report.text());
        if let Some(e) = &sc.expect.ensemble {
            if misses.is_empty() {
                out!(
                    "[expect] ensemble bounds met ({} members asked by the file, {n} run)",
                    e.members
                );
            } else {
                out!(
                    "[expect] ensemble bounds missed:\n  {}",
                    misses.join("\n  ")
                );
            }
        }
        out!(
            "wrote {} (member-NNN/, ensemble.json, ensemble.csv)",
            a.out.display()
        );
    }
    if report.members.len() < n {
        return Err(Failure::Interrupted);
    }
    if a.strict
        && (!misses.is_empty()
            || report.count("success") < report.members.len() && sc.expect.ensemble.is_none())
    {
        return Err(Failure::Outcome);
    }
    Ok(())
}
