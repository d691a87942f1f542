#!/usr/bin/env bash
# Builds the `asan` preset (AddressSanitizer + UndefinedBehaviorSanitizer, Debug -O1) and runs the
# whole CTest suite under it; any sanitizer report fails the test that raised it.
#   tools/sanitize.sh [ctest options...]
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
start=$(date +%s)
cmake --preset asan >/dev/null
cmake --build --preset asan -j "$(nproc)"
ctest --preset asan -j "$(nproc)" "$@"
echo "sanitize: build and suite under ASan+UBSan in $(( $(date +%s) - start )) s" >&2
