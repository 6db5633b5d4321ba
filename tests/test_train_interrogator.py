"""experiments/train_interrogator.py's guards: copied into a run directory as its manifest names them,
and a bad ``--guards`` or ``--guard-climbs`` exits 2 with one line before any climb is collected; ``--fit-only``
fits the networks (and a guard's, from ``--guard-climbs``) and stops before the selection."""

from __future__ import annotations

import json
import subprocess
import sys
from dataclasses import asdict
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import cof_gym
from cof_gym.agents.interrogator import FEATURE_NAMES, TARGET_NAMES, FilterNetwork, interrogator_for

EXPERIMENTS = Path(__file__).resolve().parents[1] / "experiments"
sys.path.insert(0, str(EXPERIMENTS))
from train_interrogator import install_guards  # noqa: E402


def network(bias: float) -> FilterNetwork:
    n, out = len(FEATURE_NAMES), 2 * len(TARGET_NAMES)
    return FilterNetwork(np.zeros(n), np.ones(n), (np.zeros((n, out)),), (np.full(out, bias),))


def test_guards_are_copied_into_the_run_and_load_from_its_manifest(tmp_path: Path) -> None:
    run, guard = tmp_path / "run", tmp_path / "other" / "ensemble"
    run.mkdir()
    guard.mkdir(parents=True)
    network(0.0).save(run / "member_0.npz")
    for k in range(2):
        network(-0.1 * (k + 1)).save(guard / f"member_{k}.npz")
    (run / "guard_7").mkdir()  # a stale guard of an earlier run
    names = install_guards(run, [guard])
    assert names == ["guard_0"] and not (run / "guard_7").exists()
    assert sorted(p.name for p in (run / "guard_0").iterdir()) == ["member_0.npz", "member_1.npz"]
    (run / "manifest.json").write_text('{"guards": ["guard_0"]}')
    agent = interrogator_for(gym.make(cof_gym.WAGON_ENV_ID), run)
    assert [m.biases[-1][0] for m in agent.guards[0].members] == [-0.1, -0.2]
    assert install_guards(run, []) == [] and not (run / "guard_0").exists()


def test_bad_guards_exit_2_naming_the_option(tmp_path: Path) -> None:
    done = subprocess.run([sys.executable, str(EXPERIMENTS / "train_interrogator.py"), "--out", str(tmp_path / "run"),
                           "--guards", str(tmp_path / "none")], capture_output=True, text=True, timeout=120)
    assert done.returncode == 2
    assert done.stderr.count("\n") == 1 and done.stderr.startswith("train_interrogator.py: error: --guards"), done.stderr
    assert not (tmp_path / "run").exists()


@pytest.mark.parametrize("climbs", [["bad=3"], ["env=x"], ["env=0"]])
def test_bad_guard_climbs_exit_2_naming_the_option(tmp_path: Path, climbs: list[str], experiment_exit) -> None:
    code, last = experiment_exit("train_interrogator", ["--out", str(tmp_path / "run"), "--guard-climbs", *climbs])
    assert code == 2 and last.startswith("train_interrogator.py: error: --guard-climbs:")
    assert not (tmp_path / "run").exists()


