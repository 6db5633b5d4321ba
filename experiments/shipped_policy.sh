#!/usr/bin/env bash
# Trains the shipped PPO policy (cof_gym/agents/policies/ppo_wagon) and evaluates it. 2 cores, CPU torch.
set -euo pipefail
# stage 1: 300 k steps (21.7 min here), stage 2: 300 k more, resumed (23.4 min here)
cof-gym train --algo ppo --env CofGym/TorqueInterrogation-v1 --timesteps 300000 --action-adapter incremental \
    --seed 0 --out runs/ppo_wagon --overwrite
cof-gym train --resume runs/ppo_wagon/model.zip --timesteps 300000 --out runs/ppo_wagon_600k --overwrite
mkdir -p cof_gym/agents/policies/ppo_wagon
cp runs/ppo_wagon_600k/model.zip runs/ppo_wagon_600k/vecnormalize.pkl runs/ppo_wagon_600k/train_meta.json \
    cof_gym/agents/policies/ppo_wagon/
cp runs/ppo_wagon/train_meta.json cof_gym/agents/policies/ppo_wagon/train_meta_stage1.json
cof-gym evaluate --agents staircase-paper,staircase,ppo --episodes 60 --suite default --seed 0 --out out/evaluate
