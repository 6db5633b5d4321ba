# Rule 135's checks (docs/interrogator.md), which rule 136 takes word for word; sourced by rule135.sh and rule136.sh
# (from the repository root, RULE, BASE and NAME set) after experiments/rules/pairs.sh.
# check OUT PLAYS OPTIONS...: check_plays into out/rule_check_${RULE}_OUT.md
check() { local out=$1; shift; check_plays "${RULE}_$out" "$@"; }
# (i) over the four plays at and past the draws, (ii) on an extremes set
FOUR="--gain --errors --family-wise --sign-test --discordant --more-runaways 100000"
EXTREMES="--gain --errors --family-wise --sign-test --discordant --more-runaways 100000 --strict-grid none"
