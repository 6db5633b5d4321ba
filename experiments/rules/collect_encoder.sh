#!/usr/bin/env bash
# Session 60 (docs/interrogator.md, rule 112): the recipe's probing climbs with and without drawn encoder lags, cached
# in runs/interrogator_encoder for rule 112's fit (nothing fitted; about 30 minutes per collection on 2 cores)
set -e
cd "$(dirname "$0")/../.."  # the repository root
python - <<'PY'
import sys
from pathlib import Path
sys.path.insert(0, "experiments")
from train_interrogator import load_or_collect
out = Path("runs/interrogator_encoder"); out.mkdir(parents=True, exist_ok=True)
for name in ("torque_wide_encoder", "procedural_torque_wide_encoder", "torque_wide", "procedural_torque_wide"):
    load_or_collect(out, name, 8000, 2, True)
PY
