//! The solver-setting flags that `run` and `validate` share (issue 58): `--dt`,
//! `--solver-iterations` (alias `--iterations`), `--stabilization-iterations`.

/// A solver setting given on the command line (each flag overrides the file's key).
#[derive(clap::Args, Clone, Copy, Debug, Default)]
pub struct SettingArgs {
    /// Time step, s (`simulation.dt_s`; changes physics: `tracksim validate --accuracy --dt S`
    /// says how accurate a step is).
    #[arg(long, value_name = "S")]
    pub dt: Option<f64>,
    /// Solver iterations (`simulation.solver_iterations`; changes physics).
    #[arg(long, visible_alias = "iterations", value_name = "N")]
    pub solver_iterations: Option<usize>,
    /// Position-correction passes (`simulation.stabilization_iterations`).
    #[arg(long, value_name = "N")]
    pub stabilization_iterations: Option<usize>,
    /// Share of the last step's impulses the solver starts from, (0, 1]
    /// (`simulation.warmstart_coefficient`; default Rapier's 1; 0.8 holds a tether at the friction limit).
    #[arg(long, value_name = "W")]
    pub warmstart: Option<f64>,
}

impl SettingArgs {
    /// The setting as the library's.
    pub fn setting(&self) -> tracksim::validate::SolverSetting {
        tracksim::validate::SolverSetting {
            dt_s: self.dt,
            iterations: self.solver_iterations,
            stabilization: self.stabilization_iterations,
            warmstart: self.warmstart,
        }
    }

    /// Writes the flags given into `o` (the others keep `o`'s).
    pub fn apply(&self, o: &mut tracksim::Overrides) {
        o.dt_s = self.dt.or(o.dt_s);
        o.solver_iterations = self.solver_iterations.or(o.solver_iterations);
        o.stabilization_iterations = self.stabilization_iterations.or(o.stabilization_iterations);
        o.warmstart_coefficient = self.warmstart.or(o.warmstart_coefficient);
    }
}
