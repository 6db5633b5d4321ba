#!/usr/bin/env bash
# Rule 133's confirmation (docs/interrogator.md): D (G2.25, runs/gate129c2.25, with gate_max_drive_lag_s=0.04) and the
# shipped agent on confirmation45 with every encoder lagged 5, 10, 15, 20 and 30 ms and on extremes_confirmation17,
# then rule 132's three checks
set -e
cd "$(dirname "$0")/../.."  # the repository root
NAME=rule133D
BASE=rule133shipped
SET=confirmation45
EXTREMES=extremes_confirmation17
CANDIDATE_SET=gate_max_drive_lag_s=0.04
. experiments/rules/gate_pairs.sh
confirm_return_first 133
