"""The command line: every usage error is one line on stderr naming the flag, exit status 2, no
traceback, and nothing created; evaluate writes complete outputs only, and --help shows defaults."""

from __future__ import annotations

import csv
import functools
import io
import json
import re
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

import pytest

from cof_gym import cli

SUITE_FILES = {
    "bad_json.json": "{not json",
    "list.json": "[1, 2]",
    "string_cof.json": json.dumps({"options": {"cof": "0.3"}}),
    "unknown_key.json": json.dumps({"episodes": [{"seed": 1, "opts": {}}]}),
    "empty_episodes.json": json.dumps({"episodes": []}),
    "negative_seed.json": json.dumps({"episodes": [{"seed": -1}]}),
    "string_bool.json": json.dumps({"env_kwargs": {"counter_torque": "false"}}),
    "options_list.json": json.dumps({"options": ["cof", 0.3]}),
    "unknown_option.json": json.dumps({"options": {"friction": 0.3}}),
    "bad_env_id.json": json.dumps({"env_id": "CofGym/NoSuchEnv-v9"}),
    "cartpole.json": json.dumps({"env_id": "CartPole-v1"}),  # registered, but not a cof_gym env
    "too_many_episodes.json": json.dumps({"episodes": [{}] * 100_001}),
    "table_not_increasing.json": json.dumps({"options": {"creep_law": {"table": {
        "creepage": [0.0, 0.01, 0.005, 0.02], "adhesion_ratio": [0.0, 0.5, 1.0, 0.9]}}}}),
    "polach_missing.json": json.dumps({"options": {"creep_law": {"polach": {"k_adhesion": 1.0}}}}),
    "speed_error_too_large.json": json.dumps({"options": {"speed_sensor_error": 0.5}}),
    # env_kwargs that change the interface the agents act through, or cut episodes before the task scores them
    "relative_actions.json": json.dumps({"env_kwargs": {"action_type": "relative"}}),
    "short_time_limit.json": json.dumps({"env_kwargs": {"max_episode_steps": 3}}),
    "multitone.json": json.dumps({"env_kwargs": {"excitation": "multitone"}}),
    "flat_info.json": json.dumps({"env_kwargs": {"info_layout": "flat"}}),
    "deep_nesting.json": "[" * 100_000 + "]" * 100_000,
    # the id's own arguments: a suite names the id, so that its outputs' env_id says what was played
    "vehicle_of_its_own.json": json.dumps({"env_kwargs": {"vehicle": "half_wheelset"}}),
    "task_version_of_its_own.json": json.dumps({"env_kwargs": {"task_version": 1}}),
    "float_time_limit.json": json.dumps({"env_kwargs": {"max_episode_steps": 1.5}}),
    "zero_horizon.json": json.dumps({"env_kwargs": {"max_windows": 0}}),
    "unknown_env_kwarg.json": json.dumps({"env_kwargs": {"horizon": 60}}),  # max_windows is the horizon
    # episode 1 asks the half wheelset for a load case it lacks: only its env's reset can tell
    "empty_half_wheelset.json": json.dumps({"env_id": "CofGym/HalfWheelset-v2",
                                            "episodes": [{}, {"options": {"load_case": "empty"}}]}),
}
SHIPPED = str(Path(cli.__file__).parent / "agents" / "policies" / "ppo_wagon")  # observation (38,)
# model directories beside the shipped model.zip (a link) whose statistics or train_meta.json are broken
BROKEN_MODELS = ("bad_stats", "other_stats", "bad_meta")

