"""experiments/lag_near_peak.py: the diagnostic plays the chosen episode with the overrides it is given,
in the env it is given, and refuses a malformed override before simulating."""

import sys
from pathlib import Path

import gymnasium as gym
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "experiments"))
import lag_near_peak  # noqa: E402

STEEP = Path(__file__).resolve().parents[1] / "experiments" / "suites" / "v2_validation_steep_grid.json"
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
    for bad in ("motor_lag_s", "motor_lag_s=0.5", "lag=0", "load_case=null"):  # refused before any simulation
        with pytest.raises(SystemExit) as e:
            _lags(monkeypatch, capsys, ["--set", bad])
        assert e.value.code == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.startswith("lag_near_peak.py: error: argument --set"), err


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


def test_held_dc_probe_grows_the_amplitude_at_a_fixed_dc():
    """--hold-dc: the drive keeps the DC at the held fraction of M_sat and puts the crest at each level
    (exact arithmetic), and the env's measured torque shows it: a twice larger amplitude at the same mean
    (the sensor's gain error and the motor's lag are the same in both windows, so only noise differs)."""
    assert lag_near_peak.drive(0.8, None, 0.4) == (0.8, 0.8 * 0.4)
    assert lag_near_peak.drive(0.9, 0.7, 0.4) == (0.7, 0.9 - 0.7)
    suite = lag_near_peak.make_suite(str(STEEP), 60, 0)
    k = min(range(len(suite.episodes)), key=lambda i: suite.episodes[i][1]["cof"])  # the smallest torques
    seed, options = suite.episodes[k]
    env = gym.make(suite.env_id, **suite.env_kwargs)
    _, played = lag_near_peak.windows(env, seed, options, [0.8, 0.9], 0.4, 5.0, hold_dc=0.7)
    env.close()
    assert len(played) == 2 and not any(w.clipped for w in played)
    first, second = (w.info["measurement"] for w in played)
    assert second["torque_amplitude_nm"] / first["torque_amplitude_nm"] == pytest.approx(2.0, rel=0.1)
    assert second["torque_mean_nm"] / first["torque_mean_nm"] == pytest.approx(1.0, rel=0.02)


def test_summary_table_and_its_refusals(monkeypatch, capsys, tmp_path):
    out = tmp_path / "probe.md"
    monkeypatch.setattr(sys, "argv", ["lag_near_peak.py", "--suite", str(STEEP), "--episodes", "0", "1",
                                      "--summary", "--levels", "0.9", "1.0", "--hold-dc", "0.7", "--out", str(out)])
    lag_near_peak.main()
    rows = [line for line in out.read_text().splitlines() if line.startswith("| 0.90") or line.startswith("| 1.00")]
    assert len(rows) == 2 and all(row.split("|")[2].strip() in ("1", "2") for row in rows)  # episodes reached
    assert out.read_text() in capsys.readouterr().out + "\n"
    assert "never cut: " in out.read_text().splitlines()[-2]  # the count of uncut episodes, then the runaways
    assert "ran away after" in out.read_text().splitlines()[-1]
    assert rows[0].split("|")[-3].strip() in ("0.00", "-0.00")  # the first level's creepage shift is itself
    median, p10 = (float(x) for x in rows[0].split("|")[-2].split("/"))  # the crest bound over the CoF
    assert 0.0 < p10 <= median < 1.1
    for bad in (["--hold-dc", "0"], ["--hold-dc", "0.95"], ["--out", str(out)]):  # crest <= DC; --out alone
        monkeypatch.setattr(sys, "argv", ["lag_near_peak.py", "--episodes", "0", "--levels", "0.9", *bad])
        with pytest.raises(SystemExit) as e:
            lag_near_peak.main()
        assert e.value.code == 2


def _window(creepage: float, peak: float, slip: bool = False) -> "lag_near_peak.Window":
    info = {"measurement": {"creepage_measured": creepage}, "ground_truth": {"peak_creepage": peak},
            "macro_slip": slip}
    return lag_near_peak.Window(1.0, None, info, False)


def test_the_crest_bound_over_the_cof_is_the_crest_less_a_bins_se():
    """The summary's crest column: (cycle crest - one bin's standard error) / the true CoF."""
    window = lag_near_peak.Window(1.0, None, {"measurement": {"coa_cycle_max": 0.30, "coa_cycle_bin_se": 0.01},
                                              "ground_truth": {"cof": 0.32}}, False)
    assert lag_near_peak._crest_bound_over_cof(window) == pytest.approx(0.29 / 0.32, rel=1e-12)


def test_creepage_shift_before_a_runaway():
    """The mean creepage's shift is the measured difference from the first window in peak creepages (a
    sensor offset cancels), and the runaway line reads it in the window before each runaway."""
    offset = 0.013  # a systematic creepage error: the same in every window of an episode
    calm = [_window(offset + 0.002, 0.004), _window(offset + 0.0024, 0.004)]
    runaway = [_window(offset + 0.002, 0.004), _window(offset + 0.003, 0.004), _window(0.5, 0.004, slip=True)]
    assert lag_near_peak._creepage_shift(calm, 1) == pytest.approx(0.1, abs=1e-9)
    assert lag_near_peak.before_runaway([calm, runaway]) == (
        "Episodes that ran away after their first window: 1; the measured mean creepage's shift in the window "
        "before, in peak creepages: median 0.25, largest 0.25.")
    assert lag_near_peak.before_runaway([calm]) == "No episode ran away after its first window."
