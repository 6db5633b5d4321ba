#!/usr/bin/env bash
# Rule 122 (docs/interrogator.md): TUg's five validation plays (rule120_plays.sh's pooled directories)
set -e
cd "$(dirname "$0")/../.."  # the repository root
python experiments/validation_plays.py rule122TUg --run runs/union120/filter --encoder-lag \
  --guards cof_gym/agents/policies/interrogator/guard_0 runs/union120/guard_1 cof_gym/agents/policies/interrogator/guard_1
