#!/usr/bin/env bash
# Rule 134 (docs/interrogator.md): S (the shipped agent with slow_drive_applied_estimate=true) and the shipped agent on
# the same episodes, then the rule's checks (a)-(d).
#   experiments/rules/rule134.sh qualify   # spent sets: the validation grids at the draws and with a 0.1 s drive lag,
#                                          # confirmation43 with the lag, extremes_confirmation17
#   experiments/rules/rule134.sh confirm   # fresh sets: confirmation46 at the draws and with the lag,
#                                          # extremes_confirmation18
set -e
cd "$(dirname "$0")/../.."  # the repository root
NAME=rule134S
BASE=rule134shipped
# play_both ARGS...: validation_plays.py ARGS for S and for the shipped agent
play_both() {
  python experiments/validation_plays.py "$NAME" --set slow_drive_applied_estimate=true "$@"
  python experiments/validation_plays.py "$BASE" "$@"
}
. experiments/rules/pairs.sh
# check OUT PLAYS OPTIONS...: check_plays with the rule's (a) on every pair, into out/rule_check_rule134_OUT.md
check() { local out=$1; shift; check_plays "rule134_$out" "$@" --same-climbs; }
case "$1" in
  qualify)
    play_both --only validation motor_lag_s
    play_both --confirmation confirmation43 torque_confirmation24 extremes_confirmation17 \
      --only confirmation43_motor_lag_s extremes_confirmation17
    check slow_drive "motor_lag_s confirmation43_motor_lag_s" --gain --errors --family-wise
    check extremes "extremes_confirmation17" --no-loss --errors --family-wise --strict-grid none
    check draws "validation" --no-loss
    ;;
  confirm)
    play_both --confirmation confirmation46 torque_confirmation24 extremes_confirmation18 \
      --only confirmation46 confirmation46_motor_lag_s extremes_confirmation18
    check confirmation_slow_drive "confirmation46_motor_lag_s" --gain --errors --family-wise
    check confirmation_extremes "extremes_confirmation18" --no-loss --errors --family-wise --strict-grid none
    check confirmation_draws "confirmation46" --no-loss
    ;;
  *) echo "usage: experiments/rules/rule134.sh qualify|confirm" >&2; exit 2 ;;
esac
