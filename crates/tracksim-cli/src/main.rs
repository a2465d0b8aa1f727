//! The `tracksim` command: a thin layer over the `tracksim` library.
//!
//! Exit codes: 0 success, 1 the scenario's outcome was failure (with `--strict`), 2 bad input,
//! 3 the simulation went unstable, 130 `run` interrupted by Ctrl-C (what was simulated is
//! written, with the outcome "interrupted").

use clap::{Parser, Subcommand};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use tracksim::{Error, Outcome, RunOptions};

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

mod sweep;

/// Real-time simulation of tracked robots with grousers (Okada et al., ICRA 2020) on Rapier.
#[derive(Parser)]
#[command(name = "tracksim", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Run a scenario file; write summary.json, trajectory.csv and plots into --out.
    Run {
        /// Scenario file (TOML).
        file: PathBuf,
        /// Output folder.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Print nothing but errors (no progress bar, no summary).
        #[arg(long)]
        quiet: bool,
        /// Print the summary as JSON on standard output.
        #[arg(long)]
        json: bool,
        /// Pace the simulation to the wall clock (for watching or driving it live).
        #[arg(long)]
        realtime: bool,
        /// Exit with code 1 when the scenario's outcome is failure.
        #[arg(long)]
        strict: bool,
        /// Track method, overriding the scenario's `simulation.method`.
        #[arg(long)]
        method: Option<String>,
        /// Override the simulated duration, s.
        #[arg(long)]
        duration: Option<f64>,
        /// Do not write the plot files.
        #[arg(long)]
        no_plot: bool,
        /// Replace the scenario's `[[commands]]` by those of this file (e.g. the
        /// `commands.toml` a `tracksim drive` session wrote: the run reproduces the session).
        #[arg(long)]
        commands: Option<PathBuf>,
    },
    /// Run one scenario with every track method; print a table and write a combined plot.
    Compare {
        /// Scenario file (TOML).
        file: PathBuf,
        /// Output folder (compare.csv, compare.png, compare.svg, one subfolder per method).
        #[arg(long, default_value = "out/compare")]
        out: PathBuf,
        /// Methods to run, comma-separated (default: all).
        #[arg(long, value_delimiter = ',')]
        methods: Vec<String>,
        /// Override the simulated duration, s.
        #[arg(long)]
        duration: Option<f64>,
        /// Print the table as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Benchmark every track method on the paper's Table II case (and Quince and rough cases).
    Bench {
        /// Runs per method (interleaved).
        #[arg(long, default_value_t = 5)]
        repeat: usize,
        /// Simulated seconds per run (default: the paper's 10 s).
        #[arg(long, default_value_t = 10.0)]
        duration: f64,
        /// Print the results as JSON.
        #[arg(long)]
        json: bool,
        /// Write bench.csv and bench.md into this folder.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Methods, comma-separated (default: all).
        #[arg(long, value_delimiter = ',')]
        methods: Vec<String>,
        /// Cases, comma-separated: packbot, packbot_open_top, quince, rough (default: all).
        #[arg(long, value_delimiter = ',')]
        cases: Vec<String>,
        /// Batch mode: run many independent PackBot simulations on this many threads and
        /// report the throughput per core.
        #[arg(long)]
        jobs: Option<usize>,
        /// Override the solver iterations (changes physics; reported in the output).
        #[arg(long)]
        solver_iterations: Option<usize>,
    },
    /// Reproduce the paper's Table IV (Quince steps) and run the physics checks (slope limit,
    /// skid-steer turning, Fig. 2 and Fig. 3); exits 1 if a case fails.
    Validate {
        /// Print the report as JSON.
        #[arg(long)]
        json: bool,
        /// Write report.md and one plot per case into this folder.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Track method under test.
        #[arg(long, default_value = "okada2020")]
        method: String,
        /// Young's modulus of the track rubber in the Table IV column "compliant grousers,
        /// rigid terrain, no slop", MPa (track rubber, Shore 60-80A: about 3.5-9 MPa).
        #[arg(long, default_value_t = tracksim::validate::TRACK_RUBBER_YOUNGS_MODULUS_PA / 1e6)]
        rubber_modulus_mpa: f64,
    },
    /// Drive a scenario live from a 3-D page in the browser (prints its URL); the session is
    /// a run: on stop (stop button, closed page, Ctrl-C) its outputs go to --out.
    Drive {
        /// Scenario file (TOML).
        file: PathBuf,
        /// Output folder (as `run`, plus commands.toml and controls.csv).
        #[arg(long, default_value = "out/drive")]
        out: PathBuf,
        /// Simulated seconds per wall-clock second (0.5 slower, 2 faster than real time).
        #[arg(long, default_value_t = 1.0)]
        speed: f64,
        /// TCP port of the page (0: any free port).
        #[arg(long, default_value_t = tracksim::live::DEFAULT_PORT)]
        port: u16,
        /// Address to listen on (default loopback only; any other is reachable by others).
        #[arg(long)]
        bind: Option<std::net::IpAddr>,
        /// End the session at this simulated time, s (default: when the operator stops).
        #[arg(long)]
        duration: Option<f64>,
        /// Track method, overriding the scenario's `simulation.method`.
        #[arg(long)]
        method: Option<String>,
        /// Do not write the plot files.
        #[arg(long)]
        no_plot: bool,
        /// Start simulating only once a page has connected.
        #[arg(long)]
        wait_for_page: bool,
    },
    /// Replay a finished run (of `run`, `drive` or `compare`) in the 3-D page.
    View {
        /// The run's output folder (holding scene.json, trajectory.csv, belts.csv).
        dir: PathBuf,
        /// TCP port of the page (0: any free port).
        #[arg(long, default_value_t = tracksim::live::DEFAULT_PORT)]
        port: u16,
        /// Address to listen on (default loopback only).
        #[arg(long)]
        bind: Option<std::net::IpAddr>,
    },
    /// Check vehicle and scenario files without running them; print every problem.
    Check {
        /// Files to check (vehicle or scenario files, told apart by their keys).
        #[arg(required = true)]
        files: Vec<PathBuf>,
    },
    /// Run a randomised scenario many times (a dataset): one folder per run and a manifest
    /// (one JSON line per run), sharded for job arrays, resumable.
    Sweep(sweep::SweepArgs),
    /// Merge sweep folders (shards) into one: their runs and one manifest.jsonl.
    Merge {
        /// Sweep output folders.
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Merged sweep folder (may be one of DIRS: shards that wrote into one folder).
        #[arg(long)]
        out: PathBuf,
    },
    /// List the bundled vehicles and scenarios with one-line descriptions.
    List {
        /// Folder holding `vehicles/` and `scenarios/` (default: the current folder, then the
        /// source tree this binary was built from).
        #[arg(long)]
        dir: Option<PathBuf>,
    },
}

