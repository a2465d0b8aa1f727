"""The native vector env: VectorEnv API, autoreset, bit-identical whatever the thread count."""

import numpy as np

import tracksim
from conftest import SCENARIOS, SHORT_FLAT

STEP = SCENARIOS / "random" / "packbot_step_random.toml"


def rollout(env, steps, seed):
    obs, _ = env.reset(seed=seed)
    rng = np.random.default_rng(0)
    out = [obs]
    for _ in range(steps):
        a = rng.uniform(-1, 1, env.action_space.shape).astype(np.float32)
        a[:, 0] = 1.0
        obs, r, term, trunc, info = env.step(a)
        out += [obs, r, term, trunc, info["autoreset"], info["seed"]]
    return out


def test_results_do_not_depend_on_the_thread_count(write_scenario):
    p = write_scenario(SHORT_FLAT % "0.3")
    for scenario in (p, STEP):
        runs = [rollout(tracksim.TracksimVectorEnv(scenario, 4, threads=t), 12, 3)
                for t in (1, 2, 3)]
        for other in runs[1:]:
            for x, y in zip(runs[0], other):
                np.testing.assert_array_equal(x, y)


def test_autoreset_next_step_and_matches_the_single_env(write_scenario):
    p = write_scenario(SHORT_FLAT % "0.3")  # 6 control periods per episode
    venv = tracksim.TracksimVectorEnv(p, 2, threads=2)
    assert venv.observation_space.shape == (2, venv.single_observation_space.shape[0])
    obs, infos = venv.reset(seed=10)
    env = tracksim.TracksimEnv(p)
    o1, _ = env.reset(seed=11)
    np.testing.assert_array_equal(obs[1], o1)
    a = np.tile(np.array([1.0, 0.2], np.float32), (2, 1))
    for i in range(6):
        obs, r, term, trunc, info = venv.step(a)
        o1, r1, t1, tr1, _ = env.step(a[1])
        np.testing.assert_array_equal(obs[1], o1)
        assert r[1] == r1 and trunc[1] == tr1
    assert trunc.all() and not term.any()
    obs, r, term, trunc, info = venv.step(a)
    assert info["autoreset"].all() and (r == 0).all() and not (term | trunc).any()
    assert (info["seed"] != np.array([10, 11])).all()
    # The reset observation is the start of an episode: no motion yet.
    assert np.abs(obs[:, 4:7]).max() < 0.05


def test_randomized_values_per_env_come_from_their_seeds():
    venv = tracksim.TracksimVectorEnv(STEP, 3)
    venv.reset(seed=100)
    sc = tracksim.Scenario(STEP)
    assert [venv.randomized(i) for i in range(3)] == [sc.sample(100 + i) for i in range(3)]


def _step_and_send(venv, action, queue):
    queue.put(venv.step(action)[0])


def test_a_forked_process_steps_on_threads_of_its_own(write_scenario):
    """The vector env's thread pool (started at its first step, kept) stays in the process that
    started it: a process forked after a step (multiprocessing's "fork") starts a pool of its
    own rather than waiting for its parent's threads, and steps as its parent does."""
    import multiprocessing as mp
    from queue import Empty

    p = write_scenario(SHORT_FLAT % "0.3")
    venv = tracksim.TracksimVectorEnv(p, 4, threads=2)
    venv.reset(seed=3)
    a = np.tile(np.array([1.0, 0.2], np.float32), (4, 1))
    venv.step(a)  # the pool started
    ctx = mp.get_context("fork")
    queue = ctx.Queue()
    child = ctx.Process(target=_step_and_send, args=(venv, a, queue))
    child.start()
    try:
        got = queue.get(timeout=60)
    except Empty:
        got = None
    child.join(5)
    hung = child.is_alive()
    if hung:
        child.kill()
    assert got is not None and not hung, "the forked process hung on its parent's pool"
    np.testing.assert_array_equal(got, venv.step(a)[0])
