#!/usr/bin/env bash
# Rule 126's confirmation plays (docs/interrogator.md): TUw (rule126.sh's pools), the shipped agent and the hand-built
# agents on the three unplayed sets and the first set's lagged play
set -e
cd "$(dirname "$0")/../.."  # the repository root
S="--confirmation confirmation41 torque_confirmation22 extremes_confirmation13 --encoder-lag"
python experiments/validation_plays.py rule126TUw --run runs/union126/filter \
  --guards cof_gym/agents/policies/interrogator/guard_0 runs/union126/guard_1 $S
python experiments/validation_plays.py rule126shipped $S
python experiments/validation_plays.py --hand-built $S