/// Set by the Ctrl-C handler of `run`: the run stops and writes what it simulated.
static STOP: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Exit code of a run interrupted by Ctrl-C (128 + SIGINT, as shells report it).
const EXIT_INTERRUPTED: u8 = 130;

/// Why the command failed, mapped to an exit code.
enum Failure {
    Outcome,
    /// `run` was interrupted (its outputs are written); exit 130.
    Interrupted,
    /// Already reported on standard output (by `check`); exit 2.
    Reported,
    Sim(Error),
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        Failure::Sim(e)
    }
}

struct RunArgs {
    file: PathBuf,
    out: PathBuf,
    quiet: bool,
    json: bool,
    realtime: bool,
    strict: bool,
    method: Option<String>,
    duration: Option<f64>,
    no_plot: bool,
    commands: Option<PathBuf>,
}

fn run(a: RunArgs) -> Result<(), Failure> {
    let overrides = tracksim::Overrides {
        method: a
            .method
            .as_deref()
            .map(|m| parse_method("--method", m))
            .transpose()?,
        duration_s: a.duration,
        commands: a.commands.clone(),
        ..Default::default()
    };
    let sc = tracksim::load_scenario_with(&a.file, &overrides)?;
    let show_bar = !a.quiet && !a.json && std::io::stderr().is_terminal();
    let bar = show_bar.then(|| {
        let b = indicatif::ProgressBar::new(1000);
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "{bar:40} {msg} (elapsed {elapsed}, eta {eta})",
            )
            .expect("valid template"),
        );
        b
    });
    if let Err(e) = ctrlc::set_handler(|| {
        use std::sync::atomic::Ordering;
        if STOP.swap(true, Ordering::SeqCst) {
            // A second Ctrl-C ends at once.
            std::process::exit(i32::from(EXIT_INTERRUPTED));
        }
    }) {
        eprintln!("warning: Ctrl-C will not write the outputs of an interrupted run: {e}");
    }
    let wall = std::time::Instant::now();
    let result = tracksim::run_scenario_with(
        &sc,
        RunOptions {
            realtime: a.realtime,
            stop: Some(&STOP),
        },
        |t, total| {
            if let Some(b) = &bar {
                b.set_position((1000.0 * t / total) as u64);
                b.set_message(format!(
                    "t = {t:.2} / {total:.2} s, {:.1} x real time",
                    t / wall.elapsed().as_secs_f64().max(1e-9)
                ));
            }
        },
    );
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let result = result?;
    tracksim::output::write_run(&result, &a.out)?;
    let mut written = vec![a.out.join("summary.json"), a.out.join("trajectory.csv")];
    written.extend(tracksim::output::write_replay(&sc, &result, &a.out)?);
    if !a.no_plot {
        written.extend(tracksim::output::write_run_plots(&sc, &result, &a.out)?);
    }
    let s = &result.summary;
    if a.json {
        out!(
            "{}",
            serde_json::to_string_pretty(s).expect("summary serialises")
        );
    } else if !a.quiet {
        let p = &s.final_pose;
        out!("scenario   {}", a.file.display());
        out!("vehicle    {} (method {})", s.vehicle, s.method);
        if s.paced {
            out!(
                "simulated  {:.3} s in {:.3} s wall, paced to the wall clock: {:.2} x real time",
                s.sim_time_s,
                s.elapsed_time_s,
                s.paced_real_time_factor
            );
            out!(
                "compute    stepping alone took {:.3} s: it could run {:.1} x real time",
                s.wall_time_s,
                s.real_time_factor
            );
        } else {
            out!(
                "simulated  {:.3} s in {:.3} s of stepping: real-time factor {:.1}",
                s.sim_time_s,
                s.wall_time_s,
                s.real_time_factor
            );
        }
        out!(
            "mean speed {:.4} m/s, distance {:.3} m",
            s.mean_speed_mps,
            s.distance_m
        );
        out!(
            "final pose x {:.4} y {:.4} z {:.4} m, roll {:.2} pitch {:.2} yaw {:.2} deg",
            p.x,
            p.y,
            p.z,
            p.roll.to_degrees(),
            p.pitch.to_degrees(),
            p.yaw.to_degrees()
        );
        out!(
            "contacts   deepest penetration {:.1} mm (contact slop {:.1} mm)",
            s.max_penetration_m * 1000.0,
            s.solver.contact_slop_m * 1000.0
        );
        out!(
            "outcome    {}: {} (t = {:.3} s)",
            s.outcome,
            s.outcome_reason,
            s.outcome_time_s
        );
        if !sc.expect.is_empty() && !sc.overridden.is_empty() {
            out!("expect     not checked: --method, --duration or --commands changed the run");
        } else if !sc.expect.is_empty() {
            let misses = tracksim::run::check_expectations(&sc.expect, &result);
            if misses.is_empty() {
                out!("expect     met (the file's [expect] table)");
            } else {
                out!("expect     MISSED: {}", misses.join("; "));
            }
        }
        for w in &written {
            out!("wrote      {}", w.display());
        }
    }
    if matches!(result.outcome, Outcome::Interrupted(_)) {
        eprintln!(
            "interrupted: wrote what was simulated into {}",
            a.out.display()
        );
        return Err(Failure::Interrupted);
    }
    if a.strict && matches!(result.outcome, Outcome::Failure(_)) {
        return Err(Failure::Outcome);
    }
    Ok(())
}

