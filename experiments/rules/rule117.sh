#!/usr/bin/env bash
# Rule 117 (docs/interrogator.md): Us025's and Us05's five validation plays (rule115.sh's pooled directories)
set -e
cd "$(dirname "$0")/../.."  # the repository root
G="--run runs/union115/filter --guards cof_gym/agents/policies/interrogator/guard_0 runs/union115/guard_1"
python experiments/validation_plays.py rule117Us025 $G --set spread_caution=0.25 --encoder-lag
python experiments/validation_plays.py rule117Us05 $G --set spread_caution=0.5 --encoder-lag
