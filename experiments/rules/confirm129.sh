#!/usr/bin/env bash
# Rule 129's confirmation (docs/interrogator.md; rule 127's (a') and (b)): G2.25 (runs/gate129c2.25), the shipped
# agent and the hand-built agents on the three unplayed sets and the first set's lagged play, then the rule's checks
set -e
cd "$(dirname "$0")/../.."  # the repository root
NAME=rule129G2.25
BASE=rule129shipped
S="--confirmation confirmation41 torque_confirmation22 extremes_confirmation13 --encoder-lag"
python experiments/validation_plays.py $NAME --run runs/gate129c2.25 $S
python experiments/validation_plays.py $BASE $S
python experiments/validation_plays.py --hand-built $S
FIVE="confirmation41 confirmation41_noise_level confirmation41_motor_lag_s torque_confirmation22 extremes_confirmation13"
joined() { for play in $FIVE; do printf '%s+' "out/records_$1_$play.json"; done | sed 's/+$//'; }
refs=(); lagged=()
for a in phase-rule robust-model staircase model-based; do
  refs+=("$(joined "$a")"); lagged+=("out/records_${a}_confirmation41_encoder_lag_s.json")
done
python experiments/frontier.py "$(joined $BASE)" "$(joined $NAME)" --references "${refs[@]}" \
  --shipped "$(joined $BASE)" --rows --out out/frontier_rule129_confirmation.md
python experiments/frontier.py out/records_${BASE}_confirmation41_encoder_lag_s.json \
  out/records_${NAME}_confirmation41_encoder_lag_s.json --references "${lagged[@]}" \
  --shipped out/records_${BASE}_confirmation41_encoder_lag_s.json --rows \
  --out out/frontier_rule129_confirmation_encoder_lag.md
pairs=(); for play in $FIVE; do pairs+=("out/records_${BASE}_$play.json" "out/records_${NAME}_$play.json"); done
python experiments/rule_check.py "${pairs[@]}" --no-loss --errors --error-grid family --returns --family-wise \
  --sign-test --more-runaways 2352 --discordant --out out/rule_check_rule129_confirmation.md || true
python experiments/rule_check.py out/records_${BASE}_confirmation41_encoder_lag_s.json \
  out/records_${NAME}_confirmation41_encoder_lag_s.json --gain --errors --error-grid family --returns --family-wise \
  --sign-test --more-runaways 360 --discordant --out out/rule_check_rule129_confirmation_encoder_lag.md || true