fn bad_arg(arg: &str, message: String) -> Failure {
    Failure::Sim(Error::Invalid {
        path: arg.into(),
        issues: vec![tracksim::SpecIssue::new("", message)],
    })
}

/// Parses one track method name given to `flag`.
fn parse_method(flag: &str, name: &str) -> Result<tracksim::Method, Failure> {
    use tracksim::Method as TrackMethod;
    TrackMethod::from_name(name).ok_or_else(|| {
        bad_arg(
            flag,
            format!(
                "unknown track method \"{name}\"; use one of {}",
                TrackMethod::NAMES
            ),
        )
    })
}

/// Parses a `--methods` list; empty means every compared method.
fn parse_methods(names: &[String]) -> Result<Vec<tracksim::Method>, Failure> {
    if names.is_empty() {
        return Ok(tracksim::Method::COMPARED.to_vec());
    }
    names.iter().map(|m| parse_method("--methods", m)).collect()
}

/// Checks a `--duration` value, s, for steps of `dt` s (the limits of
/// `simulation.duration_s`).
fn check_duration(d: f64, dt: f64) -> Result<f64, Failure> {
    match tracksim::model::duration_problem(d, dt) {
        None => Ok(d),
        Some(m) => Err(bad_arg("--duration", m)),
    }
}

