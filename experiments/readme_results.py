"""Copy measured agent results into the README (run from the repository root after the commands below),
so that its tables are generated, never typed:

    cof-gym evaluate --out out/evaluate                                              # v2 default suite
    cof-gym evaluate --suite experiments/suites/v2_no_systematic_errors.json --episodes 60 --out out/evaluate-v2-no-errors
    cof-gym evaluate --suite experiments/suites/v2_heldout_grid.json --out out/evaluate-v2-heldout
    cof-gym evaluate --suite experiments/suites/v1_default.json --episodes 60 --out out/evaluate-v1
    cof-gym evaluate --suite experiments/suites/heldout_grid.json --out out/evaluate-heldout   # v1 held-out
    cof-gym bench --seconds 10 --markdown out/bench.md
    python experiments/ppo_seeds.py --runs runs/ppo_lo_s0 runs/ppo_lo_s1 runs/ppo_lo_s2 --out out/ppo_seeds
    python experiments/readme_results.py

Each block sits between ``<!-- results:NAME:begin -->`` and ``<!-- results:NAME:end -->`` in README.md;
a block whose source file is missing is left as it is (and reported).
"""

from __future__ import annotations

import re
import shutil
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
SOURCES = {
    "default": ROOT / "out" / "evaluate" / "summary.md",
    "v2_no_errors": ROOT / "out" / "evaluate-v2-no-errors" / "summary.md",
    "v2_heldout": ROOT / "out" / "evaluate-v2-heldout" / "summary.md",
    "v1_default": ROOT / "out" / "evaluate-v1" / "summary.md",
    "bench": ROOT / "out" / "bench.md",
    "heldout": ROOT / "out" / "evaluate-heldout" / "summary.md",
    "ppo_seeds": ROOT / "out" / "ppo_seeds" / "report.md",
}


def body(path: Path) -> str:
    """The file without its level-1 title (the README's section says what it is)."""
    lines = path.read_text().strip().splitlines()
    lines = [f"*{line[3:]}*" if line.startswith("## ") else line for line in lines if not line.startswith("# ")]
    return "\n".join(lines).strip()


FIGURES = {  # figure of a run -> where the README shows it
    ROOT / "out" / "evaluate" / "error_vs_creepage_error.png": ROOT / "docs" / "evaluate_error_vs_creepage_error.png",
}


def main() -> None:
    for src, dst in FIGURES.items():
        if src.is_file():
            shutil.copyfile(src, dst)
            print(f"{dst.relative_to(ROOT)} <- {src.relative_to(ROOT)}")
        else:
            print(f"{src} missing: {dst.relative_to(ROOT)} left as it is")
    text = README.read_text()
    for name, path in SOURCES.items():
        pattern = re.compile(rf"(<!-- results:{name}:begin -->\n).*?(<!-- results:{name}:end -->)", re.S)
        if not pattern.search(text):
            print(f"README has no results:{name} block")
            continue
        if not path.is_file():
            print(f"{path} missing: results:{name} left as it is")
            continue
        text = pattern.sub(lambda m: m.group(1) + body(path) + "\n" + m.group(2), text)
        print(f"results:{name} <- {path.relative_to(ROOT)}")
    README.write_text(text)


if __name__ == "__main__":
    main()
