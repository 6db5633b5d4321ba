#!/usr/bin/env bash
# Rule 136 (docs/interrogator.md): G, rule 135's filter (runs/interrogator_far/ensemble, fitted by
# experiments/rules/rule135.sh fit) with the shipped guards and climb, against the shipped agent (its plays of rule
# 135, rule135shipped: the same commands).
#   experiments/rules/rule136.sh qualify   # the four validation plays and extremes_confirmation17
#   experiments/rules/rule136.sh confirm   # confirmation46 (at the draws, noise tripled, 0.1 s lag),
#                                          # torque_confirmation25 and extremes_confirmation18, both agents
set -e
cd "$(dirname "$0")/../.."  # the repository root
NAME=rule136G
BASE=rule135shipped
# g ARGS... / base ARGS...: validation_plays.py ARGS for G (the shipped guards: validation_plays.py's default) / for the
# shipped agent (qualify plays it only where its records of rule 135 are missing)
g() { python experiments/validation_plays.py "$NAME" --run runs/interrogator_far/ensemble "$@"; }
base() { python experiments/validation_plays.py "$BASE" "$@"; }
RULE=rule136
. experiments/rules/pairs.sh
. experiments/rules/far_checks.sh
case "$1" in
  qualify)
    g
    [ -f "out/records_${BASE}_motor_lag_s.json" ] || base
    X="--confirmation confirmation45 torque_confirmation24 extremes_confirmation17 --only extremes_confirmation17"
    g $X
    [ -f "out/records_${BASE}_extremes_confirmation17.json" ] || base $X
    check validation "validation validation_torque noise_level motor_lag_s" $FOUR
    check extremes "extremes_confirmation17" $EXTREMES
    ;;
  confirm)
    X="--confirmation confirmation46 torque_confirmation25 extremes_confirmation18"
    g $X
    base $X
    check confirmation "confirmation46 torque_confirmation25 confirmation46_noise_level confirmation46_motor_lag_s" \
      $FOUR
    check confirmation_extremes "extremes_confirmation18" $EXTREMES
    ;;
  *) echo "usage: experiments/rules/rule136.sh qualify|confirm" >&2; exit 2 ;;
esac