fn compare(
    file: &Path,
    out: &Path,
    methods: &[String],
    duration: Option<f64>,
    json: bool,
) -> Result<(), Failure> {
    let mut sc = tracksim::load_scenario(file)?;
    if let Some(d) = duration {
        sc.duration = check_duration(d, sc.solver.dt)?;
    }
    let methods = parse_methods(methods)?;
    std::fs::create_dir_all(out).map_err(|source| Error::Io {
        path: out.to_path_buf(),
        source,
    })?;
    let mut rows = Vec::new();
    let mut done = Vec::new();
    let mut last_error = None;
    for m in &methods {
        sc.method = *m;
        if !json {
            eprintln!("running {} ...", m.name());
        }
        match tracksim::run_scenario(&sc, |_, _| {}) {
            Ok(r) => {
                tracksim::output::write_run(&r, &out.join(m.name()))?;
                tracksim::output::write_replay(&sc, &r, &out.join(m.name()))?;
                let s = &r.summary;
                rows.push(serde_json::json!({
                    "method": m.name(),
                    "outcome": s.outcome,
                    "reason": s.outcome_reason,
                    "distance_m": s.distance_m,
                    "progress_m": s.progress_m,
                    "mean_speed_mps": s.mean_speed_mps,
                    "real_time_factor": s.real_time_factor,
                    "final_z_m": s.final_pose.z,
                }));
                done.push((m.name(), r));
            }
            Err(e) => {
                rows.push(serde_json::json!({
                    "method": m.name(),
                    "outcome": "error",
                    "reason": e.to_string(),
                }));
                last_error = Some(e);
            }
        }
    }
    let runs: Vec<(String, &tracksim::RunResult)> =
        done.iter().map(|(n, r)| (n.clone(), r)).collect();
    let plots = tracksim::output::write_compare_plots(&sc, &runs, out)?;
    let mut csv = String::from(
        "method,outcome,progress_m,distance_m,mean_speed_mps,real_time_factor,final_z_m,reason\n",
    );
    for r in &rows {
        let num = |k: &str| r[k].as_f64().map(|v| format!("{v:.4}")).unwrap_or_default();
        csv.push_str(&format!(
            "{},{},{},{},{},{},{},\"{}\"\n",
            r["method"].as_str().unwrap_or(""),
            r["outcome"].as_str().unwrap_or(""),
            num("progress_m"),
            num("distance_m"),
            num("mean_speed_mps"),
            num("real_time_factor"),
            num("final_z_m"),
            r["reason"].as_str().unwrap_or("").replace('"', "'")
        ));
    }
    let csv_path = out.join("compare.csv");
    tracksim::files::write_atomic(&csv_path, csv.as_bytes())?;
    if json {
        out!(
            "{}",
            serde_json::to_string_pretty(&serde_json::json!({ "methods": rows }))
                .expect("serialises")
        );
        return no_method_ran(done.is_empty(), last_error);
    }
    out!("scenario {}", file.display());
    out!(
        "{:<24} {:<10} {:>10} {:>10} {:>12} {:>8}  reason",
        "method",
        "outcome",
        "progress m",
        "distance m",
        "speed m/s",
        "RTF"
    );
    for r in &rows {
        let num = |k: &str, p: usize| {
            r[k].as_f64()
                .map(|v| format!("{v:.p$}"))
                .unwrap_or_else(|| "-".into())
        };
        out!(
            "{:<24} {:<10} {:>10} {:>10} {:>12} {:>8}  {}",
            r["method"].as_str().unwrap_or(""),
            r["outcome"].as_str().unwrap_or(""),
            num("progress_m", 3),
            num("distance_m", 3),
            num("mean_speed_mps", 4),
            num("real_time_factor", 1),
            r["reason"].as_str().unwrap_or("")
        );
    }
    out!("wrote {}", csv_path.display());
    for p in plots {
        out!("wrote {}", p.display());
    }
    no_method_ran(done.is_empty(), last_error)
}

/// `compare` when no method produced a run: the last method's error (exit 3 if unstable),
/// after the table and `compare.csv` are written.
fn no_method_ran(none_ran: bool, last_error: Option<Error>) -> Result<(), Failure> {
    match last_error {
        Some(e) if none_ran => Err(Failure::Sim(e)),
        _ => Ok(()),
    }
}

