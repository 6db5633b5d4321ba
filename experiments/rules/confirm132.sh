#!/usr/bin/env bash
# Rule 132's confirmation (docs/interrogator.md): G2.25 (runs/gate129c2.25) and the shipped agent on confirmation44 with
# every encoder lagged 5, 10, 15, 20 and 30 ms and on extremes_confirmation16, then the rule's three checks
set -e
cd "$(dirname "$0")/../.."  # the repository root
NAME=rule132G2.25
BASE=rule132shipped
SET=confirmation44
EXTREMES=extremes_confirmation16
S="--confirmation $SET torque_confirmation24 $EXTREMES --encoder-lag --more-encoder-lags 0.005 0.015 0.02 0.03"
LAGGED="${SET}_encoder_lag_s0.005 ${SET}_encoder_lag_s ${SET}_encoder_lag_s0.015 ${SET}_encoder_lag_s0.02"
. experiments/rules/gate_pairs.sh
play_both $S --only $LAGGED ${SET}_encoder_lag_s0.03 $EXTREMES  # the lagged plays and the extremes set's alone
mapfile -t lags < <(pairs_of $LAGGED)
mapfile -t lag30 < <(pairs_of ${SET}_encoder_lag_s0.03)
mapfile -t sharp < <(pairs_of $EXTREMES)
python experiments/rule_check.py "${lags[@]}" --gain --errors --returns --family-wise --sign-test --discordant \
  --more-runaways 1728 --out out/rule_check_rule132_confirmation_encoder_lags.md || true
python experiments/rule_check.py "${lag30[@]}" --no-loss --errors --error-grid family --returns --family-wise \
  --sign-test --discordant --more-runaways 432 --out out/rule_check_rule132_confirmation_encoder_lag30.md || true
# the extremes set has no family grid: rule 130's (b) as its five-pair check read this pair (no error condition, no
# strict grid; the return, the runaways' sign test)
python experiments/rule_check.py "${sharp[@]}" --no-loss --returns --family-wise --sign-test --discordant \
  --more-runaways 2352 --strict-grid none --out out/rule_check_rule132_confirmation.md || true
