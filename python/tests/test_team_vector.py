"""The vector form of the team environment (issue 40): many worlds of several robots stepped
together on Rust threads. Each world is bit-identical to a lone ``TeamParallelEnv`` with its seed
and actions, whatever the thread count; autoreset is per world ("next step"); an agent that ended
before its world is idle. The speed against lone environments is printed (``pytest -s``), not
asserted."""

import os
import time

import numpy as np
import pytest

import tracksim
from tracksim.team_env import OBSERVATION_SIZE, OUTCOME_REWARD, TeamParallelEnv
from tracksim.team_vector import TeamVectorEnv
from conftest import SCENARIOS

CORRIDOR = SCENARIOS / "team" / "corridor_head_on.toml"
CONVOY = SCENARIOS / "team" / "convoy.toml"

# Two PackBots in a line; the leader's own outcome is a success at x = 0.3 m, the tail has none.
LEAD_AND_TAIL = """
description = "two robots: the leader succeeds early, the tail runs to the end"
[terrain.ground]
friction = 0.6
[simulation]
duration_s = 2.0
[[vehicles]]
name = "lead"
[vehicles.vehicle]
file = "{vehicles}/packbot510.toml"
[vehicles.outcome]
success_x_m = 0.3
[[vehicles]]
name = "tail"
[vehicles.vehicle]
file = "{vehicles}/packbot510.toml"
x_m = -1.2
"""


def lone_steps(env, seed, actions):
    """The lone environment reset with `seed` and stepped with `actions` (one dict per step,
    of every agent): its reset observations, then (obs, rewards, terms, truncs) per step."""
    out = [env.reset(seed=seed)[0]]
    for a in actions:
        if not env.agents:
            break
        out.append(env.step({k: a[k] for k in env.agents})[:4])
    return out


def assert_world_equals_lone(vec_steps, i, lone):
    """World `i` of the vector's (obs, rewards, terms, truncs) per step equals the lone run's
    entries for the agents it still has: the observations byte for byte."""
    for k, (obs, rew, term, trunc) in enumerate(lone[1:]):
        vobs, vrew, vterm, vtrunc = vec_steps[k]
        for a in obs:
            assert vobs[a][i].tobytes() == obs[a].tobytes(), (k, a)
            assert vrew[a][i] == rew[a] and vterm[a][i] == term[a] and vtrunc[a][i] == trunc[a]


def random_actions(env, steps, seed):
    rng = np.random.default_rng(seed)
    return [{a: rng.uniform(-1, 1, (env.num_envs, 2)).astype(np.float32)
             for a in env.possible_agents} for _ in range(steps)]


def test_each_world_equals_a_lone_team_env_with_its_seed_and_actions():
    venv = TeamVectorEnv(CORRIDOR, 3, threads=2, control_hz=5.0, max_time_s=2.0)
    obs, infos = venv.reset(seed=7)
    assert list(infos["west"]["seed"]) == [7, 8, 9]
    actions = random_actions(venv, 10, 0)
    steps = [venv.step(a)[:4] for a in actions]
    for i in range(3):
        lone = lone_steps(TeamParallelEnv(CORRIDOR, control_hz=5.0, max_time_s=2.0), 7 + i,
                          [{a: x[a][i] for a in x} for x in actions])
        assert len(lone) == 11  # 2 s at 5 Hz, then every agent truncated
        for a in venv.possible_agents:
            assert obs[a][i].tobytes() == lone[0][a].tobytes()
        assert_world_equals_lone(steps, i, lone)
    assert all(steps[-1][3][a].all() for a in venv.possible_agents)


