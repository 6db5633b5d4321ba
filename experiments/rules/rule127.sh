#!/usr/bin/env bash
# Rule 127 (docs/interrogator.md): G's networks fitted on collect_encoder.sh's lagged-encoder climbs (hard links
# where they exist), the candidate's policy directory (the shipped one with the gate), its five validation plays and
# the shipped agent's beside them, and the rule's two checks (qualification only; the confirmation is confirm127.sh)
set -e
cd "$(dirname "$0")/../.."  # the repository root
SHIPPED=cof_gym/agents/policies/interrogator
mkdir -p runs/interrogator_smoothed
for name in torque_wide_encoder procedural_torque_wide_encoder; do
  if [ -f runs/interrogator_encoder/climbs_$name.npz ] && [ ! -f runs/interrogator_smoothed/climbs_$name.npz ]; then
    ln runs/interrogator_encoder/climbs_$name.npz runs/interrogator_smoothed/climbs_$name.npz
  fi
done
python experiments/train_interrogator.py --out runs/interrogator_smoothed --climbs torque_wide_encoder=8000 \
  --guard-climbs torque_wide_encoder=8000 procedural_torque_wide_encoder=8000 --fit-only
python experiments/assemble_policy.py --filter $SHIPPED --guards $SHIPPED/guard_0 $SHIPPED/guard_1 \
  --smoothed-filter runs/interrogator_smoothed/ensemble \
  --smoothed-guards $SHIPPED/guard_0 runs/interrogator_smoothed/guard/ensemble --out runs/gate127
python experiments/validation_plays.py rule127G --run runs/gate127 --encoder-lag
for play in validation validation_torque noise_level motor_lag_s encoder_lag_s; do  # the baseline, once
  [ -f out/records_rule95shipped53_$play.json ] || missing=1
done
if [ -n "$missing" ]; then python experiments/validation_plays.py rule95shipped53 --encoder-lag; fi
pairs=()
for play in validation validation_torque noise_level motor_lag_s; do
  pairs+=(out/records_rule95shipped53_$play.json out/records_rule127G_$play.json)
done
python experiments/rule_check.py "${pairs[@]}" --no-loss --errors --error-grid family --returns --family-wise \
  --sign-test --more-runaways 1440 --discordant --out out/rule_check_rule127G_validation.md || true
python experiments/rule_check.py out/records_rule95shipped53_encoder_lag_s.json out/records_rule127G_encoder_lag_s.json \
  --gain --errors --error-grid family --returns --family-wise --sign-test --more-runaways 360 --discordant \
  --out out/rule_check_rule127G_encoder_lag.md || true
