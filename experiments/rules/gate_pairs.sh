# Sourced by confirm130.sh-confirm132.sh (run from the repository root, NAME and BASE set): G2.25's plays
# (runs/gate129c2.25) and the shipped agent's, and the pairs of their records that rule_check.py reads.
# play_both ARGS...: validation_plays.py ARGS for G2.25 (recorded as NAME) and for the shipped agent (as BASE)
play_both() {
  python experiments/validation_plays.py "$NAME" --run runs/gate129c2.25 "$@"
  python experiments/validation_plays.py "$BASE" "$@"
}
# pairs_of PLAY...: the shipped agent's and G2.25's records of each play, one path a line
pairs_of() { for play in "$@"; do printf '%s\n' "out/records_${BASE}_$play.json" "out/records_${NAME}_$play.json"; done; }
FAMILY_WISE="--errors --error-grid family --returns --family-wise --sign-test --discordant"  # rule 127's (i) and (ii)
