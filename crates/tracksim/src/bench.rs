//! `tracksim bench`: the paper's Table II case (and others) for every track method, repeated
//! and interleaved so that machine noise hits all methods alike.

use crate::error::Result;
use crate::model::Method as TrackMethod;
use crate::model::Scenario;
use crate::run::Scripted;
use serde::Serialize;
use std::time::Instant;

/// The paper's Table II real-time factors (Gazebo 7 + ODE, dt 1 ms, i7-6500U), if it has one.
pub fn paper_rtf(m: TrackMethod) -> Option<f64> {
    match m {
        TrackMethod::Okada2020 => Some(2.79),
        TrackMethod::Okada2020NoGrousers => Some(3.96),
        TrackMethod::Wheels(4) => Some(4.86),
        TrackMethod::Wheels(13) => Some(1.79),
        TrackMethod::ConstraintToGround => Some(5.93),
        _ => None,
    }
}

/// One method's figures in one benchmark case.
#[derive(Clone, Debug, Serialize)]
pub struct MethodResult {
    /// Method name.
    pub name: String,
    /// Median real-time factor over the repeats (simulated s / wall s, stepping only).
    pub rtf_median: f64,
    /// Smallest real-time factor.
    pub rtf_min: f64,
    /// Largest real-time factor.
    pub rtf_max: f64,
    /// Median wall time per step, microseconds.
    pub us_per_step: f64,
    /// Mean number of solver contact points per step (sampled every 10 steps).
    pub contacts_per_step: f64,
    /// rtf_median / the 4-wheel model's rtf_median in the same run.
    pub ratio_to_4_wheels: Option<f64>,
    /// The paper's Table II figure.
    pub paper_rtf: Option<f64>,
    /// Every repeat's real-time factor, in run order.
    pub rtf_runs: Vec<f64>,
    /// Why the method could not run, if it could not.
    pub error: Option<String>,
}

/// The settings that change physics, reported with every benchmark.
#[derive(Clone, Debug, Serialize)]
pub struct BenchSettings {
    /// Time step, s.
    pub dt_s: f64,
    /// Simulated time per run, s.
    pub duration_s: f64,
    /// Solver iterations.
    pub solver_iterations: usize,
    /// Contact clustering.
    pub contact_clustering: bool,
    /// Smallest segment link mass, kg.
    pub min_link_mass_kg: f64,
    /// Repeats per method.
    pub repeat: usize,
}

/// One benchmark case.
#[derive(Clone, Debug, Serialize)]
pub struct CaseResult {
    /// Case name.
    pub case: String,
    /// Settings.
    pub settings: BenchSettings,
    /// Per method.
    pub methods: Vec<MethodResult>,
}

fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    if n == 0 {
        f64::NAN
    } else if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
    }
}

/// Runs `sc` once: (real-time factor, us per step, contacts per step).
pub fn time_one(sc: &Scenario) -> Result<(f64, f64, f64)> {
    let mut sim = Scripted::new(sc)?;
    let steps = (sc.duration / sc.solver.dt).round().max(1.0) as u64;
    let mut stepping = 0.0;
    let (mut contacts, mut samples) = (0usize, 0usize);
    for i in 0..steps {
        let t0 = Instant::now();
        sim.step()?;
        stepping += t0.elapsed().as_secs_f64();
        if i % 10 == 9 {
            contacts += sim.contact_count();
            samples += 1;
        }
    }
    Ok((
        sim.time() / stepping,
        stepping * 1e6 / steps as f64,
        contacts as f64 / samples.max(1) as f64,
    ))
}

