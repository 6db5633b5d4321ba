#!/usr/bin/env bash
# Rule 131's confirmation (docs/interrogator.md): G2.25 (runs/gate129c2.25) and the shipped agent on the five plays of
# confirmation43, torque_confirmation24 and extremes_confirmation15 and the first set's plays with every encoder lagged
# 5, 10, 15, 20 and 30 ms, then the rule's three checks, (b), (ii'') and (iii')
set -e
cd "$(dirname "$0")/../.."  # the repository root
NAME=rule131G2.25
BASE=rule131shipped
SET=confirmation43
S="--confirmation $SET torque_confirmation24 extremes_confirmation15 --encoder-lag --more-encoder-lags 0.005 0.015 0.02 0.03"
. experiments/rules/gate_pairs.sh
play_both $S
mapfile -t five < <(pairs_of $SET ${SET}_noise_level ${SET}_motor_lag_s torque_confirmation24 extremes_confirmation15)
mapfile -t lags < <(pairs_of ${SET}_encoder_lag_s0.005 ${SET}_encoder_lag_s ${SET}_encoder_lag_s0.015 \
  ${SET}_encoder_lag_s0.02)
mapfile -t lag30 < <(pairs_of ${SET}_encoder_lag_s0.03)
python experiments/rule_check.py "${five[@]}" --no-loss $FAMILY_WISE --more-runaways 2352 \
  --out out/rule_check_rule131_confirmation.md || true
python experiments/rule_check.py "${lags[@]}" --gain --fewer-runaways $FAMILY_WISE \
  --out out/rule_check_rule131_confirmation_encoder_lags.md || true
python experiments/rule_check.py "${lag30[@]}" --no-loss $FAMILY_WISE --more-runaways 432 \
  --out out/rule_check_rule131_confirmation_encoder_lag30.md || true
