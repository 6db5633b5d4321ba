# Sourced by confirm130.sh-confirm133.sh (run from the repository root, NAME and BASE set): G2.25's plays
# (runs/gate129c2.25) and the shipped agent's, and the pairs of their records that rule_check.py reads.
# play_both ARGS...: validation_plays.py ARGS for G2.25 (recorded as NAME; with CANDIDATE_SET=NAME=VALUE, its climb
# parameter changed: validation_plays.py --set) and for the shipped agent (as BASE)
play_both() {
  python experiments/validation_plays.py "$NAME" --run runs/gate129c2.25 ${CANDIDATE_SET:+--set "$CANDIDATE_SET"} "$@"
  python experiments/validation_plays.py "$BASE" "$@"
}
. experiments/rules/pairs.sh  # pairs_of: the shipped agent's and G2.25's records of each play
FAMILY_WISE="--errors --error-grid family --returns --family-wise --sign-test --discordant"  # rule 127's (i) and (ii)
# confirm_return_first RULE: rule 132's plays and checks (docs/interrogator.md) for rule RULE, SET and EXTREMES set:
# SET with every encoder lagged 5, 10, 15 and 20 ms together, SET at 30 ms, and EXTREMES with the encoder as drawn
confirm_return_first() {
  local rule=$1 lagged="${SET}_encoder_lag_s0.005 ${SET}_encoder_lag_s ${SET}_encoder_lag_s0.015 ${SET}_encoder_lag_s0.02"
  local lags lag30 sharp
  # the lagged plays and the extremes set's alone (the torque set named for validation_plays.py's --confirmation)
  play_both --confirmation "$SET" torque_confirmation24 "$EXTREMES" --encoder-lag \
    --more-encoder-lags 0.005 0.015 0.02 0.03 --only $lagged "${SET}_encoder_lag_s0.03" "$EXTREMES"
  mapfile -t lags < <(pairs_of $lagged)
  mapfile -t lag30 < <(pairs_of "${SET}_encoder_lag_s0.03")
  mapfile -t sharp < <(pairs_of "$EXTREMES")
  python experiments/rule_check.py "${lags[@]}" --gain --errors --returns --family-wise --sign-test --discordant \
    --more-runaways 1728 --out "out/rule_check_rule${rule}_confirmation_encoder_lags.md" || true
  python experiments/rule_check.py "${lag30[@]}" --no-loss --errors --error-grid family --returns --family-wise \
    --sign-test --discordant --more-runaways 432 --out "out/rule_check_rule${rule}_confirmation_encoder_lag30.md" || true
  # the extremes set has no family grid: rule 130's (b) as its five-pair check read this pair (no error condition, no
  # strict grid; the return, the runaways' sign test)
  python experiments/rule_check.py "${sharp[@]}" --no-loss --returns --family-wise --sign-test --discordant \
    --more-runaways 2352 --strict-grid none --out "out/rule_check_rule${rule}_confirmation.md" || true
}