fn validate(
    json: bool,
    out: Option<PathBuf>,
    method: &str,
    rubber_modulus_mpa: f64,
) -> Result<(), Failure> {
    let m = parse_method("--method", method)?;
    if !(rubber_modulus_mpa.is_finite() && (0.1..=1000.0).contains(&rubber_modulus_mpa)) {
        return Err(bad_arg(
            "--rubber-modulus-mpa",
            format!(
                "must be a Young's modulus in MPa between 0.1 and 1000 (track rubber: 3.5-9), got {rubber_modulus_mpa}"
            ),
        ));
    }
    let opts = tracksim::validate::ValidationOptions {
        rubber_youngs_modulus_pa: rubber_modulus_mpa * 1e6,
        ..Default::default()
    };
    let report = tracksim::validate::run_validation_with(&data_root(), m, opts, |line| {
        if !json {
            eprintln!("{line}");
        }
    })?;
    if json {
        out!(
            "{}",
            serde_json::to_string_pretty(&report).expect("serialises")
        );
    } else {
        out!("{}", report.to_markdown());
    }
    if let Some(dir) = out {
        for p in report.write(&dir)? {
            if !json {
                out!("wrote {}", p.display());
            }
        }
    }
    if report.passed() {
        Ok(())
    } else {
        Err(Failure::Outcome)
    }
}

struct BenchArgs {
    repeat: usize,
    duration: f64,
    json: bool,
    out: Option<PathBuf>,
    methods: Vec<String>,
    cases: Vec<String>,
    jobs: Option<usize>,
    solver_iterations: Option<usize>,
}

/// The folder holding `vehicles/` and `scenarios/`: the current folder or the source tree.
fn data_root() -> PathBuf {
    let here = PathBuf::from(".");
    if here.join("scenarios").is_dir() {
        here
    } else {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
    }
}

/// Most `bench --repeat` runs per method.
const MAX_REPEAT: usize = 1000;
/// Most `bench --jobs` threads.
const MAX_JOBS: usize = 1024;

fn bench(a: BenchArgs) -> Result<(), Failure> {
    if a.repeat == 0 || a.repeat > MAX_REPEAT {
        return Err(bad_arg(
            "--repeat",
            format!("must be from 1 to {MAX_REPEAT}, got {}", a.repeat),
        ));
    }
    if a.solver_iterations.is_some_and(|n| n == 0 || n > 100) {
        return Err(bad_arg(
            "--solver-iterations",
            "must be between 1 and 100".into(),
        ));
    }
    check_duration(a.duration, 0.001)?;
    if let Some(j) = a.jobs.filter(|j| *j == 0 || *j > MAX_JOBS) {
        return Err(bad_arg(
            "--jobs",
            format!("must be from 1 to {MAX_JOBS} threads, got {j}"),
        ));
    }
    let methods = parse_methods(&a.methods)?;
    let root = data_root();
    let all_cases: Vec<(&str, PathBuf)> = tracksim::cases::BENCH
        .iter()
        .map(|(short, case)| {
            let c = tracksim::cases::case(case).expect("bench cases are named cases");
            (*short, c.path(&root))
        })
        .collect();
    for c in &a.cases {
        if !all_cases.iter().any(|(n, _)| n == c) {
            return Err(bad_arg(
                "--cases",
                format!("unknown case \"{c}\"; use packbot, quince or rough"),
            ));
        }
    }
    let selected: Vec<(&str, &PathBuf)> = all_cases
        .iter()
        .filter(|(n, _)| a.cases.is_empty() || a.cases.iter().any(|c| c == n))
        .map(|(n, p)| (*n, p))
        .collect();
    let quiet = a.json;
    if let Some(jobs) = a.jobs {
        return bench_batch(&a, jobs, &selected, &methods);
    }
    let mut results = Vec::new();
    for (name, path) in selected {
        if !path.is_file() {
            if !quiet {
                eprintln!("skipping case {name}: {} not found", path.display());
            }
            continue;
        }
        let sc = bench_scenario(&a, path)?;
        let mut r = tracksim::bench::bench_case(name, &sc, &methods, a.repeat, |m| {
            if !quiet {
                eprintln!("{m}");
            }
        });
        if name != "packbot" {
            // The paper's figures are for its PackBot case only.
            for m in &mut r.methods {
                m.paper_rtf = None;
            }
        }
        if !quiet {
            out!("{}", r.to_markdown());
        }
        results.push(r);
    }
    if a.json {
        let cases: Vec<serde_json::Value> = results
            .iter()
            .map(|r| serde_json::to_value(r).expect("serialises"))
            .collect();
        let first = cases.first().cloned().unwrap_or_default();
        out!(
            "{}",
            serde_json::to_string_pretty(&serde_json::json!({
                "methods": first["methods"],
                "settings": first["settings"],
                "cases": cases,
            }))
            .expect("serialises")
        );
    }
    if let Some(dir) = &a.out {
        let io = |p: &Path| {
            let p = p.to_path_buf();
            move |source| Error::Io { path: p, source }
        };
        std::fs::create_dir_all(dir).map_err(io(dir))?;
        let csv: String = results
            .iter()
            .enumerate()
            .map(|(i, r)| {
                let c = r.to_csv();
                if i == 0 {
                    c
                } else {
                    c.lines().skip(1).map(|l| format!("{l}\n")).collect()
                }
            })
            .collect();
        let md: String = results.iter().map(|r| r.to_markdown() + "\n").collect();
        tracksim::files::write_atomic(&dir.join("bench.csv"), csv.as_bytes())?;
        tracksim::files::write_atomic(&dir.join("bench.md"), md.as_bytes())?;
        if !quiet {
            out!(
                "wrote {} and {}",
                dir.join("bench.csv").display(),
                dir.join("bench.md").display()
            );
        }
    }
    Ok(())
}

