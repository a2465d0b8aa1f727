//! `tracksim validate`: the paper's Table IV and the physics checks.

use super::{Failure, bad_arg, data_root, parse_method};
use std::path::PathBuf;

/// Reproduce the paper's Table IV (Quince steps) and run the physics checks (slope limit,
/// skid-steer turning, Fig. 2 and Fig. 3, deformable soil against terramechanics); exits 1 if a
/// case fails.
#[derive(clap::Args)]
pub struct ValidateArgs {
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
    /// Write report.md and one plot per case into this folder.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Track method under test.
    #[arg(long, default_value = "okada2020")]
    pub method: String,
    /// Young's modulus of the track rubber in the Table IV column "compliant grousers,
    /// rigid terrain, no slop", MPa (track rubber, Shore 60-80A: about 3.5-9 MPa).
    #[arg(long, default_value_t = tracksim::validate::TRACK_RUBBER_YOUNGS_MODULUS_PA / 1e6)]
    pub rubber_modulus_mpa: f64,
    /// Run only one group of cases: table_iv, slope, turning, figures, soil or accuracy.
    #[arg(long)]
    pub only: Option<String>,
    /// The accuracy suite (issue 58): Table IV (with grousers), the slope limit, skid steering
    /// and the accuracy rows (tether and Coulomb at friction 0.3-1.0, slope limits against
    /// atan(mu), the step-climb limit against a converged run, ten minutes straight and
    /// parked, mirror and translation). One table; exits 1 if a row fails. With `--dt`,
    /// `--iterations`, `--stabilization-iterations`: how accurate that setting is.
    #[arg(long)]
    pub accuracy: bool,
    /// The solver setting of every case (default: each case's file's: 1 ms, 4 iterations,
    /// Quince's Table IV 8).
    #[command(flatten)]
    pub setting: super::setting::SettingArgs,
    /// Also run each Table IV row (with grousers) as an ensemble of N members (member 0 the
    /// asserted run, the others perturbed as `run --ensemble`; docs/ENSEMBLE.md): each row
    /// reports "S 8/8" or "marginal 5/8".
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(2..=64))]
    pub ensemble: Option<u64>,
}

/// `tracksim validate`.
pub fn validate(a: ValidateArgs) -> Result<(), Failure> {
    let m = parse_method("--method", &a.method)?;
    let mpa = a.rubber_modulus_mpa;
    if !(mpa.is_finite() && (0.1..=1000.0).contains(&mpa)) {
        return Err(bad_arg(
            "--rubber-modulus-mpa",
            format!(
                "must be a Young's modulus in MPa between 0.1 and 1000 (track rubber: 3.5-9), got {mpa}"
            ),
        ));
    }
    let only = match a.only.as_deref() {
        None => None,
        Some(name) => Some(tracksim::validate::Group::from_name(name).ok_or_else(|| {
            bad_arg(
                "--only",
                format!(
                    "unknown group \"{name}\": use one of {}",
                    tracksim::validate::Group::NAMES.join(", ")
                ),
            )
        })?),
    };
    // The limits of the files' own keys (`simulation.dt_s`, `solver_iterations`,
    // `stabilization_iterations`), refused here with the flag before any case is built.
    let s = a.setting;
    if let Some(dt) = s.dt
        && !(dt.is_finite() && (1e-5..=0.01).contains(&dt))
    {
        return Err(bad_arg(
            "--dt",
            format!(
                "must be a time step from 1e-5 to 0.01 s (tracks with grousers need 1-2 ms), got {dt}"
            ),
        ));
    }
    if s.solver_iterations.is_some_and(|n| n == 0 || n > 100) {
        return Err(bad_arg(
            "--solver-iterations",
            "must be between 1 and 100".into(),
        ));
    }
    if s.warmstart
        .is_some_and(|w| !(w.is_finite() && w > 0.0 && w <= 1.0))
    {
        return Err(bad_arg("--warmstart", "must be in (0, 1]".into()));
    }
    if s.stabilization_iterations.is_some_and(|n| n > 16) {
        return Err(bad_arg(
            "--stabilization-iterations",
            "must be between 0 and 16".into(),
        ));
    }
    let accuracy_only = a.accuracy && only.is_none();
    let opts = tracksim::validate::ValidationOptions {
        rubber_youngs_modulus_pa: mpa * 1e6,
        accuracy: a.accuracy,
        setting: s.setting(),
        // The suite asserts the Table IV column with grousers; the others are reports.
        without_grousers: !accuracy_only,
        rigid_contact: !accuracy_only,
        compliant_grousers: !accuracy_only,
        only,
        ensemble: a.ensemble.unwrap_or(0) as usize,
        stop: Some(&super::STOP),
    };
    super::on_stop(|| {});
    let report = tracksim::validate::run_validation_with(&data_root()?, m, opts, |line| {
        if !a.json {
            eprintln!("{line}");
        }
    })?;
    if a.json {
        out!(
            "{}",
            serde_json::to_string_pretty(&report).expect("serialises")
        );
    } else {
        out!("{}", report.to_markdown());
    }
    if let Some(dir) = a.out {
        for p in report.write(&dir)? {
            if !a.json {
                out!("wrote {}", p.display());
            }
        }
    }
    if super::stopped() {
        return Err(Failure::Interrupted);
    }
    if report.passed() {
        Ok(())
    } else {
        Err(Failure::Outcome)
    }
}
