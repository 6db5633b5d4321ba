#!/usr/bin/env bash
# Rule 141 (docs/interrogator.md): R, the shipped recipe's three steps (rule 74's W, its own climbs: no far-peak
# curves) with the creepage_rise feature block read by the filter and both guards, against the shipped agent (its plays
# of rule 135, rule135shipped: the same commands).
#   experiments/rules/rule141.sh fit       # the three steps on the recipe's climb caches (runs/interrogator_far's,
#                                          # linked into runs/interrogator_rise; rule135.sh fit collects them where
#                                          # missing), step 2's on-policy climbs collected with R's own step 1
#   experiments/rules/rule141.sh qualify   # the four validation plays and extremes_confirmation17
#   experiments/rules/rule141.sh confirm   # confirmation46 (at the draws, noise tripled, 0.1 s lag),
#                                          # torque_confirmation25 and extremes_confirmation18, both agents
set -e
cd "$(dirname "$0")/../.."  # the repository root
OUT=runs/interrogator_rise
RULE=rule141
NAME=rule141R
BASE=rule135shipped
STEP1="--out $OUT --climbs torque_wide=8000 --guard-climbs torque_wide=8000 procedural_torque_wide=8000
  --torque-balance-lag 65 --features creepage_rise"
. experiments/rules/pairs.sh
. experiments/rules/far_checks.sh
. experiments/rules/recipe_steps.sh
if [ "$1" = fit ]; then
  fit_on_far_caches "$OUT" runs/rise_step1_policy runs/estimator_rise torque_wide procedural_torque_wide
else
  judge_part "$1"
fi