/// A bench case's scenario with the bench's duration and solver settings; it never stops early
/// (the benchmark measures stepping, not a mission).
fn bench_scenario(a: &BenchArgs, path: &Path) -> Result<tracksim::Scenario, Failure> {
    let mut sc = tracksim::load_scenario(path)?;
    sc.duration = a.duration;
    if let Some(n) = a.solver_iterations {
        sc.solver.iterations = n;
    }
    sc.outcome.stop = false;
    Ok(sc)
}

/// `bench --jobs N`: for every selected case and method, `N x repeat` independent runs on `N`
/// threads; the throughput per core.
fn bench_batch(
    a: &BenchArgs,
    jobs: usize,
    cases: &[(&str, &PathBuf)],
    methods: &[tracksim::Method],
) -> Result<(), Failure> {
    let runs = jobs
        .checked_mul(a.repeat)
        .ok_or_else(|| bad_arg("--jobs", "jobs x repeat is too large".into()))?;
    let mut all = Vec::new();
    for (name, path) in cases {
        let base = bench_scenario(a, path)?;
        for m in methods {
            let mut sc = base.clone();
            sc.method = *m;
            if !a.json {
                eprintln!(
                    "batch: {runs} {name} runs of {} s with {m} on {jobs} threads ...",
                    a.duration
                );
            }
            let b = tracksim::bench::batch(&sc, jobs, runs)?;
            if !a.json {
                out!(
                    "batch {name} {m}: {} runs, {:.1} simulated s in {:.2} wall s on {} threads: {:.1} sim s per wall s, {:.1} per core",
                    b.runs,
                    b.simulated_s,
                    b.wall_s,
                    b.jobs,
                    b.sim_s_per_wall_s,
                    b.sim_s_per_wall_s_per_core
                );
            }
            all.push(serde_json::json!({"case": name, "method": m.name(), "batch": b}));
        }
    }
    if a.json {
        out!(
            "{}",
            serde_json::to_string_pretty(&all).expect("serialises")
        );
    }
    Ok(())
}

/// The design figures of a vehicle (`model::design_report`), one line each, with warnings.
fn design_lines(v: &tracksim::VehicleModel) -> String {
    let d = tracksim::model::design_report(v);
    let mut text = String::new();
    for t in &d.tracks {
        text.push_str(&format!(
            "\n       track {:<16} loop {:.4} m",
            t.name, t.loop_length_m
        ));
        if let (Some(p), Some(g), Some(gap)) = (t.pitch_m, t.grouser_length_m, t.gap_m) {
            text.push_str(&format!(
                ", {} grousers: pitch {:.1} mm, grouser {:.1} mm, gap {:.1} mm",
                t.grousers,
                p * 1000.0,
                g * 1000.0,
                gap * 1000.0
            ));
        }
    }
    if let Some(c) = d.ground_clearance_m {
        let how = if c >= 0.0 {
            "body above the track bottoms"
        } else {
            "the body hangs BELOW the track bottoms: see the warning"
        };
        text.push_str(&format!(
            "\n       ground clearance {:.1} mm ({how})",
            c * 1000.0
        ));
    }
    if let Some(a) = d.approach_angle_deg {
        text.push_str(&format!(
            "\n       approach angle {a:.1} deg (steepest ramp the tracks meet before the body)"
        ));
    }
    for w in &d.warnings {
        text.push_str(&format!("\n       warning: {w}"));
    }
    text
}

