//! The controls a session gave, as a scenario's `[[commands]]` ([`CommandLog`]): one log and
//! one writer of `commands.toml` for every front end that takes controls from outside (a
//! `drive` page, ROS 2 topics, a learning environment's actions).
//!
//! Each entry is a [`CommandSpec`] in the units a scenario's command takes (m/s, rad/s,
//! degrees), applied at its `t_s` through the same compilation as a file's commands
//! ([`crate::model::compile_commands`]); `tracksim run FILE --commands DIR/commands.toml
//! --duration T --keep-running` ([`reproduce_command`]) therefore replays the session's
//! `trajectory.csv` byte for byte, a session that went on past its decided outcome too.

use crate::error::Result;
use crate::spec::CommandSpec;
use std::path::{Path, PathBuf};

/// The control changes of a session, in time order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CommandLog {
    commands: Vec<CommandSpec>,
}

/// The header of a `commands.toml`: what the controls were (`what`, one line, e.g. "The
/// operator's controls of a `tracksim drive` session") and any further comment lines
/// (`notes`, each without its `#`).
#[derive(Clone, Copy, Debug)]
pub struct LogHeader<'a> {
    /// What the controls were, one line.
    pub what: &'a str,
    /// Further comment lines.
    pub notes: &'a [String],
    /// The seed the run was instantiated with (`tracksim run --seed`), when it was: the
    /// reproducing command then says `--seed N` (issue 64: an episode of a learning
    /// environment, randomised or not, replays byte for byte only with its seed).
    pub seed: Option<u64>,
}

impl CommandLog {
    /// An empty log.
    pub fn new() -> Self {
        Self::default()
    }

    /// Records `c` unless it says the same as the last entry (apart from its time); returns
    /// whether it was recorded.
    pub fn push(&mut self, c: CommandSpec) -> bool {
        if let Some(last) = self.commands.last()
            && same_controls(last, &c)
        {
            return false;
        }
        self.commands.push(c);
        true
    }

    /// The entries, in time order.
    pub fn commands(&self) -> &[CommandSpec] {
        &self.commands
    }

    /// Number of entries.
    pub fn len(&self) -> usize {
        self.commands.len()
    }

    /// Whether nothing was recorded.
    pub fn is_empty(&self) -> bool {
        self.commands.is_empty()
    }

    /// Forgets every entry (a session that starts again).
    pub fn clear(&mut self) {
        self.commands.clear();
    }

    /// `commands.toml` (to be written at `commands_file`): the header, the command that replays
    /// the run of `scenario_file` for `duration_s` s, then the entries as `[[commands]]`.
    pub fn to_toml(
        &self,
        header: LogHeader,
        scenario_file: &Path,
        commands_file: &Path,
        duration_s: f64,
    ) -> String {
        #[derive(serde::Serialize)]
        struct File<'a> {
            commands: &'a [CommandSpec],
        }
        let body = toml::to_string(&File {
            commands: &self.commands,
        })
        .expect("commands serialise");
        header.text(scenario_file, commands_file, duration_s, "trajectory.csv") + &body
    }

    /// Writes `commands.toml` into `dir` (see [`CommandLog::to_toml`]); returns its path.
    pub fn write(
        &self,
        header: LogHeader,
        scenario_file: &Path,
        dir: &Path,
        duration_s: f64,
    ) -> Result<PathBuf> {
        let p = dir.join("commands.toml");
        let text = self.to_toml(header, scenario_file, &p, duration_s);
        crate::files::write_atomic(&p, text.as_bytes())?;
        Ok(p)
    }
}

/// A duration as the replay command's `--duration` takes it: the simulated time rounded to the
/// microsecond and printed in its shortest form (`60.87`, not the float sum
/// `60.870000000000005`). A run of that duration takes the same steps as the session: the
/// rounding (< 1 us) is far below half a time step.
pub fn duration_arg(duration_s: f64) -> String {
    format!("{}", (duration_s * 1e6).round() / 1e6)
}

/// The flag of `tracksim run` that keeps a run going past its decided outcome (the
/// scenario's `outcome.stop` set to false), as a live session goes on past it.
pub const KEEP_RUNNING_FLAG: &str = "--keep-running";

/// The command that reproduces a session of `scenario_file` whose controls are in
/// `commands_file`, for `duration_s` s: `tracksim run FILE --commands FILE --duration T
/// --keep-running`. A session goes on after its outcome is decided (a course completed, a
/// success line crossed) until its operator ends it, and `run` would stop there: the flag
/// keeps the run going to `--duration` as the session went, so that it takes every step the
/// session took (a run whose outcome is never decided is the same with or without it).
pub fn reproduce_command(scenario_file: &Path, commands_file: &Path, duration_s: f64) -> String {
    format!(
        "tracksim run {} --commands {} --duration {} {KEEP_RUNNING_FLAG}",
        scenario_file.display(),
        commands_file.display(),
        duration_arg(duration_s),
    )
}

