#!/usr/bin/env bash
# Rule 112 (docs/interrogator.md): LF's networks fitted on collect_encoder.sh's climbs, then its five validation plays
set -e
cd "$(dirname "$0")/../.."  # the repository root
python experiments/train_interrogator.py --out runs/interrogator_encoder --climbs torque_wide=8000 \
  torque_wide_encoder=8000 --guard-climbs torque_wide=8000 procedural_torque_wide=8000 torque_wide_encoder=8000 \
  procedural_torque_wide_encoder=8000 --fit-only
python experiments/validation_plays.py rule112LF --run runs/interrogator_encoder/ensemble \
  --guards cof_gym/agents/policies/interrogator/guard_0 runs/interrogator_encoder/guard/ensemble --encoder-lag
