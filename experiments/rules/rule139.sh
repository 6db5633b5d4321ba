#!/usr/bin/env bash
# Rule 139 (docs/interrogator.md): K25, the shipped agent with the slow probe's step creep_log_step 0.025 in place of
# 0.03, against the shipped agent (its plays of rule 135, rule135shipped: the same commands).
#   experiments/rules/rule139.sh qualify   # the four validation plays (rule 138's explore played them as x138a0c25)
#                                          # and extremes_confirmation17
#   experiments/rules/rule139.sh confirm   # confirmation46 (at the draws, noise tripled, 0.1 s lag),
#                                          # torque_confirmation25 and extremes_confirmation18, both agents
set -e
cd "$(dirname "$0")/../.."  # the repository root
. experiments/rules/pairs.sh
. experiments/rules/far_checks.sh
judge_setting rule139 rule139K25 creep_log_step=0.025 "$1"
