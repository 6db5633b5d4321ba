#!/usr/bin/env bash
# Rule 119 (docs/interrogator.md): U2's ten plays of the spent sets
set -e
cd "$(dirname "$0")/../.."  # the repository root
python experiments/validation_plays.py rule119U2 --run runs/union115/filter --confirmation confirmation37 torque_confirmation18 extremes_confirmation9
python experiments/validation_plays.py rule119U2 --run runs/union115/filter --confirmation confirmation38 torque_confirmation19 extremes_confirmation10
