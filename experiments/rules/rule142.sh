#!/usr/bin/env bash
# Rule 142 (docs/interrogator.md): E3, the shipped agent with elasticity_release 3 (a headroom stop deferred to a
# slow-probe step while the creep curve's offset-free elasticity is at most 3), against the shipped agent (its plays of
# rule 135, rule135shipped: the same commands).
#   experiments/rules/rule142.sh qualify   # the four validation plays and extremes_confirmation17
#   experiments/rules/rule142.sh confirm   # confirmation46 (at the draws, noise tripled, 0.1 s lag),
#                                          # torque_confirmation25 and extremes_confirmation18, both agents
set -e
cd "$(dirname "$0")/../.."  # the repository root
. experiments/rules/pairs.sh
. experiments/rules/far_checks.sh
judge_setting rule142 rule142E3 elasticity_release=3 "$1"
