#!/usr/bin/env bash
# Rule 114 (docs/interrogator.md): LFf's five validation plays (LF's filter, the shipped guards)
set -e
cd "$(dirname "$0")/../.."  # the repository root
python experiments/validation_plays.py rule114LFf --run runs/interrogator_encoder/ensemble --encoder-lag