/// Tells a vehicle file from a scenario file by its top-level keys.
fn is_vehicle_file(path: &Path) -> Result<bool, Error> {
    let text = tracksim::files::read_text_bounded(path, tracksim::files::MAX_TOML_BYTES)?;
    let table: toml_table::Table = tracksim::model::parse_toml(path, &text)?;
    Ok(table.contains_key("body") || table.contains_key("tracks"))
}

// `toml` is reached through the library's re-export to keep one version.
use tracksim::toml as toml_table;

fn check(files: &[PathBuf]) -> Result<(), Failure> {
    let mut failed = None;
    for f in files {
        let r = is_vehicle_file(f).and_then(|vehicle| {
            if vehicle {
                tracksim::load_vehicle(f)
                    .map(|v| format!("vehicle \"{}\"{}", v.name, design_lines(&v)))
            } else {
                tracksim::load_scenario(f).and_then(|s| {
                    // Build it (no step) to show what is simulated: every part's mass.
                    let sim = tracksim::Simulation::new(&s)?;
                    let m = sim.mass_report();
                    let mut text = format!(
                        "scenario with vehicle \"{}\", {:.1} s, method {}\n       mass simulated {:.3} kg (file {:.3} kg), centre of mass [{:.4}, {:.4}, {:.4}] m (body frame)",
                        s.vehicle.name,
                        s.duration,
                        sim.method(),
                        m.total_simulated_kg,
                        m.total_file_kg,
                        m.centre_of_mass_body_m[0],
                        m.centre_of_mass_body_m[1],
                        m.centre_of_mass_body_m[2]
                    );
                    for p in &m.parts {
                        text.push_str(&format!(
                            "\n       {:<22} {:8.3} kg simulated, {:8.3} kg in the file",
                            p.part, p.simulated_kg, p.file_kg
                        ));
                    }
                    text.push_str(&design_lines(&s.vehicle));
                    Ok(text)
                })
            }
        });
        match r {
            Ok(what) => out!("ok     {}: {what}", f.display()),
            Err(e) => {
                out!("error  {e}");
                failed = Some(e);
            }
        }
    }
    match failed {
        Some(_) => Err(Failure::Reported),
        None => Ok(()),
    }
}

fn description(path: &Path) -> String {
    let text = tracksim::files::read_text_bounded(path, tracksim::files::MAX_TOML_BYTES)
        .unwrap_or_default();
    text.parse::<toml_table::Table>()
        .ok()
        .and_then(|t| {
            t.get("description")
                .and_then(|d| d.as_str())
                .map(str::to_string)
        })
        .unwrap_or_default()
}

fn list(dir: Option<PathBuf>) -> Result<(), Failure> {
    let candidates = match dir {
        Some(d) => vec![d],
        None => vec![
            PathBuf::from("."),
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."),
        ],
    };
    let Some(root) = candidates
        .iter()
        .find(|d| d.join("vehicles").is_dir() || d.join("scenarios").is_dir())
    else {
        return Err(Error::Invalid {
            path: candidates[0].clone(),
            issues: vec![tracksim::SpecIssue::new(
                "",
                "no vehicles/ or scenarios/ folder here; pass --dir with the tracksim source folder",
            )],
        }
        .into());
    };
    for sub in ["vehicles", "scenarios"] {
        out!("{sub}:");
        let mut entries: Vec<PathBuf> = std::fs::read_dir(root.join(sub))
            .map(|r| r.filter_map(|e| e.ok().map(|e| e.path())).collect())
            .unwrap_or_default();
        entries.retain(|p| p.extension().is_some_and(|e| e == "toml"));
        entries.sort();
        for p in entries {
            let name = p.strip_prefix(root).unwrap_or(&p).display().to_string();
            out!("  {name:<40} {}", description(&p));
        }
    }
    Ok(())
}

/// The address to listen on: loopback unless `--bind` says otherwise (then with a warning).
fn bind_address(bind: Option<std::net::IpAddr>) -> std::net::IpAddr {
    match bind {
        Some(a) if !a.is_loopback() => {
            eprintln!(
                "warning: listening on {a}, not loopback: anyone who can reach this machine can \
                 watch, and the first to connect drives"
            );
            a
        }
        Some(a) => a,
        None => tracksim::live::DEFAULT_BIND,
    }
}

struct DriveArgs {
    file: PathBuf,
    out: PathBuf,
    speed: f64,
    port: u16,
    bind: Option<std::net::IpAddr>,
    duration: Option<f64>,
    method: Option<String>,
    no_plot: bool,
    wait_for_page: bool,
}

