#!/usr/bin/env bash
# Rule 123's confirmation plays (docs/interrogator.md): confirm123.sh NAME THRESHOLD (the candidate rule 123 chose),
# the shipped agent and the hand-built agents on the three unplayed sets
set -e
cd "$(dirname "$0")/../.."  # the repository root
S="--confirmation confirmation39 torque_confirmation20 extremes_confirmation11 --encoder-lag"
python experiments/validation_plays.py "$1" --run runs/union120/filter \
  --guards cof_gym/agents/policies/interrogator/guard_0 runs/union120/guard_1 --set "creep_while_std=$2" $S
python experiments/validation_plays.py rule123shipped $S
python experiments/validation_plays.py --hand-built $S
