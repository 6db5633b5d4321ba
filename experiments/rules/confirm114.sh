#!/usr/bin/env bash
# Rule 114's confirmation plays (docs/interrogator.md): LFf, the shipped agent and the hand-built agents
set -e
cd "$(dirname "$0")/../.."  # the repository root
S="--confirmation confirmation38 torque_confirmation19 extremes_confirmation10 --encoder-lag"
python experiments/validation_plays.py rule114LFf --run runs/interrogator_encoder/ensemble $S
python experiments/validation_plays.py rule114shipped $S
python experiments/validation_plays.py --hand-built $S