/// Benchmarks `methods` on the case `load` compiles (its file with each method as an
/// override, [`BenchLoad::scenario`]), each `repeat` times, interleaved (m1, m2, ..., m1, m2,
/// ...). A method the file refuses, or that fails, is reported with its error.
pub fn bench_case(
    case: &str,
    load: &BenchLoad,
    methods: &[TrackMethod],
    repeat: usize,
    mut progress: impl FnMut(&str),
) -> Result<CaseResult> {
    let sc = load.scenario(None)?;
    let mut errors: Vec<Option<String>> = vec![None; methods.len()];
    let scenarios: Vec<Option<Scenario>> = methods
        .iter()
        .zip(&mut errors)
        .map(|(m, error)| {
            load.scenario(Some(*m))
                .map_err(|e| *error = Some(e.to_string()))
                .ok()
        })
        .collect();
    let mut runs: Vec<Vec<(f64, f64, f64)>> = vec![Vec::new(); methods.len()];
    for r in 0..repeat {
        for (i, m) in methods.iter().enumerate() {
            let (Some(msc), None) = (&scenarios[i], &errors[i]) else {
                continue;
            };
            progress(&format!("{case}: {} run {}/{repeat}", m.name(), r + 1));
            match time_one(msc) {
                Ok(x) => runs[i].push(x),
                Err(e) => errors[i] = Some(e.to_string()),
            }
        }
    }
    let wheels4 = methods
        .iter()
        .position(|m| *m == TrackMethod::Wheels(4))
        .filter(|&i| !runs[i].is_empty())
        .map(|i| median(&runs[i].iter().map(|r| r.0).collect::<Vec<_>>()));
    let methods = methods
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let rtf: Vec<f64> = runs[i].iter().map(|r| r.0).collect();
            let us: Vec<f64> = runs[i].iter().map(|r| r.1).collect();
            let contacts = runs[i].iter().map(|r| r.2).sum::<f64>() / runs[i].len().max(1) as f64;
            let med = median(&rtf);
            MethodResult {
                name: m.name(),
                rtf_median: med,
                rtf_min: rtf.iter().copied().fold(f64::INFINITY, f64::min),
                rtf_max: rtf.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                us_per_step: median(&us),
                contacts_per_step: contacts,
                ratio_to_4_wheels: wheels4.filter(|_| !rtf.is_empty()).map(|w| med / w),
                paper_rtf: paper_rtf(*m),
                rtf_runs: rtf,
                error: errors[i].clone(),
            }
        })
        .collect();
    Ok(CaseResult {
        case: case.to_string(),
        settings: BenchSettings {
            dt_s: sc.solver.dt,
            duration_s: sc.duration,
            solver_iterations: sc.solver.iterations,
            contact_clustering: sc.solver.contact_clustering,
            min_link_mass_kg: sc.solver.min_link_mass,
            repeat,
        },
        methods,
    })
}

impl CaseResult {
    /// The table as markdown.
    pub fn to_markdown(&self) -> String {
        let s = &self.settings;
        let mut out = format!(
            "### {}\n\ndt {} s, {} s simulated per run, {} solver iterations, contact clustering {}, min link mass {} kg, {} repeats (interleaved)\n\n",
            self.case,
            s.dt_s,
            s.duration_s,
            s.solver_iterations,
            if s.contact_clustering { "on" } else { "off" },
            s.min_link_mass_kg,
            s.repeat
        );
        out.push_str("| method | RTF median | RTF min-max | us/step | contacts/step | ratio to 4 wheels | paper RTF |\n|---|---:|---:|---:|---:|---:|---:|\n");
        for m in &self.methods {
            if let Some(e) = &m.error {
                out.push_str(&format!("| {} | error: {e} | | | | | |\n", m.name));
                continue;
            }
            out.push_str(&format!(
                "| {} | {:.1} | {:.1}-{:.1} | {:.1} | {:.0} | {} | {} |\n",
                m.name,
                m.rtf_median,
                m.rtf_min,
                m.rtf_max,
                m.us_per_step,
                m.contacts_per_step,
                m.ratio_to_4_wheels
                    .map(|r| format!("{r:.2}"))
                    .unwrap_or_else(|| "-".into()),
                m.paper_rtf
                    .map(|r| format!("{r:.2}"))
                    .unwrap_or_else(|| "-".into()),
            ));
        }
        out
    }

    /// The table as CSV.
    pub fn to_csv(&self) -> String {
        let mut out = String::from(
            "case,method,rtf_median,rtf_min,rtf_max,us_per_step,contacts_per_step,ratio_to_4_wheels,paper_rtf,error\n",
        );
        for m in &self.methods {
            let opt = |x: Option<f64>| x.map(|v| format!("{v:.4}")).unwrap_or_default();
            out.push_str(&format!(
                "{},{},{:.4},{:.4},{:.4},{:.3},{:.1},{},{},\"{}\"\n",
                self.case,
                m.name,
                m.rtf_median,
                m.rtf_min,
                m.rtf_max,
                m.us_per_step,
                m.contacts_per_step,
                opt(m.ratio_to_4_wheels),
                opt(m.paper_rtf),
                m.error.clone().unwrap_or_default().replace('"', "'")
            ));
        }
        out
    }
}

/// Throughput of many independent simulations on `jobs` threads.
#[derive(Clone, Debug, Serialize)]
pub struct BatchResult {
    /// Threads.
    pub jobs: usize,
    /// Simulations run.
    pub runs: usize,
    /// Total simulated time, s.
    pub simulated_s: f64,
    /// Wall time, s.
    pub wall_s: f64,
    /// Simulated seconds per wall second.
    pub sim_s_per_wall_s: f64,
    /// Simulated seconds per wall second per core (per job).
    pub sim_s_per_wall_s_per_core: f64,
}

