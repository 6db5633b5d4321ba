#!/usr/bin/env bash
# Rule 120 (docs/interrogator.md): TU's ensembles (the shipped members and T's pooled, as rule115.sh pools U's), then
# T's and TU's five validation plays each, then TU's ten plays of the spent sets (session 63)
set -e
cd "$(dirname "$0")/../.."  # the repository root
experiments/rules/union.sh runs/union120 runs/interrogator_three
python experiments/validation_plays.py rule120T --run runs/interrogator_three/ensemble \
  --guards cof_gym/agents/policies/interrogator/guard_0 runs/interrogator_three/guard/ensemble --encoder-lag
G="--run runs/union120/filter --guards cof_gym/agents/policies/interrogator/guard_0 runs/union120/guard_1"
python experiments/validation_plays.py rule120TU $G --encoder-lag
python experiments/validation_plays.py rule120TU $G --confirmation confirmation37 torque_confirmation18 extremes_confirmation9
python experiments/validation_plays.py rule120TU $G --confirmation confirmation38 torque_confirmation19 extremes_confirmation10
