#!/usr/bin/env bash
# Regenerates docs/STABILITY.md: every friction law x integrator x float/double over K 0..100,
# damping ratio 0..2, smoothing constant 1..1e6 s/m and dt 1e-5..0.05 s (about 5 minutes on one
# core). Exits non-zero if any accepted cell is unstable.
#   tools/stability-map.sh            the full map into docs/STABILITY.md
#   tools/stability-map.sh --coarse   the CTest subset, printed
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)" --target stickslip_stability_map
if [ "${1:-}" = "--coarse" ]; then
  exec build/release/reliability/stickslip_stability_map --coarse
fi
build/release/reliability/stickslip_stability_map --output docs/STABILITY.md \
  --command "tools/stability-map.sh"
