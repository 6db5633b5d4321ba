#!/usr/bin/env bash
# Rule 132's confirmation (docs/interrogator.md): G2.25 (runs/gate129c2.25) and the shipped agent on confirmation44 with
# every encoder lagged 5, 10, 15, 20 and 30 ms and on extremes_confirmation16, then the rule's three checks
set -e
cd "$(dirname "$0")/../.."  # the repository root
NAME=rule132G2.25
BASE=rule132shipped
SET=confirmation44
EXTREMES=extremes_confirmation16
. experiments/rules/gate_pairs.sh
confirm_return_first 132
