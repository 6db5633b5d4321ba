#!/usr/bin/env bash
# Rule 128 (docs/interrogator.md): G's networks (rule127.sh) with the gated decisions' caution raised to 2.5 and 3;
# each candidate's lagged validation play and rule 127's (ii), then its four validation plays and (i) where (ii) holds
set -e
cd "$(dirname "$0")/../.."  # the repository root
SHIPPED=cof_gym/agents/policies/interrogator
for c in 2.5 3; do
  python experiments/assemble_policy.py --filter $SHIPPED --guards $SHIPPED/guard_0 $SHIPPED/guard_1 \
    --smoothed-filter runs/interrogator_smoothed/ensemble \
    --smoothed-guards $SHIPPED/guard_0 runs/interrogator_smoothed/guard/ensemble --smoothed-set caution=$c \
    --out runs/gate128c$c
  python experiments/validation_plays.py rule128G$c --run runs/gate128c$c --encoder-lag-only
  if python experiments/rule_check.py out/records_rule95shipped53_encoder_lag_s.json \
      out/records_rule128G${c}_encoder_lag_s.json --gain --errors --error-grid family --returns --family-wise \
      --sign-test --more-runaways 360 --discordant --out out/rule_check_rule128G${c}_encoder_lag.md; then
    python experiments/validation_plays.py rule128G$c --run runs/gate128c$c
    pairs=()
    for play in validation validation_torque noise_level motor_lag_s; do
      pairs+=(out/records_rule95shipped53_$play.json out/records_rule128G${c}_$play.json)
    done
    python experiments/rule_check.py "${pairs[@]}" --no-loss --errors --error-grid family --returns --family-wise \
      --sign-test --more-runaways 1440 --discordant --out out/rule_check_rule128G${c}_validation.md || true
  fi
done
