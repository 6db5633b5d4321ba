#!/usr/bin/env bash
# Rule 121 (docs/interrogator.md): TU2's and TU3's five validation plays each (rule120_plays.sh's pooled filter)
set -e
cd "$(dirname "$0")/../.."  # the repository root
python experiments/validation_plays.py rule121TU2 --run runs/union120/filter --encoder-lag
python experiments/validation_plays.py rule121TU3 --run runs/union120/filter --encoder-lag \
  --guards cof_gym/agents/policies/interrogator/guard_0 cof_gym/agents/policies/interrogator/guard_1 runs/interrogator_three/guard/ensemble
