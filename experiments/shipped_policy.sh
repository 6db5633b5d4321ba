#!/usr/bin/env bash
# Trains the shipped PPO policy (cof_gym/agents/policies/ppo_wagon) and reports it. 2 cores, CPU torch.
# Three seeds of `cof-gym train` with cof_gym/agents/hyperparams/ppo.yml (relative actions, history
# observation, shaping; 120 k steps each; measured: 2136 s wall per seed with the three running side by
# side on 2 cores, ~57 steps/s each), then model selection on experiments/suites/validation_grid.json
# only, reporting on the held-out grid and the default suite, and --ship copies the best-on-validation
# policy into the package.
set -euo pipefail
cd "$(dirname "$0")/.."
for seed in 0 1 2; do
  cof-gym train --timesteps 120000 --seed "$seed" --out "runs/ppo_s$seed" --overwrite --no-progress --eval-freq 40000 &
done
wait
python experiments/ppo_seeds.py --runs runs/ppo_s0 runs/ppo_s1 runs/ppo_s2 --out out/ppo_seeds --ship
cof-gym evaluate --out out/evaluate
cof-gym evaluate --suite experiments/suites/heldout_grid.json --out out/evaluate-heldout
python experiments/readme_results.py
