"""experiments/validation_plays.py: the four validation plays of a rule's candidate, as the reports read them."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

EXPERIMENTS = Path(__file__).resolve().parents[1] / "experiments"
sys.path.insert(0, str(EXPERIMENTS))
import validation_plays  # noqa: E402

PLAYS = ("validation", "validation_torque", "noise_level", "motor_lag_s")  # what learned_caution --report joins


def test_a_candidate_plays_four_grids_into_the_files_the_reports_read() -> None:
    commands = validation_plays.candidate_commands("cand", "a.zip+b.zip")
    assert [c[c.index("--records") + 1] for c in commands] == [f"out/records_cand_{p}.json" for p in PLAYS]
    assert [c[c.index("--grids") + 1] for c in commands] == ["validation", "validation_torque", "validation",
                                                             "validation"]
    scenarios = [c[c.index("--scenario") + 1] if "--scenario" in c else None for c in commands]
    assert scenarios == [None, None, "noise_level=3", "motor_lag_s=0.1"]
    for command in commands:  # the shipped guards alone, the caution policy as given
        assert command[1].endswith("crest_tradeoff.py") and "--guards-only" in command
        assert command[command.index("--caution-policy") + 1] == "a.zip+b.zip"
        guards = command[command.index("--guards") + 1:command.index("--guards-only")]
        assert all((EXPERIMENTS.parent / g / "member_0.npz").is_file() for g in guards) and len(guards) == 2
    assert all("--caution-policy" not in c for c in validation_plays.candidate_commands("cand", None))


def test_hand_built_agents_play_the_same_four_grids() -> None:
    commands = validation_plays.hand_built_commands()
    assert [c[c.index("--records") + 1] for c in commands] == [f"out/records_{{agent}}_{p}.json" for p in PLAYS]
    assert [c[2:c.index("--agents") + 5] for c in commands] == [["--agents", *validation_plays.HAND_BUILT]] * 4


def test_print_plays_nothing(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys) -> None:
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(sys, "argv", ["validation_plays.py", "cand", "--print"])
    monkeypatch.setattr(validation_plays.subprocess, "run", lambda *a, **k: pytest.fail("--print played"))
    validation_plays.main()
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 4 and all(line.startswith("python ") and "crest_tradeoff.py" in line for line in lines)
    assert list(tmp_path.iterdir()) == []


def test_confirmation_plays_the_five_plays_of_three_unplayed_sets() -> None:
    plays = validation_plays.confirmation_plays("confirmation36", "torque_confirmation17", "extremes_confirmation8")
    commands = validation_plays.candidate_commands("shipped", None, plays)
    assert [c[c.index("--records") + 1] for c in commands] == [
        "out/records_shipped_confirmation36.json", "out/records_shipped_confirmation36_noise_level.json",
        "out/records_shipped_confirmation36_motor_lag_s.json", "out/records_shipped_torque_confirmation17.json",
        "out/records_shipped_extremes_confirmation8.json"]
    assert [c[c.index("--grids") + 1] for c in validation_plays.hand_built_commands(plays)] == [
        "confirmation36", "confirmation36", "confirmation36", "torque_confirmation17", "extremes_confirmation8"]


def _commands(*argv: str) -> list[list[str]]:
    parser = validation_plays.build_parser()
    return validation_plays.commands_of(parser, parser.parse_args(list(argv)))


def test_the_encoder_lag_play_joins_the_plays_or_stands_alone() -> None:
    commands = _commands("cand", "--encoder-lag")
    assert [c[c.index("--records") + 1] for c in commands] == [f"out/records_cand_{p}.json"
                                                               for p in (*PLAYS, "encoder_lag_s")]
    assert commands[-1][commands[-1].index("--scenario") + 1] == "encoder_lag_s=0.01"
    (alone,) = _commands("--hand-built", "--encoder-lag-only", "--confirmation", "confirmation36",
                         "torque_confirmation17", "extremes_confirmation8")
    assert alone[alone.index("--records") + 1] == "out/records_{agent}_confirmation36_encoder_lag_s.json"
    assert alone[alone.index("--grids") + 1:alone.index("--grids") + 4] == ["confirmation36", "--scenario",
                                                                            "encoder_lag_s=0.01"]


def test_more_encoder_lags_add_a_play_each_named_by_its_lag() -> None:
    commands = _commands("cand", "--encoder-lag-only", "--more-encoder-lags", "0.005", "0.02")
    assert [c[c.index("--records") + 1] for c in commands] == [
        f"out/records_cand_{p}.json" for p in ("encoder_lag_s", "encoder_lag_s0.005", "encoder_lag_s0.02")]
    assert [c[c.index("--scenario") + 1] for c in commands] == [
        "encoder_lag_s=0.01", "encoder_lag_s=0.005", "encoder_lag_s=0.02"]


def test_only_keeps_the_named_plays_in_their_order() -> None:
    commands = _commands("cand", "--encoder-lag", "--more-encoder-lags", "0.02", "--only", "encoder_lag_s0.02",
                         "validation")
    assert [c[c.index("--records") + 1] for c in commands] == [
        "out/records_cand_validation.json", "out/records_cand_encoder_lag_s0.02.json"]


def test_a_candidate_reads_estimators_with_a_climb_setting() -> None:
    estimators = "cof_gym/agents/policies/interrogator/guard_0"
    for command in _commands("cand", "--estimators", estimators, "--set", "estimate_from=estimator"):
        assert command[command.index("--estimators") + 1] == estimators
        assert command[command.index("--set") + 1] == "estimate_from=estimator"


def test_a_candidate_plays_its_own_filter_and_guards() -> None:
    guard = "cof_gym/agents/policies/interrogator/guard_1"
    for command in _commands("cand", "--run", "cof_gym/agents/policies/interrogator", "--guards", guard):
        assert command[command.index("--run") + 1] == "cof_gym/agents/policies/interrogator"
        assert command[command.index("--guards") + 1:command.index("--guards-only")] == [guard]


@pytest.mark.parametrize("argv, message", [
    (["cand", "--estimators", "no/such/dir"], "--estimators: no networks (member_*.npz) in no/such/dir"),
    (["cand", "--set", "estimate_from"], "--set: expected NAME=VALUE"),
    (["--hand-built", "--set", "estimate_from=estimator"], "--hand-built: takes no NAME"),
    (["cand", "--run", "no/such/dir"], "--run: no networks (member_*.npz) in no/such/dir"),
    (["cand", "--guards", "cof_gym"], "--guards: no networks (member_*.npz) in cof_gym"),
])
def test_bad_candidate_arguments_are_one_line(argv, message, capsys) -> None:
    with pytest.raises(SystemExit) as exit_info:
        _commands(*argv)
    assert exit_info.value.code == 2 and message in capsys.readouterr().err
