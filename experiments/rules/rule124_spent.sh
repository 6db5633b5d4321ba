#!/usr/bin/env bash
# Rule 124 (docs/interrogator.md): a qualifying candidate's ten plays of the spent sets (rule 115's (iii)):
# rule124_spent.sh NAME THRESHOLD EXPONENT, e.g. rule124_spent.sh rule124TUkge 0.089 0.70
set -e
cd "$(dirname "$0")/../.."  # the repository root
G="--run runs/union120/filter --guards cof_gym/agents/policies/interrogator/guard_0 runs/union120/guard_1"
for sets in "confirmation37 torque_confirmation18 extremes_confirmation9" \
            "confirmation38 torque_confirmation19 extremes_confirmation10"; do
  python experiments/validation_plays.py "$1" $G --set "creep_while_std=$2" "noise_creep_exponent=$3" --confirmation $sets
done
