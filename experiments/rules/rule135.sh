#!/usr/bin/env bash
# Rule 135 (docs/interrogator.md): F, the shipped recipe's three steps with the far-peak procedural climbs added to
# every fit, against the shipped agent.
#   experiments/rules/rule135.sh fit       # the three steps (the caches in runs/interrogator_far, collected first
#                                          # where missing): 74.5 minutes from nothing, alone on 2 cores (session 71:
#                                          # each cache about 9 minutes, the on-policy climbs 11, the fits the rest)
#   experiments/rules/rule135.sh qualify   # the four validation plays and extremes_confirmation17, both agents
#   experiments/rules/rule135.sh confirm   # confirmation46 (at the draws, noise tripled, 0.1 s lag),
#                                          # torque_confirmation25 and extremes_confirmation18, both agents
set -e
cd "$(dirname "$0")/../.."  # the repository root
OUT=runs/interrogator_far
NAME=rule135F
BASE=rule135shipped
STEP1="--out $OUT --climbs torque_wide=8000 procedural_far_torque_wide=8000 --guard-climbs torque_wide=8000
  procedural_torque_wide=8000 procedural_far_torque_wide=8000 --torque-balance-lag 65"
# play_both ARGS...: validation_plays.py ARGS for F and for the shipped agent
play_both() {
  python experiments/validation_plays.py "$NAME" --run "$OUT/ensemble" \
    --guards "$OUT/guard/ensemble" "$OUT/probing_guard/ensemble" "$@"
  base "$@"
}
RULE=rule135
. experiments/rules/pairs.sh
. experiments/rules/far_checks.sh
. experiments/rules/recipe_steps.sh
case "$1" in
  fit) fit_three_steps "$OUT" runs/far_step1_policy runs/estimator_far ;;
  qualify)
    play_both
    play_both --confirmation confirmation45 torque_confirmation24 extremes_confirmation17 \
      --only extremes_confirmation17
    check validation "validation validation_torque noise_level motor_lag_s" $FOUR
    check extremes "extremes_confirmation17" $EXTREMES
    ;;
  confirm)
    play_both --confirmation confirmation46 torque_confirmation25 extremes_confirmation18
    check confirmation "confirmation46 torque_confirmation25 confirmation46_noise_level confirmation46_motor_lag_s" \
      $FOUR
    check confirmation_extremes "extremes_confirmation18" $EXTREMES
    ;;
  *) echo "usage: experiments/rules/rule135.sh fit|qualify|confirm" >&2; exit 2 ;;
esac