# (argv, a fragment the one-line message must contain)
BAD = [
    (["evaluate", "--agents", "staircase", "--suite", "table_not_increasing.json"], "creep_law.table.creepage"),
    (["evaluate", "--agents", "staircase", "--suite", "polach_missing.json"], "creep_law.polach.k_slip"),
    (["evaluate", "--agents", "staircase", "--suite", "speed_error_too_large.json"], "speed_sensor_error"),
    (["evaluate", "--agents", "staircase", "--suite", "relative_actions.json"],
     "env_kwargs.action_type must be 'absolute' (the evaluated agents act through it), got 'relative'"),
    (["evaluate", "--agents", "staircase", "--suite", "short_time_limit.json"],
     "env_kwargs.max_episode_steps must be -1 (no TimeLimit) or at least the task's horizon max_windows=30"),
    (["evaluate", "--agents", "staircase", "--suite", "multitone.json"], "env_kwargs.excitation must be 'sine'"),
    (["evaluate", "--agents", "staircase", "--suite", "flat_info.json"], "env_kwargs.info_layout must be 'nested'"),
    (["evaluate", "--agents", "staircase", "--suite", "deep_nesting.json"], "deep_nesting.json: JSON nested too deeply"),
    # the same agent under two names: staircase is registered with the crest ceiling (the pair played it twice)
    (["evaluate", "--agents", "staircase,staircase+ceiling"], "'staircase' and 'staircase+ceiling' are the same"),
    (["evaluate", "--agents", "oracle,oracle+plain"], "agents 'oracle' and 'oracle+plain' are the same agent"),
    (["evaluate", "--agents", "staircase", "--env-kwargs", "max_windows:0"], "--env-kwargs: max_windows must be an integer in [1"),
    (["evaluate", "--agents", "staircase", "--env-kwargs", "max_windows:True"], "--env-kwargs: max_windows must be an integer"),
    (["evaluate", "--agents", "staircase", "--env-kwargs", "cof:0.2", "cof:0.3"], "--env-kwargs: 'cof' given twice"),
    (["evaluate", "--agents", "staircase", "--env-kwargs", "render_mode:human"], "env_kwargs.render_mode must be None"),
    (["evaluate", "--agents", "staircase", "--env-kwargs", "horizon:60"], "--env-kwargs: unknown env argument(s) ['horizon']"),
    (["evaluate", "--agents", "staircase", "--env-kwargs", "excitation:multitone"], "--env-kwargs: env_kwargs.excitation must"),
    (["evaluate", "--agents", "staircase", "--env-kwargs", "max_episode_steps:5"], "env_kwargs.max_episode_steps must"),
    (["evaluate", "--agents", "staircase", "--env-kwargs", "noise_level:5"], "--env-kwargs: noise_level must be a finite"),
    (["evaluate", "--agents", "staircase", "--env-kwargs", "max_windows"], "--env-kwargs expects key:value pairs"),
    # two pairs joined by a comma, as --agents joins its names: the second pair named, not read as the first's value
    (["evaluate", "--agents", "staircase", "--env-kwargs", "speed_sensor_error:0.04,encoder_lag_s:0.02"],
     "--env-kwargs: 'speed_sensor_error:0.04,encoder_lag_s:0.02' joins several pairs with a comma; separate"),
    (["train", "--out", "run", "--hyperparams", "n_steps:64, batch_size:32"], "--hyperparams: 'n_steps:64, batch_size"),
    (["evaluate", "--agents", "staircase", "--env-kwargs", "cof:0.2", "--env-kwargs", "cof:0.3"],
     "--env-kwargs: 'cof' given twice"),  # a second flag would have replaced the first's value
    (["evaluate", "--agents", "staircase", "--env-kwargs", "max_episode_steps:-5"], "max_episode_steps must be -1"),
    (["evaluate", "--agents", "staircase", "--env-kwargs", "max_episode_steps:1.5"],
     "env_kwargs.max_episode_steps must be an integer (-1: no TimeLimit), got 1.5"),
    (["evaluate", "--agents", "staircase", "--env-kwargs", "vehicle:half_wheelset"],
     "env_kwargs.vehicle is the env id's own"),  # as train and a suite file say it (check_env_kwargs)
    (["evaluate", "--agents", "staircase", "--env", "CartPole-v1"],
     "--env: 'CartPole-v1' is no cof_gym env id; allowed:"),
    (["evaluate", "--agents", "staircase", "--suite", "paper", "--env", "CofGym/HalfWheelset-v2"],
     "--env: counter_torque=True needs the wagon"),  # the paper's counter torque: refused before any episode
    (["evaluate", "--agents", "staircase", "--paired", "staircase"],
     "--paired: compares every other agent with 'staircase', and --agents plays no other"),
    (["evaluate", "--agents", "staircase", "--suite", "vehicle_of_its_own.json"],
     "env_kwargs.vehicle is the env id's own (CofGym/TorqueInterrogation-v2 is made with vehicle='wagon')"),
    (["evaluate", "--agents", "staircase", "--suite", "task_version_of_its_own.json"],
     "env_kwargs.task_version is the env id's own"),
    (["evaluate", "--agents", "staircase", "--suite", "unknown_env_kwarg.json"],
     "unknown_env_kwarg.json: unknown env argument(s) ['horizon']; allowed: ['action_type',"),
    (["evaluate", "--agents", "staircase", "--suite", "empty_half_wheelset.json"], "episode 1 (options"),
    # watch checks a suite's env arguments and its episode as evaluate does, before anything is simulated
    (["watch", "--suite", "zero_horizon.json", "--out", "e.gif"],
     "--suite: zero_horizon.json: env_kwargs {'max_windows': 0}: max_windows must be an integer in [1"),
    (["watch", "--suite", "vehicle_of_its_own.json", "--out", "e.gif"], "env_kwargs.vehicle is the env id's own"),
    (["watch", "--suite", "float_time_limit.json", "--out", "e.gif"], "max_episode_steps must be an integer"),
    (["watch", "--suite", "empty_half_wheelset.json", "--episode", "1", "--out", "e.gif"],
     "empty_half_wheelset.json: episode 1 (options {'load_case': 'empty'}): load_case must be one of ['laden']"),
    (["watch", "--speed", "0", "--out", "e.gif"], "--speed: must be a finite number in [0.05, 10]"),
    (["evaluate", "--agents", "nonexistent"], "--agents"),
    (["evaluate", "--agents", "staircase-paper,staircase,pp0"], "pp0"),
    (["evaluate", "--agents", "staircase,,staircase-paper"], "--agents"),
    (["evaluate", "--agents", "staircase,staircase"], "twice"),
    (["evaluate", "--agents", "staircase,phase-rule", "--paired", "oracle"], "--paired: 'oracle' is none"),
    (["evaluate", "--agents", "staircase", "staircase"], "twice"),
    (["evaluate", "--agents", "staircase", "pp0"], "pp0"),
    (["evaluate", "--agents"], "--agents: expected at least one argument"),
    (["evaluate", "--agents", "staircase:x"], "--agents"),
    (["evaluate", "--agents", "ppo:/no/such/model.zip"], "/no/such/model"),
    (["evaluate", "--episodes", "0"], "--episodes"),
    (["evaluate", "--episodes", "many"], "--episodes"),
    (["evaluate", "--episodes", "1000000000"], "--episodes"),
    (["evaluate", "--workers", "0"], "--workers"),
    (["evaluate", "--workers", "two"], "--workers"),
    (["evaluate", "--agents", "ppo:not_a_model.zip"], "not a Stable-Baselines3 model"),
    (["evaluate", "--agents", "ppo:corrupt.zip"], "corrupt.zip"),
    (["evaluate", "--agents", "staircase", "--out", "/proc/cof_gym_out"], "--out"),
    (["evaluate", "--seed", "-1"], "--seed"),
    (["evaluate", "--seed", str(2**63)], "must be an integer in [0, 9223372036854775807]"),  # one bound, args.MAX_SEED
    (["evaluate", "--seed", str(2**63 - 1), "--episodes", "2"], "the last episode's seed 9223372036854775808"),
    (["watch", "--seed", str(2**63), "--out", "e.gif"], "--seed"),  # the seed of the episode evaluate plays
    (["train", "--out", "run", "--seed", str(2**32)], "must be an integer in [0, 4294967295]"),  # numpy's legacy seeding
    (["evaluate", "--suite", "/no/such/file.json"], "no such suite file"),
    (["evaluate", "--suite", "nonsense"], "--suite"),
    *[(["evaluate", "--suite", name, "--agents", "staircase"], name) for name in SUITE_FILES],
    (["evaluate", "--agents", "staircase", "--out", "a_file.txt"], "--out"),
    (["evaluate", "--agents", "staircase", "--out", "a_file.txt/sub"], "--out"),
    (["evaluate", "--agents", "staircase", "--out", "."], "--out"),
    (["evaluate", "--agents", "staircase", "--out", "not_an_output"], "not a cof-gym evaluate output"),
    (["evaluate", "--no-such-flag"], "cof-gym evaluate: error: unrecognized arguments: --no-such-flag"),
    (["bench", "--seconds", "0"], "--seconds"),
    (["bench", "--seconds", "nan"], "--seconds"),
    (["bench", "--seconds", "1e-300"], "must be a finite number in [0.01, 3600]"),  # no physics step: ZeroDivisionError
    (["bench", "--seconds", "1e9"], "must be a finite number in [0.01, 3600]"),  # MuJoCo's int step count overflows
    (["bench", "--seconds", "0.02", "--markdown", "."], ". is a directory; give a file"),  # refused before the benchmark
    (["bench", "--seconds", "0.02", "--markdown", "a_file.txt/speed.md"], "a_file.txt is a file, not a directory"),
    (["train", "--out", "run", "--timesteps", "0"], "--timesteps"),
    (["train", "--out", "run", "--env", "CofGym/Nope-v0"], "--env"),
    (["train", "--out", "run", "--resume", "/no/such/model.zip"], "--resume"),
    (["train", "--out", "run", "--env-kwargs", "counter_torque:false"], "counter_torque"),
    (["train", "--out", "run", "--env-kwargs", "max_episode_steps:2"], "max_episode_steps must be -1"),  # unscored
    (["train", "--out", "run", "--env-kwargs", "vehicle:half_wheelset"], "env_kwargs.vehicle is the env id's own"),
    # named in our words, as evaluate names it (gymnasium's message quoted every kwarg the creator got)
    (["train", "--out", "run", "--env-kwargs", "nosuch:1"],
     "--env-kwargs: CofGym/TorqueInterrogation-v2: unknown env argument(s) ['nosuch']; allowed: ['action_type',"),
    (["train", "--out", "run", "--env-kwargs", "cof:0.2", "--env-kwargs", "cof:0.3"], "'cof' given twice"),
    # a policy_kwargs / normalize expression that raises whatever it raises: one line naming the key
    (["train", "--out", "run", "--timesteps", "10", "--hyperparams", "policy_kwargs:dict(activation_fn=nn.Relu)"],
     "policy_kwargs: 'dict(activation_fn=nn.Relu)' does not evaluate (AttributeError"),
    # a width 0 trained a network that learns nothing; -1 was torch's "negative dimension"
    (["train", "--out", "run", "--timesteps", "10", "--hyperparams", "policy_kwargs:dict(net_arch=[0])"],
     "policy_kwargs.net_arch must be a list of layer widths (integers >= 1)"),
    (["train", "--out", "run", "--timesteps", "10", "--hyperparams",
      "policy_kwargs:dict(net_arch=dict(pi=[8], vf=[-1]))"], "policy_kwargs.net_arch must be a list of layer widths"),
    (["train", "--out", "run", "--timesteps", "10", "--resume", ""], "--resume: an empty path"),  # was ignored
    (["train", "--out", "run", "--timesteps", "10", "--hyperparams", "normalize:1/0"],
     "normalize: '1/0' does not evaluate (ZeroDivisionError"),
    (["train", "--out", "run", "--timesteps", "10", "--hyperparams", "normalize:abc"],
     "normalize: 'abc' does not evaluate (NameError"),
    (["train", "--out", "run", "--timesteps", "10", "--hyperparams", "batch_size:1"],
     "batch_size must be an integer in [2,"),
    (["train", "--out", "run", "--n-envs", "100000"], "--n-envs: must be an integer in [1, 256]"),
    (["train", "--out", "run", "--timesteps", "10", "--hyperparams", "learning_rate:1e9"], "learning_rate must be"),
    (["train", "--out", "run", "--timesteps", "10", "--hyperparams", "learning_rate:true"], "learning_rate: expected a number"),
    (["train", "--out", "run", "--hyperparams", "no_such_hyperparameter:1"], "--hyperparams"),
    (["train", "--out", "run", "--conf-file", "/no/such.yml"], "--conf-file"),
    (["train", "--out", "run", "--conf-file", "a_file.txt"], "a_file.txt: not an RL Zoo hyperparameter file"),
    (["train", "--out", "a_file.txt"], "--out"),
    (["train", "--out", "run", "--n-envs", "-2"], "--n-envs"),
    (["train", "--out", "run", "--hyperparams", "n_steps:0", "--timesteps", "100"], "n_steps"),
    (["train", "--out", "run", "--hyperparams", "gamma:1.5", "--timesteps", "100"], "gamma"),
    (["train", "--out", "run", "--resume", SHIPPED, "--env-kwargs", "observation_type:'window'"], "--env-kwargs"),
    (["train", "--out", "run", "--resume", "corrupt.zip"], "--resume"),
    (["train", "--out", "run", "--resume", "not_a_model.zip"], "--resume"),
    (["train", "--out", "/proc/cof_gym_run"], "--out"),
    # PPO arguments the command sets itself: refused before anything is written
    *[(["train", "--out", "run", "--timesteps", "10", "--n-envs", "1", "--hyperparams", f"{key}:{value}"],
       f"--hyperparams: '{key}' is set by cof-gym train itself")
      for key, value in (("seed", "3"), ("verbose", "1"), ("tensorboard_log", "'tb'"), ("_init_setup_model", "False"),
                         ("device", "'cpu'"))],
    # values that passed the check, then failed in training or became something else
    (["train", "--out", "run", "--timesteps", "10", "--hyperparams", "n_epochs:2.5"], "n_epochs must be an integer"),
    (["train", "--out", "run", "--timesteps", "10", "--hyperparams", "batch_size:2.5"], "batch_size must be an integer"),
    (["train", "--out", "run", "--timesteps", "10", "--hyperparams", "n_steps:True"], "n_steps must be an integer"),
    (["train", "--out", "run", "--timesteps", "10", "--pretrain-noise", "5"], "--pretrain-noise: must be a finite"),
    (["train", "--out", "run", "--timesteps", "10", "--pretrain-noise", "0.3"], "has no effect without --pretrain-ep"),
    (["train", "--out", "run", "--timesteps", "10", "--pretrain-agent", "staircase"], "--pretrain-agent: has no eff"),
    (["train", "--out", "run", "--timesteps", "10", "--hyperparams", "use_sde:1"], "use_sde must be a bool (True or False), got 1"),
    (["train", "--out", "run", "--timesteps", "10", "--hyperparams", "normalize_advantage:'no'"],
     "normalize_advantage must be a bool (True or False)"),
    (["train", "--out", "run", "--timesteps", "10", "--hyperparams", "n_envs:2.7"], "n_envs must be an integer in [1, 256]"),
    (["train", "--out", "run", "--timesteps", "10", "--hyperparams", "normalize:5"], "normalize must be True, False"),
    (["train", "--out", "run", "--timesteps", "10", "--hyperparams", "normalize:dict(foo=1)"], "['foo']"),
    (["train", "--out", "run", "--timesteps", "10", "--hyperparams", "normalize:dict(clip_obs=-1)"],
     "normalize.clip_obs must be a finite number in (0, 1e+12]"),
    (["train", "--out", "run", "--timesteps", "10", "--hyperparams", "normalize:dict(norm_obs=1)"], "normalize.norm_obs"),
    (["train", "--out", "run", "--timesteps", "10", "--hyperparams", "clip_range:lin_-0.1"], "clip_range (the start of"),
    (["train", "--out", "run", "--timesteps", "10", "--device", "meta"], "--device: must be auto, cpu, cuda or cuda:N"),
    (["train", "--out", "run", "--timesteps", "10", "--device", "mkldnn"], "--device"),
    (["train", "--out", "run", "--timesteps", "10", "--device", "cuda:x"], "--device"),
    (["train", "--out", "run", "--torch-threads", "100000000000"], "must be an integer in [0, 1024]"),
    (["train", "--out", "not_an_output", "--timesteps", "10"], "not a cof-gym train output"),
    (["train", "--out", "run", "--resume", "bad_meta"], "--resume: bad_meta/train_meta.json cannot be read"),
    # broken VecNormalize statistics beside a valid model: one line naming the file, from each command
    *[(argv, f"{name}/vecnormalize.pkl is not usable VecNormalize statistics")
      for name in ("bad_stats", "other_stats")
      for argv in (["train", "--out", "run", "--timesteps", "10", "--resume", name],
                   ["evaluate", "--agents", f"ppo:{name}", "--episodes", "1"],
                   ["watch", "--agent", f"ppo:{name}", "--out", "a.gif"])],
    (["watch", "--agent", "ppo:bad_policy.zip", "--out", "a.gif"], "bad_policy.zip is not a readable"),
    (["evaluate", "--agents", "ppo:bad_meta", "--episodes", "1"], "bad_meta/train_meta.json"),
    (["reproduce-paper", "--quick", "--readme", "docs_is_a_file/README.md"], "docs exists and is not a directory"),
    (["reproduce-paper", "--quick", "--readme", "/nonexistent/README.md"], "--readme"),
    (["reproduce-paper", "--quick", "--readme", "a_file.txt"], "markers"),
    (["reproduce-paper", "--quick", "--readme", ""], "--readme: an empty path"),
    (["reproduce-paper", "--quick", "--out", "/proc/cof_gym_paper"], "--out"),
    (["reproduce-paper", "--quick", "--out", "docs_is_a_file"],
     "docs_is_a_file exists and is not a cof-gym reproduce-paper output (no results.json)"),
    (["train"], "--out"),
    ([], "COMMAND"),
    (["no-such-command"], "no-such-command"),
]


