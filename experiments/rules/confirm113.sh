#!/usr/bin/env bash
# Rule 113's confirmation plays (docs/interrogator.md): LF, the shipped agent and the hand-built agents
set -e
cd "$(dirname "$0")/../.."  # the repository root
S="--confirmation confirmation37 torque_confirmation18 extremes_confirmation9 --encoder-lag"
python experiments/validation_plays.py rule113LF --run runs/interrogator_encoder/ensemble \
  --guards cof_gym/agents/policies/interrogator/guard_0 runs/interrogator_encoder/guard/ensemble $S
python experiments/validation_plays.py rule113shipped $S
python experiments/validation_plays.py --hand-built $S
