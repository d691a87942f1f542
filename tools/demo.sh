#!/usr/bin/env bash
# The main job: install what is missing, build, and run the demo (a synthetic lorry recording
# through the signum and stick-slip models, with the model the scene needs; then the recording
# replayed as CAN frames over the default bus to the ECU node, with the fault counters).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release --target stickslip -j "$(nproc)"
exec build/release/sim_host/stickslip demo "$@"