def test_worlds_autoreset_the_step_after_their_last_agent_ended(write_scenario):
    p = write_scenario(LEAD_AND_TAIL)
    venv = TeamVectorEnv(p, 2, threads=2, control_hz=5.0)
    venv.reset(seed=[3, 40])
    # World 0 drives ahead at full speed: the lead succeeds early; world 1 stands still.
    drive = {a: np.array([[1.0, 0.0], [0.0, 0.0]], np.float32) for a in venv.possible_agents}
    steps = [venv.step(drive) for _ in range(10)]
    lead_end = [k for k, s in enumerate(steps) if s[2]["lead"][0]]
    assert len(lead_end) == 1 and lead_end[0] < 9
    k = lead_end[0]
    assert steps[k][1]["lead"][0] > OUTCOME_REWARD and steps[k][4]["lead"]["outcome"][0] == "success"
    for obs, rew, term, trunc, info in steps[k + 1:]:
        # The lead ended, its world goes on: it is observed, idle, unrewarded, without flags.
        assert not info["lead"]["active"][0] and rew["lead"][0] == 0.0
        assert not term["lead"][0] and not trunc["lead"][0]
        assert info["tail"]["active"].all() and not info["tail"]["autoreset"].any()
    last = steps[-1]
    assert last[3]["tail"].all() and last[3]["lead"][1] and not last[3]["lead"][0]
    # World 0 equals a lone environment with its seed and actions, through the lead's end.
    lone_env = TeamParallelEnv(p, control_hz=5.0)
    lone = lone_steps(lone_env, 3, [{a: drive[a][0] for a in drive}] * 10)
    assert len(lone) == 11
    assert_world_equals_lone([s[:4] for s in steps], 0, lone)
    # The next step resets both worlds with the next seeds of their sequences.
    obs, rew, term, trunc, info = venv.step(drive)
    seeds = info["lead"]["seed"]
    assert info["lead"]["autoreset"].all() and list(seeds) != [3, 40]
    for a in venv.possible_agents:
        assert (rew[a] == 0).all() and not (term[a] | trunc[a]).any()
        assert not info[a]["active"].any() and (info[a]["t_s"] == 0).all()
    fresh = lone_env.reset(seed=int(seeds[0]))[0]
    for a in venv.possible_agents:
        assert obs[a][0].tobytes() == fresh[a].tobytes()
    # And the new episode goes on as a lone one started with that seed.
    obs, *_ = venv.step(drive)
    lone_obs = lone_env.step({a: drive[a][0] for a in drive})[0]
    for a in venv.possible_agents:
        assert obs[a][0].tobytes() == lone_obs[a].tobytes()


def rollout(threads):
    venv = TeamVectorEnv(CONVOY, 4, threads=threads, control_hz=5.0, max_time_s=1.0)
    out = list(venv.reset(seed=11)[0].values())
    for a in random_actions(venv, 7, 1):  # 5 steps, an autoreset, one more
        obs, rew, term, trunc, info = venv.step(a)
        for x in (obs, rew, term, trunc):
            out += list(x.values())
        out += [info[a][k] for a in info for k in ("active", "autoreset", "seed", "t_s")]
    return venv, out


def test_shapes_dtypes_and_results_the_same_whatever_the_threads():
    venv, first = rollout(1)
    assert venv.possible_agents == ["leader", "second", "third"]
    assert venv.observation_space("leader").shape == (4, OBSERVATION_SIZE)
    assert venv.single_observation_space("leader").shape == (OBSERVATION_SIZE,)
    assert venv.action_space("third").shape == (4, 2)
    obs, infos = venv.reset(seed=5)
    assert obs["second"].shape == (4, OBSERVATION_SIZE) and obs["second"].dtype == np.float32
    assert infos["second"]["seed"].dtype == np.uint64
    as_array = np.zeros((4, 3, 2), np.float32)
    obs, rew, term, trunc, info = venv.step(as_array)
    assert rew["leader"].shape == (4,) and rew["leader"].dtype == np.float64
    assert term["leader"].dtype == np.bool_ and trunc["third"].shape == (4,)
    assert info["leader"]["active"].all() and info["leader"]["outcome"] == [None] * 4
    with pytest.raises(KeyError, match="no actions for third"):
        venv.step({"leader": as_array[:, 0], "second": as_array[:, 1]})
    with pytest.raises(ValueError, match="expected shape"):
        venv.step(np.zeros((4, 2, 2), np.float32))
    for threads in (3, 3):
        _, other = rollout(threads)
        assert len(other) == len(first)
        for x, y in zip(first, other):
            assert np.asarray(x).tobytes() == np.asarray(y).tobytes()


def test_speed_of_the_vector_against_lone_envs_is_printed():
    m, steps = 8, 20
    actions = [{a: np.full((m, 2), [0.6, 0.1], np.float32) for a in ("west", "east")}] * steps
    times = {}
    for threads in (1, os.cpu_count() or 1):
        venv = TeamVectorEnv(CORRIDOR, m, threads=threads)
        venv.reset(seed=0)
        t0 = time.perf_counter()
        for a in actions:
            vobs = venv.step(a)[0]
        times[threads] = time.perf_counter() - t0
    lones = [TeamParallelEnv(CORRIDOR) for _ in range(m)]
    for i, env in enumerate(lones):
        env.reset(seed=i)
    t0 = time.perf_counter()
    for a in actions:
        last = [env.step({k: a[k][i] for k in env.agents})[0] for i, env in enumerate(lones)]
    lone_s = time.perf_counter() - t0
    vec = ", ".join(f"{t} thread{'s' if t > 1 else ''} {s:.3f} s ({lone_s / s:.2f}x)"
                    for t, s in times.items())
    print(f"\n{m} corridor worlds x {steps} steps ({steps * venv.control_period_s:.1f} s each): "
          f"{m} lone TeamParallelEnv one after another {lone_s:.3f} s; TeamVectorEnv on {vec} "
          f"({os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f})")
    for i in range(m):
        for k in ("west", "east"):
            assert vobs[k][i].tobytes() == last[i][k].tobytes()
