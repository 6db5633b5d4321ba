"""experiments/noise_colour_reading.py: each climb's noise colour, the lags an on-policy collection drew (read from
its file name), the table's rows; bad input exits 2 with one line naming the argument."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from interrogator_helpers import climbs_reading

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = ROOT / "experiments" / "noise_colour_reading.py"


def test_each_climb_reads_the_least_colour_of_its_first_windows(monkeypatch):
    monkeypatch.syspath_prepend(str(SCRIPT.parent))
    from noise_colour_reading import climb_colours

    # climb 0: colours 3, 2, 5 and a fourth window beyond the first three; climb 1: none read (a multi-tone climb)
    data = climbs_reading([0, 0, 0, 0, 1], se_reported_deg=[1.0, 1.0, 1.0, 1.0, 2.0],
                          se_corrected_deg=[3.0, 2.0, 5.0, 0.5, 180.0], frequency_hz=[5.0] * 5)
    np.testing.assert_array_equal(climb_colours(data)[0], [2.0, 0.0])


def test_the_lags_come_from_an_encoder_collections_name_and_seeds(monkeypatch):
    monkeypatch.syspath_prepend(str(SCRIPT.parent))
    from noise_colour_reading import climb_lags_s, collection_name
    from train_estimator import ON_POLICY

    first_seed, draws = ON_POLICY["env_encoder"]
    lags = climb_lags_s(collection_name(Path("runs/x/onpolicy_env_encoder_d1179b8ae0d9.npz")), 3)
    np.testing.assert_array_equal(lags, [draws.encoder_lag_s(first_seed + i) for i in range(3)])
    low, high = draws.encoder_lags_s
    assert np.all((lags >= low) & (lags <= high)) and len(set(lags)) == 3
    assert climb_lags_s(collection_name(Path("runs/x/onpolicy_env_d1179b8ae0d9.npz")), 3) is None  # a sharp one
    assert collection_name(Path("runs/x/climbs_torque_wide.npz")) is None  # not an on-policy collection
    assert climb_lags_s(None, 3) is None


def test_a_row_gives_the_percentiles_and_the_share_above_the_threshold(monkeypatch):
    monkeypatch.syspath_prepend(str(SCRIPT.parent))
    from noise_colour_reading import row

    noise = np.array([0.5, 2.0, 3.0, 4.0])
    flagged = np.array([False, False, True, True])
    assert row("x", np.array([1.0, 2.0, 3.0, 4.0]), noise, flagged, 1.0) == \
        "| x | 4 | 1.00 / 1.03 / 2.50 / 3.97 / 4.00 | 0.5000 | 25.0 | 50.0 |"


def test_the_table_of_a_climbs_file(tmp_path, capsys, monkeypatch):
    monkeypatch.syspath_prepend(str(SCRIPT.parent))
    import sys

    import noise_colour_reading

    path = tmp_path / "onpolicy_env_encoder_0123abcd.npz"
    # compliance 0.5 and 1000 N m at 5 Hz: a lock-in noise of 0.2778 N m s, far above the floor
    climbs_reading([0, 1, 1], se_reported_deg=[1.0, 1.0, 1.0], se_corrected_deg=[1.0, 4.0, 5.0],
                   compliance=[0.5] * 3, amplitude_nm=[1000.0] * 3, frequency_hz=[5.0] * 3).save(path)
    monkeypatch.setattr(sys, "argv", [str(SCRIPT), str(path), "--out", str(tmp_path / "t.md")])
    noise_colour_reading.main()
    text = (tmp_path / "t.md").read_text()
    assert "| env_encoder | 2 | 1.00 / 1.03 / 2.50 / 3.97 / 4.00 | 0.2778 | 0.0 | 50.0 |" in text
    assert text == capsys.readouterr().out


@pytest.mark.parametrize("args, name", [(["/nonexistent.npz"], "climbs: /nonexistent.npz"), ([], "required: FILE")])
def test_bad_input_exits_2_naming_the_argument(args, name, experiment_exit):
    code, last = experiment_exit("noise_colour_reading", args)
    assert code == 2 and last.startswith("noise_colour_reading.py: error: ") and name in last
