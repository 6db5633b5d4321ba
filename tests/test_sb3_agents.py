"""Policies of any Stable-Baselines3 or sb3-contrib algorithm in ``cof-gym evaluate`` (``sb3:PATH``,
cof_gym/agents/sb3_policy.py): the algorithm is read from the saved policy class, a recurrent policy keeps its state
through an episode and starts it afresh at each reset, and a model no algorithm of the table loads is refused in one
line before anything is simulated. Models are trained for a few dozen steps here: what is tested is the loading and
the playing, not the learning."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("stable_baselines3")
sb3_contrib = pytest.importorskip("sb3_contrib")

import gymnasium as gym  # noqa: E402
from stable_baselines3 import DQN, SAC  # noqa: E402
from stable_baselines3.common.env_util import make_vec_env  # noqa: E402
from stable_baselines3.common.vec_env import VecNormalize  # noqa: E402

import cof_gym  # noqa: E402
from cof_gym import cli  # noqa: E402
from cof_gym.agents.sb3_policy import ALGORITHMS, SB3Agent, check_model, model_algorithm  # noqa: E402

ENV_ID = cof_gym.WAGON_ENV_ID
SHORT_ENV = {"max_windows": 4}  # short episodes: a few steps of training see several resets


def _save(model, venv: VecNormalize | None, out: Path) -> Path:
    out.mkdir(parents=True)
    model.save(out / "model.zip")
    if venv is not None:
        venv.save(str(out / "vecnormalize.pkl"))
    return out


@pytest.fixture(scope="module")
def models(tmp_path_factory) -> dict[str, Path]:
    """A SAC run (a directory with its VecNormalize statistics) and a RecurrentPPO zip without statistics."""
    root = tmp_path_factory.mktemp("sb3")
    venv = VecNormalize(make_vec_env(ENV_ID, n_envs=1, seed=0, env_kwargs=SHORT_ENV), norm_reward=False)
    sac = SAC("MlpPolicy", venv, learning_starts=8, batch_size=8, seed=0, device="cpu")
    sac.learn(24)
    recurrent = sb3_contrib.RecurrentPPO("MlpLstmPolicy", make_vec_env(ENV_ID, n_envs=1, seed=0, env_kwargs=SHORT_ENV),
                                         n_steps=16, batch_size=8, n_epochs=1, seed=0, device="cpu")
    recurrent.learn(16)
    return {"sac": _save(sac, venv, root / "sac"), "recurrent": _save(recurrent, None, root / "recurrent") / "model.zip"}


def test_the_algorithm_is_read_from_the_saved_policy_class(models: dict[str, Path]) -> None:
    assert model_algorithm(models["sac"] / "model.zip") == "stable_baselines3:SAC"
    assert model_algorithm(models["recurrent"]) == "sb3_contrib:RecurrentPPO"
    assert set(ALGORITHMS.values()) >= {"stable_baselines3:PPO", "stable_baselines3:SAC", "sb3_contrib:RecurrentPPO"}
    sac = SB3Agent.load(models["sac"])
    assert sac.name == "sac" and sac.vec_normalize is not None and sac.vec_normalize.training is False
    with pytest.warns(UserWarning, match="no VecNormalize statistics"):
        recurrent = SB3Agent.load(models["recurrent"])
    assert recurrent.name == "recurrentppo"


def _actions(agent: SB3Agent, observations: list[np.ndarray]) -> list[np.ndarray]:
    agent.reset(observations[0], {})
    return [agent.act(obs, {}) for obs in observations]


def test_a_recurrent_policy_carries_its_state_and_starts_it_afresh_at_each_reset(models: dict[str, Path]) -> None:
    with pytest.warns(UserWarning):
        agent = SB3Agent.load(models["recurrent"])
    env = gym.make(ENV_ID, **SHORT_ENV)
    observations = [env.reset(seed=seed)[0] for seed in (3, 4, 5)]  # three real observations, fed in a row
    first = _actions(agent, observations)
    assert all(a.shape == (5,) and env.action_space.contains(a) for a in first)
    np.testing.assert_array_equal(np.stack(first), np.stack(_actions(agent, observations)))  # the reset restarts it
    alone = _actions(agent, observations[-1:])[0]  # the last observation without the two before it
    assert not np.array_equal(alone, first[-1]), "the LSTM state left the action unchanged"
    env.close()


def test_evaluate_plays_sb3_models_beside_the_other_agents(models: dict[str, Path], tmp_path: Path) -> None:
    out = tmp_path / "evaluate"
    with pytest.warns(UserWarning, match="no VecNormalize statistics"):  # the recurrent model was saved without them
        code = cli.main(["evaluate", "--agents", f"staircase,sb3:{models['sac']},sb3:{models['recurrent']}",
                         "--episodes", "2", "--env-kwargs", "max_windows:4", "--out", str(out), "--quiet"])
    assert code == 0
    with open(out / "episodes.csv") as f:
        rows = list(csv.DictReader(f))
    assert {r["agent"] for r in rows} == {"staircase", "sac:sac", "recurrentppo:model"}  # the algorithm names it
    assert all(np.isfinite(float(r["relative_error"])) for r in rows if r["scored"] == "True")


def test_a_model_no_algorithm_of_the_table_loads_is_one_line_exit_2(tmp_path: Path, capsys) -> None:
    dqn = DQN("MlpPolicy", gym.make("CartPole-v1"), learning_starts=0, device="cpu")
    dqn.save(tmp_path / "dqn.zip")
    with pytest.raises(ValueError, match="policy class .*DQNPolicy.* none of the algorithms"):
        check_model(tmp_path / "dqn.zip")
    assert cli.main(["evaluate", "--agents", f"sb3:{tmp_path / 'dqn.zip'}", "--out", str(tmp_path / "e")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "--agents" in err and "DQNPolicy" in err and not (tmp_path / "e").exists()


def test_sb3_needs_a_path(capsys, tmp_path: Path, monkeypatch) -> None:
    monkeypatch.chdir(tmp_path)  # a relative --out, as a user types it: nothing written here
    assert cli.main(["evaluate", "--agents", "sb3", "--out", "never"]) == 2
    assert "sb3:PATH needs a value" in capsys.readouterr().err
    assert not Path("never").exists()


def test_rl_zoo_records_are_read_without_running_what_they_name(models: dict[str, Path], tmp_path: Path) -> None:
    """RL Zoo's layout (``<run>/<env>.zip``, ``<run>/<env>/args.yml``): the env id and kwargs come from its YAML, read
    by a safe loader (an OrderedDict becomes a dict; any other Python tag None, never called); a record that is no
    mapping is refused naming the file."""
    from cof_gym.agents.sb3_policy import resolve_model_path, zoo_training

    run = tmp_path / "run"
    (run / "Env").mkdir(parents=True)
    (run / "Env.zip").write_bytes((models["sac"] / "model.zip").read_bytes())
    marker = tmp_path / "ran"
    (run / "Env" / "args.yml").write_text(
        "!!python/object/apply:collections.OrderedDict\n- - - env\n    - CofGym/TorqueInterrogation-v2\n"
        f"  - - env_kwargs\n    - max_windows: 4\n  - - hook\n    - !!python/object/apply:os.system ['touch {marker}']\n")
    assert resolve_model_path(run) == run / "Env.zip"
    assert zoo_training(run / "Env.zip") == {"env_id": ENV_ID, "env_kwargs": {"max_windows": 4}}
    assert not marker.exists()
    check_model(run / "Env.zip")
    (run / "best_model.zip").write_bytes((run / "Env.zip").read_bytes())  # RL Zoo's best model, beside the run's
    assert zoo_training(run / "best_model.zip") == zoo_training(run / "Env.zip")
    (run / "Env" / "config.yml").write_text("- a list\n")
    with pytest.raises(ValueError, match="config.yml holds list"):
        check_model(run / "Env.zip")


@pytest.mark.skipif(__import__("os").environ.get("COF_GYM_SKIP_ZOO") == "1", reason="COF_GYM_SKIP_ZOO=1")
@pytest.mark.parametrize("algo,short", [("sac", ["learning_starts:32"]),
                                        ("ppo_lstm", ["n_steps:32", "batch_size:32", "n_epochs:1"])])
def test_rl_zoo_trains_the_v2_wagon_with_the_shipped_starting_points_and_evaluate_plays_the_run(
        algo: str, short: list[str], tmp_path: Path) -> None:
    """cof_gym/agents/hyperparams/{sac,ppo_lstm}.yml through RL Zoo's own entry point (128 steps: the files run, nothing
    is learnt), then the run directory in cof-gym evaluate (``sb3:RUN``: the history observation of sac.yml applied on
    the agent's side, the LSTM state of ppo_lstm carried)."""
    import subprocess
    import sys

    pytest.importorskip("rl_zoo3")
    root = Path(__file__).resolve().parents[1]
    cmd = [sys.executable, "-m", "rl_zoo3.train", "--algo", algo, "--env", ENV_ID, "--gym-packages", "cof_gym",
           "--conf-file", str(root / "cof_gym/agents/hyperparams" / f"{algo}.yml"), "-n", "128", "--eval-freq", "-1",
           "--seed", "0", "--log-folder", str(tmp_path / "logs"), "--device", "cpu", "--hyperparams", *short]
    done = subprocess.run(cmd, cwd=root, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    run = tmp_path / "logs" / algo / "CofGym-TorqueInterrogation-v2_1"
    out = tmp_path / "evaluate"
    assert cli.main(["evaluate", "--agents", f"sb3:{run}", "--episodes", "1", "--out", str(out), "--quiet"]) == 0
    with open(out / "episodes.csv") as f:
        (row,) = list(csv.DictReader(f))
    assert row["agent"] == {"sac": "sac", "ppo_lstm": "recurrentppo"}[algo] + ":CofGym-TorqueInterrogation-v2_1"
