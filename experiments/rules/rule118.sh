#!/usr/bin/env bash
# Rule 118 (docs/interrogator.md): U2's five validation plays (rule115.sh's pooled filter, the shipped guards)
set -e
cd "$(dirname "$0")/../.."  # the repository root
python experiments/validation_plays.py rule118U2 --run runs/union115/filter --encoder-lag
