"""PPO (skrl, JAX backend, CPU only: no torch, no CUDA) on the PackBot steps task: PackBot 510
with flippers at a step of random height 0.12-0.24 m, edge 0.5-0.9 m ahead, friction 0.6-0.9
(`tracksim/PackBotSteps-v0`, the file scenarios/random/packbot_flippers_step_random.toml).

    python python/examples/train_ppo.py --minutes 25     # 149k env steps on 2 busy cores
    python python/examples/train_ppo.py --task tracksim/PackBotSteps-v0 --steps 50000

The learner drives the native vector env (`tracksim.TracksimVectorEnv`, `--envs` copies on
`--threads` Rust threads) through skrl's Gymnasium wrapper and skrl's sequential trainer.

Action (`--action flippers`, the default): the policy sets both flippers' normalised targets
(one value in [-1, 1] onto the vehicle's flipper range) while the robot drives straight at
the scripted baseline's speed (`--forward 0.6` of max_forward_mps, 0.3 m/s); `--action full`
learns forward speed, yaw rate and each flipper. Observation: the env's state vector (roll,
pitch, yaw, height, body velocities, flipper angles, belt speeds) and the terrain heights
relative to the body at 0.1, 0.2, ..., 0.6 m ahead on the centre line (ray casts). Reward:
10 x progress (m) per step plus 5 on success (the scenario's outcome: past the step's edge
+ 0.7 m within 8 s, tilt < 70 deg).

Evaluation: the learned policy (deterministic: the Gaussian's mean) and the scripted baseline
(flippers level, same forward speed) on the same held-out seeds (`--test-episodes` from
`--test-seed` 10000; training seeds start at `--seed` 0). Writes the learning curve (training
episodes: success rate and return against env steps; `wall_s` scaled linearly from the env
steps) to `--csv` and `--png`, and prints the result (success rates, env steps, wall times) as
JSON with `--json`.

Checkpoints: the trained agent is saved (skrl's checkpoint, `--save`, default OUT/agent.pickle);
`--load FILE` starts from one (`--steps 0`: evaluate it only). `--watch N` records N episodes of
the policy on the held-out seeds as run folders OUT/watch/seed<S>-ep0, each with its MP4
(video.mp4): `tracksim view OUT/watch/seed<S>-ep0` replays it in 3-D, and
`tracksim run TASK_FILE --seed S --commands OUT/watch/seed<S>-ep0/commands.toml --duration T`
re-runs it byte for byte. Measured result and curve: docs/LEARNING.md (held-out success 0.99 against
the baseline's 0.23 after 25 min).
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import pathlib
import shutil
import time

import gymnasium as gym
import numpy as np

import tracksim

ROOT = pathlib.Path(__file__).resolve().parents[2]
DEFAULT_TASK = ROOT / "scenarios" / "random" / "packbot_flippers_step_random.toml"
#: The observation: the state vector plus terrain heights 0.1-0.6 m ahead on the centre line.
CONFIG = {"grid_shape": (6, 1), "grid_spacing_m": (0.1, 0.1), "grid_ahead_m": 0.1}
PROGRESS_WEIGHT = 10.0  # reward per metre of progress
SUCCESS_BONUS = 5.0  # reward when the episode ends in success


def resolve_task(task: str) -> tracksim.Scenario:
    """The scenario of ``task``: a scenario file's path, or a registered gymnasium id
    (``tracksim/...``) whose env carries its scenario."""
    if os.path.exists(task):
        return tracksim.Scenario(task)
    try:
        env = gym.make(task)
    except gym.error.Error as e:
        raise SystemExit(f"--task {task!r}: neither a scenario file nor a registered gymnasium "
                         f"id ({e}); give a path such as {DEFAULT_TASK.relative_to(ROOT)} or an "
                         f"id such as tracksim/PackBotSteps-v0") from None
    scenario = env.unwrapped.scenario
    env.close()
    return scenario


class LearnerVecEnv(gym.vector.VectorEnv):
    """The task as the learner sees it: ``TracksimVectorEnv`` with the action reduced to the
    learned part (``mode="flippers"``: one value for both flippers, forward speed fixed), the
    shaped reward, and episode statistics for the learning curve.

    The native env resets in Gymnasium's "next step" mode: the step after an episode ended
    ignores its action and returns the new episode's first observation. That transition is
    reported here as terminated with reward 0, so that the learner neither bootstraps across
    two episodes nor credits the ignored action with anything.
    """

    metadata = {"autoreset_mode": gym.vector.AutoresetMode.NEXT_STEP}

    def __init__(self, scenario, num_envs: int, threads: int, mode: str, forward: float,
                 seed=None, record_dir=None):
        config = {**CONFIG, "record_dir": str(record_dir)} if record_dir else CONFIG
        self.env = tracksim.TracksimVectorEnv(scenario, num_envs, threads=threads, config=config)
        self.seed = seed  # the seeds of the first reset (overrides the caller's)
        self.num_envs = num_envs
        self.mode = mode
        self.forward = float(forward)
        self.full_dim = self.env.single_action_space.shape[0]
        flippers = self.full_dim - 2  # twist action: forward, yaw rate, one per flipper
        if mode == "flippers" and flippers < 1:
            raise SystemExit(f"--action flippers: the vehicle of {self.env.scenario.path} has "
                             "no flippers; use --action full")
        dim = 1 if mode == "flippers" else self.full_dim
        self.single_observation_space = self.env.single_observation_space
        self.single_action_space = gym.spaces.Box(-1.0, 1.0, (dim,), np.float32)
        self.observation_space = self.env.observation_space
        self.action_space = gym.vector.utils.batch_space(self.single_action_space, num_envs)
        self.env_steps = 0  # physics env steps (autoreset steps excluded)
        self.episodes = []  # (env_steps at the end, success, return, progress_m)
        self._ret = np.zeros(num_envs)

    def full_action(self, actions):
        """The env's action (forward, yaw rate, flippers...) of the learner's ``actions``."""
        actions = np.clip(np.asarray(actions, np.float32).reshape(self.num_envs, -1), -1, 1)
        if self.mode == "full":
            return actions
        a = np.zeros((self.num_envs, self.full_dim), np.float32)
        a[:, 0] = self.forward
        a[:, 2:] = actions[:, :1]
        return a

    def reset(self, *, seed=None, options=None):
        self._ret[:] = 0.0
        return self.env.reset(seed=self.seed if self.seed is not None else seed, options=options)

    def step(self, actions):
        obs, _, term, trunc, info = self.env.step(self.full_action(actions))
        auto = np.asarray(info["autoreset"], bool)
        success = np.array([o == "success" for o in info["outcome"]])
        reward = PROGRESS_WEIGHT * np.asarray(info["progress_delta_m"]) + SUCCESS_BONUS * success
        reward = np.where(auto, 0.0, reward)
        self.env_steps += int((~auto).sum())
        self._ret += reward
        for i in np.flatnonzero(term | trunc):
            self.episodes.append((self.env_steps, bool(success[i]), float(self._ret[i]),
                                  float(info["progress_m"][i])))
            self._ret[i] = 0.0
        return obs, reward, term | auto, trunc & ~auto, info

    def close(self, **kwargs):
        pass


def make_agent(env, args):
    """skrl's PPO with a Gaussian policy (its mean through tanh, in the action bounds) and a
    value network (2 x 64 tanh each) on ``env`` (a skrl-wrapped env), observations and
    values standardised on the fly."""
    from skrl.agents.jax.ppo import PPO, PPO_CFG
    from skrl.memories.jax import RandomMemory
    from skrl.resources.preprocessors.jax import RunningStandardScaler
    from skrl.resources.schedulers.jax import KLAdaptiveLR
    from skrl.utils.model_instantiators.jax import deterministic_model, gaussian_model

    net = [{"name": "net", "input": "OBSERVATIONS", "layers": [64, 64], "activations": "tanh"}]
    models = {
        "policy": gaussian_model(observation_space=env.observation_space,
                                 action_space=env.action_space, device=env.device,
                                 clip_actions=True, initial_log_std=-0.5, network=net,
                                 output="tanh(ACTIONS)"),
        "value": deterministic_model(observation_space=env.observation_space,
                                     action_space=env.action_space, device=env.device,
                                     network=net, output="ONE"),
    }
    for role, model in models.items():
        model.init_state_dict(role=role)
    cfg = PPO_CFG(
        rollouts=args.rollouts, learning_epochs=args.epochs, mini_batches=args.mini_batches,
        discount_factor=0.99, gae_lambda=0.95, learning_rate=args.lr,
        # A fixed rate by default: with skrl's KL-adaptive rate (up to 1e-2) the training
        # success rate rose to 0.94 by 30k env steps and fell to 0.38 by 90k.
        learning_rate_scheduler=KLAdaptiveLR if args.kl_adaptive else None,
        learning_rate_scheduler_kwargs={"kl_threshold": 0.01} if args.kl_adaptive else {},
        observation_preprocessor=RunningStandardScaler,
        observation_preprocessor_kwargs={"size": env.observation_space, "device": env.device},
        value_preprocessor=RunningStandardScaler,
        value_preprocessor_kwargs={"size": 1, "device": env.device},
        entropy_loss_scale=0.0, value_loss_scale=1.0, ratio_clip=0.2, value_clip=0.2,
        grad_norm_clip=0.5, time_limit_bootstrap=False,
    )
    cfg.experiment.directory = str(args.out)
    cfg.experiment.write_interval = 0  # no TensorBoard files: the curve is ours
    cfg.experiment.checkpoint_interval = 0
    memory = RandomMemory(memory_size=args.rollouts, num_envs=env.num_envs, device=env.device)
    return PPO(models=models, memory=memory, observation_space=env.observation_space,
               action_space=env.action_space, device=env.device, cfg=cfg)


def evaluate(scenario, seeds, threads, policy, mode, forward, record_dir=None):
    """Success rate, mean return and mean progress (m) of ``policy`` (observations -> learner
    actions, or None for the scripted baseline: flippers level) over one episode per seed;
    with ``record_dir`` each seed's episode is written there as a run folder
    ``seed<SEED>-ep0`` (the folders of episodes an autoreset began after it are removed)."""
    env = LearnerVecEnv(scenario, len(seeds), threads, "flippers" if policy is None else mode,
                        forward, seed=list(seeds), record_dir=record_dir)
    obs, _ = env.reset()
    done = np.zeros(len(seeds), bool)
    first = {}
    while not done.all():
        act = (np.zeros((len(seeds), 1), np.float32) if policy is None else policy(obs))
        before = len(env.episodes)
        obs, _, term, trunc, info = env.step(act)
        ended = (term | trunc) & ~np.asarray(info["autoreset"], bool)
        for k, i in enumerate(np.flatnonzero(ended)):
            if i not in first:
                first[i] = env.episodes[before + k]
        done |= ended
    eps = [first[i] for i in range(len(seeds))]
    if record_dir:
        env.env.close()  # writes the episodes in progress
        for d in pathlib.Path(record_dir).iterdir():
            if not d.name.endswith("-ep0"):
                shutil.rmtree(d)
    return (float(np.mean([e[1] for e in eps])), float(np.mean([e[2] for e in eps])),
            float(np.mean([e[3] for e in eps])))


def curve(episodes, bins, train_wall_s, env_steps):
    """Rows of the learning curve: training episodes grouped by the env steps at their end."""
    if not episodes:
        return []
    edges = np.linspace(0, env_steps, bins + 1)
    at = np.array([e[0] for e in episodes])
    rows = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        sel = [e for e, s in zip(episodes, at) if lo < s <= hi]
        if sel:
            rows.append({"env_steps": int(hi), "wall_s": round(train_wall_s * hi / env_steps, 1),
                         "episodes": len(sel),
                         "success_rate": round(float(np.mean([e[1] for e in sel])), 4),
                         "mean_return": round(float(np.mean([e[2] for e in sel])), 4),
                         "mean_progress_m": round(float(np.mean([e[3] for e in sel])), 4)})
    return rows


def plot(rows, baseline, learned, path, title):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    x = [r["env_steps"] for r in rows]
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    a1.plot(x, [r["success_rate"] for r in rows], "o-", ms=3,
            label="training episodes (stochastic policy)")
    a1.axhline(baseline, color="grey", ls="--",
               label=f"scripted baseline, held-out: {baseline:.2f}")
    a1.axhline(learned, color="C2", ls=":", label=f"PPO final, held-out (deterministic): "
               f"{learned:.2f}")
    a1.set_ylabel("success rate")
    a1.set_ylim(-0.02, 1.02)
    a1.legend(loc="upper left", fontsize=8)
    a1.set_title(title, fontsize=10)
    a2.plot(x, [r["mean_return"] for r in rows], "o-", ms=3, color="C1")
    a2.set_ylabel("episode return")
    a2.set_xlabel("env steps (50 ms each)")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--task", default=str(DEFAULT_TASK),
                    help="scenario file or gymnasium id (e.g. tracksim/PackBotSteps-v0)")
    ap.add_argument("--steps", type=int, default=200_000, help="training env steps")
    ap.add_argument("--minutes", type=float, default=0.0,
                    help="stop training after the update that passes this wall time (0: none)")
    ap.add_argument("--envs", type=int, default=16, help="environments of the vector env")
    ap.add_argument("--threads", type=int, default=os.cpu_count() or 1,
                    help="Rust threads of the vector env (default: the cores)")
    ap.add_argument("--action", choices=("flippers", "full"), default="flippers")
    ap.add_argument("--physics", choices=("validated", "training", "clustered"),
                    default="validated",
                    help="physics to train on (tracksim.TRAINING_PHYSICS, "
                         "TRAINING_PHYSICS_CLUSTERED); the held-out evaluation always runs the "
                         "validated physics of the file")
    ap.add_argument("--forward", type=float, default=0.6,
                    help="normalised forward speed with --action flippers and of the baseline")
    ap.add_argument("--rollouts", type=int, default=64, help="steps per env between updates")
    ap.add_argument("--epochs", type=int, default=5, help="learning epochs per update")
    ap.add_argument("--mini-batches", type=int, default=4)
    ap.add_argument("--lr", type=float, default=3e-4, help="Adam's learning rate")
    ap.add_argument("--kl-adaptive", action="store_true",
                    help="skrl's KL-adaptive learning rate (threshold 0.01) instead of --lr")
    ap.add_argument("--seed", type=int, default=0, help="training seeds start here")
    ap.add_argument("--test-seed", type=int, default=10_000)
    ap.add_argument("--test-episodes", type=int, default=100)
    ap.add_argument("--bins", type=int, default=25, help="points of the learning curve")
    ap.add_argument("--out", type=pathlib.Path, default=ROOT / "out" / "ppo")
    ap.add_argument("--csv", type=pathlib.Path, default=None, help="default OUT/curve.csv")
    ap.add_argument("--png", type=pathlib.Path, default=None, help="default OUT/curve.png")
    ap.add_argument("--json", action="store_true", help="print the result as one JSON line")
    ap.add_argument("--save", type=pathlib.Path, default=None,
                    help="write the trained agent (skrl checkpoint) here; default "
                         "OUT/agent.pickle")
    ap.add_argument("--load", type=pathlib.Path, default=None,
                    help="start from this checkpoint (one --save wrote, same --action); "
                         "with --steps 0 it is only evaluated (and watched)")
    ap.add_argument("--watch", type=int, default=0, metavar="N",
                    help="record N episodes of the trained policy on the held-out seeds as "
                         "run folders OUT/watch/seed<S>-ep0 (tracksim view DIR; tracksim run "
                         "TASK --seed S --commands DIR/commands.toml replays one) with an "
                         "MP4 video each (video.mp4)")
    args = ap.parse_args()
    for k, v in (("--steps", args.steps), ("--envs", args.envs), ("--threads", args.threads),
                 ("--rollouts", args.rollouts), ("--test-episodes", args.test_episodes)):
        if v < 1 and not (k == "--steps" and v == 0 and args.load):
            raise SystemExit(f"{k} must be at least 1 (got {v}; --steps 0 only with --load)")
    if args.watch < 0:
        raise SystemExit(f"--watch must be at least 0 (got {args.watch})")
    if args.load and not args.load.is_file():
        raise SystemExit(f"--load {args.load}: no such checkpoint file (one --save wrote)")
    if not -1.0 <= args.forward <= 1.0:
        raise SystemExit(f"--forward must be in [-1, 1] (got {args.forward})")
    args.out.mkdir(parents=True, exist_ok=True)
    csv_path = args.csv or args.out / "curve.csv"
    png_path = args.png or args.out / "curve.png"

    # The networks are small: one XLA thread leaves the cores to the simulation.
    os.environ.setdefault("XLA_FLAGS", "--xla_cpu_multi_thread_eigen=false "
                          "intra_op_parallelism_threads=1")
    import jax
    from skrl.envs.wrappers.jax import wrap_env
    from skrl.trainers.jax import SequentialTrainer
    from skrl.utils import set_seed

    import skrl

    skrl.config.jax.device = "cpu"  # skrl's default asks for cuda:0 first, with a warning
    set_seed(args.seed)
    scenario = resolve_task(args.task)
    overrides = {"validated": {}, "training": tracksim.TRAINING_PHYSICS,
                 "clustered": tracksim.TRAINING_PHYSICS_CLUSTERED}[args.physics]
    train_scenario = tracksim.Scenario(scenario.path, **overrides) if overrides else scenario
    t0 = time.time()
    # Training seeds: env i starts with seed + i, then its autoresets go on from there.
    learner_env = LearnerVecEnv(train_scenario, args.envs, args.threads, args.action,
                                args.forward, seed=args.seed)
    env = wrap_env(learner_env, wrapper="gymnasium", verbose=False)
    agent = make_agent(env, args)
    if args.load:
        try:
            agent.load(str(args.load))
        except Exception as e:  # a pickle of other shapes: name the file and the fix
            raise SystemExit(f"--load {args.load}: not a checkpoint of this agent ({e}); give "
                             f"one that --save wrote with the same --action") from None
    # skrl's trainer, run one PPO update's worth of steps at a time (its env wrapper carries
    # the observations over), so that the budget can be wall time as well as env steps.
    trainer = SequentialTrainer(env=env, agents=agent, cfg={
        "timesteps": args.rollouts, "headless": True, "disable_progressbar": True,
        "close_environment_at_exit": False})
    vector_steps, updates = 0, 0
    while (vector_steps * args.envs < args.steps
           and (not args.minutes or time.time() - t0 < 60 * args.minutes)):
        trainer.train()
        vector_steps += args.rollouts
        updates += 1
        if not args.json and updates % 10 == 0:
            recent = learner_env.episodes[-50:]
            print(f"{learner_env.env_steps} env steps, {time.time() - t0:.0f} s, "
                  f"{len(learner_env.episodes)} episodes; last {len(recent)}: success "
                  f"{np.mean([e[1] for e in recent]) if recent else float('nan'):.2f}, return "
                  f"{np.mean([e[2] for e in recent]) if recent else float('nan'):.2f}",
                  flush=True)
    train_wall_s = time.time() - t0
    env_steps = learner_env.env_steps
    checkpoint = args.save or args.out / "agent.pickle"
    agent.save(str(checkpoint))

    agent.enable_training_mode(False)

    def policy(obs):
        _, out = agent.act(jax.numpy.asarray(obs, jax.numpy.float32), None, timestep=0,
                           timesteps=1)
        return np.asarray(out["mean_actions"])

    # The policy's action at an all-zero observation: a fingerprint of the agent (a loaded
    # checkpoint gives the trained one's).
    zero = np.zeros((1,) + learner_env.single_observation_space.shape, np.float32)
    policy_at_zero = [round(float(x), 6) for x in policy(zero)[0]]

    t1 = time.time()
    seeds = list(range(args.test_seed, args.test_seed + args.test_episodes))
    base = evaluate(scenario, seeds, args.threads, None, args.action, args.forward)
    learned = evaluate(scenario, seeds, args.threads, policy, args.action, args.forward)
    eval_wall_s = time.time() - t1
    watched = []
    if args.watch:
        watch_dir = args.out / "watch"
        if watch_dir.exists():
            shutil.rmtree(watch_dir)
        evaluate(scenario, range(args.test_seed, args.test_seed + args.watch), args.threads,
                 policy, args.action, args.forward, record_dir=watch_dir)
        for d in sorted(watch_dir.iterdir()):
            watched.append(str(tracksim.write_video(d, size=(320, 240))))

    rows = curve(learner_env.episodes, args.bins, train_wall_s, env_steps)
    with open(csv_path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["env_steps", "wall_s", "episodes", "success_rate",
                                          "mean_return", "mean_progress_m"])
        w.writeheader()
        w.writerows(rows)
    title = (f"PPO (skrl/JAX) on PackBot steps 0.12-0.24 m, action={args.action}: "
             f"{env_steps} env steps, {train_wall_s / 60:.1f} min")
    plot(rows, base[0], learned[0], png_path, title)
    result = {
        "task": args.task, "action": args.action, "forward": args.forward,
        "physics": args.physics,
        "env_steps": env_steps, "updates": updates, "train_episodes": len(learner_env.episodes),
        "train_wall_s": round(train_wall_s, 1),
        "env_steps_per_s": round(env_steps / train_wall_s, 1),
        "eval_wall_s": round(eval_wall_s, 1), "test_episodes": args.test_episodes,
        "test_seed": args.test_seed, "baseline_success": base[0], "learned_success": learned[0],
        "baseline_return": round(base[1], 3), "learned_return": round(learned[1], 3),
        "baseline_progress_m": round(base[2], 3), "learned_progress_m": round(learned[2], 3),
        "csv": str(csv_path), "png": str(png_path), "checkpoint": str(checkpoint),
        "watched": watched, "policy_at_zero": policy_at_zero,
    }
    if args.json:
        print(json.dumps(result))
    else:
        print(f"{env_steps} env steps in {train_wall_s:.0f} s ({result['env_steps_per_s']} /s); "
              f"held-out success over {args.test_episodes} episodes from seed {args.test_seed}: "
              f"scripted baseline {base[0]:.2f}, PPO {learned[0]:.2f}; curve {csv_path}, "
              f"{png_path}")


if __name__ == "__main__":
    main()
