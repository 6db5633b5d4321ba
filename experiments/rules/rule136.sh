#!/usr/bin/env bash
# Rule 136 (docs/interrogator.md): G, rule 135's filter (runs/interrogator_far/ensemble, fitted by
# experiments/rules/rule135.sh fit) with the shipped guards and climb, against the shipped agent (its plays of rule
# 135, rule135shipped: the same commands).
#   experiments/rules/rule136.sh qualify   # the four validation plays and extremes_confirmation17
#   experiments/rules/rule136.sh confirm   # confirmation46 (at the draws, noise tripled, 0.1 s lag),
#                                          # torque_confirmation25 and extremes_confirmation18, both agents
set -e
cd "$(dirname "$0")/../.."  # the repository root
RULE=rule136
NAME=rule136G
BASE=rule135shipped
# g ARGS...: validation_plays.py ARGS for G (the shipped guards: validation_plays.py's default)
g() { python experiments/validation_plays.py "$NAME" --run runs/interrogator_far/ensemble "$@"; }
. experiments/rules/pairs.sh
. experiments/rules/far_checks.sh
judge_part "$1"
