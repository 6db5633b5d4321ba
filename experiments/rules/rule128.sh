#!/usr/bin/env bash
# Rule 128 (docs/interrogator.md): G's networks (rule127.sh) with the gated decisions' caution raised to 2.5 and 3;
# each candidate's lagged validation play and rule 127's (ii), then its four validation plays and (i) where (ii) holds.
# Rule 129: experiments/rules/rule128.sh 2.25 129 (the cautions, then the rule's number)
set -e
cd "$(dirname "$0")/../.."  # the repository root
SHIPPED=cof_gym/agents/policies/interrogator
CAUTIONS=${1:-"2.5 3"}
RULE=${2:-128}
for c in $CAUTIONS; do
  python experiments/assemble_policy.py --filter $SHIPPED --guards $SHIPPED/guard_0 $SHIPPED/guard_1 \
    --smoothed-filter runs/interrogator_smoothed/ensemble \
    --smoothed-guards $SHIPPED/guard_0 runs/interrogator_smoothed/guard/ensemble --smoothed-set caution=$c \
    --out runs/gate${RULE}c$c
  python experiments/validation_plays.py rule${RULE}G$c --run runs/gate${RULE}c$c --encoder-lag-only
  if python experiments/rule_check.py out/records_rule95shipped53_encoder_lag_s.json \
      out/records_rule${RULE}G${c}_encoder_lag_s.json --gain --errors --error-grid family --returns --family-wise \
      --sign-test --more-runaways 360 --discordant --out out/rule_check_rule${RULE}G${c}_encoder_lag.md; then
    python experiments/validation_plays.py rule${RULE}G$c --run runs/gate${RULE}c$c
    pairs=()
    for play in validation validation_torque noise_level motor_lag_s; do
      pairs+=(out/records_rule95shipped53_$play.json out/records_rule${RULE}G${c}_$play.json)
    done
    python experiments/rule_check.py "${pairs[@]}" --no-loss --errors --error-grid family --returns --family-wise \
      --sign-test --more-runaways 1440 --discordant --out out/rule_check_rule${RULE}G${c}_validation.md || true
  fi
done
