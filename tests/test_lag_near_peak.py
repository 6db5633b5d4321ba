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


def test_harmonics_read_silent_tones_without_changing_the_drive(monkeypatch, capsys):
    """With --harmonics the torque is still the one sine (the extra tones are silent) and the silent tones'
    regressors at 2 f and 3 f are orthogonal to the fundamental's over the window's whole cycles, so the
    fundamental's lag is the sine run's to the printed 0.1 deg (a rounding boundary at most); H2 and H3
    are printed."""
    plain = _lags(monkeypatch, capsys, [])
    monkeypatch.setattr(sys, "argv", ARGS + ["--harmonics"])
    lag_near_peak.main()
    out = capsys.readouterr().out
    assert "| H2 | H3 |" in out
    rows = [line.split("|") for line in out.splitlines() if line.startswith("| 0.")]
    assert len(rows) == len(plain) == 2
    for row, lag in zip(rows, plain):
        value = float(row[2].split("+-")[0])
        assert abs(value - lag) <= 0.1 + 1e-9
        assert all(0.0 <= float(row[k]) < 1.0 for k in (6, 7))  # harmonics below the fundamental
    monkeypatch.setattr(sys, "argv", ARGS + ["--harmonics", "--frequency", "8"])
    with pytest.raises(SystemExit) as e:
        lag_near_peak.main()
    assert e.value.code == 2
