#!/bin/bash
set -e
cd /work/main
. .venv/bin/activate
t() { local s=$(date +%s); "$@" > /dev/null; echo "$(( $(date +%s) - s )) s: $*"; }
t python experiments/estimate_interval.py --write --out out/estimate_interval.md
t cof-gym evaluate --out out/evaluate
t cof-gym evaluate --suite experiments/suites/v2_no_systematic_errors.json --episodes 60 --out out/evaluate-v2-no-errors
t cof-gym evaluate --suite experiments/suites/v2_stress_tables_grid.json --out out/evaluate-v2-stress-tables
t cof-gym evaluate --suite experiments/suites/v2_extremes_grid.json --out out/evaluate-v2-extremes
for k in "" 2 3 4 5 6 7; do t cof-gym evaluate --suite experiments/suites/v2_heldout${k}_grid.json --out out/evaluate-v2-heldout$k; done
t cof-gym evaluate --suite experiments/suites/v1_default.json --episodes 60 --out out/evaluate-v1
t cof-gym evaluate --suite experiments/suites/heldout_grid.json --out out/evaluate-heldout
t cof-gym evaluate --env-kwargs max_windows:45 --agents oracle,phase-rule,robust-model,interrogator
t cof-gym evaluate --env-kwargs max_windows:60 --agents oracle,phase-rule,robust-model,interrogator
for k in "" 2 3 4 5 6 7; do t cof-gym evaluate --suite experiments/suites/v2_heldout${k}_grid.json --env-kwargs max_windows:60 --agents oracle,phase-rule,robust-model,interrogator; done
t python experiments/sensor_sensitivity.py --out out/sensor_sensitivity.md
t python experiments/train_interrogator.py --out runs/interrogator_shipped --report-only
t python experiments/torque_balance.py
t python experiments/torque_balance.py --suites experiments/suites/v2_heldout_grid.json experiments/suites/v2_heldout{2,3,4,5,6,7}_grid.json --out out/torque_balance_heldout.md
echo done
