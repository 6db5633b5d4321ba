#!/usr/bin/env bash
# Rule 138 (docs/interrogator.md): the shipped agent with a faster approach, approach_fraction 0.25 (a25) or 0.5 (a50)
# (far from the peak a step may close that fraction of the cautious gap where that is more than max_log_step 0.15),
# against the shipped agent (its plays of rule 135, rule135shipped: the same commands).
#   experiments/rules/rule138.sh qualify a25|a50   # the four validation plays and extremes_confirmation17
#   experiments/rules/rule138.sh confirm a25|a50   # confirmation46 (at the draws, noise tripled, 0.1 s lag),
#                                                  # torque_confirmation25 and extremes_confirmation18, both agents
set -e
cd "$(dirname "$0")/../.."  # the repository root
case "$2" in
  a25) FRACTION=0.25 ;;
  a50) FRACTION=0.5 ;;
  *) echo "usage: experiments/rules/rule138.sh qualify|confirm a25|a50" >&2; exit 2 ;;
esac
RULE=rule138$2
NAME=rule138$2
BASE=rule135shipped
# g ARGS... / base ARGS...: validation_plays.py ARGS for the candidate / for the shipped agent
g() { python experiments/validation_plays.py "$NAME" --set approach_fraction=$FRACTION "$@"; }
base() { python experiments/validation_plays.py "$BASE" "$@"; }
. experiments/rules/pairs.sh
. experiments/rules/far_checks.sh
judge_part "$1"