@functools.lru_cache(maxsize=None)
def _broken_bytes() -> dict[str, bytes]:
    """Statistics for another observation shape (4,), and the shipped zip with a garbage policy.pth."""
    import gymnasium as gym
    from stable_baselines3.common.vec_env import DummyVecEnv, VecNormalize

    with tempfile.TemporaryDirectory() as tmp:
        stats = Path(tmp) / "vecnormalize.pkl"
        VecNormalize(DummyVecEnv([lambda: gym.make("CartPole-v1")])).save(str(stats))
        other = stats.read_bytes()
        buffer = io.BytesIO()
        with zipfile.ZipFile(Path(SHIPPED) / "model.zip") as z, zipfile.ZipFile(buffer, "w") as w:
            for name in z.namelist():
                w.writestr(name, b"garbage" if name == "policy.pth" else z.read(name))
    return {"other_stats": other, "bad_policy": buffer.getvalue()}


@pytest.fixture()
def workdir(tmp_path: Path, monkeypatch) -> Path:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "a_file.txt").write_text("not a directory\n")
    (tmp_path / "not_an_output").mkdir()
    (tmp_path / "not_an_output" / "notes.txt").write_text("mine\n")
    for name, text in SUITE_FILES.items():
        (tmp_path / name).write_text(text)
    with zipfile.ZipFile(tmp_path / "not_a_model.zip", "w") as z:  # a valid zip, not a model
        z.writestr("notes.txt", "not a model\n")
    (tmp_path / "corrupt.zip").write_bytes(b"PK\x03\x04" + b"\x00garbage" * 8)
    for name in BROKEN_MODELS:
        (tmp_path / name).mkdir()
        (tmp_path / name / "model.zip").symlink_to(Path(SHIPPED) / "model.zip")
    (tmp_path / "bad_stats" / "vecnormalize.pkl").write_bytes(b"garbage\n")
    (tmp_path / "other_stats" / "vecnormalize.pkl").write_bytes(_broken_bytes()["other_stats"])
    (tmp_path / "bad_meta" / "vecnormalize.pkl").symlink_to(Path(SHIPPED) / "vecnormalize.pkl")
    (tmp_path / "bad_meta" / "train_meta.json").write_text("{not json")
    (tmp_path / "bad_policy.zip").write_bytes(_broken_bytes()["bad_policy"])
    (tmp_path / "docs_is_a_file").mkdir()
    (tmp_path / "docs_is_a_file" / "README.md").write_text("# x\n<!-- reproduce-paper:begin -->\n"
                                                          "<!-- reproduce-paper:end -->\n")
    (tmp_path / "docs_is_a_file" / "docs").write_text("a file where the figures' directory should be\n")
    return tmp_path


