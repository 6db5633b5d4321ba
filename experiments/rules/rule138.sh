#!/usr/bin/env bash
# Rule 138 (docs/interrogator.md): the shipped agent with a faster approach, approach_fraction 0.25 (a25) or 0.5 (a50)
# (far from the peak a step may close that fraction of the cautious gap where that is more than max_log_step 0.15),
# against the shipped agent (its plays of rule 135, rule135shipped: the same commands).
#   experiments/rules/rule138.sh qualify a25|a50   # the four validation plays and extremes_confirmation17
#   experiments/rules/rule138.sh confirm a25|a50   # confirmation46 (at the draws, noise tripled, 0.1 s lag),
#                                                  # torque_confirmation25 and extremes_confirmation18, both agents
#   experiments/rules/rule138.sh explore           # information after neither qualified, no rule: the shipped agent
#                                                  # with the slow probe's step creep_log_step 0.02 or 0.025, alone and
#                                                  # with either approach, on the four validation plays; then every
#                                                  # play of the rule side by side (out/frontier_rule138.md)
set -e
cd "$(dirname "$0")/../.."  # the repository root
BASE=rule135shipped
. experiments/rules/pairs.sh
. experiments/rules/far_checks.sh
FOUR_PLAYS="validation validation_torque noise_level motor_lag_s"
# plays NAME...: each name's four validation plays joined by + (frontier.py counts them as one play)
plays() {
  for n in "$@"; do
    printf '%s+' out/records_"${n}"_{validation,validation_torque,noise_level,motor_lag_s}.json | sed 's/+$/\n/'
  done
}
if [ "$1" = explore ]; then
  for fraction in 0 0.25 0.5; do
    for step in 0.02 0.025; do
      NAME=x138a${fraction#0.}c${step#0.0}
      APPROACH=approach_fraction=$fraction
      [ "$fraction" = 0 ] && APPROACH=""  # the shipped approach, as its records name it
      python experiments/validation_plays.py "$NAME" --set $APPROACH creep_log_step=$step --only $FOUR_PLAYS
      check_plays "$NAME" "$FOUR_PLAYS" $FOUR
    done
  done
  python experiments/frontier.py $(plays $BASE rule138a25 rule138a50 x138a0c2 x138a0c25 x138a25c2 x138a25c25 x138a5c2 \
    x138a5c25) --shipped $(plays $BASE) --endings --out out/frontier_rule138.md
  exit 0
fi
case "$2" in
  a25) FRACTION=0.25 ;;
  a50) FRACTION=0.5 ;;
  *) echo "usage: experiments/rules/rule138.sh qualify|confirm a25|a50, or explore" >&2; exit 2 ;;
esac
RULE=rule138$2
NAME=rule138$2
# g ARGS...: validation_plays.py ARGS for the candidate
g() { python experiments/validation_plays.py "$NAME" --set approach_fraction=$FRACTION "$@"; }
judge_part "$1"
