//! Episodes written as run folders (`record_dir`): what `tracksim run` writes (`summary.json`,
//! `trajectory.csv`, the replay data `scene.json` + `belts.csv` that `tracksim view DIR`
//! opens, the sensor streams of a dict observation; no plots) and `commands.toml`, the
//! episode's controls as a scenario's `[[commands]]`, through the writer every front end uses
//! ([`crate::output::write_outputs`]).
//!
//! An episode's folder is `record_dir/seed<SEED>-ep<K>` (K counts the stepped episodes of
//! one environment from 0), written when the next episode starts ([`super::Env::reset`], a vector
//! environment's autoreset) or the recording is flushed ([`super::Env::flush_record`], what the
//! Python environments' `close()` calls); an episode that was not stepped writes nothing.
//!
//! Replay: the controls are recorded in the units a scenario's command takes and applied
//! through the same conversions (skid-steer twist, per-track belt speeds, flipper targets in
//! degrees), before the step at the time they were given, as `run::Timeline` applies a
//! command; so `tracksim run FILE --commands DIR/commands.toml --duration T` writes the same
//! `trajectory.csv`, byte for byte, when FILE gives the episode's scenario: a file without
//! `[randomize]` (any seed), or a randomised one run with the episode's seed (`tracksim run FILE
//! --seed SEED ...`; the episode's drawn values are in `summary.json` and in the header of
//! `commands.toml`), and without `outcome.stop` (the run would stop at the decided outcome,
//! the episode ran its control period to the end).

use crate::error::Result;
use crate::model::Scenario;
use crate::run::{CommandLog, End, LogHeader, Runner};
use crate::spec::{CommandSpec, PerTrack};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The recording of one episode: where it goes and its controls so far.
#[derive(Clone, Debug)]
pub(super) struct EpisodeRecord {
    /// The folder of every episode (`record_dir`).
    pub dir: PathBuf,
    /// The episode's index among the environment's recorded episodes.
    pub episode: u64,
    /// The control changes, in time order.
    pub log: CommandLog,
}

/// The drive part of a recorded command.
pub(super) enum Drive {
    /// Forward speed m/s and yaw rate rad/s.
    Twist(f64, f64),
    /// One belt speed per track, m/s.
    Belts,
}

impl EpisodeRecord {
    /// A recording into `dir` of the environment's episode number `episode`.
    pub fn new(dir: PathBuf, episode: u64) -> Self {
        EpisodeRecord {
            dir,
            episode,
            log: CommandLog::new(),
        }
    }

    /// Records the controls applied at `t` s (if they differ from those in force): `drive`,
    /// the belt speeds `belts` (m/s, with [`Drive::Belts`]) and the flipper targets `deg`.
    pub fn push(&mut self, sc: &Scenario, t: f64, drive: Drive, belts: &[f64], deg: &[f64]) {
        let v = &sc.vehicle;
        let mut c = CommandSpec {
            t_s: t,
            flipper_angle_deg: v
                .flippers
                .iter()
                .zip(deg)
                .map(|(f, d)| (f.name.clone(), *d))
                .collect(),
            ..CommandSpec::default()
        };
        match drive {
            Drive::Twist(f, w) => {
                c.forward_mps = Some(f);
                c.yaw_rate_rad_s = Some(w);
            }
            Drive::Belts => {
                let by: BTreeMap<String, f64> = v
                    .tracks
                    .iter()
                    .zip(belts)
                    .map(|(t, b)| (t.name.clone(), *b))
                    .collect();
                c.belt_speed_mps = Some(PerTrack::ByName(by));
            }
        }
        self.log.push(c);
    }

    /// The episode's folder.
    pub fn folder(&self, seed: u64) -> PathBuf {
        self.dir.join(format!("seed{seed}-ep{}", self.episode))
    }

    /// Finishes `runner` (`ended`: the episode reached its end, else it was cut short) and
    /// writes the folder of the episode of `sc` with `seed` from the template at `file`;
    /// returns the folder. Nothing is written for an episode without a step.
    pub fn write(
        &self,
        runner: Runner,
        sc: &Scenario,
        file: &Path,
        seed: u64,
        ended: bool,
    ) -> Result<Option<PathBuf>> {
        if runner.sim().steps() == 0 {
            return Ok(None);
        }
        let dir = self.folder(seed);
        let result = runner.finish(if ended {
            End::Reached
        } else {
            End::Interrupted
        });
        let which = crate::output::Outputs {
            replay: true,
            plots: false,
            mcap: false,
            raw_images: false,
        };
        let what = format!("The controls of a learning environment's episode (seed {seed})");
        let notes = if sc.randomized.is_empty() {
            Vec::new()
        } else {
            vec![
                format!(
                    "The episode's [randomize] values (seed {seed}): {}.",
                    crate::model::sampled_text(&sc.randomized)
                ),
                format!(
                    "They are drawn again from --seed {seed} in the command above (without it \
                     the run draws from the file's simulation.seed)."
                ),
            ]
        };
        let header = LogHeader {
            what: &what,
            notes: &notes,
            seed: Some(seed),
        };
        // Marked while it is written (issue 45): an episode folder a killed process left half
        // written is never read as a result.
        crate::output::incomplete::mark_incomplete(&dir)?;
        crate::output::write_session(sc, &result, (&self.log, header), file, &dir, which)?;
        crate::output::incomplete::mark_complete(&dir)?;
        Ok(Some(dir))
    }
}
