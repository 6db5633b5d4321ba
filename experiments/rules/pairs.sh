# Sourced by the rules' scripts (run from the repository root, BASE and NAME set: the baseline's and the candidate's
# names in the records' file names): the pairs of their records that rule_check.py reads.
# pairs_of PLAY...: BASE's and NAME's records of each play, one path a line
pairs_of() { for play in "$@"; do printf '%s\n' "out/records_${BASE}_$play.json" "out/records_${NAME}_$play.json"; done; }
# check_plays OUT PLAYS OPTIONS...: rule_check.py with OPTIONS on the pairs of PLAYS (space-separated), its verdict
# also in out/rule_check_OUT.md (a failing verdict does not stop the script)
check_plays() {
  local out=$1 plays=$2 pairs
  shift 2
  mapfile -t pairs < <(pairs_of $plays)
  python experiments/rule_check.py "${pairs[@]}" "$@" --out "out/rule_check_$out.md" || true
}
