//! [`VecEnv`]: many [`Env`]s stepped on threads, with autoreset. Each environment is advanced by
//! exactly one thread per step and owns all its state, so results do not depend on the thread
//! count.

use super::seeds::Seeds;
use super::{Env, EnvConfig, StepInfo};
use crate::error::{Error, Result};
use crate::model::ScenarioTemplate;
use rayon::prelude::*;
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
    pool: StepPool,
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
            pool: StepPool::new(threads),
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
        self.pool.threads()
    }

    /// Sets the threads used per step (at least 1): the pool of the old count stops, one of the
    /// new count starts at the next step.
    pub fn set_threads(&mut self, t: usize) {
        self.pool.set_threads(t);
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
        let out = self.pool.run(&mut self.envs, |i, env| {
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
        self.pool.run(&mut parts, |_, (env, o)| {
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
        self.pool.run(&mut self.envs, |i, e| f(e, i)).map(|_| ())
    }
}

/// The threads that step the environments of a [`VecEnv`] or [`super::TeamVecEnv`]: a rayon
/// pool of `threads` worker threads started at the first step that needs it and kept for every
/// step after (issue 44: threads used to be started and joined at every step), until the thread
/// count changes or the environment is dropped. One thread steps on the calling thread, without
/// a pool. A process forked from the one that started the pool (Python's multiprocessing
/// "fork") has none of its threads: it starts a pool of its own.
pub(crate) struct StepPool {
    threads: usize,
    /// The pool and the process id that started it.
    pool: Option<(u32, rayon::ThreadPool)>,
}

impl StepPool {
    /// A pool of `threads` threads (0 is taken as 1), started at its first use.
    pub(crate) fn new(threads: usize) -> Self {
        StepPool {
            threads: threads.max(1),
            pool: None,
        }
    }

    /// Threads used per step.
    pub(crate) fn threads(&self) -> usize {
        self.threads
    }

    /// Sets the threads used per step (at least 1); another count stops the pool's threads
    /// (the next step starts the new count).
    pub(crate) fn set_threads(&mut self, t: usize) {
        let t = t.max(1);
        if t != self.threads {
            self.threads = t;
            self.stop();
        }
    }

    /// Stops the pool's threads. In a forked process the pool's threads stayed in the parent:
    /// dropping the pool there would signal threads that are not there (under locks they may
    /// have held at the fork), so it is left alone (its memory kept) instead.
    fn stop(&mut self) {
        if let Some((owner, pool)) = self.pool.take()
            && owner != std::process::id()
        {
            std::mem::forget(pool);
        }
    }

    /// `f(i, &mut items[i])` for every item, on the pool's threads; the results in item order.
    /// Each item is visited by exactly one thread, and every item is visited even when some
    /// fail, so results and states that depend only on the item do not depend on the thread
    /// count or on the scheduling. The first error in item order is returned. A pool that
    /// cannot be started (the system refused the threads) is an error naming the setting.
    pub(crate) fn run<T: Send, R: Send>(
        &mut self,
        items: &mut [T],
        f: impl Fn(usize, &mut T) -> Result<R> + Sync,
    ) -> Result<Vec<R>> {
        let results: Vec<Result<R>> = if self.threads == 1 || items.len() < 2 {
            items.iter_mut().enumerate().map(|(i, x)| f(i, x)).collect()
        } else {
            let pid = std::process::id();
            if self.pool.as_ref().is_some_and(|(owner, _)| *owner != pid) {
                self.stop(); // forked: a pool of this process is started below
            }
            let (_, pool) = match &mut self.pool {
                Some(p) => p,
                slot => slot.insert((
                    pid,
                    rayon::ThreadPoolBuilder::new()
                        .num_threads(self.threads)
                        .thread_name(|i| format!("tracksim-env-{i}"))
                        .build()
                        .map_err(|e| {
                            Error::setting(
                                "vector environment",
                                "threads",
                                format!("could not start {} threads: {e}", self.threads),
                            )
                        })?,
                )),
            };
            pool.install(|| {
                items
                    .par_iter_mut()
                    .enumerate()
                    .map(|(i, x)| f(i, x))
                    .collect()
            })
        };
        results.into_iter().collect()
    }
}

impl Drop for StepPool {
    fn drop(&mut self) {
        self.stop();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeSet;

    /// The names of the threads that ran each of `n` items.
    fn names(pool: &mut StepPool, n: usize) -> Vec<String> {
        let mut items = vec![0u8; n];
        pool.run(&mut items, |_, _| {
            // Long enough that every worker takes a share.
            std::thread::sleep(std::time::Duration::from_millis(2));
            Ok(std::thread::current().name().unwrap_or("").to_string())
        })
        .unwrap()
    }

    /// The pool's threads are started once and step every later call (the threads of a
    /// second and third step are the first step's), until the thread count changes; one
    /// thread steps on the caller.
    #[test]
    fn the_pool_is_started_once_and_reused() {
        let caller = std::thread::current().name().map(str::to_string);
        let mut pool = StepPool::new(3);
        let first: BTreeSet<String> = names(&mut pool, 24).into_iter().collect();
        assert!(first.len() > 1, "several threads stepped: {first:?}");
        assert!(
            first.iter().all(|n| n.starts_with("tracksim-env-")),
            "{first:?}"
        );
        let ids = |pool: &mut StepPool| -> BTreeSet<String> {
            let mut items = vec![0u8; 24];
            let got = pool
                .run(&mut items, |_, _| {
                    std::thread::sleep(std::time::Duration::from_millis(2));
                    Ok(format!("{:?}", std::thread::current().id()))
                })
                .unwrap();
            got.into_iter().collect()
        };
        // Threads started per step would be new threads (new ids) at every step.
        let all: BTreeSet<String> = (0..4).flat_map(|_| ids(&mut pool)).collect();
        assert!(
            (2..=3).contains(&all.len()),
            "four steps on the pool's 3 threads: {all:?}"
        );
        pool.set_threads(1);
        assert_eq!(pool.threads(), 1);
        let one: BTreeSet<Option<String>> = names(&mut pool, 5)
            .into_iter()
            .map(|n| (!n.is_empty()).then_some(n))
            .collect();
        assert_eq!(one, BTreeSet::from([caller]), "one thread: the caller's");
    }

    /// Results come in item order whatever the threads; every item is visited even when some
    /// fail, and the first error in item order is returned.
    #[test]
    fn results_in_order_every_item_visited_the_first_error_returned() {
        for threads in [1, 2, 5] {
            let mut pool = StepPool::new(threads);
            let mut items: Vec<u32> = (0..40).collect();
            let out = pool.run(&mut items, |i, x| Ok((i, *x * 2))).unwrap();
            assert_eq!(out, (0..40).map(|i| (i, i as u32 * 2)).collect::<Vec<_>>());
            let err = pool
                .run(&mut items, |i, x| {
                    *x += 100;
                    if i == 7 || i == 31 {
                        Err(Error::setting("test", "item", format!("item {i} failed")))
                    } else {
                        Ok(())
                    }
                })
                .unwrap_err();
            assert!(
                err.to_string().contains("item 7 failed"),
                "{threads}: {err}"
            );
            assert!(
                items.iter().all(|x| *x >= 100),
                "{threads}: every item visited"
            );
        }
    }
}
