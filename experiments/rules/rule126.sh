#!/usr/bin/env bash
# Rule 126 (docs/interrogator.md): TUw's pools (the shipped networks and T's, read within generations), its five
# validation plays and its ten plays of the spent sets
set -e
cd "$(dirname "$0")/../.."  # the repository root
SHIPPED=cof_gym/agents/policies/interrogator
[ -d runs/union126/filter ] || python experiments/pool_ensembles.py --within-generations --out runs/union126/filter \
  $SHIPPED runs/interrogator_three/ensemble
[ -d runs/union126/guard_1 ] || python experiments/pool_ensembles.py --within-generations --out runs/union126/guard_1 \
  $SHIPPED/guard_1 runs/interrogator_three/guard/ensemble
G="--run runs/union126/filter --guards $SHIPPED/guard_0 runs/union126/guard_1"
python experiments/validation_plays.py rule126TUw $G --encoder-lag
for sets in "confirmation37 torque_confirmation18 extremes_confirmation9" \
            "confirmation38 torque_confirmation19 extremes_confirmation10"; do
  python experiments/validation_plays.py rule126TUw $G --confirmation $sets
done