fn drive(a: DriveArgs) -> Result<(), Failure> {
    use tracksim::live::{DriveOptions, Hub, Mode, Server};
    let overrides = tracksim::Overrides {
        method: a
            .method
            .as_deref()
            .map(|m| parse_method("--method", m))
            .transpose()?,
        ..Default::default()
    };
    let sc = tracksim::load_scenario_with(&a.file, &overrides)?;
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
    let hub = Hub::new();
    let scene_json = tracksim::output::Scene::new(&sc).to_json();
    let mut server = Server::start(
        bind_address(a.bind),
        a.port,
        Mode::Drive {
            hub: hub.clone(),
            scene_json,
        },
    )?;
    let h = hub.clone();
    if let Err(e) = ctrlc::set_handler(move || h.request_stop()) {
        eprintln!("warning: Ctrl-C will not end the session cleanly: {e}");
    }
    out!(
        "drive      open {} in a browser (the first page to connect drives)",
        server.url()
    );
    out!("           stop: the page's stop button, closing the page, or Ctrl-C");
    let session = tracksim::live::run_session(
        &sc,
        &hub,
        DriveOptions {
            speed: a.speed,
            max_time,
            wait_for_page: a.wait_for_page,
        },
    );
    hub.request_stop();
    server.shutdown();
    let session = session?;
    let written = session.write(&sc, &a.file, &a.out, !a.no_plot)?;
    let s = &session.result.summary;
    out!(
        "simulated  {:.3} s in {:.3} s wall ({:.2} x real time paced, stepping alone {:.1} x)",
        s.sim_time_s,
        s.elapsed_time_s,
        s.paced_real_time_factor,
        s.real_time_factor
    );
    out!("outcome    {}: {}", s.outcome, s.outcome_reason);
    for w in &written {
        out!("wrote      {}", w.display());
    }
    out!(
        "replay     tracksim view {}   (or reproduce: tracksim run {} --commands {} --duration {})",
        a.out.display(),
        a.file.display(),
        a.out.join("commands.toml").display(),
        session.duration()
    );
    Ok(())
}

fn view(dir: &Path, port: u16, bind: Option<std::net::IpAddr>) -> Result<(), Failure> {
    use tracksim::live::{Mode, Server};
    let files = tracksim::live::view_files(dir)?;
    let server = Server::start(bind_address(bind), port, Mode::View { files })?;
    out!("view       open {} in a browser; Ctrl-C ends", server.url());
    let (tx, rx) = std::sync::mpsc::channel();
    let _ = ctrlc::set_handler(move || {
        let _ = tx.send(());
    });
    let _ = rx.recv();
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
            realtime,
            strict,
            method,
            duration,
            no_plot,
            commands,
        } => run(RunArgs {
            file,
            out,
            quiet,
            json,
            realtime,
            strict,
            method,
            duration,
            no_plot,
            commands,
        }),
        Cmd::Check { files } => check(&files),
        Cmd::Validate {
            json,
            out,
            method,
            rubber_modulus_mpa,
        } => validate(json, out, &method, rubber_modulus_mpa),
        Cmd::Bench {
            repeat,
            duration,
            json,
            out,
            methods,
            cases,
            jobs,
            solver_iterations,
        } => bench(BenchArgs {
            repeat,
            duration,
            json,
            out,
            methods,
            cases,
            jobs,
            solver_iterations,
        }),
        Cmd::Compare {
            file,
            out,
            methods,
            duration,
            json,
        } => compare(&file, &out, &methods, duration, json),
        Cmd::List { dir } => list(dir),
        Cmd::Drive {
            file,
            out,
            speed,
            port,
            bind,
            duration,
            method,
            no_plot,
            wait_for_page,
        } => drive(DriveArgs {
            file,
            out,
            speed,
            port,
            bind,
            duration,
            method,
            no_plot,
            wait_for_page,
        }),
        Cmd::View { dir, port, bind } => view(&dir, port, bind),
        Cmd::Sweep(a) => sweep::sweep(a),
        Cmd::Merge { dirs, out } => sweep::merge(&dirs, &out),
    };
    match r {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Outcome) => ExitCode::from(1),
        Err(Failure::Interrupted) => ExitCode::from(EXIT_INTERRUPTED),
        Err(Failure::Reported) => ExitCode::from(2),
        Err(Failure::Sim(e)) => {
            eprintln!("error: {e}");
            ExitCode::from(match e {
                Error::Unstable { .. } => 3,
                _ => 2,
            })
        }
    }
}
