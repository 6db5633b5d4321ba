#!/usr/bin/env bash
# Trains the shipped PPO policy (cof_gym/agents/policies/ppo_wagon) and reports it. 2 cores, CPU torch.
# A v1 policy (CofGym/TorqueInterrogation-v1, where it was selected and is reported; `cof-gym train` trains v2 by
# default). Three seeds of `cof-gym train` with cof_gym/agents/hyperparams/ppo.yml (identified actions,
# identification observation, no shaping): each first clones the model-based agent over 600 DART
# episodes (policy and value; cof_gym/agents/pretrain.py; exploration log std -3 on the torque step,
# -2 elsewhere), then runs 40 k steps of PPO, with checkpoints every 10 k. Measured: ~470 s of cloning
# + ~1150 s of PPO per seed with six runs sharing 2 cores (<= 27 min wall per seed). Then model selection
# on experiments/suites/validation_grid.json only, reporting on the held-out grid and the v1 default
# suite, and --ship copies the best-on-validation policy into the package.
set -euo pipefail
cd "$(dirname "$0")/.."
for seed in 0 1 2; do
  cof-gym train --env CofGym/TorqueInterrogation-v1 --timesteps 40000 --seed "$seed" --out "runs/ppo_lo_s$seed" \
    --overwrite --no-progress --eval-freq 10000 --eval-episodes 20 --save-freq 10000 --pretrain-episodes 600 \
    --pretrain-log-std=-3,-2,-2,-2,-2 &
done
wait
python experiments/ppo_seeds.py --runs runs/ppo_lo_s0 runs/ppo_lo_s1 runs/ppo_lo_s2 --out out/ppo_seeds --ship
cof-gym evaluate --out out/evaluate
cof-gym evaluate --suite experiments/suites/heldout_grid.json --out out/evaluate-heldout
cof-gym evaluate --suite experiments/suites/v1_default.json --episodes 60 --out out/evaluate-v1
python experiments/readme_results.py
