#!/usr/bin/env bash
# Rule 123 (docs/interrogator.md): TUk's and TUkg's five validation plays (rule120_plays.sh's pooled directories, the
# slow probe's threshold from match_creep_threshold.py)
set -e
cd "$(dirname "$0")/../.."  # the repository root
G="--run runs/union120/filter --guards cof_gym/agents/policies/interrogator/guard_0 runs/union120/guard_1"
python experiments/validation_plays.py rule123TUk $G --set creep_while_std=0.086 --encoder-lag
python experiments/validation_plays.py rule123TUkg $G --set creep_while_std=0.089 --encoder-lag
