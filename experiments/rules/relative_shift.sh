#!/usr/bin/env bash
# Session 70's exploration (docs/interrogator.md, no rule): the shipped agent with its estimate shifted by
# ClimbParameters.relative_error_shift 0, 0.5, 1 and 2 on spent sets (the validation grids at the draws and with the
# noise tripled, confirmation43 at the draws); about 14 minutes on 2 cores
set -e
cd "$(dirname "$0")/../.."  # the repository root
GUARDS="cof_gym/agents/policies/interrogator/guard_0 cof_gym/agents/policies/interrogator/guard_1"
SHIFTS="relative_error_shift=0 relative_error_shift=0.5 relative_error_shift=1 relative_error_shift=2"
play() {  # play NAME GRID-ARGS...
  local name=$1
  shift
  python experiments/crest_tradeoff.py --guards $GUARDS --guards-only --targets 0.1 --stops --return-digits 4 "$@" \
    --set $SHIFTS --records "out/records_relative_shift_$name.json" --out "out/crest_tradeoff_relative_shift_$name.md"
}
play validation --grids validation
play confirmation43 --grids confirmation43
play validation_noise --grids validation --scenario noise_level=3
