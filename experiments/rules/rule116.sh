#!/usr/bin/env bash
# Rule 116 (docs/interrogator.md): Us1's and Us2's five validation plays (rule115.sh's pooled directories)
set -e
cd "$(dirname "$0")/../.."  # the repository root
G="--run runs/union115/filter --guards cof_gym/agents/policies/interrogator/guard_0 runs/union115/guard_1"
for k in 1 2; do python experiments/validation_plays.py rule116Us$k $G --set spread_caution=$k --encoder-lag; done
