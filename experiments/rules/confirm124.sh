#!/usr/bin/env bash
# Rule 124's confirmation plays (docs/interrogator.md): confirm124.sh NAME THRESHOLD EXPONENT (the candidate rule 124
# chose), the shipped agent and the hand-built agents on the three unplayed sets
set -e
cd "$(dirname "$0")/../.."  # the repository root
S="--confirmation confirmation40 torque_confirmation21 extremes_confirmation12 --encoder-lag"
python experiments/validation_plays.py "$1" --run runs/union120/filter \
  --guards cof_gym/agents/policies/interrogator/guard_0 runs/union120/guard_1 \
  --set "creep_while_std=$2" "noise_creep_exponent=$3" $S
python experiments/validation_plays.py rule124shipped $S
python experiments/validation_plays.py --hand-built $S
