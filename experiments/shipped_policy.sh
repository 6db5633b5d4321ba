#!/usr/bin/env bash
# Trains the shipped PPO policy (cof_gym/agents/policies/ppo_wagon) and reports it. 2 cores, CPU torch.
# Three seeds of `cof-gym train` with cof_gym/agents/hyperparams/ppo.yml (identified actions,
# identification observation, shaping): each first clones the model-based agent over 600 episodes
# (policy and value; cof_gym/agents/pretrain.py), then runs 100 k steps of PPO. Wall time: see
# README ("PPO"), measured with the three seeds running side by side on 2 cores. Then model selection
# on experiments/suites/validation_grid.json only, reporting on the held-out grid and the default
# suite, and --ship copies the best-on-validation policy into the package.
set -euo pipefail
cd "$(dirname "$0")/.."
for seed in 0 1 2; do
  cof-gym train --timesteps 100000 --seed "$seed" --out "runs/ppo_id_s$seed" --overwrite --no-progress \
    --eval-freq 25000 --eval-episodes 20 --pretrain-episodes 600 &
done
wait
python experiments/ppo_seeds.py --runs runs/ppo_id_s0 runs/ppo_id_s1 runs/ppo_id_s2 --out out/ppo_seeds --ship
cof-gym evaluate --out out/evaluate
cof-gym evaluate --suite experiments/suites/heldout_grid.json --out out/evaluate-heldout
python experiments/readme_results.py
