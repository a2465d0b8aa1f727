//! [`VecEnv`]: many [`Env`]s stepped on threads, with autoreset. Each environment is advanced by
//! exactly one thread per step and owns all its state, so results do not depend on the thread
//! count.

use super::seeds::Seeds;
use super::{Env, EnvConfig, StepInfo};
use crate::error::{Error, Result};
use crate::model::ScenarioTemplate;
use std::sync::Arc;

/// Most environments of one [`VecEnv`].
pub const MAX_ENVS: usize = 100_000;

/// `n` environments of one template stepped together on `threads` threads. Autoreset as
/// Gymnasium's "next step" mode: the step after an episode ended resets that environment
/// (with the next seed of its sequence) and ignores its action.
pub struct VecEnv {
    envs: Vec<Env>,
    seeds: Seeds,
    ended: Vec<bool>,
    threads: usize,
}

/// What one environment's step gave: its info and whether it was an autoreset.
#[derive(Clone, Debug)]
pub struct VecStep {
    /// The step's info (default values for an autoreset).
    pub info: StepInfo,
    /// This step reset the environment (the action was ignored).
    pub reset: bool,
    /// The episode seed in effect after the step.
    pub seed: u64,
}

impl VecEnv {
    /// `n` environments (at least 1, at most [`MAX_ENVS`]), environment `i` starting with
    /// seed `seed + i`, stepped on `threads` threads (0 is taken as 1). The configuration is
    /// checked as by [`Env::new`].
    pub fn new(
        template: Arc<ScenarioTemplate>,
        cfg: EnvConfig,
        n: usize,
        seed: u64,
        threads: usize,
    ) -> Result<Self> {
        if !(1..=MAX_ENVS).contains(&n) {
            return Err(Error::setting(
                "vector environment",
                "num_envs",
                format!("must be from 1 to {MAX_ENVS} environments, got {n}"),
            ));
        }
        cfg.check()?;
        let seeds = Seeds::from_base(n, seed);
        let envs = seeds
            .as_slice()
            .iter()
            .map(|s| Env::new(template.clone(), cfg.clone(), *s))
            .collect::<Result<Vec<_>>>()?;
        Ok(VecEnv {
            envs,
            ended: vec![false; n],
            seeds,
            threads: threads.max(1),
        })
    }

    /// Number of environments.
    pub fn len(&self) -> usize {
        self.envs.len()
    }

    /// True without environments.
    pub fn is_empty(&self) -> bool {
        self.envs.is_empty()
    }

    /// The environments.
    pub fn envs(&self) -> &[Env] {
        &self.envs
    }

    /// Threads used per step.
    pub fn threads(&self) -> usize {
        self.threads
    }

    /// Sets the threads used per step (at least 1).
    pub fn set_threads(&mut self, t: usize) {
        self.threads = t.max(1);
    }

    /// Resets every environment, `i` with seed `seed + i` (or its current seed with `None`).
    pub fn reset(&mut self, seed: Option<u64>) -> Result<()> {
        if let Some(s) = seed {
            self.seeds.rebase(s);
        }
        let seeds = self.seeds.clone();
        self.par(|env, i| env.reset(seeds.as_slice()[i]).map(|_| ()))?;
        self.ended.iter_mut().for_each(|e| *e = false);
        Ok(())
    }

    /// Resets environment `i` with `seeds[i]` (one seed per environment).
    pub fn reset_seeds(&mut self, seeds: &[u64]) -> Result<()> {
        self.seeds.replace(seeds, "environment")?;
        self.reset(None)
    }

    /// Checks that an array of actions of `shape` fits [`VecEnv::step`]: `[len(), action_dim]`
    /// (one row per environment) or `[len() * action_dim]`.
    pub fn check_actions_shape(&self, shape: &[usize]) -> Result<()> {
        let (n, na) = (self.len(), self.action_dim());
        if shape == [n, na] || shape == [n * na] {
            return Ok(());
        }
        Err(Error::setting(
            "step",
            "actions",
            format!(
                "expected shape ({n}, {na}) (one row of {na} actions per environment), got \
                 {shape:?}"
            ),
        ))
    }

    /// Actions per environment (0 without environments).
    pub fn action_dim(&self) -> usize {
        self.envs.first().map_or(0, |e| e.action_dim())
    }

    /// Observation entries per environment (0 without environments).
    pub fn obs_dim(&self) -> usize {
        self.envs.first().map_or(0, |e| e.obs_dim())
    }

    /// Steps every environment with its row of `actions` (`len() * action_dim` values), writing
    /// observations into `obs` (`len() * obs_dim`); other lengths are refused (keys `actions`,
    /// `obs`).
    pub fn step(&mut self, actions: &[f32], obs: &mut [f32]) -> Result<Vec<VecStep>> {
        let (na, no) = match self.envs.first() {
            Some(e) => (e.action_dim(), e.obs_dim()),
            None => return Ok(Vec::new()),
        };
        let n = self.envs.len();
        for (key, len, per) in [("actions", actions.len(), na), ("obs", obs.len(), no)] {
            if len != n * per {
                return Err(Error::setting(
                    "step",
                    key,
                    format!(
                        "expected {} values ({n} environments times {per}), got {len}",
                        n * per
                    ),
                ));
            }
        }
        let ended = self.ended.clone();
        let seeds = self.seeds.after(&ended);
        let out = on_threads(&mut self.envs, self.threads, |i, env| {
            Ok(if ended[i] {
                env.reset(seeds.as_slice()[i])?;
                VecStep {
                    info: StepInfo::default(),
                    reset: true,
                    seed: seeds.as_slice()[i],
                }
            } else {
                VecStep {
                    info: env.step(&actions[i * na..(i + 1) * na]),
                    reset: false,
                    seed: seeds.as_slice()[i],
                }
            })
        })?;
        self.seeds = seeds;
        self.observe(obs);
        for (e, s) in self.ended.iter_mut().zip(&out) {
            *e = s.info.terminated || s.info.truncated;
        }
        Ok(out)
    }

