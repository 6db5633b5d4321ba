"""experiments/lag_near_peak.py: the diagnostic plays the chosen episode with the overrides it is given,
in the env it is given, and refuses a malformed override before simulating."""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "experiments"))
import lag_near_peak  # noqa: E402

ARGS = ["lag_near_peak.py", "--episodes", "6", "--levels", "0.3", "0.8", "--amplitude-ratio", "0.4"]


def _lags(monkeypatch, capsys, extra):
    monkeypatch.setattr(sys, "argv", ARGS + extra)
    lag_near_peak.main()
    rows = [line for line in capsys.readouterr().out.splitlines() if line.startswith("| 0.")]
    return [float(row.split("|")[2].split("+-")[0]) for row in rows]


def test_overrides_and_env_reach_the_episode(monkeypatch, capsys):
    wagon = _lags(monkeypatch, capsys, ["--set", "load_case=laden", "motor_lag_s=0"])
    # the half wheelset admits only the laden case: without the override its reset of this episode fails
    half = _lags(monkeypatch, capsys, ["--set", "load_case=laden", "motor_lag_s=0", "--env", "CofGym/HalfWheelset-v2"])
    assert len(wagon) == len(half) == 2
    assert wagon != half  # another env, another response to the same drive
    with pytest.raises(SystemExit) as e:
        _lags(monkeypatch, capsys, ["--set", "motor_lag_s"])
    assert e.value.code == 2
