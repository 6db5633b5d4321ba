#!/usr/bin/env bash
# Rule 125's confirmation plays (docs/interrogator.md): TUk (the pooled networks, creep_while_std 0.086), the shipped
# agent and the hand-built agents on the three unplayed sets and the first set's lagged play
set -e
cd "$(dirname "$0")/../.."  # the repository root
S="--confirmation confirmation40 torque_confirmation21 extremes_confirmation12 --encoder-lag"
python experiments/validation_plays.py rule125TUk --run runs/union120/filter \
  --guards cof_gym/agents/policies/interrogator/guard_0 runs/union120/guard_1 --set creep_while_std=0.086 $S
python experiments/validation_plays.py rule125shipped $S
python experiments/validation_plays.py --hand-built $S