def _tree(root: Path) -> dict[str, float]:
    return {str(p.relative_to(root)): p.stat().st_mtime for p in root.rglob("*")}


@pytest.mark.parametrize("argv,fragment", BAD, ids=[" ".join(a) or "(none)" for a, _ in BAD])
def test_usage_errors_are_one_line_exit_2_and_create_nothing(argv, fragment, workdir: Path, capsys) -> None:
    before = _tree(workdir)
    try:
        code = cli.main(argv)
    except SystemExit as e:  # argparse's own errors
        code = e.code
    captured = capsys.readouterr()
    err = captured.err.strip()
    assert code == 2, (argv, captured)
    assert err and "\n" not in err, err
    assert "Traceback" not in captured.err and "Traceback" not in captured.out
    assert err.startswith("cof-gym") and "error:" in err and fragment in err, err
    assert _tree(workdir) == before, "a usage error created or changed files"
    assert not Path("out").exists()


def test_bench_writes_its_markdown_table_into_a_new_folder(tmp_path: Path, monkeypatch, capsys) -> None:
    monkeypatch.chdir(tmp_path)
    cli.main(["bench", "--seconds", "0.01", "--markdown", "new/speed.md"])  # the folder is made, as --out's are
    table = (tmp_path / "new" / "speed.md").read_text()
    assert table.startswith("# cof-gym bench") and "| ratio native / bare" in table
    for row in ("high vertical irregularity / level track", "pulse encoder read by the rotation lock-in / continuous"):
        line = next(line for line in table.splitlines() if row in line)
        assert 0.0 < float(line.split("|")[2]) < 10.0  # a ratio of two rates that were measured
    assert "ratio native / bare" in capsys.readouterr().out