def test_fit_only_leaves_the_networks_and_no_selection(tmp_path: Path) -> None:
    run = tmp_path / "run"
    done = subprocess.run([sys.executable, str(EXPERIMENTS / "train_interrogator.py"), "--out", str(run), "--climbs",
                           "env=10", "--guard-climbs", "env=10", "procedural=6", "--seeds", "0", "1", "--epochs", "1",
                           "--workers", "1", "--fit-only"], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    for networks in (run, run / "guard"):
        assert sorted(p.name for p in (networks / "ensemble").iterdir()) == ["member_0.npz", "member_1.npz"]
        assert (networks / "seed_1" / "member_0.npz").is_file()
    # the guard's climbs share OUT's caches with the filter's; it learns from the procedural climbs too
    assert sorted(p.name for p in run.glob("climbs*.npz")) == ["climbs.npz", "climbs_procedural.npz"]
    filter_0, guard_0 = (FilterNetwork.load(d / "seed_0" / "member_0.npz") for d in (run, run / "guard"))
    assert not np.array_equal(filter_0.weights[0], guard_0.weights[0])
    assert not list(run.rglob("manifest.json")) and not (run / "report.md").exists()


def test_a_bad_loss_exits_2_naming_the_option(tmp_path: Path, experiment_exit) -> None:
    code, last = experiment_exit("train_interrogator", ["--out", str(tmp_path / "run"), "--loss", "squared"])
    assert code == 2 and last.startswith("train_interrogator.py: error: argument --loss")
    assert not (tmp_path / "run").exists()


@pytest.mark.parametrize("option", ["--add-climbs", "--add-guard-climbs"])
@pytest.mark.parametrize("content", [None, b"not a climbs file"])
def test_bad_added_climbs_exit_2_naming_the_option(tmp_path: Path, option: str, content, experiment_exit) -> None:
    file = tmp_path / "climbs.npz"
    if content is not None:
        file.write_bytes(content)
    code, last = experiment_exit("train_interrogator", ["--out", str(tmp_path / "run"), option, str(file)])
    assert code == 2 and last.startswith(f"train_interrogator.py: error: {option}")
    assert not (tmp_path / "run").exists()  # checked before any climb is collected


def test_guard_climbs_added_without_a_guard_exit_2(tmp_path: Path, experiment_exit) -> None:
    code, last = experiment_exit("train_interrogator", ["--out", str(tmp_path / "run"), "--guard-climbs", "none",
                                                        "--add-guard-climbs", str(tmp_path / "climbs.npz")])
    assert code == 2 and last == ("train_interrogator.py: error: --add-guard-climbs: no guard is fitted "
                                  "(--guard-climbs none) (see train_interrogator.py --help)")
    assert not (tmp_path / "run").exists()


@pytest.mark.filterwarnings("error::RuntimeWarning")  # fewer than 10 climbs: no held-apart score, not a NaN one
def test_added_climbs_join_the_training_climbs_of_the_networks_named(tmp_path: Path, monkeypatch) -> None:
    """The filter's member is standardised on a bootstrap resample of the collected climbs and those of
    ``--add-climbs`` together, the guard's on the collected ones and those of ``--add-guard-climbs`` (the same
    episodes, resample and arithmetic give the same mean, bit for bit)."""
    import train_interrogator
    from cof_gym.agents.interrogator.training import Dataset, collect

    added_file, guard_file = tmp_path / "onpolicy.npz", tmp_path / "onpolicy_guard.npz"
    collect(cof_gym.WAGON_ENV_ID, [{}], 3, first_seed=2_000_900).save(added_file)
    collect(cof_gym.WAGON_ENV_ID, [{}], 2, first_seed=2_000_950).save(guard_file)
    run = tmp_path / "run"
    monkeypatch.setattr(sys, "argv", ["train_interrogator.py", "--out", str(run), "--climbs", "env=4", "--guard-climbs",
                                      "env=4", "--add-climbs", str(added_file), "--add-guard-climbs", str(guard_file),
                                      "--seeds", "0", "--epochs", "1", "--workers", "1", "--fit-only",
                                      "--torque-balance-lag", "none"])
    train_interrogator.main()
    collected = Dataset.load(run / "climbs.npz")
    for networks, added in ((run, added_file), (run / "guard", guard_file)):
        data = Dataset.concatenate([collected, Dataset.load(added)])
        train, _ = train_interrogator.split(data)
        rng = np.random.default_rng(0)  # fit_member's bootstrap of the episodes (seed 0)
        episodes = np.unique(train.episode)
        rows = np.concatenate([np.flatnonzero(train.episode == e) for e in rng.choice(episodes, len(episodes))])
        member = FilterNetwork.load(networks / "seed_0" / "member_0.npz")
        np.testing.assert_array_equal(member.feature_mean, train.features[rows].mean(axis=0))


def test_torque_balance_lag_fits_on_calibrated_readings_and_recollects_caches_without_the_balance(
        tmp_path: Path, monkeypatch, experiment_exit) -> None:
    """``--torque-balance-lag`` standardises each member on the climbs as Dataset.calibrated reads them, records
    the bound beside what the networks were fitted on, collects again a cache recorded without the balance, and
    refuses added climbs recorded without it (exit 2, before any climb is collected)."""
    import train_interrogator
    from cof_gym.agents.interrogator.training import READING_FIELDS, Dataset

    run = tmp_path / "run"
    run.mkdir()
    stale = train_interrogator.collect(run, {"env": 4}, 1)
    stale.readings[:, READING_FIELDS.index("torque_balance")] = 0.0  # as recorded before the balance was read
    stale.save(run / "climbs.npz")
    monkeypatch.setattr(sys, "argv", ["train_interrogator.py", "--out", str(run), "--climbs", "env=4", "--guard-climbs",
                                      "none", "--seeds", "0", "--epochs", "1", "--workers", "1", "--fit-only",
                                      "--torque-balance-lag", "65"])
    train_interrogator.main()
    collected = Dataset.load(run / "climbs.npz")
    assert collected.reads_torque_balance
    train, _ = train_interrogator.split(collected.calibrated(65.0))
    rng = np.random.default_rng(0)  # fit_member's bootstrap of the episodes (seed 0)
    episodes = np.unique(train.episode)
    rows = np.concatenate([np.flatnonzero(train.episode == e) for e in rng.choice(episodes, len(episodes))])
    member = FilterNetwork.load(run / "seed_0" / "member_0.npz")
    np.testing.assert_array_equal(member.feature_mean, train.features[rows].mean(axis=0))
    assert json.loads((run / "training.json").read_text())["torque_balance_max_lag_deg"] == 65.0
    stale.save(tmp_path / "stale.npz")
    code, last = experiment_exit("train_interrogator", ["--out", str(tmp_path / "other"), "--torque-balance-lag", "65",
                                                        "--add-climbs", str(tmp_path / "stale.npz")])
    assert code == 2 and "was recorded without the torque balance" in last
    assert not (tmp_path / "other").exists()


def test_reuse_refits_only_the_networks_whose_climbs_changed(tmp_path: Path, monkeypatch) -> None:
    """``--reuse`` keeps networks fitted on the same climbs and settings (OUT/training.json) and fits again
    those whose climbs changed: the recipe's third step keeps the filter and refits the guard on its added
    climbs."""
    import train_interrogator
    from cof_gym.agents.interrogator.training import collect

    guard_file = tmp_path / "onpolicy_guard.npz"
    collect(cof_gym.WAGON_ENV_ID, [{}], 2, first_seed=2_000_950).save(guard_file)
    run = tmp_path / "run"
    base = ["train_interrogator.py", "--out", str(run), "--climbs", "env=4", "--guard-climbs", "env=4", "--seeds", "0",
            "--epochs", "1", "--workers", "1", "--fit-only", "--reuse"]

    def fit(*extra: str) -> tuple[bytes, bytes]:
        monkeypatch.setattr(sys, "argv", [*base, *extra])
        train_interrogator.main()
        return tuple((d / "seed_0" / "member_0.npz").read_bytes() for d in (run, run / "guard"))

    filter_1, guard_1 = fit()
    filter_2, guard_2 = fit("--add-guard-climbs", str(guard_file))
    assert filter_2 == filter_1 and guard_2 != guard_1
    record = json.loads((run / "guard" / "training.json").read_text())
    assert record["added_sha256"] == [train_interrogator.file_digest(guard_file)]
    assert fit("--add-guard-climbs", str(guard_file)) == (filter_2, guard_2)  # the same climbs: both kept


def test_a_probing_guard_without_added_climbs_exits_2(tmp_path: Path, experiment_exit) -> None:
    code, last = experiment_exit("train_interrogator", ["--out", str(tmp_path / "run"), "--probing-guard"])
    assert code == 2 and last.startswith("train_interrogator.py: error: --probing-guard: needs --add-guard-climbs")
    assert not (tmp_path / "run").exists()


def test_the_probing_guard_is_the_first_steps_guard(tmp_path: Path, monkeypatch) -> None:
    """``--probing-guard`` (the recipe's third step, rule 45) fits beside the guard that learns the added climbs
    the networks the first step fitted as its guard, byte for byte, and keeps them on a repeat."""
    import train_interrogator
    from cof_gym.agents.interrogator.training import collect

    guard_file = tmp_path / "onpolicy_guard.npz"
    collect(cof_gym.WAGON_ENV_ID, [{}], 2, first_seed=2_000_950).save(guard_file)
    base = ["--climbs", "env=5", "--guard-climbs", "env=4", "--seeds", "0", "--epochs", "1", "--workers", "1",
            "--fit-only", "--reuse"]  # the filter on other climbs than the guards

    def fit(run: Path, *extra: str) -> dict[str, bytes]:
        monkeypatch.setattr(sys, "argv", ["train_interrogator.py", "--out", str(run), *base, *extra])
        train_interrogator.main()
        return {d.name: (d / "seed_0" / "member_0.npz").read_bytes()
                for d in (run, run / "guard", run / "probing_guard") if d.is_dir()}

    first = fit(tmp_path / "first")
    third = fit(tmp_path / "third", "--add-guard-climbs", str(guard_file), "--probing-guard")
    assert "probing_guard" not in first and first["guard"] != first["first"]
    assert third["probing_guard"] == first["guard"] != third["guard"]
    assert fit(tmp_path / "third", "--add-guard-climbs", str(guard_file), "--probing-guard") == third


def test_the_shipped_climb_carries_the_recipes_fixed_parts() -> None:
    """The parts of the climb the recipe sets after its selection (the adopted rules' constants in
    train_interrogator.py, ``ADOPTED_CLIMB``) are the shipped manifest's, and every part of the shipped climb that
    is not ClimbParameters' default is either one of them or one the selection chooses: a rule adopted in one place
    and not the other fails here."""
    import train_interrogator as recipe
    from cof_gym.agents.interrogator import SHIPPED_INTERROGATOR, ClimbParameters

    climb = json.loads((SHIPPED_INTERROGATOR / "manifest.json").read_text())["climb"]
    fixed = {"estimate_from": recipe.GUARDED_ESTIMATE, **recipe.ADOPTED_CLIMB}
    assert {name: climb[name] for name in fixed} == fixed
    defaults = asdict(ClimbParameters())
    selected = set(recipe.grid_columns(recipe.GRIDS["recipe"])) | set(recipe.ESTIMATES[0])
    assert {name for name, value in climb.items() if value != defaults[name]} <= set(fixed) | selected


def test_the_shipped_networks_were_fitted_as_the_recipe_fits_them() -> None:
    """The shipped manifest's training record is the recipe's defaults: its collections for the filter and the
    guards and the torque balance's lag bound the readings were calibrated with (the shipped climb's own): a recipe
    changed in one place and not the other fails here."""
    import train_interrogator as recipe
    from cof_gym.agents.interrogator import SHIPPED_INTERROGATOR

    manifest = json.loads((SHIPPED_INTERROGATOR / "manifest.json").read_text())
    training = manifest["training"]
    assert training["climbs"] == recipe.EPISODES and training["guard_climbs"] == recipe.GUARD_EPISODES
    assert training.get("torque_balance_max_lag_deg") == recipe.RECIPE_BALANCE_LAG_DEG
    assert manifest["climb"]["torque_balance_max_lag_deg"] == recipe.RECIPE_BALANCE_LAG_DEG


def test_a_ship_keeps_the_model_card_and_leaves_no_stale_file(tmp_path: Path) -> None:
    """``--ship`` replaces the package by the run's ensemble (members, guards, manifest), keeps the package's
    hand-written card and leaves neither the old networks nor an interval calibrated for them."""
    from train_interrogator import MODEL_CARD, ship

    from cof_gym.agents.interrogator import INTERVAL_FILE

    package, run = tmp_path / "package", tmp_path / "ensemble"
    (package / "guard_0").mkdir(parents=True)
    for name, text in ((MODEL_CARD, "the card"), (INTERVAL_FILE, "{}"), ("member_5.npz", "old"),
                       ("guard_0/member_0.npz", "old guard")):
        (package / name).write_text(text)
    (run / "guard_1").mkdir(parents=True)
    for name in ("member_0.npz", "manifest.json", "guard_1/member_0.npz", INTERVAL_FILE):
        (run / name).write_text(f"new {name}")
    ship(run, package)
    files = sorted(str(p.relative_to(package)) for p in package.rglob("*") if p.is_file())
    assert files == sorted([MODEL_CARD, "guard_1/member_0.npz", "manifest.json", "member_0.npz"])
    assert (package / MODEL_CARD).read_text() == "the card"
    assert (package / "member_0.npz").read_text() == "new member_0.npz"


@pytest.mark.parametrize("text, value", [("none", None), ("65", 65.0), ("90", 90.0)])
def test_the_balance_lag_reads_a_bound_or_none(text: str, value: float | None) -> None:
    from train_interrogator import lag_or_none

    assert lag_or_none(text) == value


@pytest.mark.parametrize("text", ["0", "95", "nan", "soon"])
def test_a_bad_balance_lag_names_both_accepted_forms(text: str) -> None:
    import argparse

    from train_interrogator import lag_or_none

    message = rf"^must be 'none' or a finite number in \(0, 90\], got '{text}'$"
    with pytest.raises(argparse.ArgumentTypeError, match=message):
        lag_or_none(text)


@pytest.mark.parametrize("env_id", [cof_gym.WAGON_ENV_ID, cof_gym.WAGON_IN_SERVICE_ENV_ID])
def test_the_report_only_runs_are_the_shipped_agent_member_by_member(tmp_path: Path, env_id: str) -> None:
    """``--report-only`` plays seed K as the package's member K alone (the package shipped for ``--env``), with the
    package's guards and manifest, and the ensemble as the package, without its calibrated interval; a stale run
    directory is replaced."""
    from train_interrogator import shipped_runs

    from cof_gym.agents.policy_files import SHIPPED_INTERROGATORS

    package = SHIPPED_INTERROGATORS[env_id]
    (tmp_path / "seed_0" / "guard_9").mkdir(parents=True)  # a stale run
    runs = shipped_runs(tmp_path, package)
    members = sorted(package.glob("member_*.npz"))
    assert [r.name for r in runs] == [f"seed_{k}" for k in range(len(members))] + ["ensemble"]
    for k, run in enumerate(runs[:-1]):
        assert sorted(p.name for p in run.glob("member_*.npz")) == ["member_0.npz"]
        assert (run / "member_0.npz").read_bytes() == members[k].read_bytes()
        assert not (run / "guard_9").exists()
    for run in runs:
        assert (run / "manifest.json").read_text() == (package / "manifest.json").read_text()
        assert not (run / "interval.json").exists()  # calibrated for the shipped networks alone
    assert [p.read_bytes() for p in sorted(runs[-1].glob("member_*.npz"))] == [p.read_bytes() for p in members]
    agent = interrogator_for(gym.make(env_id), runs[0])
    guards = json.loads((package / "manifest.json").read_text())["guards"]
    assert len(agent.ensemble.members) == 1 and [len(g.members) for g in agent.guards] == [len(members)] * len(guards)


@pytest.mark.parametrize("options", [["--ship"], ["--reuse"], ["--fit-only"], ["--guards", "x"]])
def test_report_only_refuses_what_fits_selects_or_ships(tmp_path: Path, options: list[str], experiment_exit) -> None:
    code, last = experiment_exit("train_interrogator", ["--out", str(tmp_path / "run"), "--report-only", *options])
    assert code == 2 and last.startswith("train_interrogator.py: error: --report-only: plays the shipped agent")
    assert not (tmp_path / "run").exists()


def test_training_collections_draw_disjoint_seeds() -> None:
    """Every training collection (and every on-policy one of train_estimator.py) starts 100 000 seeds or more from
    every other, so that no two of them, of up to 100 000 climbs each, share an episode's draw; and each lies at or
    above TRAINING_SEED, far from every evaluation and validation seed."""
    import train_estimator
    import train_interrogator
    from cof_gym.agents.interrogator.training import TRAINING_SEED

    starts = sorted([first for _, first, _ in train_interrogator.COLLECTIONS.values()]
                    + [first for first, _ in train_estimator.ON_POLICY.values()])
    assert starts[0] >= TRAINING_SEED
    assert all(b - a >= 100_000 for a, b in zip(starts, starts[1:])), starts


def test_env_collects_on_that_id_into_caches_and_records_of_its_own(tmp_path: Path, monkeypatch) -> None:
    """``--env`` (task v3's id) collects the climbs on that id, into cache files named for its version (a v2 run's
    caches in the same directory are neither read nor overwritten), records the id beside what the networks were
    fitted on (``training.json``); ``--ship`` writes each id's own package, the one the registry's agent for that id
    plays."""
    import train_interrogator
    from cof_gym.agents.interrogator.training import Dataset, collect

    v3 = cof_gym.WAGON_IN_SERVICE_ENV_ID
    assert train_interrogator.cache_file("climbs_torque_wide.npz") == "climbs_torque_wide.npz"
    assert train_interrogator.cache_file("climbs_torque_wide.npz", v3) == "climbs_torque_wide_v3.npz"
    run = tmp_path / "run"
    run.mkdir()
    v2_cache = train_interrogator.collect(run, {"env": 2}, 1)
    monkeypatch.setattr(sys, "argv", ["train_interrogator.py", "--out", str(run), "--climbs", "env=2", "--guard-climbs",
                                      "none", "--seeds", "0", "--epochs", "1", "--workers", "1", "--fit-only",
                                      "--env", v3])
    train_interrogator.main()
    on_v3 = Dataset.load(run / "climbs_v3.npz")
    expected = collect(v3, train_interrogator.CONFIGS, 2, train_interrogator.TRAINING_SEED)
    np.testing.assert_array_equal(on_v3.readings, expected.readings)
    assert not np.array_equal(on_v3.readings, v2_cache.readings)  # the same seeds read otherwise on v3
    np.testing.assert_array_equal(Dataset.load(run / "climbs.npz").readings, v2_cache.readings)
    assert json.loads((run / "training.json").read_text())["env_id"] == v3
    from cof_gym.agents import registry
    from cof_gym.agents.policy_files import SHIPPED_INTERROGATORS

    assert set(train_interrogator.TRAINING_ENV_IDS) == set(SHIPPED_INTERROGATORS)
    assert SHIPPED_INTERROGATORS == {
        cof_gym.WAGON_ENV_ID: registry.AGENTS["interrogator"].shipped.parent,
        v3: registry.AGENTS["interrogator-in-service"].shipped.parent}
