#!/usr/bin/env bash
# Rule 120 (docs/interrogator.md): T's networks fitted on collect_three.sh's climbs (about 38 minutes on 2 cores)
set -e
cd "$(dirname "$0")/../.."  # the repository root
python experiments/train_interrogator.py --out runs/interrogator_three --climbs torque_wide=8000 \
  torque_wide_encoder=8000 noisy_torque_wide=8000 --guard-climbs torque_wide=8000 procedural_torque_wide=8000 \
  torque_wide_encoder=8000 procedural_torque_wide_encoder=8000 noisy_torque_wide=8000 \
  procedural_noisy_torque_wide=8000 --fit-only
