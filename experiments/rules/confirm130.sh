#!/usr/bin/env bash
# Rule 130's confirmation (docs/interrogator.md): G2.25 (runs/gate129c2.25) and the shipped agent on the five plays of
# confirmation42, torque_confirmation23 and extremes_confirmation14 and the first set's plays with every encoder lagged
# 10, 5 and 20 ms, then the rule's three checks, (b), (ii') and (iii)
set -e
cd "$(dirname "$0")/../.."  # the repository root
NAME=rule130G2.25
BASE=rule130shipped
SET=confirmation42
S="--confirmation $SET torque_confirmation23 extremes_confirmation14 --encoder-lag --more-encoder-lags 0.005 0.02"
. experiments/rules/gate_pairs.sh
play_both $S
mapfile -t five < <(pairs_of $SET ${SET}_noise_level ${SET}_motor_lag_s torque_confirmation23 extremes_confirmation14)
mapfile -t lag10 < <(pairs_of ${SET}_encoder_lag_s)
mapfile -t lags < <(pairs_of ${SET}_encoder_lag_s0.005 ${SET}_encoder_lag_s0.02)
python experiments/rule_check.py "${five[@]}" --no-loss $FAMILY_WISE --more-runaways 2352 \
  --out out/rule_check_rule130_confirmation.md || true
python experiments/rule_check.py "${lag10[@]}" --gain $FAMILY_WISE --fewer-runaways \
  --out out/rule_check_rule130_confirmation_encoder_lag.md || true
python experiments/rule_check.py "${lags[@]}" --no-loss $FAMILY_WISE --more-runaways 0 \
  --out out/rule_check_rule130_confirmation_encoder_lags.md || true
