#!/usr/bin/env bash
# The soak run: 1e9 samples (11.6 days of ride at 1 ms) of the lorry-like scene through the
# stick-slip oscillator and its running statistics, in float (the ECU's type), checking no NaN,
# an exact integer sample count and the statistics against a blockwise recomputation (see
# reliability/src/soak_main.cpp). About a minute per 1e9 samples on an idle core.
#   tools/soak.sh [--samples N] [--type float|double]
# Checkpoints go to build/soak-<type>.csv.
set -euo pipefail
cd "$(dirname "$0")/.."
samples=1e9
type=float
while [ $# -gt 0 ]; do
  case "$1" in
    --samples) samples=$2; shift 2 ;;
    --type) type=$2; shift 2 ;;
    *) echo "soak: unknown option '$1' (--samples N, --type float|double)" >&2; exit 2 ;;
  esac
done
bash tools/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)" --target stickslip_soak
build/release/reliability/stickslip_soak --samples "$samples" --type "$type" \
  --csv "build/soak-$type.csv"
