#!/usr/bin/env bash
# Rule 115 (docs/interrogator.md): U's ensembles (the shipped members and LF's pooled), then its five validation plays
# and its ten plays of the spent sets (about 16 minutes of plays on 2 cores)
set -e
cd "$(dirname "$0")/../.."  # the repository root
experiments/rules/union.sh runs/union115 runs/interrogator_encoder
G="--run runs/union115/filter --guards cof_gym/agents/policies/interrogator/guard_0 runs/union115/guard_1"
python experiments/validation_plays.py rule115U $G --encoder-lag
python experiments/validation_plays.py rule115U $G --confirmation confirmation37 torque_confirmation18 extremes_confirmation9
python experiments/validation_plays.py rule115U $G --confirmation confirmation38 torque_confirmation19 extremes_confirmation10
