#!/usr/bin/env bash
# Rule 143 (docs/interrogator.md): ER, the shipped agent with an on-policy estimator that reads the creepage's rise
# (runs/estimator_rise/ensemble, estimate_from guard_estimator_pooled), against the shipped agent (its plays of rule
# 135, rule135shipped: the same commands).
#   experiments/rules/rule143.sh fit       # the two estimators (train_estimator.py), the rise one and the plain one
#   experiments/rules/rule143.sh qualify   # the four validation plays and extremes_confirmation17
#   experiments/rules/rule143.sh confirm   # confirmation46 (at the draws, noise tripled, 0.1 s lag),
#                                          # torque_confirmation25 and extremes_confirmation18, both agents
set -e
cd "$(dirname "$0")/../.."  # the repository root
. experiments/rules/pairs.sh
. experiments/rules/far_checks.sh
if [ "$1" = fit ]; then
  python experiments/train_estimator.py --out runs/estimator_rise --features creepage_rise
  mkdir -p runs/estimator_plain && cp runs/estimator_rise/onpolicy_*.npz runs/estimator_plain/
  python experiments/train_estimator.py --out runs/estimator_plain
  exit 0
fi
RULE=rule143 NAME=rule143ER BASE=rule135shipped
g() { python experiments/validation_plays.py "$NAME" --estimators runs/estimator_rise/ensemble \
  --set estimate_from=guard_estimator_pooled "$@"; }
judge_part "$1"