def test_a_usage_error_in_a_subprocess(tmp_path: Path) -> None:
    proc = subprocess.run([sys.executable, "-m", "cof_gym.cli", "evaluate", "--agents", "staircase,pp0"],
                          cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and "pp0" in proc.stderr and "Traceback" not in proc.stderr
    assert list(tmp_path.iterdir()) == []


def test_help_shows_defaults_and_every_flag_has_help(capsys) -> None:
    parser = cli.build_parser()
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    assert set(sub.choices) >= {"evaluate", "train", "bench", "reproduce-paper"}
    for name, p in sub.choices.items():
        for action in p._actions:
            if action.option_strings and action.dest != "help":
                assert action.help, f"{name} {action.option_strings} has no help"
    with pytest.raises(SystemExit):
        cli.main(["evaluate", "--help"])
    text = capsys.readouterr().out
    assert "(default: 60)" in text and "(default: default)" in text
    assert re.search(r"--seed SEED\s+seed of the first episode .*?\(default: 0\)", text, re.S)  # 0 is no False
    assert "``" not in (parser.description or "") and ":class:" not in (parser.description or "")


def test_help_shows_a_default_as_it_is_typed(monkeypatch, tmp_path: Path) -> None:
    from cof_gym.commands.args import Parser

    monkeypatch.chdir(tmp_path)
    parser = Parser(prog="x")
    parser.add_argument("--policy", type=Path, nargs="+", default=[tmp_path / "runs" / "a", Path("/elsewhere")],
                        help="policies")
    parser.add_argument("--set", nargs="*", default=[], help="overrides")
    parser.add_argument("--kwargs", nargs="*", default={}, help="arguments")
    parser.add_argument("--share", type=float, default=0.5, help="a share in %% of the total")
    text = " ".join(parser.format_help().split())
    assert "policies (default: runs/a /elsewhere)" in text
    assert "overrides" in text and "overrides (default" not in text  # an empty list is no default worth showing
    assert "arguments" in text and "arguments (default" not in text  # nor an empty dict
    assert "a share in % of the total (default: 0.5)" in text


def test_evaluate_env_arguments_play_the_suite_in_that_env_and_name_the_output(workdir: Path) -> None:
    from cof_gym.commands.evaluate import default_out

    assert cli.main(["evaluate", "--agents", "staircase", "--episodes", "2", "--env-kwargs", "max_windows:3",
                     "counter_torque:True", "--windows", "--quiet"]) == 0
    out = workdir / "out" / "evaluate-max_windows=3-counter_torque=true"  # never the default suite's out/evaluate
    result = json.loads((out / "summary.json").read_text())
    assert result["env_kwargs"] == {"max_windows": 3, "counter_torque": True}
    assert result["suite"] == "default (env max_windows=3 counter_torque=true)"
    assert "suite default (env max_windows=3 counter_torque=true)" in (out / "summary.md").read_text()
    assert all(int(r["steps"]) <= 3 for r in csv.DictReader(open(out / "episodes.csv")))
    steps = sum(int(r["steps"]) for r in csv.DictReader(open(out / "episodes.csv")))
    assert len(list(csv.DictReader(open(out / "windows.csv")))) == steps  # --windows: a row a step
    assert not (workdir / "out" / "evaluate").exists()
    assert default_out("experiments/suites/x.json", {"creep_law": {"table": [1]}}) == Path(
        "out/evaluate-x-creep_law=__table____1__")


def test_evaluate_on_another_env_plays_the_suite_there_and_names_the_output(workdir: Path) -> None:
    """``--env``: the default suite's seeds on task v3, its outputs saying so and apart from the default suite's."""
    in_service = "CofGym/TorqueInterrogationInService-v3"
    assert cli.main(["evaluate", "--agents", "staircase", "--episodes", "1", "--env", in_service, "--env-kwargs",
                     "max_windows:2", "--quiet"]) == 0
    out = workdir / "out" / "evaluate-env=_CofGym_TorqueInterrogationInService-v3_-max_windows=2"
    result = json.loads((out / "summary.json").read_text())
    assert result["env_id"] == in_service and result["suite"] == f"default (on {in_service}) (env max_windows=2)"
    assert not (workdir / "out" / "evaluate-max_windows=2").exists()


def test_evaluate_takes_its_agents_comma_or_space_separated() -> None:
    """``--agents a,b``, ``--agents a b`` and a mix name the same agents, in the order given."""
    from cof_gym.commands.evaluate import prepare

    parser = cli.build_parser()
    chosen = [prepare(parser.parse_args(["evaluate", "--agents", *given]))[0]
              for given in (["staircase,phase-rule,oracle"], ["staircase", "phase-rule", "oracle"],
                            ["staircase,phase-rule", "oracle"])]
    assert chosen == [["staircase", "phase-rule", "oracle"]] * 3


def test_evaluate_writes_complete_outputs_and_replaces_its_own(workdir: Path, capsys) -> None:
    suite = workdir / "suite.json"
    suite.write_text(json.dumps({"options": {"condition": "dry", "cof": 0.3}}))
    assert cli.main(["evaluate", "--agents", "staircase", "--episodes", "2", "--suite", str(suite), "--quiet"]) == 0
    out = workdir / "out" / "evaluate-suite"  # not out/evaluate: suites never overwrite each other
    names = sorted(p.name for p in out.iterdir())
    assert names == sorted(["episodes.csv", "summary.md", "summary.json", "error_per_cof.png",
                            "error_vs_discomfort.png", "error_vs_peak_torque.png", "episode_traces.png", "error_vs_creepage_error.png"])
    first = (out / "summary.json").read_text()
    assert cli.main(["evaluate", "--agents", "staircase", "--episodes", "2", "--suite", str(suite), "--quiet",
                     "--seed", "1"]) == 0
    assert (out / "summary.json").read_text() != first
    assert not [p for p in (workdir / "out").iterdir() if p.name.startswith(".")]  # no staging left behind


def test_evaluate_pairs_every_agent_with_the_one_named_over_the_same_episodes(workdir: Path) -> None:
    """``--paired A``: each other agent's differences against A are those of the episodes both played (the point
    values recomputed from episodes.csv), in summary.json and summary.md; without it neither has a paired part."""
    import csv

    import numpy as np

    run = ["evaluate", "--agents", "staircase,staircase-zeroed,phase-rule", "--episodes", "6", "--quiet"]
    assert cli.main([*run, "--paired", "staircase", "--out", "paired"]) == 0
    paired = json.loads((workdir / "paired" / "summary.json").read_text())["paired"]
    assert paired["baseline"] == "staircase" and list(paired["agents"]) == ["staircase-zeroed", "phase-rule"]
    with open(workdir / "paired" / "episodes.csv") as f:
        rows = list(csv.DictReader(f))
    column = lambda agent, key: np.array([float(r[key]) for r in rows if r["agent"] == agent])  # noqa: E731
    base = column("staircase", "relative_error")
    for agent, entry in paired["agents"].items():
        other = column(agent, "relative_error")
        assert entry["median"][0] == pytest.approx(100 * (np.median(other) - np.median(base)), abs=1e-9)
        assert entry["lower_error"][0] == pytest.approx(100 * np.mean((other < base) + 0.5 * (other == base)))
        assert entry["median"][1] <= entry["median"][0] <= entry["median"][2]
        slips = [sum(r["macro_slip"] == "True" for r in rows if r["agent"] == a) for a in ("staircase", agent)]
        assert entry["macro_slips"] == slips
    assert "## Paired against staircase" in (workdir / "paired" / "summary.md").read_text()
    assert cli.main([*run, "--out", "plain"]) == 0
    assert "paired" not in json.loads((workdir / "plain" / "summary.json").read_text())
    assert "Paired" not in (workdir / "plain" / "summary.md").read_text()


def test_an_interrupted_evaluate_leaves_nothing(workdir: Path, monkeypatch) -> None:
    from cof_gym.commands import evaluate as ev

    calls = {"n": 0}
    real = ev.run_episode

    def interrupted(*args, **kwargs):
        calls["n"] += 1
        if calls["n"] == 2:
            raise KeyboardInterrupt
        return real(*args, **kwargs)

    monkeypatch.setattr(ev, "run_episode", interrupted)
    assert cli.main(["evaluate", "--agents", "staircase", "--episodes", "3", "--out", "deep/res", "--quiet"]) == 130
    assert sorted(p.name for p in workdir.iterdir()) == sorted(["a_file.txt", "not_an_output", "not_a_model.zip",
                                                               "corrupt.zip", *SUITE_FILES, *BROKEN_MODELS,
                                                               "bad_policy.zip", "docs_is_a_file"])


def test_agents_lists_every_registered_agent_with_its_description(capsys) -> None:
    from cof_gym.agents import registry

    assert cli.main(["agents"]) == 0
    listing = " ".join(capsys.readouterr().out.split())
    for name in registry.names():
        entry = registry.AGENTS[name]
        assert " ".join(entry.help.split()) in listing, name
    assert "oracle [oracle, default]" in listing and "sb3:PATH " in listing and " sb3 " not in listing
    assert cli.main(["agents", "--names"]) == 0
    names = capsys.readouterr().out.split()
    assert set(registry.default_agents()) <= set(names) and "py:FILE.py:NAME" in names and "sb3" not in names
    for spelling in names:  # every name listed is one evaluate accepts
        registry.parse(spelling.replace(":PATH", ":x").replace(":DIR", ":x").replace(":FILE.py:NAME", ":x.py:X"))
