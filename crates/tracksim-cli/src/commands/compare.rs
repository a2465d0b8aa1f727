//! `tracksim compare`: one scenario with several track methods.

use super::{Failure, parse_methods, scenario_file};
use std::path::PathBuf;

/// Run one scenario with every track method; print a table and write a combined plot.
#[derive(clap::Args)]
pub struct CompareArgs {
    /// Scenario file (TOML), or the name of a bundled scenario.
    pub file: PathBuf,
    /// Output folder (compare.csv, compare.png, compare.svg, one subfolder per method).
    #[arg(long, default_value = "out/compare")]
    pub out: PathBuf,
    /// Methods to run, comma-separated (default: all).
    #[arg(long, value_delimiter = ',')]
    pub methods: Vec<String>,
    /// Override the simulated duration, s.
    #[arg(long)]
    pub duration: Option<f64>,
    /// Print the table as JSON.
    #[arg(long)]
    pub json: bool,
    /// Also run each method as an ensemble of N perturbed members (as `run --ensemble`,
    /// docs/ENSEMBLE.md) into --out/ensemble-METHOD/, and print each method's verdict
    /// ("S 16/16", "marginal 9/16").
    #[arg(long, value_name = "N")]
    pub ensemble: Option<usize>,
}

/// `tracksim compare`; exits 3 when no method produced a run and the last was unstable.
pub fn compare(a: CompareArgs) -> Result<(), Failure> {
    let file = scenario_file(&a.file)?;
    let methods = parse_methods(&a.methods)?;
    super::on_stop(|| {});
    let stop = Some(&super::STOP);
    let report = tracksim::compare::run_compare(&file, &methods, a.duration, &a.out, stop, |m| {
        if !a.json {
            eprintln!("running {m} ...");
        }
    })?;
    if a.json {
        out!("{}", report.to_json());
    } else {
        out!("{}", report.to_table().trim_end());
        for p in &report.written {
            out!("wrote {}", p.display());
        }
    }
    if let Some(n) = a.ensemble
        && !report.interrupted
    {
        let rows =
            tracksim::compare::run_compare_ensembles(&file, &methods, a.duration, n, &a.out, stop)?;
        out!(
            "ensembles of {n} members:\n{}",
            tracksim::compare::ensemble_table(&rows).trim_end()
        );
    }
    if report.interrupted {
        eprintln!("interrupted: wrote what ran into {}", a.out.display());
        return Err(Failure::Interrupted);
    }
    match report.error {
        Some(e) => Err(Failure::Sim(e)),
        None => Ok(()),
    }
}
