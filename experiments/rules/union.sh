#!/usr/bin/env bash
# union.sh OUT RUN: the shipped networks pooled with a run's (rules 115 and 120, docs/interrogator.md): OUT/filter
# from the shipped filter and RUN/ensemble, OUT/guard_1 from the shipped probing guard and RUN/guard/ensemble; each
# pool written once (an existing one is kept)
set -e
cd "$(dirname "$0")/../.."  # the repository root
SHIPPED=cof_gym/agents/policies/interrogator
[ -d "$1/filter" ] || python experiments/pool_ensembles.py --out "$1/filter" $SHIPPED "$2/ensemble"
[ -d "$1/guard_1" ] || python experiments/pool_ensembles.py --out "$1/guard_1" $SHIPPED/guard_1 "$2/guard/ensemble"
