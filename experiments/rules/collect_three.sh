#!/usr/bin/env bash
# Session 62 (docs/interrogator.md, rule 120): the recipe's noisy climbs (noise and drive lag past the draws, rule 78's
# draws) cached in runs/interrogator_three beside the sharp and lagged-encoder collections of collect_encoder.sh
# (hard links where those exist, else collected); nothing fitted
set -e
cd "$(dirname "$0")/../.."  # the repository root
mkdir -p runs/interrogator_three
for name in torque_wide torque_wide_encoder procedural_torque_wide procedural_torque_wide_encoder; do
  if [ -f runs/interrogator_encoder/climbs_$name.npz ] && [ ! -f runs/interrogator_three/climbs_$name.npz ]; then
    ln runs/interrogator_encoder/climbs_$name.npz runs/interrogator_three/climbs_$name.npz
  fi
done
python - <<'PY'
import sys
from pathlib import Path
sys.path.insert(0, "experiments")
from train_interrogator import load_or_collect
out = Path("runs/interrogator_three")
for name in ("noisy_torque_wide", "procedural_noisy_torque_wide"):
    load_or_collect(out, name, 8000, 2, True)
PY