    /// Writes every environment's observation into `obs`.
    pub fn observe(&self, obs: &mut [f32]) {
        if let Some(no) = self.envs.first().map(|e| e.obs_dim()) {
            for (e, o) in self.envs.iter().zip(obs.chunks_mut(no)) {
                e.observe(o);
            }
        }
    }

    /// The sensor entries of each environment's dict observation (empty unless
    /// `observation = "dict"`), see [`Env::sensor_obs_spec`].
    pub fn sensor_obs_spec(&self) -> Vec<super::SensorObs> {
        self.envs
            .first()
            .map_or_else(Vec::new, |e| e.sensor_obs_spec())
    }

    /// Writes every environment's sensor entries ([`Env::observe_sensors`], `sensor_obs_dim`
    /// values each) into `out`, environment after environment.
    pub fn observe_sensors(&self, out: &mut [f32]) {
        if let Some(n) = self.envs.first().map(|e| e.sensor_obs_dim()) {
            if n == 0 {
                return;
            }
            for (e, o) in self.envs.iter().zip(out.chunks_mut(n)) {
                e.observe_sensors(o);
            }
        }
    }

    /// Width and height of every environment's frames ([`Env::render_size`]), pixels.
    pub fn render_size(&self) -> (usize, usize) {
        self.envs.first().map_or((0, 0), |e| e.render_size())
    }

    /// Every environment's frame of its current state ([`Env::render`]) on the threads, one
    /// after the other into `out` (resized to `len() * height * width * 3` bytes: shape
    /// `(n, height, width, 3)`, rgb8); returns `(width, height)`.
    pub fn render(&mut self, out: &mut Vec<u8>) -> Result<(usize, usize)> {
        let (w, h) = self.render_size();
        let per = 3 * w * h;
        out.clear();
        out.resize(self.envs.len() * per, 0);
        let mut parts: Vec<(&mut Env, &mut [u8])> = self
            .envs
            .iter_mut()
            .zip(out.chunks_mut(per.max(1)))
            .collect();
        on_threads(&mut parts, self.threads, |_, (env, o)| {
            let f = env.render();
            if f.rgb.len() == o.len() {
                o.copy_from_slice(&f.rgb);
            }
            Ok(())
        })?;
        Ok((w, h))
    }

    /// Writes every environment's episode so far as a run folder (with `record_dir`, see
    /// [`Env::flush_record`]; closing a recording vector environment); returns the folders.
    /// An environment whose episode had ended starts its next one at the next step as usual;
    /// one cut short starts its episode again with the same seed.
    pub fn flush_records(&mut self) -> Result<Vec<std::path::PathBuf>> {
        let mut out = Vec::new();
        for e in &mut self.envs {
            out.extend(e.flush_record()?);
        }
        Ok(out)
    }

    /// Runs `f` on every environment on the threads.
    fn par(&mut self, f: impl Fn(&mut Env, usize) -> Result<()> + Sync) -> Result<()> {
        on_threads(&mut self.envs, self.threads, |i, e| f(e, i)).map(|_| ())
    }
}

/// `f(i, &mut items[i])` for every item, on up to `threads` scoped threads (the items split in
/// contiguous chunks, the last chunk on the calling thread); the results in item order. Each
/// item is visited by exactly one thread, so results that depend only on the item do not
/// depend on `threads`. The first error (in chunk order) is returned. Shared by [`VecEnv`] and
/// [`super::TeamVecEnv`].
pub(crate) fn on_threads<T: Send, R: Send>(
    items: &mut [T],
    threads: usize,
    f: impl Fn(usize, &mut T) -> Result<R> + Sync,
) -> Result<Vec<R>> {
    if items.is_empty() {
        return Ok(Vec::new());
    }
    let chunk = items.len().div_ceil(threads.max(1));
    let f = &f;
    let run = move |k: usize, part: &mut [T]| -> Result<Vec<R>> {
        part.iter_mut()
            .enumerate()
            .map(|(j, x)| f(k * chunk + j, x))
            .collect()
    };
    let parts: Vec<Result<Vec<R>>> = std::thread::scope(|scope| {
        let mut chunks = items.chunks_mut(chunk).enumerate();
        let last = chunks.next_back();
        let handles: Vec<_> = chunks
            .map(|(k, part)| scope.spawn(move || run(k, part)))
            .collect();
        let mine = last.map(|(k, part)| run(k, part));
        let mut out: Vec<_> = handles
            .into_iter()
            .map(|h| h.join().expect("environment thread panicked"))
            .collect();
        out.extend(mine);
        out
    });
    let parts = parts.into_iter().collect::<Result<Vec<Vec<R>>>>()?;
    Ok(parts.into_iter().flatten().collect())
}
