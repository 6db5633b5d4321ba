#!/usr/bin/env bash
# Rule 123 (docs/interrogator.md): a qualifying candidate's ten plays of the spent sets (rule 115's (iii)):
# rule123_spent.sh NAME THRESHOLD, e.g. rule123_spent.sh rule123TUk 0.086
set -e
cd "$(dirname "$0")/../.."  # the repository root
G="--run runs/union120/filter --guards cof_gym/agents/policies/interrogator/guard_0 runs/union120/guard_1"
for sets in "confirmation37 torque_confirmation18 extremes_confirmation9" \
            "confirmation38 torque_confirmation19 extremes_confirmation10"; do
  python experiments/validation_plays.py "$1" $G --set "creep_while_std=$2" --confirmation $sets
done
