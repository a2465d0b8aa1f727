//! `tracksim bench`: the paper's Table II (speed) per track method, and the batch mode.

use super::{Failure, bad_arg, check_duration, data_root, parse_methods};
use std::path::PathBuf;
use tracksim::Method;

/// Benchmark every track method on the paper's Table II case (and Quince and rough cases).
#[derive(clap::Args)]
pub struct BenchArgs {
    /// Runs per method (interleaved).
    #[arg(long, default_value_t = 5)]
    pub repeat: usize,
    /// Simulated seconds per run (default: the paper's 10 s).
    #[arg(long, default_value_t = 10.0)]
    pub duration: f64,
    /// Print the results as JSON.
    #[arg(long)]
    pub json: bool,
    /// Write bench.csv and bench.md into this folder.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Methods, comma-separated (default: all).
    #[arg(long, value_delimiter = ',')]
    pub methods: Vec<String>,
    /// Cases, comma-separated: packbot, packbot_open_top, quince, rough, sand (default: all).
    #[arg(long, value_delimiter = ',')]
    pub cases: Vec<String>,
    /// Batch mode: run many independent PackBot simulations on this many threads and
    /// report the throughput per core.
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Override the solver iterations (changes physics; reported in the output).
    #[arg(long)]
    pub solver_iterations: Option<usize>,
    /// What sensing costs: the PackBot flat case without and with the typical sensor set, and
    /// the stairs without and with every sensor, interleaved (docs/SENSORS.md).
    #[arg(long)]
    pub sensors: bool,
    /// What a colour camera costs: the PackBot flat case without and with a 160 x 120 camera
    /// at 10 Hz, interleaved, and frame times at three sizes on one thread and every core
    /// (docs/SENSORS.md).
    #[arg(long)]
    pub camera: bool,
    /// What more robots in one world cost: worlds of these many PackBots apart on flat ground
    /// (e.g. `--robots 1,2,4,8`), timed in interleaved rounds (--repeat) for --duration s;
    /// prints the step time per robot against one robot's (docs/TEAMS.md).
    #[arg(long, value_delimiter = ',')]
    pub robots: Vec<usize>,
}

/// Most `bench --repeat` runs per method.
const MAX_REPEAT: usize = 1000;
/// Most `bench --jobs` threads.
const MAX_JOBS: usize = 1024;

fn check_args(a: &BenchArgs) -> Result<(), Failure> {
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
    Ok(())
}

/// The selected bench cases: (short name, file).
fn selected_cases(a: &BenchArgs) -> Result<Vec<(&'static str, PathBuf)>, Failure> {
    let root = data_root()?;
    let all: Vec<(&str, PathBuf)> = tracksim::cases::BENCH
        .iter()
        .map(|(short, case)| {
            let c = tracksim::cases::case(case).expect("bench cases are named cases");
            (*short, c.path(&root))
        })
        .collect();
    for c in &a.cases {
        if !all.iter().any(|(n, _)| n == c) {
            let names: Vec<&str> = all.iter().map(|(n, _)| *n).collect();
            return Err(bad_arg(
                "--cases",
                format!("unknown case \"{c}\"; use {}", names.join(", ")),
            ));
        }
    }
    Ok(all
        .into_iter()
        .filter(|(n, _)| a.cases.is_empty() || a.cases.iter().any(|c| c == n))
        .collect())
}

/// `tracksim bench`; Ctrl-C or SIGTERM stops after the case running and writes what ran.
pub fn bench(a: BenchArgs) -> Result<(), Failure> {
    check_args(&a)?;
    let methods = parse_methods(&a.methods)?;
    let selected = selected_cases(&a)?;
    if let Some(jobs) = a.jobs {
        return bench_batch(&a, jobs, &selected, &methods);
    }
    if !a.robots.is_empty() {
        let rows =
            tracksim::team_bench::bench_team(&data_root()?, &a.robots, a.duration, a.repeat)?;
        if a.json {
            out!(
                "{}",
                serde_json::to_string_pretty(&rows).expect("serialises")
            );
        } else {
            out!("{}", tracksim::team_bench::to_markdown(&rows));
        }
        return Ok(());
    }
    if a.camera {
        let b = tracksim::camera_bench::bench_camera(&data_root()?, a.duration, a.repeat, 21)?;
        if a.json {
            out!("{}", serde_json::to_string_pretty(&b).expect("serialises"));
        } else {
            out!("{}", tracksim::camera_bench::to_markdown(&b));
        }
        return Ok(());
    }
    if a.sensors {
        let pairs = tracksim::sensor_bench::bench_sensors(&data_root()?, a.duration, a.repeat)?;
        if a.json {
            out!(
                "{}",
                serde_json::to_string_pretty(&pairs).expect("serialises")
            );
        } else {
            out!("{}", tracksim::sensor_bench::to_markdown(&pairs));
        }
        return Ok(());
    }
    super::on_stop(|| eprintln!("stopping after the case running ..."));
    let quiet = a.json;
    let mut report = tracksim::bench::BenchReport::default();
    for (name, path) in selected {
        if super::stopped() {
            break;
        }
        let load = tracksim::bench::BenchLoad {
            path,
            duration_s: a.duration,
            solver_iterations: a.solver_iterations,
        };
        let mut r = tracksim::bench::bench_case(name, &load, &methods, a.repeat, |m| {
            if !quiet {
                eprintln!("{m}");
            }
        })?;
        if name != "packbot" {
            // The paper's figures are for its PackBot case only.
            for m in &mut r.methods {
                m.paper_rtf = None;
            }
        }
        if !quiet {
            out!("{}", r.to_markdown());
        }
        report.cases.push(r);
    }
    if a.json {
        out!("{}", report.to_json());
    }
    if let Some(dir) = &a.out {
        let written = report.write(dir)?;
        if !quiet {
            for p in written {
                out!("wrote {}", p.display());
            }
        }
    }
    if super::stopped() {
        return Err(Failure::Interrupted);
    }
    Ok(())
}

/// `bench --jobs N`: for every selected case and method, `N x repeat` independent runs on `N`
/// threads; the throughput per core.
fn bench_batch(
    a: &BenchArgs,
    jobs: usize,
    cases: &[(&str, PathBuf)],
    methods: &[Method],
) -> Result<(), Failure> {
    let runs = jobs
        .checked_mul(a.repeat)
        .ok_or_else(|| bad_arg("--jobs", "jobs x repeat is too large".into()))?;
    let mut all = Vec::new();
    for (name, path) in cases {
        let load = tracksim::bench::BenchLoad {
            path: path.clone(),
            duration_s: a.duration,
            solver_iterations: a.solver_iterations,
        };
        for m in methods {
            let sc = load.scenario(Some(*m))?;
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
