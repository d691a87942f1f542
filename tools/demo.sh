#!/usr/bin/env bash
# The main job: install what is missing, build, and run the demo (a synthetic lorry recording
# through the signum and stick-slip models, with the model the scene needs; then the recording
# replayed as CAN frames over the default bus to the ECU node, with the fault counters).
# The demo's files go into ./stickslip-demo of the directory this script was started from (or
# --out-dir DIR); nothing is left in the temp directory.
set -euo pipefail
caller_dir=$PWD
cd "$(dirname "$0")/.."
repo_dir=$PWD
bash tools/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release --target stickslip -j "$(nproc)"
cd "$caller_dir"
exec "$repo_dir/build/release/sim_host/stickslip" demo "$@"
