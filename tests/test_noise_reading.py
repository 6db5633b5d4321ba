"""experiments/noise_reading.py: the noise the shipped interrogator reads from its first windows follows the
sensors' noise level, and a malformed option is refused before any simulation."""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "experiments"))
import noise_reading  # noqa: E402


def test_the_first_windows_read_noise_in_proportion_to_its_level():
    """The same episodes read the same noise samples scaled by the level: each window's fit residual is that noise
    whatever torque the climb drove there (the residual at level 0, what a sine does not fit, adds in quadrature
    and is under 2 % of level 1's)."""
    quiet, quiet_reported, _ = noise_reading.read_noise(1.0, {}, 2)
    loud, loud_reported, windows = noise_reading.read_noise(2.0, {}, 2)
    assert len(quiet) == len(loud) == 2 and len(windows) >= 2
    for a, b in [*zip(quiet, loud), *zip(quiet_reported, loud_reported)]:
        assert a > 0.0 and b / a == pytest.approx(2.0, rel=0.03)
    for clipped, reported in zip(quiet + loud, quiet_reported + loud_reported):
        assert reported >= clipped  # the clip only lowers a standard error


@pytest.mark.parametrize("bad, option", [(["--levels", "4"], "--levels"), (["--levels", "x"], "--levels"),
                                         (["--episodes", "0"], "--episodes")])
def test_a_malformed_option_is_one_line_and_exit_2(monkeypatch, capsys, bad, option):
    monkeypatch.setattr(sys, "argv", ["noise_reading.py", *bad])
    with pytest.raises(SystemExit) as e:
        noise_reading.main()
    assert e.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("noise_reading.py: error: ") and option in err, err
