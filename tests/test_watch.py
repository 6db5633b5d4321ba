"""``cof-gym watch``: the scenery leaves the dynamics bit-identical, a frame shows a lit scene and the
panels, and bad command lines get one line and exit status 2 before anything is simulated or written."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import cof_gym
from cof_gym.cli import main
from cof_gym.commands import watch
from cof_gym.commands.watch_frames import CURVE_COLOR

SUITES = Path(__file__).resolve().parents[1] / "experiments" / "suites"


def _clear_model_caches() -> None:
    from cof_gym.task import ground_truth, task

    task.built_model.cache_clear()
    task._limits.cache_clear()
    ground_truth.load_transfer_coefficient.cache_clear()


def _episode(env_id: str, seed: int) -> tuple[bytes, bytes]:
    import gymnasium as gym

    from cof_gym.agents import registry
    from cof_gym.commands.evaluate_episodes import run_episode

    env = gym.make(env_id)
    trace: list = []
    record = run_episode(env, registry.make_agent("model-based", env), seed, {}, 0, trace)
    obs = env.unwrapped.episode.observation
    env.close()
    return np.asarray(obs).tobytes(), repr((record, trace)).encode()


@pytest.mark.parametrize("env_id", [cof_gym.WAGON_V1_ENV_ID if hasattr(cof_gym, "WAGON_V1_ENV_ID")
                                    else cof_gym.WAGON_ENV_ID, cof_gym.HALF_WHEELSET_ENV_ID])
def test_scenery_leaves_the_episode_bit_identical(env_id, monkeypatch):
    import cof_gym.physics.models as models

    _clear_model_caches()
    with_scenery = _episode(env_id, 3)
    monkeypatch.setattr(models, "add_scenery", lambda *args, **kwargs: None)
    _clear_model_caches()
    try:
        bare = _episode(env_id, 3)
    finally:
        monkeypatch.undo()
        _clear_model_caches()
    assert with_scenery == bare


def _request(tmp_path, suffix: str = ".gif", **kw) -> watch.WatchRequest:
    return watch.WatchRequest(**{"agent": "model-based", "oracle": False, "env_id": cof_gym.WAGON_ENV_ID, "seed": 0,
                                 "out": tmp_path / f"episode{suffix}", "fps": 10, "width": 640, "speed": 1.0, **kw})


def test_a_frame_shows_the_scene_and_the_panels(tmp_path):
    error = watch.gl_error()
    if error is not None:
        pytest.skip(error)
    facts = watch.watch(_request(tmp_path), max_frames=4)
    frame = facts["last_frame"]
    assert frame.shape == (352, 640, 3) and (tmp_path / "episode.gif").is_file()
    assert [p.name for p in tmp_path.iterdir()] == ["episode.gif"]  # no partial file left
    scene, panels = frame[:, :320].astype(float), frame[:, 320:].astype(float)
    assert scene.std() > 20.0, "the scene is near-uniform"
    assert (scene.max(axis=2) < 30).mean() < 0.5, "the scene is mostly black"
    curve = np.array([int(CURVE_COLOR[i:i + 2], 16) for i in (1, 3, 5)], dtype=float)
    assert (np.abs(panels - curve).max(axis=2) < 40).sum() > 100, "no creep curve drawn in the panels"
    assert (panels.min(axis=2) < 200).mean() > 0.05, "the panels are blank"


def test_the_replay_is_the_scored_episode():
    """The video's windows end, bit for bit, where the env's did (replay raises otherwise)."""
    record, env = watch.play(_request(Path("/nonexistent")))
    try:
        rep = watch.replay(env, [w for w in env.windows if w.ran], 0.1)
    finally:
        env.close()
    assert len(rep.window_end_s) == record.steps + 1 - sum(not w.ran for w in env.windows)
    assert rep.samples["t"].size > 100


def test_the_video_carries_the_learned_interrogators_in_flight_bound_and_no_other_agents():
    """Each window the interrogator chose while its climb had not stopped records the in-flight lower bound it
    held then; the model-based agent reports none (the panel then has no such line). Playing through the
    recorder leaves the scored episode as cof-gym evaluate plays it."""
    import gymnasium as gym

    from cof_gym.agents import registry
    from cof_gym.commands.evaluate_episodes import run_episode

    for agent, reports in (("interrogator", True), ("model-based", False)):
        record, env = watch.play(_request(Path("/nonexistent"), agent=agent))
        env.close()
        bounds = [w.lower_bound for w in env.windows[1:]]
        assert any(np.isfinite(bounds)) == reports, agent
        if reports:
            driven = [b for b, w in zip(bounds, env.windows[1:]) if w.ran]
            assert np.isnan(driven[0]) and all(0.0 < b < w.estimate * 10 for b, w in zip(driven[1:], env.windows[2:]))
            plain = gym.make(cof_gym.WAGON_ENV_ID)
            assert run_episode(plain, registry.make_agent(agent, plain), 0, {}, 0) == record
            plain.close()


def test_an_episode_of_a_suite_is_the_one_evaluate_plays(tmp_path):
    """``--suite SUITE --episode K`` plays episode K as ``cof-gym evaluate --suite SUITE`` plays it (its seed, options,
    env id and env arguments: the paper suite's counter torque); the default and paper suites' episode K has seed
    ``--seed`` + K."""
    import gymnasium as gym

    from cof_gym.agents import registry
    from cof_gym.cli import build_parser
    from cof_gym.commands.evaluate_episodes import run_episode
    from cof_gym.commands.suites import make_suite
    from cof_gym.envs.torque_interrogation import make_kwargs

    for name, episode, seed in ((str(SUITES / "v2_heldout_grid.json"), 3, "0"), ("paper", 2, "10")):
        suite = make_suite(name, episode + 1, int(seed))
        args = build_parser().parse_args(["watch", "--agent", "staircase-zeroed", "--suite", name, "--episode",
                                          str(episode), "--seed", seed, "--out", str(tmp_path / "e.gif")])
        request = watch.prepare(args)
        ep_seed, options = suite.episodes[episode]
        assert (request.env_id, request.env_kwargs, request.seed, request.options) == (
            suite.env_id, suite.env_kwargs, ep_seed, options)
        record, env = watch.play(request)
        env.close()
        plain = gym.make(suite.env_id, **make_kwargs(suite.env_kwargs))
        assert run_episode(plain, registry.make_agent("staircase-zeroed", plain), ep_seed, options, 0) == record
        plain.close()
    assert (request.env_kwargs, request.seed) == ({"counter_torque": True}, 12)


@pytest.mark.parametrize("argv, flag", [
    (["--agent", "nope"], "--agent"),
    (["--agent", "ppo:/nonexistent/model.zip"], "--agent"),
    (["--out", "{tmp}/episode.avi"], "--out"),
    (["--out", "{tmp}"], "--out"),
    (["--out", "/proc/cof-gym-test/episode.mp4"], "--out"),
    (["--seed", "-1"], "--seed"),
    (["--fps", "0"], "--fps"),
    (["--width", "10"], "--width"),
    (["--speed", "100"], "--speed"),
    (["--env", "CartPole-v1"], "--env"),
    (["--episode", "3"], "--episode"),
    (["--suite", "nope.json"], "--suite"),
    (["--suite", "paper", "--episode", "-1"], "--episode"),
    (["--suite", str(SUITES / "v2_heldout_grid.json"), "--episode", "48"], "--episode"),
    (["--suite", "paper", "--env", cof_gym.WAGON_ENV_ID], "--env"),
])
def test_bad_input_one_line_exit_2_nothing_written(argv, flag, tmp_path, monkeypatch, capsys):
    def no_simulation(*args, **kwargs):
        raise AssertionError("simulated before the command line was checked")

    monkeypatch.setattr(watch, "play", no_simulation)
    monkeypatch.chdir(tmp_path)
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    if "--out" not in argv:
        argv += ["--out", str(tmp_path / "episode.mp4")]
    assert _exit_code(["watch", *argv]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and flag in err, err
    assert list(tmp_path.iterdir()) == []


def _exit_code(argv: list[str]) -> int:
    """The CLI's exit status (argparse exits, the commands return)."""
    try:
        return main(argv)
    except SystemExit as e:
        return int(e.code)


def test_a_gif_frame_shows_for_the_hundredths_of_a_second_the_format_stores() -> None:
    """A GIF stores frame durations in hundredths of a second: at 12 fps a frame shows 0.08 s, and the video's length
    watch reports is the one the file plays (an MP4 holds its fps exactly)."""
    from pathlib import Path

    from cof_gym.commands.watch import frame_s

    assert frame_s(Path("e.gif"), 12) == 0.08 and frame_s(Path("e.gif"), 25) == 0.04
    assert frame_s(Path("e.mp4"), 12) == 1 / 12
