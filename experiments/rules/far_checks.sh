# Rule 135's checks (docs/interrogator.md), which rules 136-142 take word for word; sourced by rule135.sh to
# rule142.sh (from the repository root, RULE, BASE and NAME set, or by judge_setting) after experiments/rules/pairs.sh.
# check OUT PLAYS OPTIONS...: check_plays into out/rule_check_${RULE}_OUT.md
check() { local out=$1; shift; check_plays "${RULE}_$out" "$@"; }
# (i) over the four plays at and past the draws, (ii) on an extremes set
FOUR="--gain --errors --family-wise --sign-test --discordant --more-runaways 100000"
EXTREMES="--gain --errors --family-wise --sign-test --discordant --more-runaways 100000 --strict-grid none"
# base ARGS...: validation_plays.py ARGS for the shipped agent (BASE)
base() { python experiments/validation_plays.py "$BASE" "$@"; }
# judge_part qualify|confirm: a candidate against the shipped agent's plays of rule 135 (rules 136-141), with g ARGS...
# (validation_plays.py ARGS for the candidate) defined; qualify plays the shipped agent only where its records of rule
# 135 are missing
judge_part() {
  local X
  case "$1" in
    qualify)
      g
      [ -f "out/records_${BASE}_motor_lag_s.json" ] || base
      X="--confirmation confirmation45 torque_confirmation24 extremes_confirmation17 --only extremes_confirmation17"
      g $X
      [ -f "out/records_${BASE}_extremes_confirmation17.json" ] || base $X
      check validation "validation validation_torque noise_level motor_lag_s" $FOUR
      check extremes "extremes_confirmation17" $EXTREMES
      ;;
    confirm)
      X="--confirmation confirmation46 torque_confirmation25 extremes_confirmation18"
      g $X
      base $X
      check confirmation "confirmation46 torque_confirmation25 confirmation46_noise_level confirmation46_motor_lag_s" \
        $FOUR
      check confirmation_extremes "extremes_confirmation18" $EXTREMES
      ;;
    *) echo "usage: experiments/rules/$RULE.sh qualify|confirm" >&2; exit 2 ;;
  esac
}
# judge_setting RULE NAME SETTING qualify|confirm: a rule whose candidate NAME is the shipped agent with
# validation_plays.py's --set SETTING (rules 139 and 142), judged by judge_part against the shipped agent's plays of
# rule 135 (g and the names judge_part reads set here; bash's locals are seen by the functions this one calls)
judge_setting() {
  RULE=$1 NAME=$2 BASE=rule135shipped
  local setting=$3
  g() { python experiments/validation_plays.py "$NAME" --set "$setting" "$@"; }
  judge_part "$4"
}
