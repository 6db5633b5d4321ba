#!/usr/bin/env bash
# Rule 124 (docs/interrogator.md): TUke's and TUkge's five validation plays (rule120_plays.sh's pooled directories, the
# slow probe's threshold and noise exponent from match_creep_threshold.py)
set -e
cd "$(dirname "$0")/../.."  # the repository root
G="--run runs/union120/filter --guards cof_gym/agents/policies/interrogator/guard_0 runs/union120/guard_1"
python experiments/validation_plays.py rule124TUke $G --set creep_while_std=0.086 noise_creep_exponent=0.71 --encoder-lag
python experiments/validation_plays.py rule124TUkge $G --set creep_while_std=0.089 noise_creep_exponent=0.70 --encoder-lag