impl LogHeader<'_> {
    /// The comment lines opening a `commands.toml`: what the controls were, the command that
    /// reproduces `what_replays` of the run of `scenario_file` for `duration_s` s, the notes.
    fn text(
        &self,
        scenario_file: &Path,
        commands_file: &Path,
        duration_s: f64,
        what_replays: &str,
    ) -> String {
        let seed = self.seed.map_or(String::new(), |s| format!(" --seed {s}"));
        let mut text = format!(
            "# {}, applied at these simulated times.\n\
             # This run reproduces its {what_replays}:\n\
             #   {}{seed}\n",
            self.what,
            reproduce_command(scenario_file, commands_file, duration_s),
        );
        for n in self.notes {
            text.push_str(&format!("# {n}\n"));
        }
        text
    }
}

/// The `commands.toml` of a session of several robots (to be written at `commands_file`): the
/// header, then each robot's entries under its name as `[[vehicles]]` with
/// `[[vehicles.commands]]` (every robot listed, in `logs`' order), which `tracksim run
/// --commands` reads in place of the robots' own commands.
pub fn team_toml(
    logs: &[(&str, &CommandLog)],
    header: LogHeader,
    scenario_file: &Path,
    commands_file: &Path,
    duration_s: f64,
) -> String {
    #[derive(serde::Serialize)]
    struct Robot<'a> {
        name: &'a str,
        commands: &'a [CommandSpec],
    }
    #[derive(serde::Serialize)]
    struct File<'a> {
        vehicles: Vec<Robot<'a>>,
    }
    let file = File {
        vehicles: logs
            .iter()
            .map(|(name, log)| Robot {
                name,
                commands: log.commands(),
            })
            .collect(),
    };
    let body = toml::to_string(&file).expect("commands serialise");
    header.text(
        scenario_file,
        commands_file,
        duration_s,
        "robots' trajectory.csv",
    ) + &body
}

/// Writes [`team_toml`] as `commands.toml` into `dir`; returns its path.
pub fn write_team_log(
    logs: &[(&str, &CommandLog)],
    header: LogHeader,
    scenario_file: &Path,
    dir: &Path,
    duration_s: f64,
) -> Result<PathBuf> {
    let p = dir.join("commands.toml");
    let text = team_toml(logs, header, scenario_file, &p, duration_s);
    crate::files::write_atomic(&p, text.as_bytes())?;
    Ok(p)
}

/// Whether two entries give the same controls (their times aside).
fn same_controls(a: &CommandSpec, b: &CommandSpec) -> bool {
    CommandSpec {
        t_s: b.t_s,
        ..a.clone()
    } == *b
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::PerTrack;

    fn twist(t: f64, v: f64) -> CommandSpec {
        CommandSpec {
            t_s: t,
            forward_mps: Some(v),
            yaw_rate_rad_s: Some(0.0),
            ..CommandSpec::default()
        }
    }

    #[test]
    fn a_repeated_control_is_recorded_once() {
        let mut log = CommandLog::new();
        assert!(log.push(twist(0.0, 0.3)));
        assert!(!log.push(twist(0.5, 0.3)));
        assert!(log.push(twist(1.0, 0.0)));
        let belts = CommandSpec {
            t_s: 1.5,
            belt_speed_mps: Some(PerTrack::ByName(
                [("left".to_string(), 0.0), ("right".to_string(), 0.0)].into(),
            )),
            ..CommandSpec::default()
        };
        assert!(log.push(belts.clone()), "other keys are other controls");
        assert!(!log.push(CommandSpec { t_s: 2.0, ..belts }));
        assert_eq!(log.len(), 3);
        log.clear();
        assert!(log.is_empty());
    }

    #[test]
    fn the_replay_duration_is_printed_without_float_noise() {
        assert_eq!(duration_arg(60.870000000000005), "60.87");
        assert_eq!(duration_arg(0.1 + 0.2), "0.3");
        assert_eq!(duration_arg(2.5), "2.5");
        assert_eq!(duration_arg(1_234.000_001), "1234.000001");
    }

    #[test]
    fn commands_toml_parses_back_to_the_entries() {
        let mut log = CommandLog::new();
        log.push(twist(0.0, 0.3));
        let mut flip = twist(0.123_456_789_012_345_67, -0.1);
        flip.flipper_angle_deg.insert("front".into(), 1.0 / 3.0);
        log.push(flip);
        let notes = ["a note".to_string()];
        let text = log.to_toml(
            LogHeader {
                what: "Test controls",
                notes: &notes,
                seed: None,
            },
            Path::new("s.toml"),
            Path::new("d/commands.toml"),
            2.5,
        );
        assert!(text.starts_with("# Test controls, applied at these simulated times.\n"));
        assert!(text.contains(
            "#   tracksim run s.toml --commands d/commands.toml --duration 2.5 --keep-running\n"
        ));
        assert!(text.contains("# a note\n"));
        #[derive(serde::Deserialize)]
        struct File {
            commands: Vec<CommandSpec>,
        }
        let back: File = toml::from_str(&text).unwrap();
        assert_eq!(back.commands, log.commands(), "times and angles exactly");
    }
}
