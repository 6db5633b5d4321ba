#!/usr/bin/env bash
# Rule 140 (docs/interrogator.md): FR, rule 135's F (the shipped recipe's three steps with the far-peak procedural
# climbs added to every fit) with the creepage_rise feature block read by the filter and both guards, against the
# shipped agent (its plays of rule 135, rule135shipped: the same commands).
#   experiments/rules/rule140.sh fit       # the three steps on rule 135's climb caches (runs/interrogator_far,
#                                          # linked into runs/interrogator_far_rise; rule135.sh fit collects them where
#                                          # missing), step 2's on-policy climbs collected with FR's own step 1
#   experiments/rules/rule140.sh qualify   # the four validation plays and extremes_confirmation17
#   experiments/rules/rule140.sh trace     # information: FR as a policy directory (runs/far_rise_policy), its climbs
#                                          # of the two far tables session 71 traced (trace_climb.py)
#   experiments/rules/rule140.sh confirm   # confirmation46 (at the draws, noise tripled, 0.1 s lag),
#                                          # torque_confirmation25 and extremes_confirmation18, both agents
set -e
cd "$(dirname "$0")/../.."  # the repository root
OUT=runs/interrogator_far_rise
RULE=rule140
NAME=rule140FR
BASE=rule135shipped
STEP1="--out $OUT --climbs torque_wide=8000 procedural_far_torque_wide=8000 --guard-climbs torque_wide=8000
  procedural_torque_wide=8000 procedural_far_torque_wide=8000 --torque-balance-lag 65 --features creepage_rise"
. experiments/rules/pairs.sh
. experiments/rules/far_checks.sh
. experiments/rules/recipe_steps.sh
if [ "$1" = fit ]; then
  fit_on_far_caches "$OUT" runs/far_rise_step1_policy runs/estimator_far_rise torque_wide procedural_torque_wide \
    procedural_far_torque_wide
elif [ "$1" = trace ]; then
  python experiments/assemble_policy.py --filter "$OUT/ensemble" --guards "$OUT/guard/ensemble" \
    "$OUT/probing_guard/ensemble" --out runs/far_rise_policy
  python experiments/trace_climb.py --suite experiments/suites/v2_extremes_confirmation17_grid.json --episodes 3 22 \
    --agent runs/far_rise_policy
else
  judge_part "$1"
fi
