#!/usr/bin/env bash
# Rule 137 (docs/interrogator.md): H, the shipped filter and climb behind rule 135's two guards
# (runs/interrogator_far/guard/ensemble and probing_guard/ensemble, fitted by experiments/rules/rule135.sh fit),
# against the shipped agent (its plays of rule 135, rule135shipped: the same commands).
#   experiments/rules/rule137.sh qualify   # the four validation plays and extremes_confirmation17
#   experiments/rules/rule137.sh confirm   # confirmation46 (at the draws, noise tripled, 0.1 s lag),
#                                          # torque_confirmation25 and extremes_confirmation18, both agents
set -e
cd "$(dirname "$0")/../.."  # the repository root
RULE=rule137
NAME=rule137H
BASE=rule135shipped
# g ARGS... / base ARGS...: validation_plays.py ARGS for H (the shipped filter: validation_plays.py's default) / for the
# shipped agent
g() {
  python experiments/validation_plays.py "$NAME" --guards runs/interrogator_far/guard/ensemble \
    runs/interrogator_far/probing_guard/ensemble "$@"
}
base() { python experiments/validation_plays.py "$BASE" "$@"; }
. experiments/rules/pairs.sh
. experiments/rules/far_checks.sh
judge_part "$1"
