# The shipped recipe's three steps (rule 74's W) on any first step's climbs, as rule 135 fitted F; sourced by the rules'
# scripts that fit networks (from the repository root, STEP1 set: train_interrogator.py's first-step options, --out OUT
# among them).
# fit_three_steps OUT POLICY ESTIMATOR: step 1 (filter and guard), step 2 (8000 on-policy env climbs of step 1's
# networks with the shipped climb, assembled in POLICY, into ESTIMATOR), step 3 (the guard again with those added, step
# 1's guard as the probing guard); --reuse: an interrupted fit resumes
fit_three_steps() {
  local out=$1 policy=$2 estimator=$3
  python experiments/train_interrogator.py $STEP1 --fit-only --reuse
  python experiments/assemble_policy.py --filter "$out/ensemble" --guards "$out/guard/ensemble" --out "$policy"
  python experiments/train_estimator.py --policy "$policy" --set ceiling_stop=false --out "$estimator" \
    --climbs env=8000 --collect-only
  python experiments/train_interrogator.py $STEP1 --fit-only --reuse \
    --add-guard-climbs "$estimator"/onpolicy_env_*.npz --probing-guard
}
# fit_on_far_caches OUT POLICY ESTIMATOR CACHE...: fit_three_steps on rule 135's climb caches
# (runs/interrogator_far/climbs_CACHE.npz, collected by rule135.sh fit), linked into OUT
fit_on_far_caches() {
  local out=$1 policy=$2 estimator=$3 cache
  shift 3
  mkdir -p "$out"
  for cache in "$@"; do
    [ -e "$out/climbs_$cache.npz" ] || ln -s "$PWD/runs/interrogator_far/climbs_$cache.npz" "$out/climbs_$cache.npz"
  done
  fit_three_steps "$out" "$policy" "$estimator"
}
# g ARGS...: validation_plays.py ARGS for NAME's fitted networks in OUT (filter, guard, probing guard), as
# far_checks.sh's judge_part plays them
g() {
  python experiments/validation_plays.py "$NAME" --run "$OUT/ensemble" \
    --guards "$OUT/guard/ensemble" "$OUT/probing_guard/ensemble" "$@"
}
