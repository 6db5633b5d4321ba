"""experiments/train_estimator.py: the on-policy estimator's recipe. A bad ``--policy`` or ``--climbs`` exits 2
with one line before any climb; the cache of a policy's climbs is keyed by what steers them (not by the
reported estimate); a small run writes the networks and the held-apart report; ``--collect-only`` the climbs alone."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from cof_gym.agents.interrogator import SHIPPED_INTERROGATOR, read_manifest

EXPERIMENTS = Path(__file__).resolve().parents[1] / "experiments"
sys.path.insert(0, str(EXPERIMENTS))
from train_estimator import policy_digest, policy_with  # noqa: E402

SCRIPT = str(EXPERIMENTS / "train_estimator.py")


@pytest.mark.parametrize("args, option", [(["--policy", "nowhere"], "--policy"), (["--climbs", "bad=3"], "--climbs"),
                                          (["--climbs", "env=0"], "--climbs"), (["--loss", "l2"], "argument --loss"),
                                          (["--set", "no_such_field=1"], "argument --set"),
                                          (["--set", "caution=x"], "--set: caution must be a number"),
                                          (["--set", "caution=-1"], "--set: caution"),
                                          (["--set", "creep_log_step=0.2"], "--set: creep_log_step"),
                                          (["--set", "guard_cautions=[2]"], "--set: guard_cautions names 1"),
                                          (["--env", "CofGym/TorqueInterrogation-v1"], "argument --env")])
def test_bad_options_exit_2_naming_the_option(tmp_path: Path, args: list[str], option: str, experiment_exit) -> None:
    code, last = experiment_exit("train_estimator", ["--out", str(tmp_path / "run"), *args])
    assert code == 2 and last.startswith(f"train_estimator.py: error: {option}")
    assert not (tmp_path / "run").exists()


def test_the_cache_key_follows_what_steers_the_climb_not_the_reported_estimate(tmp_path: Path) -> None:
    policy = tmp_path / "policy"
    shutil.copytree(SHIPPED_INTERROGATOR, policy)
    manifest = json.loads((policy / "manifest.json").read_text())
    digest = policy_digest(policy)

    def digest_with(**climb) -> str:
        (policy / "manifest.json").write_text(json.dumps({**manifest, "climb": {**manifest["climb"], **climb}}))
        return policy_digest(policy)

    assert digest_with(estimate_from="filter") == digest
    assert digest_with(crest_floor=False) == digest_with(runaway_estimate=False) == digest  # estimates only
    assert digest_with(crest_ceiling=not manifest["climb"].get("crest_ceiling", False)) == digest
    assert digest_with(creep_sticky_below=None) == digest  # a default written out: the same climb
    assert digest_with(creep_release=None) != digest  # the shipped probe's release (rule 94) steers
    assert digest_with(caution=1.5) != digest
    digest_with()
    (policy / "guard_0" / "member_0.npz").write_bytes((policy / "guard_0" / "member_1.npz").read_bytes())
    assert policy_digest(policy) != digest


def test_a_small_run_writes_the_estimator_and_its_report(tmp_path: Path) -> None:
    """A run under the Laplace loss (the Gaussian's fit is the recipe's, tested with it)."""
    out = tmp_path / "run"
    done = subprocess.run([sys.executable, SCRIPT, "--out", str(out), "--climbs", "env=12", "procedural=8",
                           "--seeds", "0", "1", "--workers", "1", "--loss", "laplace"],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert sorted(p.name for p in (out / "ensemble").iterdir()) == ["member_0.npz", "member_1.npz"]
    assert len(list(out.glob("onpolicy_env_*.npz"))) == len(list(out.glob("onpolicy_procedural_*.npz"))) == 1
    report = json.loads((out / "report.json").read_text())
    guards = read_manifest(SHIPPED_INTERROGATOR)["guards"]  # every guard of the policy (the shipped one here)
    for metric in ("rmse", "mae"):
        assert set(report[f"estimate_window_correction_{metric}"]) == {"estimator", "filter", *guards}
    assert report["settings"]["loss"] == "laplace"


def test_a_cache_extended_holds_the_climbs_collected_at_once(tmp_path: Path) -> None:
    """Asking for more on-policy climbs than a cache holds collects only the missing ones, and the data are
    those of one collection of them all (same seeds, configurations and order)."""
    from train_estimator import collect_on_policy

    at_once = collect_on_policy(SHIPPED_INTERROGATOR, tmp_path / "a", {"env": 4}, 1)
    collect_on_policy(SHIPPED_INTERROGATOR, tmp_path / "b", {"env": 2}, 1)
    extended = collect_on_policy(SHIPPED_INTERROGATOR, tmp_path / "b", {"env": 4}, 1)
    for field in ("readings", "counter_torque", "targets", "episode"):
        assert (getattr(extended, field) == getattr(at_once, field)).all(), field
    assert len(list((tmp_path / "b").glob("onpolicy_env_*.npz"))) == 1


def test_collect_only_writes_the_cache_and_fits_nothing(tmp_path: Path) -> None:
    """``--collect-only`` leaves the policy's climbs in OUT's cache (what ``train_interrogator.py --add-climbs``
    reads) and fits no network."""
    from cof_gym.agents.interrogator.training import Dataset

    out = tmp_path / "run"
    done = subprocess.run([sys.executable, SCRIPT, "--out", str(out), "--climbs", "env=2", "--workers", "1",
                           "--collect-only"], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert [p.name for p in out.iterdir()] == [f"onpolicy_env_{policy_digest(SHIPPED_INTERROGATOR)}.npz"]
    assert sorted(set(Dataset.load(next(out.iterdir())).episode.tolist())) == [0, 1]
    assert f"of 2 climbs in {out}" in done.stdout


def test_env_collects_the_policys_climbs_on_that_id_into_a_cache_of_its_own(tmp_path: Path) -> None:
    """``--env`` (task v3's id): the policy climbs that id's wagon, the same seeds and configurations as
    :func:`~cof_gym.agents.interrogator.training.collect` with the policy there, into a cache named for the id's
    version beside (not over) the v2 wagon's."""
    import cof_gym
    from cof_gym.agents.interrogator.training import Dataset, collect
    from train_estimator import CONFIGS, ON_POLICY, collect_on_policy

    v3, out = cof_gym.WAGON_IN_SERVICE_ENV_ID, tmp_path / "run"
    on_v2 = collect_on_policy(SHIPPED_INTERROGATOR, out, {"env": 2}, 1)
    done = subprocess.run([sys.executable, SCRIPT, "--out", str(out), "--climbs", "env=2", "--workers", "1",
                           "--collect-only", "--env", v3], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    digest = policy_digest(SHIPPED_INTERROGATOR)
    assert sorted(p.name for p in out.iterdir()) == [f"onpolicy_env_{digest}.npz", f"onpolicy_env_{digest}_v3.npz"]
    on_v3 = Dataset.load(out / f"onpolicy_env_{digest}_v3.npz")
    first_seed, draws = ON_POLICY["env"]
    expected = collect(v3, CONFIGS, 2, first_seed, draws, str(SHIPPED_INTERROGATOR))
    np.testing.assert_array_equal(on_v3.readings, expected.readings)
    assert on_v3.readings.shape != on_v2.readings.shape or not np.array_equal(on_v3.readings, on_v2.readings)
    np.testing.assert_array_equal(Dataset.load(out / f"onpolicy_env_{digest}.npz").readings, on_v2.readings)
    assert v3 in done.stdout


def test_set_climbs_a_copy_of_the_policy_with_those_parameters(tmp_path: Path) -> None:
    """``--set`` collects with a copy of the policy (OUT/policy/) whose manifest's climb has the parameters
    changed, its networks and guards unchanged; the cache key follows the change where it steers the climb."""
    shipped = json.loads((SHIPPED_INTERROGATOR / "manifest.json").read_text())
    assert policy_with(SHIPPED_INTERROGATOR, {}, tmp_path) == SHIPPED_INTERROGATOR
    stop = not shipped["climb"].get("ceiling_stop", False)
    copy = policy_with(SHIPPED_INTERROGATOR, {"ceiling_stop": stop}, tmp_path)
    assert copy == tmp_path / "policy"
    manifest = json.loads((copy / "manifest.json").read_text())
    assert manifest == {**shipped, "climb": {**shipped["climb"], "ceiling_stop": stop}}
    for member in SHIPPED_INTERROGATOR.rglob("member_*.npz"):
        assert (copy / member.relative_to(SHIPPED_INTERROGATOR)).read_bytes() == member.read_bytes()
    assert policy_digest(copy) != policy_digest(SHIPPED_INTERROGATOR)


def test_set_is_checked_against_the_policys_own_climb(tmp_path: Path, experiment_exit) -> None:
    """A ``--set`` value that the shipped climb refuses (a slow-probe step above its largest step) but the
    ``--policy``'s climb accepts collects with that policy."""
    policy = tmp_path / "policy"
    shutil.copytree(SHIPPED_INTERROGATOR, policy)
    manifest = json.loads((policy / "manifest.json").read_text())
    manifest["climb"]["max_log_step"] = 0.3
    (policy / "manifest.json").write_text(json.dumps(manifest))
    out = tmp_path / "run"
    done = subprocess.run([sys.executable, SCRIPT, "--policy", str(policy), "--out", str(out), "--set",
                           "creep_log_step=0.2", "--climbs", "env=2", "--workers", "1", "--collect-only"],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert read_manifest(out / "policy")["climb"]["creep_log_step"] == 0.2


def test_an_assembled_policy_of_the_shipped_networks_plays_the_shipped_climb(tmp_path, env, monkeypatch):
    """experiments/assemble_policy.py: the shipped filter and guards, assembled under the shipped climb, make the
    shipped agent (the same actions and estimate on an episode); the manifest names where each network came from."""
    from cof_gym.agents.interrogator import interrogator_for, manifest_guards
    from cof_gym.commands.evaluate_episodes import run_episode

    monkeypatch.syspath_prepend(str(Path(__file__).resolve().parents[1] / "experiments"))
    from assemble_policy import assemble

    monkeypatch.chdir(Path(__file__).resolve().parents[1])  # the repository root: the manifest names paths below it
    guards = list(manifest_guards(SHIPPED_INTERROGATOR))
    manifest = assemble(SHIPPED_INTERROGATOR, guards, SHIPPED_INTERROGATOR, tmp_path / "policy")
    assert manifest == json.loads((tmp_path / "policy" / "manifest.json").read_text())
    assert manifest["guards"] == [f"guard_{k}" for k in range(len(guards))]
    assert manifest["training"]["assembled_from"]["guards"] == [
        f"cof_gym/agents/policies/interrogator/guard_{k}" for k in range(len(guards))]
    played = []
    for directory in (SHIPPED_INTERROGATOR, tmp_path / "policy"):
        agent = interrogator_for(env, directory)
        record = run_episode(env, agent, 11, {}, 0)
        played.append((record.estimate, [d.steering_headroom for d in agent.decisions]))
    assert played[0] == played[1]