/// Runs `runs` independent copies of `sc` on `jobs` threads (the model is shared, each thread
/// owns its worlds).
pub fn batch(sc: &Scenario, jobs: usize, runs: usize) -> Result<BatchResult> {
    let jobs = jobs.max(1);
    let next = std::sync::atomic::AtomicUsize::new(0);
    let t0 = Instant::now();
    let results: Vec<Result<f64>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..jobs)
            .map(|_| {
                s.spawn(|| -> Result<f64> {
                    let mut simulated = 0.0;
                    while next.fetch_add(1, std::sync::atomic::Ordering::Relaxed) < runs {
                        let mut sim = Scripted::new(sc)?;
                        let steps = (sc.duration / sc.solver.dt).round() as u64;
                        for _ in 0..steps {
                            sim.step()?;
                        }
                        simulated += sim.time();
                    }
                    Ok(simulated)
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("benchmark thread panicked"))
            .collect()
    });
    let wall = t0.elapsed().as_secs_f64();
    let mut simulated = 0.0;
    for r in results {
        simulated += r?;
    }
    Ok(BatchResult {
        jobs,
        runs,
        simulated_s: simulated,
        wall_s: wall,
        sim_s_per_wall_s: simulated / wall,
        sim_s_per_wall_s_per_core: simulated / wall / jobs as f64,
    })
}

/// How a bench case's file is loaded: its duration and solver iterations overridden, and it
/// never stops early (`outcome.stop = false`: the benchmark measures stepping, not a mission).
#[derive(Clone, Debug)]
pub struct BenchLoad {
    /// The scenario file.
    pub path: std::path::PathBuf,
    /// Simulated time per run, s.
    pub duration_s: f64,
    /// Solver iterations (`None`: the file's).
    pub solver_iterations: Option<usize>,
}

impl BenchLoad {
    /// The overrides of the file's keys, with `method` if given.
    pub fn overrides(&self, method: Option<TrackMethod>) -> crate::model::Overrides {
        crate::model::Overrides {
            method,
            duration_s: Some(self.duration_s),
            solver_iterations: self.solver_iterations,
            stop_at_outcome: Some(false),
            ..Default::default()
        }
    }

    /// The case's scenario with `method` (`None`: the file's).
    pub fn scenario(&self, method: Option<TrackMethod>) -> Result<Scenario> {
        crate::model::load_scenario_with(&self.path, &self.overrides(method))
    }
}

/// A bench case's scenario with the file's method ([`BenchLoad::scenario`]).
pub fn bench_scenario(
    path: &std::path::Path,
    duration_s: f64,
    solver_iterations: Option<usize>,
) -> Result<Scenario> {
    BenchLoad {
        path: path.to_path_buf(),
        duration_s,
        solver_iterations,
    }
    .scenario(None)
}

/// The results of every benchmarked case, as `tracksim bench` prints and writes them.
#[derive(Clone, Debug, Default)]
pub struct BenchReport {
    /// One table per case.
    pub cases: Vec<CaseResult>,
}

impl BenchReport {
    /// Every case's table as markdown.
    pub fn to_markdown(&self) -> String {
        self.cases.iter().map(|r| r.to_markdown() + "\n").collect()
    }

    /// One CSV of every case (one header).
    pub fn to_csv(&self) -> String {
        self.cases
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
            .collect()
    }

    /// JSON: the first case's methods and settings at the top (the Table II case), and every
    /// case.
    pub fn to_json(&self) -> String {
        let cases: Vec<serde_json::Value> = self
            .cases
            .iter()
            .map(|r| serde_json::to_value(r).expect("serialises"))
            .collect();
        let first = cases.first().cloned().unwrap_or_default();
        serde_json::to_string_pretty(&serde_json::json!({
            "methods": first["methods"],
            "settings": first["settings"],
            "cases": cases,
        }))
        .expect("serialises")
    }

    /// Writes `bench.csv` and `bench.md` into `dir` (created if needed); returns their paths.
    pub fn write(&self, dir: &std::path::Path) -> Result<Vec<std::path::PathBuf>> {
        std::fs::create_dir_all(dir).map_err(|source| crate::error::Error::Io {
            path: dir.to_path_buf(),
            source,
        })?;
        let (csv, md) = (dir.join("bench.csv"), dir.join("bench.md"));
        crate::files::write_atomic(&csv, self.to_csv().as_bytes())?;
        crate::files::write_atomic(&md, self.to_markdown().as_bytes())?;
        Ok(vec![csv, md])
    }
}
