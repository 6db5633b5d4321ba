"""experiments/crest_tradeoff.py's command line: bad input exits 2 with one line naming the option,
before any episode is played."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parent.parent / "experiments" / "crest_tradeoff.py"


@pytest.mark.parametrize("args, option", [(["--cautions", "-1"], "--cautions"), (["--targets", "1.5"], "--targets"),
                                          (["--run", "no/such/run"], "--run"),
                                          (["--spread-cautions", "nan"], "--spread-cautions"),
                                          (["--guards", "no/such/guard"], "--guards")])
def test_bad_options_exit_2_naming_the_option(args: list[str], option: str, tmp_path: Path) -> None:
    done = subprocess.run([sys.executable, str(SCRIPT), *args, "--out", str(tmp_path / "t.md")],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 2
    assert option in done.stderr.strip().splitlines()[-1]
    assert not (tmp_path / "t.md").exists()
