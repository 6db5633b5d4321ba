#!/usr/bin/env bash
# Trains the shipped PPO policy (agents/policies/ppo_wagon) and evaluates it. 2 cores, CPU torch.
set -euo pipefail
cof-gym train --algo ppo --env CofGym/TorqueInterrogation-v0 --timesteps 300000 --action-adapter incremental \
    --seed 0 --out runs/ppo_wagon --overwrite
mkdir -p agents/policies/ppo_wagon
cp runs/ppo_wagon/model.zip runs/ppo_wagon/vecnormalize.pkl runs/ppo_wagon/train_meta.json agents/policies/ppo_wagon/
cof-gym evaluate --agents staircase-paper,staircase,ppo --episodes 60 --suite default --seed 0 --out out/evaluate
