#!/usr/bin/env bash
# Rule 137 (docs/interrogator.md): H, the shipped filter and climb behind rule 135's two guards
# (runs/interrogator_far/guard/ensemble and probing_guard/ensemble, fitted by experiments/rules/rule135.sh fit),
# against the shipped agent (its plays of rule 135, rule135shipped: the same commands).
#   experiments/rules/rule137.sh qualify   # the four validation plays and extremes_confirmation17
#   experiments/rules/rule137.sh confirm   # confirmation46 (at the draws, noise tripled, 0.1 s lag),
#                                          # torque_confirmation25 and extremes_confirmation18, both agents
#   experiments/rules/rule137.sh spent     # information after H failed to qualify, no rule: both agents on the spent
#                                          # confirmation45 (at the draws, noise tripled, 0.1 s lag) and
#                                          # torque_confirmation24, read as (i) reads the four validation plays
set -e
cd "$(dirname "$0")/../.."  # the repository root
RULE=rule137
NAME=rule137H
BASE=rule135shipped
# g ARGS...: validation_plays.py ARGS for H (the shipped filter: validation_plays.py's default)
g() {
  python experiments/validation_plays.py "$NAME" --guards runs/interrogator_far/guard/ensemble \
    runs/interrogator_far/probing_guard/ensemble "$@"
}
. experiments/rules/pairs.sh
. experiments/rules/far_checks.sh
if [ "$1" = spent ]; then
  X="--confirmation confirmation45 torque_confirmation24 extremes_confirmation17 --only confirmation45
    confirmation45_noise_level confirmation45_motor_lag_s torque_confirmation24"
  g $X
  base $X
  check spent "confirmation45 torque_confirmation24 confirmation45_noise_level confirmation45_motor_lag_s" $FOUR
else
  judge_part "$1"
fi
